//! The plan's model: passes with their steps, the frame plan (attachments and their uses are in
//! `attachments`). Built by `build`, completed by `derive`; what it costs in memory and traffic
//! is `workload`.

pub(super) use super::attachments::{AttachmentPlan, AttachmentRole, Format, Use};
use super::ops::{AttachmentId, PassBarriers};
use super::pipeline::PipelineDesc;
use super::steps::{CountedStep, DrawSet, Step};
use super::{CullConfig, Resolution, StereoMode, FRAME_VIEWS};
use crate::foveation::FoveationGeometry;
use crate::mffr::{MffrGeometry, MffrOrder};
use crate::view::{Eye, EyeParams, FovTangents, HmdProfile, LensRegion, RadialDistortion};

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

/// What a pass does.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub enum PassKind {
    /// Draws the scene (and, when planned, stencil masks and the coverage probe).
    Scene,
    /// The output stage: what the display shows, from the images it samples (a foveated
    /// frame's views composed at full resolution; lens distortion when planned).
    Output,
    /// MFFR: the far field, once, into an image the eye passes sample.
    FarField,
    /// Radial density masking: the skipped quads filled from their neighbours.
    Reconstruct,
    /// The periphery accumulated over frames at its own texels, before the output pass
    /// composes it ([`HistoryAt::Periphery`](crate::foveation::HistoryAt::Periphery)).
    Accumulate,
    /// A view's image, resolved alone, copied into its layer (`plan/split_views.rs`).
    LayerCopy,
}

impl PassKind {
    /// A pass of one full-view draw per eye sampling earlier images (not the scene).
    pub fn is_full_view(self) -> bool {
        !matches!(self, PassKind::Scene | PassKind::FarField)
    }
}

/// One render pass of the frame.
#[derive(Clone, Debug, PartialEq)]
pub struct PassPlan {
    /// Its name in the printout, debug labels and per-pass times.
    pub name: &'static str,
    /// What the pass draws.
    pub kind: PassKind,
    /// Multiview view mask; 0 for a pass without multiview.
    pub view_mask: u32,
    /// The colour attachment.
    pub color: Use,
    /// The depth (and stencil) attachment, if any.
    pub depth: Option<Use>,
    /// In-pass MSAA resolve target (`pResolveAttachments`).
    pub resolve: Option<Use>,
    /// In-pass resolve of the multisampled depth to one sample (its sample 0), for a later
    /// pass to sample (`pDepthStencilResolveAttachment`; the accumulated periphery's).
    pub depth_resolve: Option<Use>,
    /// The next frame's history, written as a second colour attachment (location 1) beside
    /// `color` (temporal accumulation folded into the output stage). Its image swaps roles
    /// with the history the pass samples every frame ([`FramePlan::history`]).
    pub history: Option<Use>,
    /// Attachments of earlier passes this pass samples.
    pub samples: Vec<AttachmentId>,
    /// How its views are submitted (multiview, pass per eye, instanced …).
    pub submission: Submission,
    /// What the pass does, in order (mask fans, far composite, scene, probe; or composition).
    pub steps: Vec<Step>,
    /// What the pass waits on as it begins and signals as it ends (derived: who touched each
    /// of its images before, who touches them next).
    pub barriers: PassBarriers,
    /// Each step's pipeline, as its builder states it (one per step, in step order; stated
    /// once the frame's stencil states and counter slots are known).
    pub pipelines: Vec<PipelineDesc>,
    /// Depth clamp instead of clipping at the near and far planes (the MFFR split), to work
    /// around [`DriverQuirks`](super::DriverQuirks) dropping clipped primitives' views.
    pub depth_clamp: bool,
    /// Emulated guard band: clip-space x and y are divided by this factor and the viewport
    /// grown by it, so primitives reaching less than this many view widths past the edge need
    /// no clipping. 1 = off; set only to work around [`DriverQuirks`](super::DriverQuirks).
    pub guard_band: u32,
    /// The frame view the pass's view 0 is (`gl_ViewIndex` + this): 2 for the fovea pass of the
    /// two-pass fovea layout, 0 otherwise.
    pub first_view: u32,
}

impl PassPlan {
    /// A pass writing `color`, with nothing else yet: no depth, no resolve, nothing sampled, no
    /// steps, no workaround; barriers and pipelines are derived once the frame is planned.
    pub(super) fn new(
        name: &'static str,
        kind: PassKind,
        view_mask: u32,
        submission: Submission,
        color: Use,
    ) -> Self {
        PassPlan {
            name,
            kind,
            view_mask,
            color,
            depth: None,
            resolve: None,
            depth_resolve: None,
            history: None,
            samples: Vec::new(),
            submission,
            steps: Vec::new(),
            depth_clamp: false,
            guard_band: 1,
            first_view: 0,
            barriers: PassBarriers::default(),
            pipelines: Vec::new(),
        }
    }

    /// Every attachment use of the pass: colour, depth, resolve, history, depth resolve (the
    /// render pass's attachment order).
    pub fn uses(&self) -> impl Iterator<Item = &Use> {
        [
            Some(&self.color),
            self.depth.as_ref(),
            self.resolve.as_ref(),
            self.history.as_ref(),
            self.depth_resolve.as_ref(),
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

    pub(super) fn uses_mut(&mut self) -> impl Iterator<Item = &mut Use> {
        [
            Some(&mut self.color),
            self.depth.as_mut(),
            self.resolve.as_mut(),
            self.history.as_mut(),
            self.depth_resolve.as_mut(),
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

/// One counted step: its pass (index into [`FramePlan::passes`]) and what it draws. Its five
/// counter slots (views 0–3, then the MFFR far view) start at [`FramePlan::counter_base`].
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub struct CountedSlot {
    /// The pass (index into [`FramePlan::passes`]).
    pub pass: usize,
    /// What the counted step draws.
    pub step: CountedStep,
}

/// Counter slots per counted step: six views and the MFFR far view.
pub const COUNTER_SLOTS_PER_STEP: u32 = FRAME_VIEWS + 1;

/// Counter slots of an accumulating counting frame's history outcomes: nine outcomes
/// (`render::HistoryOutcome`) by three regions (fovea, band, periphery).
pub const HISTORY_OUTCOME_SLOTS: u32 = 9 * 3;

/// A buffer that exists only because an effect asked for it.
#[derive(Clone, Debug, PartialEq)]
pub struct BufferPlan {
    /// Its name in the printout.
    pub name: &'static str,
    /// Its size.
    pub bytes: u64,
}

/// Everything a frame consists of, decided before any Vulkan object exists.
#[derive(Clone, Debug, PartialEq)]
pub struct FramePlan {
    /// The headset the frame is for.
    pub hmd: &'static HmdProfile,
    /// Each eye's field, offset and the IPD.
    pub eyes: EyeParams,
    /// Pixels per eye at the output.
    pub eye_resolution: Resolution,
    /// How the eyes are submitted.
    pub stereo: StereoMode,
    /// Views of the frame: 2, 4 with foveation, 6 with a parafoveal ring (in the fovea's pass).
    pub views: u32,
    /// MSAA samples per pixel (1 without).
    pub samples: u32,
    /// Near plane, metres.
    pub near: f32,
    /// Far plane, metres (reverse Z: depth 0 there).
    pub far: f32,
    /// How views map to render targets.
    pub layout: TargetLayout,
    /// Every image the frame renders into.
    pub attachments: Vec<AttachmentPlan>,
    /// The passes, in submission order.
    pub passes: Vec<PassPlan>,
    /// Effect-only buffers (e.g. the fragment counter); empty when no such effect is on.
    pub buffers: Vec<BufferPlan>,
    /// Timestamp queries per frame (before the frame, after each pass); 0 when timing is off.
    pub timestamp_queries: u32,
    /// Pipeline-statistics queries per frame, one around each pass: counting frames on a device
    /// that has them (0 otherwise; timed frames never carry them).
    pub statistics_queries: u32,
    /// Slots each query pool has past the queries it is read for, where the driver writes a
    /// query recorded after a multiview pass into one slot per view
    /// ([`DriverQuirks::queries_after_multiview_span_views`](super::DriverQuirks)): the most
    /// views of any pass, less one. 0 elsewhere, and when no query is made.
    pub query_spare_slots: u32,
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
    /// MFFR as resolved for this frame: `None` when off, or nothing lies beyond the split.
    pub mffr: Option<MffrGeometry>,
    /// Per-frame culling, when on.
    pub culling: Option<CullConfig>,
    /// Radial density masking as resolved, when on.
    pub radial_density: Option<super::config::RadialDensityGeometry>,
    /// The sets culled each frame, in order; a scene step's `cull_slot` indexes this (empty
    /// when every pass draws every instance).
    pub cull_slots: Vec<DrawSet>,
    /// The scene's clusters, culled per draw set; `None` when its meshes are whole or no pass
    /// draws a culled set (a clustered mesh is then drawn whole).
    pub clusters: Option<ClusterPlan>,
    /// Level of detail as planned: `None` when off, or when no mesh of the scene has levels.
    pub lod: Option<LodPlan>,
    /// Instances of the scene the plan was made for: buffers are sized for them, and a
    /// renderer refuses another scene.
    pub scene_instances: usize,
    /// Absent instances of each mesh planned after the scene's own, for instances added while
    /// rendering ([`RenderConfig::spare_instances`](crate::plan::RenderConfig::spare_instances)).
    pub spare_instances: u32,
    /// A foveated frame's pass layout, and why the planner chose it.
    pub fovea_layout: Option<FoveaLayoutChoice>,
    /// The scene has lit materials: its pipelines shade PBR with textures and lights, and its
    /// renderer makes the textures (a flat scene's makes none).
    pub lit: bool,
    /// Point lights a lit frame shades (0 flat): a constant of its pipelines, never a uniform
    /// (lavapipe 22.3 recompiles and leaks a shader whose loop a uniform bounds, at every bind).
    pub point_lights: u32,
    /// Some lit material is alpha-masked: the scene's fragment shader discards and tests depth
    /// late (only such a scene pays for that).
    pub alpha_mask: bool,
    /// How lit materials are sampled: anisotropically up to this many samples, or trilinearly
    /// (`None`: the device lacks it, or a quirk makes it too slow).
    pub anisotropy: Option<f32>,
    /// Lens distortion in the output stage, when the output is for the lens.
    pub lens: Option<LensOutput>,
    /// The output image is handed in per frame (see [`RenderConfig::external_output`](crate::plan::RenderConfig::external_output)).
    pub external_output: bool,
    /// An engine draws the scene steps with its own pipelines (`plan::plan_for_engine`): the
    /// plan has no scene of foveate's (no instances, culling, MFFR or levels of detail).
    pub engine_draws: bool,
    /// The HMD mask drops a hidden-area mesh handed in per frame (see
    /// [`RenderConfig::hidden_area_mesh`](crate::plan::RenderConfig::hidden_area_mesh)).
    pub hidden_area_mesh: bool,
    /// Frame slots the renderer keeps: frames that may be in flight at once
    /// ([`RenderConfig::frames_in_flight`](crate::plan::RenderConfig::frames_in_flight)).
    pub frame_slots: u32,
    /// The temporal history's two images, when the periphery is accumulated: they swap roles
    /// every frame, so no pass copies the history.
    pub history: Option<HistoryPair>,
    /// With the history, the periphery's depth as a pair too: the periphery pass writes one
    /// (`written` on even frames) while the output pass samples it and the other, the frame
    /// before's, to tell whether the history saw the same surface.
    pub depth_history: Option<HistoryPair>,
}

/// A history kept across frames in two images that swap roles every frame: even frames
/// sample `read` and write `written`, odd frames the reverse. The plan's passes name the even
/// frames' roles; barriers treat the two as one image.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub struct HistoryPair {
    /// The image even frames sample (the history the frame before left).
    pub read: AttachmentId,
    /// The image even frames write (the history the next frame samples).
    pub written: AttachmentId,
}

impl HistoryPair {
    /// The roles in frame `frame` (counted from the renderer's first).
    pub fn of_frame(self, frame: u64) -> HistoryPair {
        if frame.is_multiple_of(2) {
            self
        } else {
            HistoryPair {
                read: self.written,
                written: self.read,
            }
        }
    }

    /// Whether `id` is one of the two.
    pub fn contains(self, id: AttachmentId) -> bool {
        id == self.read || id == self.written
    }
}

/// Clusters in the plan: what the culled draw sets test per cluster, and what the id buffer
/// is sized for.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub struct ClusterPlan {
    /// Clusters over all meshes.
    pub clusters: usize,
    /// Meshes split into clusters.
    pub meshes: usize,
    /// Triangles in the largest cluster.
    pub max_triangles: u32,
    /// Why the clusters are drawn whole rather than culled, when they are.
    pub drawn_whole: Option<&'static str>,
}

impl ClusterPlan {
    /// Whether the culled draw sets cull cluster by cluster.
    pub fn culled(&self) -> bool {
        self.drawn_whole.is_none()
    }
}

/// Level of detail per draw set.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct LodPlan {
    /// The most a drawn level's error projects to, in each drawing view's pixels.
    pub max_error_px: f32,
    /// Simplified levels over all meshes, and the meshes that have them.
    pub levels: usize,
    /// Meshes with simplified levels.
    pub meshes: usize,
}

/// How a foveated frame renders its four views, and why.
#[derive(Clone, Debug, PartialEq)]
pub struct FoveaLayoutChoice {
    /// `OnePass` or `TwoPass` (never `Auto`).
    pub layout: super::FoveaLayout,
    /// Whether the fovea views draw only what their frusta see.
    pub cull: bool,
    /// Why this layout was chosen (printed with the plan).
    pub reason: String,
}

/// The output stage's lens: its distortion and each eye's display field, solved so the
/// display's edges show the rendered field's edges.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct LensOutput {
    /// The lens's radial distortion.
    pub distortion: RadialDistortion,
    /// Each eye's display field, as tangents.
    pub display: [FovTangents; 2],
}

impl LensOutput {
    /// The lens output for `distortion`, with each eye's display field solved from `eyes`.
    pub fn new(distortion: RadialDistortion, eyes: &EyeParams) -> Self {
        LensOutput {
            distortion,
            display: Eye::BOTH.map(|e| distortion.display_fov(eyes.fov(e))),
        }
    }

    /// Where the centre of display pixel (`x`, `y`) of `eye` shows the rendered image, in
    /// pixels of a `screen`-sized eye image rendered with field `fov`: what the output stage
    /// samples there (`None` beyond the rendered field: black on the display). Accuracy
    /// regions on the output image are found with it.
    pub fn rendered_px(
        &self,
        eye: Eye,
        fov: FovTangents,
        screen: Resolution,
        x: u32,
        y: u32,
    ) -> Option<glam::Vec2> {
        let d = self.display[eye.index()];
        let (w, h) = (screen.width as f32, screen.height as f32);
        let (u, v) = ((x as f32 + 0.5) / w, (y as f32 + 0.5) / h);
        let td = glam::Vec2::new(-d.left + u * (d.left + d.right), d.up - v * (d.up + d.down));
        let t = self.distortion.eye_from_display(td);
        let px = (t.x + fov.left) / (fov.left + fov.right) * w;
        let py = (fov.up - t.y) / (fov.up + fov.down) * h;
        ((0.0..=w).contains(&px) && (0.0..=h).contains(&py)).then_some(glam::Vec2::new(px, py))
    }
}

impl FramePlan {
    /// The periphery views' pixels per side over the screen's, as resolved (the configured
    /// density, or the fovea's ratio); `None` without foveation.
    pub fn periphery_density(&self) -> Option<f64> {
        let g = self.foveation?;
        Some(g.periphery_view.width as f64 / self.eye_resolution.width as f64)
    }

    /// Slots of the timestamp query pool: the timestamps read, then the spare slots (0 when
    /// timing is off).
    pub fn timestamp_pool_slots(&self) -> u32 {
        self.pool_slots(self.timestamp_queries)
    }

    /// Slots of the pipeline-statistics query pool (0 when no pass is counted that way).
    pub fn statistics_pool_slots(&self) -> u32 {
        self.pool_slots(self.statistics_queries)
    }

    fn pool_slots(&self, queries: u32) -> u32 {
        if queries == 0 {
            0
        } else {
            queries + self.query_spare_slots
        }
    }

    /// The per-view fragment counter, when fragment counting is on.
    pub fn fragment_counter(&self) -> Option<&BufferPlan> {
        self.buffers.iter().find(|b| b.name == FRAGMENT_COUNTER)
    }

    /// Whether the plan counts fragments per view (a counting frame).
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

    /// Where a counting frame's history-outcome slots start in the fragment counter (after
    /// every counted step's): [`HISTORY_OUTCOME_SLOTS`] of them, outcome by outcome, each
    /// region by region. `None` unless the frame counts and its output accumulates.
    pub fn history_outcome_base(&self) -> Option<u32> {
        (self.count_fragments() && self.output_accumulates())
            .then(|| COUNTER_SLOTS_PER_STEP * self.counted.len() as u32)
    }

    /// Whether the output pass accumulates the periphery over frames.
    pub(crate) fn output_accumulates(&self) -> bool {
        (self.passes.iter().flat_map(|p| &p.steps))
            .any(|s| matches!(s, super::steps::Step::Output(o) if o.temporal))
    }

    /// The per-frame list of culled instance ids, when some pass draws a culled set.
    pub fn instance_ids(&self) -> Option<&BufferPlan> {
        self.buffers.iter().find(|b| b.name == INSTANCE_IDS)
    }

    /// The instance buffer each frame slot keeps when instances move between frames
    /// ([`RenderConfig::moving_instances`](crate::plan::RenderConfig::moving_instances)).
    pub fn moving_instances(&self) -> Option<&BufferPlan> {
        self.buffers.iter().find(|b| b.name == MOVING_INSTANCES)
    }

    /// The MFFR far pass, when planned.
    pub fn far_pass(&self) -> Option<&PassPlan> {
        self.passes.iter().find(|p| p.kind == PassKind::FarField)
    }

    /// How the frame's output holds the two eyes: one layer each after an output or
    /// reconstruction pass, else as the scene passes wrote them.
    pub fn output_layout(&self) -> TargetLayout {
        let full_view = |p: &PassPlan| matches!(p.kind, PassKind::Output | PassKind::Reconstruct);
        if self.passes.iter().any(full_view) {
            TargetLayout::Layered
        } else {
            self.layout
        }
    }

    /// Attachments a pass samples before any pass of the frame writes them, and both images of
    /// the history pair: what the previous frame left. The renderer makes them sampleable
    /// before the first frame.
    pub fn sampled_before_written(&self) -> Vec<AttachmentId> {
        (0..self.attachments.len())
            .filter(|&id| {
                if self.history_pairs().any(|h| h.contains(id)) {
                    return true;
                }
                let first_sampled = self.passes.iter().position(|p| p.samples.contains(&id));
                let first_written = self
                    .passes
                    .iter()
                    .position(|p| p.uses().any(|u| u.attachment == id));
                matches!((first_sampled, first_written), (Some(s), w) if w.is_none_or(|w| s < w))
            })
            .collect()
    }

    /// The image pairs that swap roles every frame: the history, the periphery's depth.
    pub fn history_pairs(&self) -> impl Iterator<Item = HistoryPair> + '_ {
        self.history.into_iter().chain(self.depth_history)
    }

    /// The image attachment `id` names in frame `frame`: on odd frames each pair's two swap.
    pub fn in_frame(&self, id: AttachmentId, frame: u64) -> AttachmentId {
        self.history_pairs()
            .find(|h| h.contains(id))
            .map_or(id, |h| {
                let (even, now) = (h, h.of_frame(frame));
                if id == even.read {
                    now.read
                } else {
                    now.written
                }
            })
    }

    /// The attachments read after the frame, in eye order: the stereo image.
    pub fn outputs(&self) -> Vec<AttachmentId> {
        (0..self.attachments.len())
            .filter(|&i| self.attachments[i].read_after_frame)
            .collect()
    }
}

/// Linear-light colour of the sky: every colour attachment clears to it (the MFFR far pass
/// with alpha 0: the sky is infinitely far, see `shaders/scene.frag`).
pub const SKY: [f32; 4] = [0.22, 0.38, 0.62, 1.0];

pub(crate) const FRAGMENT_COUNTER: &str = "fragment counter";
pub(crate) const INSTANCE_IDS: &str = "instance ids";
/// The name of the per-slot instance buffer of a scene whose instances move.
pub(crate) const MOVING_INSTANCES: &str = "moving instances (one per frame slot)";
