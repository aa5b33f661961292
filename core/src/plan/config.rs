use std::fmt;
use std::str::FromStr;

use glam::Vec4;

use super::{ConfigError, Resolution};
use crate::cull::Strategy;
use crate::foveation::FoveationConfig;
use crate::mffr::MffrConfig;
use crate::view::{Eye, EyeParams, FovTangents, HmdProfile, HMD_PROFILES};
use crate::vocab::named_enum;

/// foveate's own limit on views in one pass: two eyes, or two eyes × (periphery, fovea).
pub const MAX_VIEWS: u32 = 4;

/// How the two eyes' views are submitted (Wilson 2015, and Vulkan multiview).
#[derive(Clone, Copy, Debug, PartialEq, Eq, Hash)]
pub enum StereoMode {
    /// One render pass, view mask 0b11, `gl_ViewIndex` picks the eye (`VK_KHR_multiview`).
    Multiview,
    /// The whole scene recorded twice, one render pass per eye.
    TwoPass,
    /// One pass, each object drawn twice with the view state (viewport, eye index) switched.
    PerObject,
    /// One pass, instance count doubled; the eye comes from the instance index and each eye is
    /// squeezed into its half of a double-wide target with a clip distance (Wilson 2015).
    Instanced,
}

impl StereoMode {
    /// Every mode, in the order the benchmarks print them.
    pub const ALL: [StereoMode; 4] = [
        StereoMode::Multiview,
        StereoMode::TwoPass,
        StereoMode::PerObject,
        StereoMode::Instanced,
    ];

    /// Its name on the command line and in the printout.
    pub fn name(self) -> &'static str {
        match self {
            StereoMode::Multiview => "multiview",
            StereoMode::TwoPass => "two-pass",
            StereoMode::PerObject => "per-object",
            StereoMode::Instanced => "instanced",
        }
    }
}

impl fmt::Display for StereoMode {
    fn fmt(&self, f: &mut fmt::Formatter<'_>) -> fmt::Result {
        f.write_str(self.name())
    }
}

impl FromStr for StereoMode {
    type Err = ConfigError;
    fn from_str(s: &str) -> Result<Self, Self::Err> {
        StereoMode::ALL
            .into_iter()
            .find(|m| m.name() == s)
            .ok_or_else(|| {
                ConfigError::new(
                    "stereo",
                    s,
                    "one of multiview, two-pass, per-object, instanced",
                )
            })
    }
}

/// What the frame's last pass writes.
#[derive(Clone, Copy, Debug, PartialEq, Eq, Hash)]
pub enum OutputStage {
    /// The rendered eye images as they are (a foveated frame composed at full resolution):
    /// what an OpenXR application hands its runtime, whose compositor distorts for the lens;
    /// and what tests and goldens compare.
    Undistorted,
    /// What the display shows: each eye pre-distorted for the headset's lens by a full-view
    /// output pass, into which a foveated frame's composition folds (a phone VR app's
    /// compositor pass). Every frame pays for it, the stereo baseline included.
    Lens,
}

/// The format of the image a frame ends in (its output, handed in or the renderer's own).
#[derive(Clone, Copy, Debug, Default, PartialEq, Eq, Hash)]
pub enum OutputFormat {
    /// 8-bit sRGB (`R8G8B8A8_SRGB`): the display's encoding, linear light in blending and
    /// resolves.
    #[default]
    Srgb8,
    /// 8-bit linear values (`R8G8B8A8_UNORM`), for a consumer that takes the image as linear
    /// (dark tones get few levels).
    Unorm8,
    /// Linear half floats (`R16G16B16A16_SFLOAT`): an engine's HDR chain.
    Float16,
}

/// How a foveated frame renders its four views.
#[derive(Clone, Copy, Debug, PartialEq, Eq, Hash)]
pub enum FoveaLayout {
    /// The planner chooses from the scene and the device's quirks (`foveate plan` says why).
    Auto,
    /// One 4-view multiview pass; with culling, instances a fovea frustum misses emit no
    /// primitives in the fovea views (a per-instance view mask read by the vertex shader).
    OnePass,
    /// A 2-view periphery pass and a 2-view fovea pass, each drawing its own culled set.
    TwoPass,
}

named_enum!(OutputStage, "output", [OutputStage::Undistorted => "undistorted", OutputStage::Lens => "lens"]);
named_enum!(FoveaLayout, "fovea layout", [
    FoveaLayout::Auto => "auto",
    FoveaLayout::OnePass => "one-pass",
    FoveaLayout::TwoPass => "two-pass",
]);

/// Per-frame culling of the scene's instances on the CPU (Preißner 2020 §3): distance culling at the
/// draw distance and a stereo strategy's volume, over the scene's chunk-and-octree hierarchy.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct CullConfig {
    /// [`Strategy::PerEye`] culls each eye's own pass with its own frustum in two-pass stereo
    /// (two culls, the thesis' baseline) and with both frusta into one set otherwise.
    pub strategy: Strategy,
    /// Instances farther than this from the head are not drawn (the thesis: 320 units).
    pub draw_distance: f32,
}

impl CullConfig {
    /// The thesis' setting: per-eye frusta, draw distance 320.
    pub const THESIS: CullConfig = CullConfig {
        strategy: Strategy::PerEye,
        draw_distance: 320.0,
    };
}

/// Everything a user chooses about a frame. Validated by `plan()`.
#[derive(Clone, Debug, PartialEq)]
pub struct RenderConfig {
    /// Headset profile name (see [`HMD_PROFILES`]).
    pub hmd: String,
    /// Per-eye resolution; `None` uses the headset's panel resolution.
    pub resolution: Option<Resolution>,
    /// How the eyes are submitted: multiview by default.
    pub stereo: StereoMode,
    /// Views per pass: `None` (the default) derives them, 2 for stereo and 4 with foveation
    /// (periphery and fovea per eye); a number given must be that one.
    pub views: Option<u32>,
    /// MSAA samples on the scene pass: 1 or 4.
    pub msaa: u32,
    /// Interpupillary distance override in metres.
    pub ipd_m: Option<f32>,
    /// Outward cant of each eye in degrees, overriding the profile's.
    pub cant_deg: Option<f32>,
    /// Left-eye FOV tangents overriding the profile's (the right eye mirrors them).
    pub fov: Option<FovTangents>,
    /// Near plane in metres.
    pub near: f32,
    /// Far plane in metres.
    pub far: f32,
    /// A counting frame: every step that shades fragments counts them per view (atomic
    /// counters in the fragment shaders). Off by default: timed frames carry no counters, so
    /// counts come from separate frames ([`RenderConfig::counting`]).
    pub count_fragments: bool,
    /// Record GPU timestamps around the frame.
    pub timestamps: bool,
    /// Foveated rendering: four views (periphery and fovea per eye) in one multiview pass.
    pub foveation: Option<FoveationConfig>,
    /// The HMD stencil mask: pixels the lens hides are masked out in stencil at the start of
    /// the scene pass, so no scene fragment is shaded there.
    pub hmd_mask: bool,
    /// Monoscopic far-field rendering: the far field once, composited into each eye.
    pub mffr: Option<MffrConfig>,
    /// Radial density masking: 2×2 quads skipped in the periphery, reconstructed after the
    /// scene pass.
    pub radial_density: Option<RadialDensity>,
    /// Count every pixel each view renders (a full-view draw under the pass's stencil masks,
    /// counted by the fragment counter) — `foveate pixels` measures with it.
    pub coverage_probe: bool,
    /// Cull the scene per frame on the CPU; `None` draws every instance.
    pub culling: Option<CullConfig>,
    /// The frame's last pass: undistorted (the library's default, as for an OpenXR runtime
    /// that distorts itself) or pre-distorted for the lens (the command line's default).
    pub output: OutputStage,
    /// A foveated frame's pass layout.
    pub fovea_layout: FoveaLayout,
    /// Level of detail: each draw set draws the coarsest of a mesh's simplified levels
    /// ([`Scene::with_lod`](crate::scene::Scene::with_lod)) whose error projects within the
    /// bound in its views' pixels; `None` draws every mesh in full.
    pub lod: Option<crate::scene::LodSettings>,
    /// The frame's output image is handed in per frame (an OpenXR runtime's swapchain image)
    /// instead of made by the renderer: the output is one two-layer image, left in
    /// `COLOR_ATTACHMENT_OPTIMAL` as a runtime's compositor takes it.
    pub external_output: bool,
    /// The HMD mask drops the runtime's hidden-area mesh, handed in per frame
    /// (`Renderer::set_hidden_area`), instead of
    /// keeping the ellipse fitted to the profile; needs `hmd_mask`.
    pub hidden_area_mesh: bool,
    /// Frames that may be in flight at once: the renderer keeps one frame slot each (uniforms,
    /// descriptor sets, query pools, the counting buffer), so frame N+1 records while frame N
    /// runs on the GPU. 1 to [`MAX_FRAMES_IN_FLIGHT`]; 2 by default, as engines and OpenXR
    /// runtimes pace frames.
    pub frames_in_flight: u32,
    /// Instances move between frames (`Renderer::move_instance`):
    /// each frame slot keeps its own copy of the instance buffer, brought up to date before a
    /// frame records into the slot after a move, and culling follows the instances where they
    /// are. Off, the instances stay where the scene
    /// put them, in one buffer on the device.
    pub moving_instances: bool,
    /// Room for instances added while rendering (`Renderer::add_instance`): this many absent
    /// instances of each mesh, planned after the scene's own (which keep their numbers), so
    /// the buffers are sized for them. Needs `moving_instances`; 0 to
    /// [`MAX_SPARE_INSTANCES`], 0 by default.
    pub spare_instances: u32,
    /// The format of the image the frame ends in (sRGB 8-bit by default).
    pub output_format: OutputFormat,
}

/// The most spare instances per mesh ([`RenderConfig::spare_instances`]).
pub const MAX_SPARE_INSTANCES: u32 = 4096;

/// The most frames a renderer keeps in flight ([`RenderConfig::frames_in_flight`]).
pub const MAX_FRAMES_IN_FLIGHT: u32 = 4;

impl Default for RenderConfig {
    fn default() -> Self {
        Self {
            hmd: "index".into(),
            resolution: Some(Resolution::square(1024)),
            stereo: StereoMode::Multiview,
            views: None,
            msaa: 4,
            ipd_m: None,
            cant_deg: None,
            fov: None,
            near: 0.05,
            far: 500.0,
            count_fragments: false,
            timestamps: true,
            foveation: None,
            hmd_mask: false,
            mffr: None,
            radial_density: None,
            coverage_probe: false,
            culling: None,
            output: OutputStage::Undistorted,
            fovea_layout: FoveaLayout::Auto,
            lod: None,
            external_output: false,
            hidden_area_mesh: false,
            frames_in_flight: 2,
            moving_instances: false,
            spare_instances: 0,
            output_format: OutputFormat::Srgb8,
        }
    }
}

impl RenderConfig {
    /// The views per pass: as given, or derived from the configuration (2 for stereo, 4 with
    /// foveation).
    pub fn view_count(&self) -> u32 {
        self.views
            .unwrap_or(if self.foveation.is_some() { 4 } else { 2 })
    }

    /// The same frame as a counting frame: fragment counters on, timestamps off (its time is
    /// not a measurement). Timed frames use `self` with counting off.
    pub fn counting(&self) -> RenderConfig {
        RenderConfig {
            count_fragments: true,
            timestamps: false,
            ..self.clone()
        }
    }

    /// The headset profile `hmd` names, or an error listing the names.
    pub fn hmd_profile(&self) -> Result<&'static HmdProfile, ConfigError> {
        HmdProfile::by_name(&self.hmd).ok_or_else(|| {
            let names: Vec<_> = HMD_PROFILES.iter().map(|p| p.name).collect();
            ConfigError::new("hmd", &self.hmd, format!("one of {}", names.join(", ")))
        })
    }
}

/// Radial density masking as a user chooses it (Preißner 2020 §4.4.2; builder: `radial_density.rs`).
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct RadialDensity {
    /// Inside this radius (1 = the lens edge) every quad is shaded.
    pub inner: f32,
    /// Past this radius three quads in four are skipped; between the two, every other one.
    pub outer: f32,
}

impl Default for RadialDensity {
    fn default() -> Self {
        RadialDensity {
            inner: 0.5,
            outer: 0.8,
        }
    }
}

/// Radial density masking as planned: the configuration and each eye's lens ellipse in NDC.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct RadialDensityGeometry {
    /// The configuration.
    pub config: RadialDensity,
    /// Centre x, y and radius x, y per eye.
    pub lens: [Vec4; 2],
    /// The view's size in pixels.
    pub view: Resolution,
}

impl RadialDensity {
    pub(super) fn resolve(
        &self,
        hmd: &HmdProfile,
        eyes: &EyeParams,
        view: Resolution,
    ) -> Result<RadialDensityGeometry, ConfigError> {
        let ok = |r: f32| r.is_finite() && r >= 0.0;
        if !(ok(self.inner) && ok(self.outer) && self.inner < self.outer) {
            return Err(ConfigError::new(
                "radial_density",
                format!("inner {}, outer {}", self.inner, self.outer),
                "finite radii with 0 ≤ inner < outer (1 = the lens edge)",
            ));
        }
        Ok(RadialDensityGeometry {
            config: *self,
            lens: Eye::BOTH.map(|e| hmd.lens_region(eyes.fov(e)).ndc_ellipse()),
            view,
        })
    }
}
