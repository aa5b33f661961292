//! The frame configuration `render` and `plan` share: headset, stereo mode, MSAA, resolution and
//! every effect's switches, turned into a [`RenderConfig`].

use anyhow::Result;
use clap::Args;
use foveate::foveation::{
    ClipNeighbourhood, FoveationConfig, HistoryAt, HistoryClip, HistoryFilter, HistoryFormat,
    NewSample, PeripheryFilter, TemporalConfig,
};
use foveate::mffr::MffrConfig;
use foveate::plan::{FramePlan, RadialDensity, RenderConfig, Resolution, StereoMode};
use foveate::scene::{named_scene, ClusterSettings, LodSettings, Scene, Shading};
use foveate::view::{look_at_head, HmdProfile};
use glam::Vec3;

/// Frame configuration shared by `render` and `plan`.
#[derive(Args, Clone)]
pub struct ConfigArgs {
    /// Headset profile: index, vive, rift-cv1, quest2, quest3, or eye-tracked quest-pro, psvr2,
    /// vision-pro, galaxy-xr, varjo-xr4 (`foveate plan` prints each one's figures and sources).
    #[arg(long, default_value = "index")]
    pub hmd: String,
    /// Stereo submission: multiview, two-pass, per-object, instanced (`render` also takes `all`).
    #[arg(long, default_value = "multiview")]
    pub stereo: String,
    /// MSAA samples on the scene pass: 1 or 4.
    #[arg(long, default_value_t = 4)]
    pub msaa: u32,
    /// Per-eye resolution: N (square), WxH, or `native` for the headset's panel.
    #[arg(long, default_value = "1024")]
    pub res: String,
    /// Views per pass (default: derived, 2 for stereo and 4 with foveation).
    #[arg(long)]
    pub views: Option<u32>,
    /// Interpupillary distance in millimetres (default 64).
    #[arg(long)]
    pub ipd_mm: Option<f32>,
    /// Outward cant of each eye in degrees (default: the headset's).
    #[arg(long)]
    pub cant: Option<f32>,
    /// Foveated rendering at this ratio (e.g. 0.35). Without further flags, the library's
    /// default: the periphery at 0.6 density accumulated over jittered frames (the cheapest
    /// configuration measured at least as accurate as stereo without MSAA in every motion).
    #[arg(long)]
    pub foveate: Option<f32>,
    /// With --foveate: single frames instead of the accumulated periphery: the periphery at the
    /// ratio's density (or --periphery-density), upscaled, nothing kept between frames.
    #[arg(long)]
    pub single_frame: bool,
    /// Pixels per side of the four foveated views (default: resolution × ratio).
    #[arg(long)]
    pub view_res: Option<u32>,
    /// Fixed fovea diameter on screen in pixels (default: the whole fovea window).
    #[arg(long)]
    pub fovea_size: Option<u32>,
    /// Blend band in screen pixels at the fovea's edge (smoothstep); default: an eighth of the
    /// fovea's diameter.
    #[arg(long)]
    pub blend_band: Option<f32>,
    /// Sharpen the upscaled periphery in the output pass (contrast-adaptive, AMD CAS's filter):
    /// strength 0 (off) to 1.
    #[arg(long)]
    pub sharpen: Option<f32>,
    /// How the output pass upscales the periphery: `bilinear` (the default) or `catmull-rom`
    /// (sixteen texels, sharper).
    #[arg(long)]
    pub periphery_filter: Option<String>,
    /// The periphery views' pixels per side as a fraction of the screen's (default: 0.6, or
    /// with --single-frame the foveation ratio); another density than the ratio renders the
    /// periphery and fovea pairs into images of their own (the two-pass layout).
    #[arg(long)]
    pub periphery_density: Option<f32>,
    /// MSAA samples of the periphery views (default: --msaa), e.g. 1 with a 4x fovea.
    #[arg(long)]
    pub periphery_msaa: Option<u32>,
    /// Accumulate the periphery over frames in the output pass (the default with --foveate;
    /// the flag says so explicitly): its views jittered (Halton), a history at the output's
    /// pixels (32 bits each, two images swapping roles) reprojected by depth. The periphery is
    /// then 1x unless --periphery-msaa asks for more (its depth is resolved to one sample in its
    /// pass, on devices with VK_KHR_depth_stencil_resolve).
    #[arg(long)]
    pub temporal: bool,
    /// With --temporal: a new sample's weight against the history where the point moved
    /// (0 < w ≤ 1). Default: the library's.
    #[arg(long)]
    pub temporal_blend: Option<f32>,
    /// With --temporal: the same weight where nothing moved (the head's motion moved the
    /// point less than a tenth of a periphery texel, no moving instance near). Default: the
    /// library's.
    #[arg(long)]
    pub temporal_still_blend: Option<f32>,
    /// With --temporal: frames in the jitter cycle (1: no jitter; default 8).
    #[arg(long)]
    pub jitter_cycle: Option<u32>,
    /// With --temporal: how the reprojected history is held to the periphery's neighbourhood:
    /// `variance[:SIGMAS]` (Salvi's variance clipping, 1 standard deviation by default),
    /// `range` (its min/max box), `moved` (the range only where the head's motion moved the
    /// point or a moving instance lies: sharper with the head still), `depth`
    /// (the depth test alone) or `off` (a moving surface leaves a trail). Default: the
    /// library's.
    #[arg(long)]
    pub temporal_clip: Option<HistoryClip>,
    /// With --temporal: how the history is read where the point moved: `bilinear` or
    /// `catmull-rom` (sharper, four times the reads: 16 where bilinear makes 4). Default: the library's.
    #[arg(long)]
    pub temporal_filter: Option<HistoryFilter>,
    /// With --temporal: which periphery texels make the clip's box: `3x3` or `cross` (the texel
    /// and its four edge neighbours: five reads for nine, a faster frame and more flicker along
    /// a walk). Default: the library's.
    #[arg(long)]
    pub temporal_neighbourhood: Option<ClipNeighbourhood>,
    /// With --temporal: what of each frame's periphery enters the history: `nearest` (the
    /// nearest texel alone) or `weighted` (where the point moved, the 3×3 texels around the
    /// pixel, each by its distance, from the clip box's reads: less flicker along a walk).
    /// Default: the library's.
    #[arg(long)]
    pub temporal_new_sample: Option<NewSample>,
    /// With --temporal: where the history's pixels lie: `output` (the output's pixels, in the
    /// output pass: detail beyond the periphery's density) or `periphery` (the periphery's own
    /// texels, in a pass of its own: the periphery anti-aliased, a history density² the size).
    /// Default: the library's.
    #[arg(long)]
    pub temporal_history: Option<HistoryAt>,
    /// With --temporal-history periphery: the history's pass at this density (of the screen's
    /// pixels per side) instead of the periphery's own, finer than the periphery's texels and
    /// coarser than the output's. Default: the periphery's density.
    #[arg(long)]
    pub temporal_history_density: Option<f32>,
    /// With --temporal: what the history keeps of a pixel: `colour` (32 bits) or `luma` (one
    /// byte, dithered; the chroma from each frame's periphery). Default: the library's.
    #[arg(long)]
    pub temporal_history_format: Option<HistoryFormat>,
    /// With --temporal: accumulate only within this eccentricity of the gaze (degrees); beyond
    /// it each frame's periphery is shown as it is and does none of the accumulation's work
    /// (the two blend over the last 5°). Default: everywhere.
    #[arg(long)]
    pub temporal_within: Option<f32>,
    /// With --foveate --single-frame, lit scenes: prefilter the periphery's highlights by the
    /// spread of the normals its coarser pixels average (Toksvig). Measured to lose; off.
    #[arg(long)]
    pub periphery_prefilter: bool,
    /// With --foveate --single-frame: a third level, a parafoveal ring this fraction of the
    /// field wide around the fovea, in views of the fovea's pixels. Measured to lose; off.
    #[arg(long, value_name = "RATIO")]
    pub ring: Option<f32>,
    /// Foveation without the inset/outset stencil masks.
    #[arg(long)]
    pub no_stencil: bool,
    /// How a foveated frame renders its four views: one 4-view pass, a periphery and a fovea
    /// pass, or `auto` (the plan chooses and `foveate plan` says why).
    #[arg(long, default_value = "auto")]
    pub fovea_layout: String,
    /// The fovea views draw every instance the periphery draws, not only what their frusta see.
    #[arg(long)]
    pub no_fovea_cull: bool,
    /// What the frame's last pass writes: `lens` (pre-distorted for the headset's lens, as the
    /// display shows it) or `undistorted` (plain eye images, foveated frames still composed).
    #[arg(long, default_value = "lens")]
    pub output: String,
    /// Gaze of both eyes, normalised: X,Y in -1..1 (x right, y up).
    #[arg(long, value_delimiter = ',', allow_hyphen_values = true)]
    pub gaze: Option<Vec<f32>>,
    /// Tint the composed image: fovea green, band yellow, a ring orange, periphery blue.
    #[arg(long)]
    pub tint: bool,
    /// The HMD stencil mask: no fragment is shaded where the lens hides the image.
    #[arg(long)]
    pub hmd_mask: bool,
    /// Monoscopic far-field rendering: far-first, near-first, alternate-eye or depth-shift.
    #[arg(long)]
    pub mffr: Option<String>,
    /// Where MFFR splits near from far: a disparity (`1px`, the default: z = IPD x focal / 1 px)
    /// or metres (`40m`).
    #[arg(long)]
    pub split: Option<String>,
    /// MFFR's far pass's MSAA samples, 1 or 4 (default: the frame's `--msaa`).
    #[arg(long)]
    pub far_msaa: Option<u32>,
    /// MFFR's far image's pixel density, a fraction of the eyes' in 0.25..=1 (default 0.8, the
    /// library's: the cheapest measured as accurate as aliased stereo).
    #[arg(long)]
    pub far_density: Option<f32>,
    /// Radial density masking: 2x2 quads skipped in the periphery (every other past
    /// `--radial-inner`, three in four past `--radial-outer`), reconstructed after the pass.
    #[arg(long)]
    pub radial_density: bool,
    /// Where radial density masking starts, in units of the lens radius (default 0.5).
    #[arg(long)]
    pub radial_inner: Option<f32>,
    /// Where it skips three quads in four (default 0.8).
    #[arg(long)]
    pub radial_outer: Option<f32>,
    /// Scene: `default` (cubes and spheres, near and far), `fill` (24 full-view walls drawn
    /// back to front: a fill-bound frame), `city` (blocks from 28 m to 400 m: far-heavy),
    /// `thesis` (the thesis' object grid), `atrium` (an arcaded courtyard, lit), or a glTF 2.0
    /// file (`.gltf` or `.glb`, lit).
    #[arg(long, default_value = "default")]
    pub scene: String,
    /// Shading: `flat` (vertex colour, one light) or `lit` (PBR materials with textures and
    /// lights); default: the scene's own (`atrium` and files lit, the others flat).
    #[arg(long)]
    pub shading: Option<String>,
    #[command(flatten)]
    pub head: HeadArgs,
    #[command(flatten)]
    pub clusters: ClusterArgs,
}

impl ConfigArgs {
    /// The scene `--scene` names, shaded, clustered and its head placed as asked.
    pub fn scene(&self) -> Result<Scene> {
        scene_from(
            &self.scene,
            self.shading.as_deref(),
            &self.head,
            &self.clusters,
        )
    }
}

/// Whether the scene's large meshes are split into clusters culled per draw set, and given
/// simplified levels chosen per draw set.
#[derive(Args, Clone, Default)]
pub struct ClusterArgs {
    /// Split meshes of more triangles than N into clusters of at most N (default 124; a
    /// multiple of 4 in 32..=256), each culled per draw set against the set's own frustum and
    /// back-face cones wherever the frame culls (foveation's fovea pass, `--cull`, MFFR).
    #[arg(long, value_name = "N", num_args = 0..=1, default_missing_value = "124")]
    pub clusters: Option<u32>,
    /// Simplify meshes of 64 triangles or more into up to 4 coarser levels (meshoptimizer);
    /// each draw set draws per instance the coarsest whose measured error projects within PX of
    /// its views' pixels (default 1; 0.125..=8), so the periphery's coarse pixels take coarser
    /// levels.
    #[arg(long, value_name = "PX", num_args = 0..=1, default_missing_value = "1")]
    pub lod: Option<f32>,
}

impl ClusterArgs {
    /// `scene` clustered and simplified as asked.
    pub fn apply(&self, scene: Scene) -> Result<Scene> {
        let scene = match self.clusters {
            Some(n) => scene.with_clusters(ClusterSettings::new(n)?)?,
            None => scene,
        };
        Ok(match self.lod {
            Some(_) => scene.with_lod()?,
            None => scene,
        })
    }

    /// The level-of-detail bound asked for.
    pub fn lod(&self) -> Result<Option<LodSettings>> {
        Ok(self.lod.map(LodSettings::new).transpose()?)
    }
}

/// Where the head is: the scene's own pose (a file's first camera, or framing its bounds)
/// unless given.
#[derive(Args, Clone, Default)]
pub struct HeadArgs {
    /// Head position in the scene, metres: X,Y,Z (looking along -z unless --look-at).
    #[arg(long, value_delimiter = ',', allow_hyphen_values = true)]
    pub head: Option<Vec<f32>>,
    /// The point the head looks at: X,Y,Z (from --head, or from the scene's head position).
    #[arg(long, value_delimiter = ',', allow_hyphen_values = true)]
    pub look_at: Option<Vec<f32>>,
}

impl HeadArgs {
    /// `scene` with its head moved as asked.
    pub fn apply(&self, mut scene: Scene) -> Result<Scene> {
        let point = |name: &str, v: &Option<Vec<f32>>| -> Result<Option<Vec3>> {
            match v.as_deref() {
                None => Ok(None),
                Some(&[x, y, z]) if [x, y, z].iter().all(|c| c.is_finite()) => {
                    Ok(Some(Vec3::new(x, y, z)))
                }
                Some(v) => anyhow::bail!("invalid {name} = {v:?}: three finite numbers X,Y,Z"),
            }
        };
        let eye = point("head", &self.head)?;
        let target = point("look-at", &self.look_at)?;
        if eye.is_none() && target.is_none() {
            return Ok(scene);
        }
        let eye = eye.unwrap_or_else(|| scene.head.transform_point3(Vec3::ZERO));
        let target = target.unwrap_or(eye - Vec3::Z);
        let forward = target - eye;
        anyhow::ensure!(
            forward.length() > 1e-6 && forward.normalize().cross(Vec3::Y).length() > 1e-4,
            "invalid look-at = {target}: a point away from the head {eye} and not straight above or below it"
        );
        scene.head = look_at_head(eye, target);
        Ok(scene)
    }
}

/// A built-in scene or glTF file by name, shaded as asked (or as it was built), the head
/// where asked.
pub fn scene_from(
    name: &str,
    shading: Option<&str>,
    head: &HeadArgs,
    clusters: &ClusterArgs,
) -> Result<Scene> {
    let scene = named_scene(name)?;
    clusters.apply(head.apply(match shading {
        Some(s) => scene.with_shading(s.parse::<Shading>()?),
        None => scene,
    })?)
}

/// A per-eye resolution as the command line gives it: N (square), WxH, or `native` (`None`:
/// the headset's panel).
pub fn parse_res(res: &str) -> Result<Option<Resolution>> {
    Ok(match res {
        "native" => None,
        r => Some(r.parse::<Resolution>()?),
    })
}

/// The headset profile named `name`, or an error listing the names.
/// `config` with `frames_in_flight` frames in flight, checked against the renderer's limit.
pub fn with_frames_in_flight(
    config: foveate::plan::RenderConfig,
    frames_in_flight: u32,
) -> Result<foveate::plan::RenderConfig> {
    anyhow::ensure!(
        (1..=foveate::plan::MAX_FRAMES_IN_FLIGHT).contains(&frames_in_flight),
        "invalid frames-in-flight = {frames_in_flight}: 1 to {}",
        foveate::plan::MAX_FRAMES_IN_FLIGHT
    );
    Ok(foveate::plan::RenderConfig {
        frames_in_flight,
        ..config
    })
}

pub fn profile(name: &str) -> Result<&'static HmdProfile> {
    HmdProfile::by_name(name).ok_or_else(|| {
        anyhow::anyhow!(
            "invalid hmd = {name}: one of {}",
            HmdProfile::names().join(", ")
        )
    })
}

/// The per-eye screen `res` resolves to on headset `hmd` (`native`: its panel).
pub fn screen(hmd: &str, res: &str) -> Result<Resolution> {
    let panel = profile(hmd)?.panel_per_eye;
    Ok(parse_res(res)?.unwrap_or(Resolution {
        width: panel.0,
        height: panel.1,
    }))
}

/// The headset and screen a report was measured at, as its header says them: the profile,
/// whether it tracks the eyes, the per-eye resolution and the pixels per degree at the lens axis.
pub fn headset_line(plan: &FramePlan) -> String {
    format!(
        "{} ({}{}), {} per eye, {:.1} px/° at the lens axis",
        plan.hmd.display_name,
        plan.hmd.name,
        if plan.hmd.eye_tracker.is_some() {
            ", eye-tracked"
        } else {
            ", no eye tracker"
        },
        plan.eye_resolution,
        plan.pixels_per_degree(foveate::view::Eye::Left)
    )
}

impl ConfigArgs {
    /// The config for one stereo mode (`stereo` may be `all`; the caller picks the mode).
    pub fn config(&self, stereo: StereoMode) -> Result<RenderConfig> {
        self.check_modes()?;
        let resolution = parse_res(&self.res)?;
        let periphery_filter = match &self.periphery_filter {
            Some(name) => name.parse::<PeripheryFilter>()?,
            None => PeripheryFilter::default(),
        };
        let defaults = if self.single_frame {
            FoveationConfig::single_frame()
        } else {
            FoveationConfig::default()
        };
        let foveation = self.foveate.map(|ratio| FoveationConfig {
            ratio,
            view_resolution: self.view_res,
            stencil: !self.no_stencil,
            fovea_size: self.fovea_size,
            blend_band_px: self.blend_band.unwrap_or(defaults.blend_band_px),
            debug_tint: self.tint,
            cull_fovea: !self.no_fovea_cull,
            periphery_sharpen: self.sharpen.unwrap_or(defaults.periphery_sharpen),
            periphery_filter,
            periphery_density: self.periphery_density.or(defaults.periphery_density),
            periphery_msaa: self.periphery_msaa,
            periphery_prefilter: self.periphery_prefilter,
            ring_ratio: self.ring,
            periphery_temporal: defaults.periphery_temporal.map(|default| TemporalConfig {
                blend: self.temporal_blend.unwrap_or(default.blend),
                still_blend: self.temporal_still_blend.unwrap_or(default.still_blend),
                jitter_cycle: self.jitter_cycle.unwrap_or(default.jitter_cycle),
                clip: self.temporal_clip.unwrap_or(default.clip),
                filter: self.temporal_filter.unwrap_or(default.filter),
                neighbourhood: self.temporal_neighbourhood.unwrap_or(default.neighbourhood),
                new_sample: self.temporal_new_sample.unwrap_or(default.new_sample),
                history_at: self.temporal_history.unwrap_or(default.history_at),
                history_density: self.temporal_history_density.or(default.history_density),
                history_format: self
                    .temporal_history_format
                    .unwrap_or(default.history_format),
                within_deg: self.temporal_within.or(default.within_deg),
                ..default
            }),
            ..defaults
        });
        let mffr = self
            .mffr
            .as_deref()
            .map(|name| {
                let split = self.split.as_deref().unwrap_or("1px").parse()?;
                Ok::<_, anyhow::Error>(MffrConfig {
                    far_msaa: self.far_msaa,
                    far_density: self
                        .far_density
                        .unwrap_or(MffrConfig::default().far_density),
                    ..MffrConfig::named(name, split)?
                })
            })
            .transpose()?;
        let radial_density = self.radial_density.then(|| {
            let default = RadialDensity::default();
            RadialDensity {
                inner: self.radial_inner.unwrap_or(default.inner),
                outer: self.radial_outer.unwrap_or(default.outer),
            }
        });
        Ok(RenderConfig {
            radial_density,
            hmd: self.hmd.clone(),
            hmd_mask: self.hmd_mask,
            mffr,
            resolution,
            stereo,
            views: self.views,
            foveation,
            msaa: self.msaa,
            ipd_m: self.ipd_mm.map(|mm| mm / 1000.0),
            cant_deg: self.cant,
            output: self.output.parse()?,
            fovea_layout: self.fovea_layout.parse()?,
            lod: self.clusters.lod()?,
            ..RenderConfig::default()
        })
    }

    /// Options that set a mode's parameters are refused without their mode: silently ignored,
    /// they would leave the user believing they measured something they did not.
    fn check_modes(&self) -> Result<()> {
        // Display, so the error repeats the value as it was typed (`catmull-rom`, not
        // `CatmullRom`).
        fn given<T: std::fmt::Display>(
            name: &'static str,
            v: &Option<T>,
        ) -> Option<(&'static str, String)> {
            v.as_ref().map(|v| (name, v.to_string()))
        }
        fn flag(name: &'static str, on: bool) -> Option<(&'static str, String)> {
            on.then(|| (name, "true".to_string()))
        }
        let foveate = self.foveate.is_some();
        // The periphery accumulates with --foveate unless --single-frame says otherwise.
        let accumulation = match (foveate, self.single_frame) {
            (_, true) => ("accumulation", "drop --single-frame"),
            _ => ("accumulation (--foveate)", "add --foveate"),
        };
        let modes = [
            (
                ("--foveate", "add --foveate"),
                foveate,
                vec![
                    given("--view-res", &self.view_res),
                    given("--fovea-size", &self.fovea_size),
                    given("--blend-band", &self.blend_band),
                    given("--sharpen", &self.sharpen),
                    given("--periphery-filter", &self.periphery_filter),
                    given("--periphery-density", &self.periphery_density),
                    given("--periphery-msaa", &self.periphery_msaa),
                    flag("--temporal", self.temporal),
                    flag("--single-frame", self.single_frame),
                    flag("--no-stencil", self.no_stencil),
                    flag("--no-fovea-cull", self.no_fovea_cull),
                    flag("--tint", self.tint),
                ],
            ),
            (
                accumulation,
                foveate && !self.single_frame,
                vec![
                    given("--temporal-blend", &self.temporal_blend),
                    given("--temporal-still-blend", &self.temporal_still_blend),
                    given("--jitter-cycle", &self.jitter_cycle),
                    given("--temporal-clip", &self.temporal_clip),
                    given("--temporal-filter", &self.temporal_filter),
                    given("--temporal-neighbourhood", &self.temporal_neighbourhood),
                    given("--temporal-new-sample", &self.temporal_new_sample),
                    given("--temporal-history", &self.temporal_history),
                    given("--temporal-history-density", &self.temporal_history_density),
                    given("--temporal-history-format", &self.temporal_history_format),
                    given("--temporal-within", &self.temporal_within),
                ],
            ),
            (
                ("single frames", "add --foveate --single-frame"),
                foveate && self.single_frame,
                vec![
                    flag("--periphery-prefilter", self.periphery_prefilter),
                    given("--ring", &self.ring),
                ],
            ),
            (
                ("--mffr", "add --mffr"),
                self.mffr.is_some(),
                vec![
                    given("--split", &self.split),
                    given("--far-msaa", &self.far_msaa),
                    given("--far-density", &self.far_density),
                ],
            ),
            (
                ("--radial-density", "add --radial-density"),
                self.radial_density,
                vec![
                    given("--radial-inner", &self.radial_inner),
                    given("--radial-outer", &self.radial_outer),
                ],
            ),
        ];
        for ((mode, remedy), on, options) in modes {
            if let Some((option, value)) = options.into_iter().flatten().find(|_| !on) {
                anyhow::bail!("invalid {option} = {value}: it sets a parameter of {mode}, which is off ({remedy}, or leave {option} out)");
            }
        }
        anyhow::ensure!(
            !(self.temporal && self.single_frame),
            "invalid --temporal with --single-frame: the one accumulates the periphery, the other asks for single frames (leave one out)"
        );
        Ok(())
    }

    /// The stereo modes asked for: one, or all four for `all`.
    pub fn stereo_modes(&self) -> Result<Vec<StereoMode>> {
        if self.stereo == "all" {
            Ok(StereoMode::ALL.to_vec())
        } else {
            Ok(vec![self.stereo.parse()?])
        }
    }
}
