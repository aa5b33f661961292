use super::derive::{is_transient, Access, ClearValue, Layout, LoadOp, StoreOp};
use super::steps::{stencil_states, Step};
use super::{ConfigError, CullConfig, DeviceCaps, RenderConfig, Resolution, StereoMode, MAX_VIEWS};
use crate::cull::Strategy;
use crate::foveation::FoveationGeometry;
use crate::mffr::{MffrGeometry, MffrOrder};
use crate::scene::Scene;
use crate::view::{Eye, EyeParams, HmdProfile, LensRegion};

/// Pixel formats the planner uses.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub enum Format {
    /// Colour: 8-bit sRGB, so MSAA resolves and blending happen in linear light.
    Rgba8Srgb,
    /// Reverse-Z depth without stencil.
    D32,
    /// Reverse-Z depth with stencil, only when an effect writes stencil masks.
    D32S8,
}

impl Format {
    pub fn bytes_per_pixel(self) -> u64 {
        match self {
            Format::Rgba8Srgb | Format::D32 => 4,
            // D32_SFLOAT_S8_UINT is commonly stored as 4 + 1 bytes (plus padding).
            Format::D32S8 => 5,
        }
    }

    pub fn is_depth(self) -> bool {
        matches!(self, Format::D32 | Format::D32S8)
    }
}

#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub enum AttachmentRole {
    Color,
    Depth,
    /// Single-sample target an MSAA colour attachment resolves into inside the pass.
    Resolve,
}

/// Index into [`FramePlan::attachments`].
pub type AttachmentId = usize;

/// One image the frame renders into, and its fate.
#[derive(Clone, Debug, PartialEq)]
pub struct AttachmentPlan {
    pub name: &'static str,
    pub role: AttachmentRole,
    pub format: Format,
    pub samples: u32,
    pub width: u32,
    pub height: u32,
    pub layers: u32,
    /// Read after the frame (readback or presentation).
    pub read_after_frame: bool,
    /// Sampled by a later pass (a texture, not an attachment, there).
    pub sampled: bool,
    /// Never loaded nor stored by any pass: may live on tile only.
    pub transient: bool,
}

impl AttachmentPlan {
    pub fn bytes(&self) -> u64 {
        self.width as u64
            * self.height as u64
            * self.layers as u64
            * self.samples as u64
            * self.format.bytes_per_pixel()
    }

    fn layer_bytes(&self) -> u64 {
        self.bytes() / self.layers as u64
    }
}

/// A pass's use of (some layers of) an attachment, with the ops derived from intent.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct Use {
    pub attachment: AttachmentId,
    pub base_layer: u32,
    pub layer_count: u32,
    pub access: Access,
    pub load: LoadOp,
    pub store: StoreOp,
    /// Layout at the pass's start and end (derived: [`Layout::around`]).
    pub initial_layout: Layout,
    pub final_layout: Layout,
    /// What a cleared use starts as; `None` unless `load` clears.
    pub clear: Option<ClearValue>,
}

impl Use {
    fn new(attachment: AttachmentId, base_layer: u32, layer_count: u32, access: Access) -> Self {
        // Ops are placeholders until `derive_ops` has seen the whole frame.
        Self {
            attachment,
            base_layer,
            layer_count,
            access,
            load: LoadOp::from_access(access),
            store: StoreOp::DontCare,
            initial_layout: Layout::Undefined,
            final_layout: Layout::Undefined,
            clear: None,
        }
    }

    fn overlaps(&self, other: &Use) -> bool {
        self.attachment == other.attachment
            && self.base_layer < other.base_layer + other.layer_count
            && other.base_layer < self.base_layer + self.layer_count
    }
}

/// How a pass submits the scene.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub enum Submission {
    /// Once, broadcast to the views in the pass's view mask.
    Multiview,
    /// Once, for one eye.
    SingleEye(Eye),
    /// Every object twice, switching eye and viewport between the draws.
    PerObject,
    /// Every draw with its instance count doubled.
    Instanced,
    /// Once, from the MFFR far view.
    FarView,
}

/// Which instances a scene pass draws.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub enum DrawSet {
    /// Every instance, straight from the scene's draws.
    All,
    /// Instances the culling strategy keeps for the pass's views (culled per frame).
    Visible,
    /// Instances one eye's own frustum keeps: per-eye culling of a two-pass frame.
    VisibleToEye(Eye),
    /// Instances reaching in front of the MFFR split (culled per frame).
    NearField,
    /// Instances reaching beyond the MFFR far pass's near plane (culled per frame).
    FarField,
}

/// What a pass does.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub enum PassKind {
    /// Draws the scene (and, when planned, stencil masks and the coverage probe).
    Scene,
    /// Composes each eye at full resolution from the periphery and fovea views it samples.
    Composite,
    /// MFFR: the far field, once, into an image the eye passes sample.
    FarField,
}

/// One render pass of the frame.
#[derive(Clone, Debug, PartialEq)]
pub struct PassPlan {
    pub name: &'static str,
    pub kind: PassKind,
    /// Multiview view mask; 0 for a pass without multiview.
    pub view_mask: u32,
    pub color: Use,
    pub depth: Option<Use>,
    /// In-pass MSAA resolve target (`pResolveAttachments`).
    pub resolve: Option<Use>,
    /// Attachments of earlier passes this pass samples.
    pub samples: Vec<AttachmentId>,
    pub submission: Submission,
    /// What the pass does, in order (mask fans, far composite, scene, probe; or composition).
    pub steps: Vec<Step>,
    /// Depth clamp instead of clipping at the near and far planes (the MFFR split), to work
    /// around [`DriverQuirks`](super::DriverQuirks) dropping clipped primitives' views.
    pub depth_clamp: bool,
    /// Emulated guard band: clip-space x and y are divided by this factor and the viewport
    /// grown by it, so primitives reaching less than this many view widths past the edge need
    /// no clipping. 1 = off; set only to work around [`DriverQuirks`](super::DriverQuirks).
    pub guard_band: u32,
}

impl PassPlan {
    pub fn uses(&self) -> impl Iterator<Item = &Use> {
        [
            Some(&self.color),
            self.depth.as_ref(),
            self.resolve.as_ref(),
        ]
        .into_iter()
        .flatten()
    }

    /// Whether the pass writes stencil masks first.
    pub fn has_masks(&self) -> bool {
        self.steps
            .iter()
            .any(|s| matches!(s, Step::MaskFans { .. }))
    }

    /// The MFFR far image is composited into this pass: before the scene (far-first) or after
    /// it, into the pixels it left (near-first).
    pub fn far_composite(&self) -> Option<MffrOrder> {
        let far = self
            .steps
            .iter()
            .position(|s| matches!(s, Step::FarComposite { .. }))?;
        let scene = self
            .steps
            .iter()
            .position(|s| matches!(s, Step::Scene { .. }))?;
        Some(if far < scene {
            MffrOrder::FarFirst
        } else {
            MffrOrder::NearFirst
        })
    }

    /// The instances the pass's scene step draws.
    pub fn draw_set(&self) -> Option<DrawSet> {
        self.steps.iter().find_map(|s| match s {
            Step::Scene { draw_set, .. } => Some(*draw_set),
            _ => None,
        })
    }

    fn uses_mut(&mut self) -> impl Iterator<Item = &mut Use> {
        [
            Some(&mut self.color),
            self.depth.as_mut(),
            self.resolve.as_mut(),
        ]
        .into_iter()
        .flatten()
    }
}

/// How the two eyes' images are laid out in the frame's images.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub enum TargetLayout {
    /// One array layer per eye of one image (multiview).
    Layered,
    /// One image per eye (two-pass on a driver with
    /// [`DriverQuirks::layered_resolve_ignores_base_layer`](super::DriverQuirks); elsewhere
    /// each two-pass eye pass renders its own layer of a layered image).
    PerEye,
    /// Both eyes side by side in one double-wide image (per-object, instanced).
    SideBySide,
}

/// A step of a pass that shades fragments, counted on its own in counting frames.
#[derive(Clone, Copy, Debug, PartialEq, Eq, Hash)]
pub enum CountedStep {
    /// Stencil mask fans (the HMD mask, foveation's inset/outset), at the start of the pass.
    Mask,
    /// The MFFR far image composited into the eye views.
    FarComposite,
    /// The scene's meshes.
    Scene,
    /// The coverage probe's full-view draw.
    Probe,
    /// Foveated composition: each eye at full resolution.
    Composite,
}

impl CountedStep {
    pub fn name(self) -> &'static str {
        match self {
            CountedStep::Mask => "mask",
            CountedStep::FarComposite => "far composite",
            CountedStep::Scene => "scene",
            CountedStep::Probe => "probe",
            CountedStep::Composite => "composite",
        }
    }
}

/// One counted step: its pass (index into [`FramePlan::passes`]) and what it draws. Its five
/// counter slots (views 0–3, then the MFFR far view) start at [`FramePlan::counter_base`].
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub struct CountedSlot {
    pub pass: usize,
    pub step: CountedStep,
}

/// Counter slots per counted step: four views and the MFFR far view.
pub const COUNTER_SLOTS_PER_STEP: u32 = MAX_VIEWS + 1;

/// A buffer that exists only because an effect asked for it.
#[derive(Clone, Debug, PartialEq)]
pub struct BufferPlan {
    pub name: &'static str,
    pub bytes: u64,
}

/// Everything a frame consists of, decided before any Vulkan object exists.
#[derive(Clone, Debug, PartialEq)]
pub struct FramePlan {
    pub hmd: &'static HmdProfile,
    pub eyes: EyeParams,
    pub eye_resolution: Resolution,
    pub stereo: StereoMode,
    pub views: u32,
    pub samples: u32,
    pub near: f32,
    pub far: f32,
    pub layout: TargetLayout,
    pub attachments: Vec<AttachmentPlan>,
    pub passes: Vec<PassPlan>,
    /// Effect-only buffers (e.g. the fragment counter); empty when no such effect is on.
    pub buffers: Vec<BufferPlan>,
    /// Timestamp queries per frame (before the frame, after each pass); 0 when timing is off.
    pub timestamp_queries: u32,
    /// Steps whose fragments a counting frame counts, in recording order; empty unless
    /// fragment counting is on.
    pub counted: Vec<CountedSlot>,
    /// Draw calls one frame records for the scene it was planned with, estimated before culling
    /// (the renderer's `FrameStats` has the recorded tally).
    pub draw_calls_estimate: u64,
    /// Foveation as resolved for this frame; `None` renders plain stereo.
    pub foveation: Option<FoveationGeometry>,
    /// Each eye's lens-visible region, when the HMD stencil mask is on.
    pub hmd_mask: Option<[LensRegion; 2]>,
    /// MFFR as resolved for this frame: `None` when off, or when the scene has nothing beyond
    /// the split.
    pub mffr: Option<MffrGeometry>,
    /// Per-frame culling, when on.
    pub culling: Option<CullConfig>,
    /// The sets culled each frame, in order; a scene step's `cull_slot` indexes this (empty
    /// when every pass draws every instance).
    pub cull_slots: Vec<DrawSet>,
    /// Instances of the scene the plan was made for: buffers are sized for them, and a
    /// renderer refuses another scene.
    pub scene_instances: usize,
}

impl FramePlan {
    /// The per-view fragment counter, when fragment counting is on.
    pub fn fragment_counter(&self) -> Option<&BufferPlan> {
        self.buffers.iter().find(|b| b.name == FRAGMENT_COUNTER)
    }

    pub fn count_fragments(&self) -> bool {
        self.fragment_counter().is_some()
    }

    /// Where the counter slots of `step` in pass `pass` start, when that step is counted. A
    /// single-eye pass's mask fans count into their eye's slot (the shader sees view 0).
    pub fn counter_base(&self, pass: usize, step: CountedStep) -> Option<u32> {
        let slot = self
            .counted
            .iter()
            .position(|c| c.pass == pass && c.step == step)?;
        let eye_offset = match (step, self.passes[pass].submission) {
            (CountedStep::Mask, Submission::SingleEye(eye)) => eye.index() as u32,
            _ => 0,
        };
        Some(slot as u32 * COUNTER_SLOTS_PER_STEP + eye_offset)
    }

    /// The per-frame list of culled instance ids, when some pass draws a culled set.
    pub fn instance_ids(&self) -> Option<&BufferPlan> {
        self.buffers.iter().find(|b| b.name == INSTANCE_IDS)
    }

    /// The MFFR far pass, when planned.
    pub fn far_pass(&self) -> Option<&PassPlan> {
        self.passes.iter().find(|p| p.kind == PassKind::FarField)
    }

    /// The attachments read after the frame, in eye order: the stereo image.
    pub fn outputs(&self) -> Vec<AttachmentId> {
        (0..self.attachments.len())
            .filter(|&i| self.attachments[i].read_after_frame)
            .collect()
    }

    /// Bytes of attachments that must be backed by memory (not transient).
    pub fn resident_bytes(&self) -> u64 {
        self.attachments
            .iter()
            .filter(|a| !a.transient)
            .map(AttachmentPlan::bytes)
            .sum()
    }

    /// Bytes of attachments that may live on tile only.
    pub fn transient_bytes(&self) -> u64 {
        self.attachments
            .iter()
            .filter(|a| a.transient)
            .map(AttachmentPlan::bytes)
            .sum()
    }

    /// Estimated external memory traffic per frame on a tile GPU: bytes loaded into tile
    /// memory, stored out of it, sampled by later passes, and read back as the output.
    pub fn external_traffic_bytes(&self) -> u64 {
        let attachment_traffic: u64 = self
            .passes
            .iter()
            .flat_map(|p| p.uses())
            .map(|u| {
                let a = &self.attachments[u.attachment];
                let bytes = a.layer_bytes() * u.layer_count as u64;
                let loaded = if u.load == LoadOp::Load { bytes } else { 0 };
                let stored = if u.store == StoreOp::Store { bytes } else { 0 };
                loaded + stored
            })
            .sum();
        let sampled: u64 = self
            .passes
            .iter()
            .flat_map(|p| &p.samples)
            .map(|&i| self.attachments[i].bytes())
            .sum();
        let read_back: u64 = self
            .outputs()
            .iter()
            .map(|&i| self.attachments[i].bytes())
            .sum();
        attachment_traffic + sampled + read_back
    }
}

/// Linear-light colour of the sky: every colour attachment clears to it (the MFFR far pass
/// with alpha 0: the sky is infinitely far, see `shaders/scene.frag`).
pub const SKY: [f32; 4] = [0.22, 0.38, 0.62, 1.0];

pub(crate) const FRAGMENT_COUNTER: &str = "fragment counter";
pub(crate) const INSTANCE_IDS: &str = "instance ids";

/// Plans a frame. Rejects a configuration the device or foveate cannot render with an error
/// naming the field, the value and the limit.
pub fn plan(
    scene: &Scene,
    config: &RenderConfig,
    caps: &DeviceCaps,
) -> Result<FramePlan, ConfigError> {
    let hmd = config.hmd_profile()?;
    let eyes = validate_eyes(config, hmd)?;
    let eye_resolution = validate_resolution(config, hmd, caps)?;
    validate_views(config, caps)?;
    let foveation = config
        .foveation
        .map(|f| f.geometry(eye_resolution))
        .transpose()?;
    validate_msaa(config, caps)?;
    validate_depth_range(config)?;
    validate_features(config, caps)?;
    validate_culling(config)?;
    let hmd_mask = config
        .hmd_mask
        .then(|| Eye::BOTH.map(|e| hmd.lens_region(eyes.fov(e))));
    let mffr = match config.mffr {
        Some(m) => MffrGeometry::resolve(m, &eyes, eye_resolution, config.near, config.far)?
            // A scene whose every point is nearer than the split has no far field to render.
            .filter(|g| scene.content_reach() > g.split_m),
        None => None,
    };
    if let Some(g) = &mffr {
        let max = caps.max_image_dimension_2d;
        if g.resolution.width > max || g.resolution.height > max {
            return Err(ConfigError::new(
                "mffr split",
                g.config.split,
                format!(
                    "a far image within {max}x{max} on this device; it needs {}",
                    g.resolution
                ),
            ));
        }
    }

    let layout = match config.stereo {
        StereoMode::Multiview => TargetLayout::Layered,
        StereoMode::TwoPass if caps.quirks.layered_resolve_ignores_base_layer => {
            TargetLayout::PerEye
        }
        StereoMode::TwoPass => TargetLayout::Layered,
        StereoMode::PerObject | StereoMode::Instanced => TargetLayout::SideBySide,
    };
    let mut attachments = Vec::new();
    let render_resolution = foveation.map_or(eye_resolution, |f| f.view);
    let far = mffr.map(|g| far_pass(config, g.resolution, &mut attachments));
    let far_colour = far
        .as_ref()
        .map(|p| p.resolve.unwrap_or(p.color).attachment);
    let mut passes: Vec<PassPlan> = far.into_iter().collect();
    passes.extend(scene_passes(
        config,
        render_resolution,
        layout,
        mffr.map(|g| {
            (
                g.config.order,
                far_colour.expect("planned with the far pass"),
            )
        }),
        &mut attachments,
    ));
    if foveation.is_some() {
        let scene = passes.iter().find(|p| p.kind == PassKind::Scene);
        let composite = composite_pass(
            scene.expect("a foveated frame has its scene pass"),
            eye_resolution,
            &mut attachments,
        );
        passes.push(composite);
    }
    if caps.quirks.multiview_clipping_drops_views {
        for p in passes.iter_mut().filter(|p| p.view_mask != 0) {
            let a = &attachments[p.color.attachment];
            p.guard_band = guard_band(
                Resolution {
                    width: a.width,
                    height: a.height,
                },
                caps,
            );
            // Clipping at the MFFR split would drop views too: clamp depth instead, so what lies
            // beyond the split lands on the far plane's depth, 0, and fails the depth test
            // against the clear value (reverse-Z, GREATER) without any primitive being clipped.
            p.depth_clamp = p.far_composite().is_some() && caps.depth_clamp;
        }
    }
    let mut plan = FramePlan {
        hmd,
        eyes,
        eye_resolution,
        stereo: config.stereo,
        views: config.views,
        samples: config.msaa,
        near: config.near,
        far: config.far,
        layout,
        attachments,
        passes,
        buffers: Vec::new(),
        timestamp_queries: 0,
        counted: Vec::new(),
        draw_calls_estimate: 0,
        foveation,
        hmd_mask,
        mffr,
        culling: config.culling,
        cull_slots: Vec::new(),
        scene_instances: scene.instance_count(),
    };
    assign_cull_slots(&mut plan);
    plan.draw_calls_estimate = draw_calls_estimate(scene, &plan);
    if config.timestamps {
        // One before the frame and one after each pass.
        plan.timestamp_queries = plan.passes.len() as u32 + 1;
    }
    if config.count_fragments {
        plan.counted = counted_steps(&plan.passes);
        plan.buffers.push(BufferPlan {
            name: FRAGMENT_COUNTER,
            bytes: 4 * (COUNTER_SLOTS_PER_STEP * plan.counted.len() as u32) as u64,
        });
    }
    if !plan.cull_slots.is_empty() {
        // Near and far sets of one frame, each at most every instance.
        plan.buffers.push(BufferPlan {
            name: INSTANCE_IDS,
            bytes: 2 * 4 * (scene.instance_count().max(1) as u64),
        });
    }
    derive_ops(&mut plan);
    Ok(plan)
}

/// Every step that shades fragments, pass by pass in recording order: a pass's mask fans, its
/// far composite (far-first before the scene, near-first after it), its scene, its probe; the
/// composition pass's full-view draw.
fn counted_steps(passes: &[PassPlan]) -> Vec<CountedSlot> {
    passes
        .iter()
        .enumerate()
        .flat_map(|(pass, p)| {
            p.steps.iter().map(move |s| CountedSlot {
                pass,
                step: match s {
                    Step::MaskFans { .. } => CountedStep::Mask,
                    Step::FarComposite { .. } => CountedStep::FarComposite,
                    Step::Scene { .. } => CountedStep::Scene,
                    Step::Probe { .. } => CountedStep::Probe,
                    Step::Composite => CountedStep::Composite,
                },
            })
        })
        .collect()
}

/// One cull slot per distinct culled draw set, in pass order (at most two: both eyes' set,
/// each eye's own, or MFFR's near and far fields), and each scene step pointed at its slot.
fn assign_cull_slots(plan: &mut FramePlan) {
    let mut slots: Vec<DrawSet> = Vec::new();
    for pass in &mut plan.passes {
        for step in &mut pass.steps {
            if let Step::Scene {
                draw_set,
                cull_slot,
                ..
            } = step
            {
                if *draw_set == DrawSet::All {
                    continue;
                }
                let slot = slots.iter().position(|s| s == draw_set).unwrap_or_else(|| {
                    slots.push(*draw_set);
                    slots.len() - 1
                });
                *cull_slot = Some(slot);
            }
        }
    }
    debug_assert!(slots.len() <= 2, "the instance-id buffer holds two sets");
    plan.cull_slots = slots;
}

/// The scene pass(es) of a stereo frame and the attachments they use.
fn scene_passes(
    config: &RenderConfig,
    eye: Resolution,
    layout: TargetLayout,
    far_field: Option<(MffrOrder, AttachmentId)>,
    attachments: &mut Vec<AttachmentPlan>,
) -> Vec<PassPlan> {
    let msaa = config.msaa > 1;
    // Image shape: one layer per view for multiview, one double-wide image for the side-by-side
    // modes; two-pass renders one eye per pass into single-layer scratch images and resolves
    // into its eye's layer of the output (layered) or its eye's own image (per eye).
    let two_pass = config.stereo == StereoMode::TwoPass;
    let (width, layers) = match layout {
        TargetLayout::Layered if two_pass => (eye.width, 1),
        TargetLayout::Layered => (eye.width, config.views),
        TargetLayout::SideBySide => (eye.width * 2, 1),
        TargetLayout::PerEye => (eye.width, 1),
    };
    let output_layers = if two_pass && layout == TargetLayout::Layered {
        2
    } else {
        layers
    };
    let mut add = |name, role, format, samples, read_after_frame, layers| {
        attachments.push(AttachmentPlan {
            name,
            role,
            format,
            samples,
            width,
            height: eye.height,
            layers,
            read_after_frame,
            sampled: false,
            transient: false,
        });
        attachments.len() - 1
    };
    // Scratch images are shared by the passes (two-pass reuses them for the second eye).
    let color = msaa.then(|| {
        add(
            "scene colour (MSAA)",
            AttachmentRole::Color,
            Format::Rgba8Srgb,
            config.msaa,
            false,
            layers,
        )
    });
    let stencil_masks = config.foveation.is_some_and(|f| f.stencil) || config.hmd_mask;
    let near_first = far_field.is_some_and(|(order, _)| order == MffrOrder::NearFirst);
    let depth_format = if stencil_masks || near_first {
        Format::D32S8
    } else {
        Format::D32
    };
    let depth = add(
        "scene depth",
        AttachmentRole::Depth,
        depth_format,
        config.msaa,
        false,
        layers,
    );
    let output_role = if msaa {
        AttachmentRole::Resolve
    } else {
        AttachmentRole::Color
    };
    let outputs: Vec<AttachmentId> = match layout {
        TargetLayout::PerEye => vec![
            add(
                "left eye colour",
                output_role,
                Format::Rgba8Srgb,
                1,
                true,
                1,
            ),
            add(
                "right eye colour",
                output_role,
                Format::Rgba8Srgb,
                1,
                true,
                1,
            ),
        ],
        _ => vec![add(
            if config.views == 4 {
                "views (periphery, fovea)"
            } else {
                "stereo colour"
            },
            output_role,
            Format::Rgba8Srgb,
            1,
            true,
            output_layers,
        )],
    };

    let pass = |name, view_mask, output: AttachmentId, submission| {
        let whole = |id, access| Use::new(id, 0, layers, access);
        // A single-eye pass into a layered output writes only its eye's layer.
        let output_use = |access| match submission {
            Submission::SingleEye(eye) if output_layers == 2 => {
                Use::new(output, eye.index() as u32, 1, access)
            }
            _ => whole(output, access),
        };
        PassPlan {
            name,
            view_mask,
            color: color.map_or(output_use(Access::Clear), |c| whole(c, Access::Clear)),
            depth: Some(whole(depth, Access::Clear)),
            resolve: color.map(|_| output_use(Access::Overwrite)),
            submission,
            kind: PassKind::Scene,
            samples: far_field.map(|(_, far)| far).into_iter().collect(),
            steps: {
                let draw_set = match (far_field, config.culling, submission) {
                    (Some(_), _, _) => DrawSet::NearField,
                    (None, None, _) => DrawSet::All,
                    (None, Some(c), Submission::SingleEye(eye))
                        if c.strategy == Strategy::PerEye =>
                    {
                        DrawSet::VisibleToEye(eye)
                    }
                    (None, Some(_), _) => DrawSet::Visible,
                };
                let (fans, scene, probe, far) = stencil_states(stencil_masks, near_first);
                let mut steps = Vec::new();
                if stencil_masks {
                    steps.push(Step::MaskFans { stencil: fans });
                }
                let far_step = Step::FarComposite { stencil: far };
                if far_field.is_some() && !near_first {
                    steps.push(far_step);
                }
                steps.push(Step::Scene {
                    draw_set,
                    cull_slot: None,
                    stencil: scene,
                });
                if near_first {
                    steps.push(far_step);
                }
                if config.coverage_probe {
                    steps.push(Step::Probe { stencil: probe });
                }
                steps
            },
            depth_clamp: false,
            guard_band: 1,
        }
    };
    match config.stereo {
        StereoMode::Multiview => {
            let (name, mask) = if config.views == 4 {
                ("scene (foveated multiview)", 0b1111)
            } else {
                ("scene (multiview)", 0b11)
            };
            vec![pass(name, mask, outputs[0], Submission::Multiview)]
        }
        StereoMode::TwoPass => vec![
            pass(
                "scene (left eye)",
                0,
                outputs[0],
                Submission::SingleEye(Eye::Left),
            ),
            pass(
                "scene (right eye)",
                0,
                outputs[outputs.len() - 1],
                Submission::SingleEye(Eye::Right),
            ),
        ],
        StereoMode::PerObject => vec![pass(
            "scene (per-object)",
            0,
            outputs[0],
            Submission::PerObject,
        )],
        StereoMode::Instanced => vec![pass(
            "scene (instanced)",
            0,
            outputs[0],
            Submission::Instanced,
        )],
    }
}

/// Composition of a foveated frame: each eye at full resolution, the fovea over the bilinearly
/// upscaled periphery, from the scene pass's views sampled as a texture (which therefore is
/// stored, not read after the frame).
fn composite_pass(
    scene: &PassPlan,
    eye: Resolution,
    attachments: &mut Vec<AttachmentPlan>,
) -> PassPlan {
    let views = scene
        .resolve
        .map_or(scene.color.attachment, |r| r.attachment);
    attachments[views].read_after_frame = false;
    attachments.push(AttachmentPlan {
        name: "stereo colour",
        role: AttachmentRole::Color,
        format: Format::Rgba8Srgb,
        samples: 1,
        width: eye.width,
        height: eye.height,
        layers: 2,
        read_after_frame: true,
        sampled: false,
        transient: false,
    });
    PassPlan {
        name: "composite (fovea over periphery)",
        kind: PassKind::Composite,
        view_mask: 0b11,
        color: Use::new(attachments.len() - 1, 0, 2, Access::Overwrite),
        depth: None,
        resolve: None,
        samples: vec![views],
        submission: Submission::Multiview,
        steps: vec![Step::Composite],
        depth_clamp: false,
        guard_band: 1,
    }
}

/// The MFFR far pass: the far field once, from one view, resolved into an image every eye
/// pass samples (and which is therefore stored).
fn far_pass(
    config: &RenderConfig,
    size: Resolution,
    attachments: &mut Vec<AttachmentPlan>,
) -> PassPlan {
    let mut add = |name, role, format, samples| {
        attachments.push(AttachmentPlan {
            name,
            role,
            format,
            samples,
            width: size.width,
            height: size.height,
            layers: 1,
            read_after_frame: false,
            sampled: false,
            transient: false,
        });
        attachments.len() - 1
    };
    let msaa = config.msaa > 1;
    let color = msaa.then(|| {
        add(
            "far colour (MSAA)",
            AttachmentRole::Color,
            Format::Rgba8Srgb,
            config.msaa,
        )
    });
    let depth = add("far depth", AttachmentRole::Depth, Format::D32, config.msaa);
    let output_role = if msaa {
        AttachmentRole::Resolve
    } else {
        AttachmentRole::Color
    };
    let output = add("far field colour", output_role, Format::Rgba8Srgb, 1);
    let whole = |id, access| Use::new(id, 0, 1, access);
    PassPlan {
        name: "far field (mono)",
        kind: PassKind::FarField,
        view_mask: 0,
        color: whole(color.unwrap_or(output), Access::Clear),
        depth: Some(whole(depth, Access::Clear)),
        resolve: color.map(|_| whole(output, Access::Overwrite)),
        samples: Vec::new(),
        submission: Submission::FarView,
        steps: vec![Step::Scene {
            draw_set: DrawSet::FarField,
            cull_slot: None,
            stencil: None,
        }],
        depth_clamp: false,
        guard_band: 1,
    }
}

/// The largest guard band (a power of two up to 8) whose grown viewport the device accepts.
fn guard_band(eye: Resolution, caps: &DeviceCaps) -> u32 {
    let side = eye.width.max(eye.height) as f32;
    let fits = |k: u32| {
        let k = k as f32;
        k * side <= caps.max_viewport_dimension as f32
            && -(k - 1.0) * 0.5 * side >= caps.viewport_bounds.0
            && (k + 1.0) * 0.5 * side <= caps.viewport_bounds.1
    };
    [8, 4, 2].into_iter().find(|&k| fits(k)).unwrap_or(1)
}

/// Fills in every use's store op and every attachment's transient flag from declared intent:
/// a use stores only if a later pass keeps its contents or the frame's reader needs them and no
/// later pass replaces them first.
fn derive_ops(plan: &mut FramePlan) {
    let all_uses: Vec<(usize, Use)> = plan
        .passes
        .iter()
        .enumerate()
        .flat_map(|(i, p)| p.uses().map(move |u| (i, *u)))
        .collect();
    // Attachments sampled by some pass after pass i.
    let sampled_after: Vec<Vec<AttachmentId>> = (0..plan.passes.len())
        .map(|i| {
            plan.passes[i + 1..]
                .iter()
                .flat_map(|p| p.samples.iter().copied())
                .collect()
        })
        .collect();
    for (i, pass) in plan.passes.iter_mut().enumerate() {
        let sky = if pass.kind == PassKind::FarField {
            [SKY[0], SKY[1], SKY[2], 0.0]
        } else {
            SKY
        };
        for u in pass.uses_mut() {
            let later = all_uses.iter().filter(|(j, v)| *j > i && v.overlaps(u));
            let mut kept_later = false;
            let mut replaced_later = false;
            for (_, v) in later {
                match v.access {
                    Access::Keep if !replaced_later => kept_later = true,
                    Access::Clear | Access::Overwrite => replaced_later = true,
                    Access::Keep => {}
                }
            }
            kept_later |= sampled_after[i].contains(&u.attachment);
            let read_by_frame_reader =
                plan.attachments[u.attachment].read_after_frame && !replaced_later;
            u.load = LoadOp::from_access(u.access);
            u.store = StoreOp::from_read_later(kept_later || read_by_frame_reader);
            let a = &plan.attachments[u.attachment];
            let working = if a.format.is_depth() {
                Layout::DepthStencilAttachment
            } else {
                Layout::ColorAttachment
            };
            (u.initial_layout, u.final_layout) = Layout::around(
                working,
                u.load,
                u.store,
                a.read_after_frame,
                sampled_after[i].contains(&u.attachment),
            );
            // Reverse-Z: depth clears to the far plane, 0.
            u.clear = (u.load == LoadOp::Clear).then_some(if a.format.is_depth() {
                ClearValue::DepthStencil {
                    depth: 0.0,
                    stencil: 0,
                }
            } else {
                ClearValue::Color(sky)
            });
        }
    }
    for (id, a) in plan.attachments.iter_mut().enumerate() {
        let uses: Vec<&Use> = plan
            .passes
            .iter()
            .flat_map(|p| p.uses())
            .filter(|u| u.attachment == id)
            .collect();
        let loads: Vec<LoadOp> = uses.iter().map(|u| u.load).collect();
        let stores: Vec<StoreOp> = uses.iter().map(|u| u.store).collect();
        a.sampled = plan.passes.iter().any(|p| p.samples.contains(&id));
        a.transient = !a.read_after_frame && !a.sampled && is_transient(&loads, &stores);
    }
}

/// Draw calls one frame records without culling, estimated: each scene pass's draws of the
/// scene (one per mesh; per object, two per instance), plus the full-view draws of composition
/// and the far composite. Mask fans and probes are left out; the renderer tallies what it
/// records.
fn draw_calls_estimate(scene: &Scene, plan: &FramePlan) -> u64 {
    let meshes = scene.draws().count() as u64;
    plan.passes
        .iter()
        .map(|p| {
            let scene_draws = match p.submission {
                _ if p.kind == PassKind::Composite => 1,
                Submission::PerObject => 2 * scene.instance_count() as u64,
                _ => meshes,
            };
            scene_draws + p.far_composite().is_some() as u64
        })
        .sum()
}

fn validate_eyes(config: &RenderConfig, hmd: &HmdProfile) -> Result<EyeParams, ConfigError> {
    let ipd = config.ipd_m.unwrap_or(crate::view::DEFAULT_IPD_M);
    if !ipd.is_finite() || !(0.0..=0.1).contains(&ipd) {
        return Err(ConfigError::new(
            "ipd",
            ipd,
            "a finite distance in metres, 0 ≤ ipd ≤ 0.1",
        ));
    }
    let mut eyes = hmd.eyes(ipd);
    if let Some(cant) = config.cant_deg {
        if !cant.is_finite() || cant.abs() > 45.0 {
            return Err(ConfigError::new(
                "cant",
                cant,
                "finite degrees, |cant| ≤ 45",
            ));
        }
        eyes.cant_rad = cant.to_radians();
    }
    if let Some(fov) = config.fov {
        // Each half-angle within (-89°, 89°) and the two halves of an axis spanning > 0.
        let max = 89f32.to_radians().tan();
        let ok = |t: f32| t.is_finite() && t.abs() < max;
        let valid = fov.as_array().into_iter().all(ok)
            && fov.left + fov.right > 0.0
            && fov.up + fov.down > 0.0;
        if !valid {
            return Err(ConfigError::new(
                "fov",
                format!("{:?}", fov.as_array()),
                format!("finite tangents with |t| < {max:.1} (89°) spanning a positive angle on each axis"),
            ));
        }
        eyes.left_fov = fov;
        eyes.right_fov = fov.mirrored();
    }
    Ok(eyes)
}

fn validate_resolution(
    config: &RenderConfig,
    hmd: &HmdProfile,
    caps: &DeviceCaps,
) -> Result<Resolution, ConfigError> {
    let res = config.resolution.unwrap_or(Resolution {
        width: hmd.panel_per_eye.0,
        height: hmd.panel_per_eye.1,
    });
    let side_by_side = matches!(config.stereo, StereoMode::PerObject | StereoMode::Instanced);
    let max_width = if side_by_side {
        caps.max_image_dimension_2d / 2
    } else {
        caps.max_image_dimension_2d
    };
    let max_height = caps.max_image_dimension_2d;
    if res.width == 0 || res.height == 0 || res.width > max_width || res.height > max_height {
        let why = if side_by_side {
            " (both eyes share one double-wide image)"
        } else {
            ""
        };
        return Err(ConfigError::new(
            "resolution",
            res,
            format!(
                "each side 1..={} wide and 1..={max_height} high per eye on this device{why}",
                max_width
            ),
        ));
    }
    Ok(res)
}

fn validate_views(config: &RenderConfig, caps: &DeviceCaps) -> Result<(), ConfigError> {
    let limit = MAX_VIEWS.min(caps.max_multiview_views);
    if config.views == 0 || config.views > limit {
        return Err(ConfigError::new(
            "views",
            config.views,
            format!(
                "at most {limit} (foveate renders up to {MAX_VIEWS} views in one pass; this device's maxMultiviewViewCount is {})",
                caps.max_multiview_views
            ),
        ));
    }
    let wanted = if config.foveation.is_some() { 4 } else { 2 };
    if config.views != wanted {
        let why = if wanted == 4 {
            "foveated rendering uses exactly 4 views (periphery and fovea per eye)"
        } else {
            "stereo rendering uses exactly 2 views (4 with foveation)"
        };
        return Err(ConfigError::new("views", config.views, why));
    }
    if config.foveation.is_some() && config.stereo != StereoMode::Multiview {
        return Err(ConfigError::new(
            "stereo",
            config.stereo,
            "foveation renders its 4 views with multiview",
        ));
    }
    Ok(())
}

fn validate_msaa(config: &RenderConfig, caps: &DeviceCaps) -> Result<(), ConfigError> {
    let device: Vec<String> = caps.sample_counts().iter().map(u32::to_string).collect();
    if !matches!(config.msaa, 1 | 4) || !caps.supports_samples(config.msaa) {
        return Err(ConfigError::new(
            "msaa",
            config.msaa,
            format!(
                "1 or 4, and one the device supports (it supports {})",
                device.join(", ")
            ),
        ));
    }
    Ok(())
}

fn validate_depth_range(config: &RenderConfig) -> Result<(), ConfigError> {
    if !config.near.is_finite() || config.near <= 0.0 {
        return Err(ConfigError::new(
            "near",
            config.near,
            "a finite distance > 0",
        ));
    }
    if config.far.is_nan() || config.far <= config.near {
        return Err(ConfigError::new(
            "far",
            config.far,
            format!("greater than near ({})", config.near),
        ));
    }
    Ok(())
}

fn validate_culling(config: &RenderConfig) -> Result<(), ConfigError> {
    match config.culling {
        Some(c) if !(c.draw_distance.is_finite() && c.draw_distance > config.near) => {
            Err(ConfigError::new(
                "draw distance",
                c.draw_distance,
                format!("a finite distance beyond near ({})", config.near),
            ))
        }
        // The cones drop what the lens hides; without the mask those pixels would show the
        // scene minus the culled objects, an error no lens-region score would see.
        Some(c) if c.strategy.culls_to_lens() && !config.hmd_mask => Err(ConfigError::new(
            "culling",
            c.strategy.name(),
            "lens-region culling needs the HMD mask on (hmd_mask, --hmd-mask): it drops what only the mask hides",
        )),
        _ => Ok(()),
    }
}

fn validate_features(config: &RenderConfig, caps: &DeviceCaps) -> Result<(), ConfigError> {
    let need = |ok: bool, field, value: &str, what: &str| {
        if ok {
            Ok(())
        } else {
            Err(ConfigError::new(
                field,
                value,
                format!("needs {what}, which {} lacks", caps.device_name),
            ))
        }
    };
    match config.stereo {
        StereoMode::Multiview => need(
            caps.max_multiview_views >= 2,
            "stereo",
            "multiview",
            "VK_KHR_multiview",
        )?,
        StereoMode::Instanced => need(
            caps.shader_clip_distance,
            "stereo",
            "instanced",
            "shaderClipDistance",
        )?,
        _ => {}
    }
    if config.count_fragments {
        need(
            caps.fragment_stores_and_atomics,
            "count_fragments",
            "true",
            "fragmentStoresAndAtomics",
        )?;
    }
    if config.timestamps {
        need(
            caps.timestamps,
            "timestamps",
            "true",
            "timestamp queries on the graphics queue",
        )?;
    }
    if config.mffr.is_some()
        && !matches!(config.stereo, StereoMode::Multiview | StereoMode::TwoPass)
    {
        return Err(ConfigError::new(
            "stereo",
            config.stereo,
            "MFFR composites the far field into multiview or two-pass eye passes",
        ));
    }
    if config.coverage_probe && (config.stereo != StereoMode::Multiview || !config.count_fragments)
    {
        return Err(ConfigError::new(
            "coverage_probe",
            "true",
            "needs multiview and fragment counting",
        ));
    }
    Ok(())
}
