use ash::vk;
use glam::{Mat4, Vec2};

use super::culling::FrameCulling;
use super::materials::MaterialSet;
use super::moving::MovingInstances;
use super::scene_buffers::{check_scene, SceneBuffers};
use crate::foveation_layer::far_view::FarView;
use crate::foveation_layer::frame_input::{FrameInput, FrameRecord};
use crate::foveation_layer::frame_slot::SharedBindings;
use crate::foveation_layer::layer::{FoveationLayer, PreparedFrame, SceneFigures};
use crate::foveation_layer::recorder::FrameDraws;
use crate::foveation_layer::stats::FrameStats;
use crate::foveation_layer::vulkan_recorder::SceneSteps;
use crate::foveation_layer::StereoImage;
use crate::gpu::{BlitSource, Gpu, GpuError};
use crate::plan::{ConfigError, FramePlan, RenderConfig, Step};
use crate::scene::{Draw, Scene};
use crate::view::{EyeParams, HiddenArea};

/// A [`FramePlan`] compiled into Vulkan objects for one scene: foveate's own scene drawn by
/// the [`FoveationLayer`] the plan also compiles into (the views, masks, output stage and frame
/// slots are the layer's; the scene's buffers, materials, culling and moving instances are the
/// renderer's).
///
/// A renderer records frames into command buffers ([`Renderer::record`]): the caller's, which
/// the caller submits with its own semaphores and fence, or its own ([`Renderer::render_frame`],
/// which submits and waits). It keeps [`FramePlan::frame_slots`] frame slots — uniforms,
/// descriptor sets and query pools of their own — so up to that many frames may be in flight.
/// It holds a handle to its [`Gpu`] (no borrow) and may move to another thread.
pub struct Renderer {
    /// Everything around the scene steps (its slots' descriptor sets bind the scene's buffers
    /// and materials below, so it goes first).
    pub(super) layer: FoveationLayer,
    /// Per-frame culling (only when a pass draws a culled set).
    pub(super) culling: Option<FrameCulling>,
    /// The instances as they stand, when they move between frames.
    pub(super) moving: Option<MovingInstances>,
    /// The draws of the instances in the scene, once some are absent (the scene's draws
    /// otherwise).
    pub(super) present_draws: Option<Vec<Draw>>,
    /// A lit scene's textures, materials and lights (after the bindings that refer to them).
    _materials: Option<MaterialSet>,
    pub(super) scene: SceneBuffers,
}

impl Renderer {
    /// Builds everything `plan` calls for, and nothing else: no counter buffer without fragment
    /// counting, no query pool without timestamps, no MSAA images at 1×.
    pub fn new(gpu: &Gpu, plan: &FramePlan, scene: &Scene) -> Result<Self, GpuError> {
        Self::build(gpu, plan, scene, &[])
    }

    /// A renderer whose frames end in one of `output_images` (an OpenXR runtime's swapchain
    /// images, each made as [`output_image_desc`](crate::foveation_layer::output_image_desc) says) instead of an image of its own:
    /// `plan` must have [`RenderConfig::external_output`]; [`Renderer::select_output`] picks
    /// the image before each frame. (A renderer made with [`Renderer::new`] for such a plan
    /// takes its images frame by frame instead: [`FrameInput::output`].)
    pub fn with_output_images(
        gpu: &Gpu,
        plan: &FramePlan,
        scene: &Scene,
        output_images: &[vk::Image],
    ) -> Result<Self, GpuError> {
        if output_images.is_empty() {
            return Err(GpuError::NoOutputImages);
        }
        Self::build(gpu, plan, scene, output_images)
    }

    fn build(
        gpu: &Gpu,
        plan: &FramePlan,
        scene: &Scene,
        output_images: &[vk::Image],
    ) -> Result<Self, GpuError> {
        if plan.engine_draws {
            return Err(ConfigError::new(
                "plan",
                "planned for an engine's draws",
                "a plan made for foveate's scene (foveate::plan): an engine's plan is a FoveationLayer's",
            )
            .into());
        }
        // The plan's spare instances join the scene, absent until added.
        let own = scene.instance_count();
        let spared =
            (plan.spare_instances > 0).then(|| scene.with_spare_instances(plan.spare_instances));
        let scene = spared.as_ref().unwrap_or(scene);
        check_scene(plan, scene)?;
        let scene_buffers = SceneBuffers::upload(gpu, scene)?;
        let materials = plan
            .lit
            .then(|| MaterialSet::new(gpu, plan, scene))
            .transpose()?;
        let shared = SharedBindings {
            instances: Some(&scene_buffers.instances),
            lit: materials.as_ref().map(MaterialSet::bindings),
        };
        let mut layer = FoveationLayer::build(gpu, plan, shared, output_images, &[])?;
        layer.light_dir = scene.light_dir;
        log::debug!(
            "renderer: {} passes, {} attachments, {} instances in {} draws, {} shading, {} frame slots",
            plan.passes.len(),
            plan.attachments.len(),
            scene.instance_count(),
            scene.batches.len(),
            scene.shading(),
            layer.frame_slots()
        );
        Ok(Renderer {
            culling: plan
                .instance_ids()
                .is_some()
                .then(|| FrameCulling::new(scene, &scene_buffers, plan)),
            moving: plan
                .moving_instances()
                .is_some()
                .then(|| MovingInstances::new(scene, own, layer.frame_slots())),
            layer,
            present_draws: None,
            _materials: materials,
            scene: scene_buffers,
        })
    }

    /// The layer the renderer draws its scene through: its views, masks, output stage and
    /// frame slots.
    pub fn layer(&self) -> &FoveationLayer {
        &self.layer
    }

    /// The device the renderer records for.
    pub fn gpu(&self) -> &Gpu {
        self.layer.gpu()
    }

    /// The plan the renderer was made from.
    pub fn plan(&self) -> &FramePlan {
        self.layer.plan()
    }

    /// The output image the next frames end in, by its index among those handed to
    /// [`Renderer::with_output_images`].
    pub fn select_output(&mut self, index: usize) -> Result<(), GpuError> {
        self.layer.select_output(index)
    }

    /// This frame's eyes (an OpenXR runtime's located views), without replanning: they must
    /// fit the plan's — each field-of-view tangent and the IPD at most the planned ones, the
    /// cant the planned one — so every image size, culling reach and far view the plan fixed
    /// still covers them. Anything else needs a new plan (and renderer); the error says which.
    pub fn set_eyes(&mut self, eyes: EyeParams) -> Result<(), ConfigError> {
        self.layer.set_eyes(eyes)
    }

    /// Each eye's hidden-area mesh (a runtime's `XR_KHR_visibility_mask`) for the following
    /// frames: the HMD mask drops it. The plan must have taken one
    /// ([`RenderConfig::hidden_area_mesh`]).
    pub fn set_hidden_area(&mut self, areas: [HiddenArea; 2]) -> Result<(), ConfigError> {
        self.layer.set_hidden_area(areas)
    }

    /// Sets each eye's gaze (normalised −1…1, x right, y up) for the following frames. A gaze
    /// that is not finite or lies outside −1…1 is an error and the previous gaze stays
    /// ([`crate::foveation::check_gaze`]): filter raw tracker samples first
    /// ([`crate::foveation::GazeFilter`]).
    pub fn set_gaze(&mut self, gaze: [Vec2; 2]) -> Result<(), ConfigError> {
        self.layer.set_gaze(gaze)
    }

    /// Each eye's gaze for the next frame.
    pub fn gaze(&self) -> [Vec2; 2] {
        self.layer.gaze()
    }

    /// Renders one frame with the head at `world_from_head` (a finite matrix, or an error) and
    /// waits for it: [`Renderer::render`] with nothing else changed.
    pub fn render_frame(&mut self, world_from_head: Mat4) -> Result<FrameStats, GpuError> {
        self.render(&FrameInput::new(world_from_head))
    }

    /// Renders one frame from `input` into the next frame slot's own command buffer, submits
    /// it and waits for it: the convenience over [`Renderer::record`] for programs that do not
    /// overlap frames.
    pub fn render(&mut self, input: &FrameInput) -> Result<FrameStats, GpuError> {
        let own = self.layer.begin_own_buffer()?;
        // SAFETY: the buffer is the slot's own, recording; its previous frame was waited on.
        let frame = unsafe { self.record(own.cmd, input)? };
        self.layer.submit_own_buffer(own, frame)
    }

    /// Records the frame `input` describes into `cmd`, using only the resources of the next
    /// frame slot (its uniforms, descriptor sets and queries; images the GPU alone touches are
    /// shared, ordered by the queue and the plan's barriers). The caller submits `cmd` with its
    /// own semaphores and fence, and reads the frame's figures with
    /// [`Renderer::frame_stats`] once it has run.
    ///
    /// A bad input (a head that is not finite, a gaze outside −1…1, eyes that do not fit the
    /// plan) is an error naming it, recorded nothing and changed nothing.
    ///
    /// An engine's loop, two frames in flight (each slot's fence waited on only when the slot
    /// comes round again):
    ///
    /// ```no_run
    /// # fn main() -> Result<(), Box<dyn std::error::Error>> {
    /// use ash::vk;
    /// use foveate::gpu::{Gpu, GpuOptions};
    /// use foveate::render::{FrameInput, Renderer};
    ///
    /// let gpu = Gpu::new(&GpuOptions::default())?; // or Gpu::from_engine: the engine's device
    /// let scene = foveate::scene::default_scene();
    /// let config = foveate::plan::RenderConfig { frames_in_flight: 2, ..Default::default() };
    /// let plan = foveate::plan(&scene, &config, gpu.caps())?;
    /// let mut renderer = Renderer::new(&gpu, &plan, &scene)?;
    /// // The engine's command buffers and fences, one per frame slot.
    /// let pool = gpu.command_pool(vk::CommandPoolCreateFlags::RESET_COMMAND_BUFFER)?;
    /// let slots: Vec<_> = (0..renderer.frame_slots())
    ///     .map(|_| Ok((gpu.allocate_command_buffer(&pool)?, gpu.fence()?)))
    ///     .collect::<Result<_, foveate::gpu::GpuError>>()?;
    /// let mut in_flight = vec![None; slots.len()];
    /// for frame in 0..100 {
    ///     let (cmd, fence) = &slots[frame % slots.len()];
    ///     if let Some(record) = in_flight[frame % slots.len()].take() {
    ///         gpu.wait(fence)?; // the frame this slot held has finished
    ///         let stats = renderer.frame_stats(record)?.expect("finished");
    ///         println!("GPU {:?} ms", stats.gpu_ms);
    ///     }
    ///     let device = gpu.device();
    ///     unsafe { device.begin_command_buffer(*cmd, &vk::CommandBufferBeginInfo::default())? };
    ///     // SAFETY: the slot's previous frame finished; the buffer is this device's.
    ///     let record = unsafe { renderer.record(*cmd, &FrameInput::new(scene.head))? };
    ///     // … the engine records its own work after the frame (a copy, its compositor) …
    ///     unsafe { device.end_command_buffer(*cmd)? };
    ///     unsafe { gpu.submit(*cmd, fence)? }; // or the engine's own vkQueueSubmit
    ///     in_flight[frame % slots.len()] = Some(record);
    /// }
    /// gpu.wait_idle()?; // before the renderer goes
    /// # Ok(())
    /// # }
    /// ```
    ///
    /// # Safety
    /// `cmd` is a primary command buffer of this renderer's device, recording (begun by the
    /// caller, outside a render pass), to be submitted to a queue of the renderer's queue
    /// family (a command buffer not begun is not one Vulkan lets the renderer detect). The
    /// frame this slot held [`FramePlan::frame_slots`] frames ago has finished on the GPU (its
    /// fence signalled): if it has not, the call is an error
    /// ([`GpuError::SlotInFlight`]).
    pub unsafe fn record(
        &mut self,
        cmd: vk::CommandBuffer,
        input: &FrameInput,
    ) -> Result<FrameRecord, GpuError> {
        // Before the slot's buffers are written: its last frame may still read them.
        self.layer.check_next_slot()?;
        let slot = self.layer.next_slot();
        let placing_ms = self.follow_instances(slot);
        let instance_removed = self.moving.as_mut().is_some_and(|m| m.take_removed());
        let frame = self.layer.prepare(input, instance_removed)?;
        let cpu_cull_ms = placing_ms + self.cull(frame.slot, &frame);
        let figures = SceneFigures {
            cpu_cull_ms,
            instances_drawn: self.instances_drawn(),
        };
        let draws = FrameDraws::Scene {
            all: self.present_draws.as_ref().unwrap_or(&self.scene.draws),
            culled: self.culling.as_ref().map_or(&[][..], |c| &c.sets),
        };
        let scene = SceneSteps::Foveate(self.scene.geometry());
        self.layer
            .record_prepared(cmd, &frame, &draws, scene, figures)
    }

    /// The figures of a frame [`Renderer::record`] recorded: `Ok(None)` while its GPU queries
    /// are not yet available (it has not finished; read again after its fence), an error once
    /// its slot was recorded into again. A counting frame's counts are read as they lie: ask
    /// for them after the frame's fence.
    pub fn frame_stats(&mut self, record: FrameRecord) -> Result<Option<FrameStats>, GpuError> {
        self.layer.frame_stats(record)
    }

    /// Culls the frame's draw sets into slot `slot`'s id buffer, with the views the layer
    /// placed; returns the CPU time it took, in ms.
    fn cull(&mut self, slot: usize, frame: &PreparedFrame) -> f64 {
        let ids = self.layer.slots[slot].instance_ids.as_mut();
        let (Some(culling), Some(ids)) = (&mut self.culling, ids) else {
            return 0.0;
        };
        let start = std::time::Instant::now();
        culling.cull(
            &self.layer.plan,
            frame.world_from_head,
            self.layer.frames_rendered,
            frame.views.far.as_ref().map(FarView::frustum),
            frame.fovea.as_ref(),
        );
        ids.write(&culling.ids);
        start.elapsed().as_secs_f64() * 1e3
    }

    /// The number of frame slots: how many frames may be in flight at once.
    pub fn frame_slots(&self) -> usize {
        self.layer.frame_slots()
    }

    /// The frame slot the next [`Renderer::record`] records into (slots are taken in turn).
    pub fn next_slot(&self) -> usize {
        self.layer.next_slot()
    }

    /// Instances each scene step drew this frame, in plan order.
    fn instances_drawn(&self) -> Vec<u64> {
        let scene_steps = self.plan().passes.iter().flat_map(|p| &p.steps);
        scene_steps
            .filter_map(|s| match *s {
                Step::Scene { cull_slot, .. } => Some(
                    self.draws(cull_slot)
                        .iter()
                        .map(|d| d.instance_count as u64)
                        .sum(),
                ),
                _ => None,
            })
            .collect()
    }

    /// The draws of a scene step: this frame's cull slot, or every instance.
    pub(super) fn draws(&self, cull_slot: Option<usize>) -> &[Draw] {
        match (cull_slot, &self.culling) {
            (Some(slot), Some(culling)) => &culling.sets[slot],
            _ => self.present_draws.as_ref().unwrap_or(&self.scene.draws),
        }
    }

    /// How many transient attachments got lazily allocated memory (tile GPUs; 0 on lavapipe).
    pub fn lazy_attachments(&self) -> usize {
        self.layer.lazy_attachments()
    }
}

/// Renders one counting frame of `config` (fragment counters on, no timestamps: its time is no
/// measurement) with each eye's `gaze` and the head at `world_from_head`. Timed frames run
/// without counters; their fragment counts come from here.
pub fn counting_frame(
    gpu: &Gpu,
    scene: &Scene,
    config: &RenderConfig,
    gaze: [Vec2; 2],
    world_from_head: Mat4,
) -> Result<FrameStats, GpuError> {
    let plan = crate::plan(scene, &config.counting(), gpu.caps())?;
    let mut renderer = Renderer::new(gpu, &plan, scene)?;
    renderer.set_gaze(gaze)?;
    renderer.render_frame(world_from_head)
}

/// The renderer's output is its layer's.
impl Renderer {
    /// Copies the last frame's stereo image back to the CPU.
    pub fn readback(&mut self) -> Result<StereoImage, GpuError> {
        self.layer.readback()
    }

    /// The last frame's eye images where they lie (left, right) for a swapchain to show
    /// ([`crate::gpu::Swapchain::present`]); the outputs stay in `TRANSFER_SRC_OPTIMAL`.
    pub fn present_sources(&self) -> Result<[BlitSource; 2], GpuError> {
        self.layer.present_sources()
    }
}

// A renderer can move to a render thread (its layer and buffers are `Send`):
// checked at compile time, so a field that is not fails the build.
const _: () = {
    const fn send<T: Send>() {}
    send::<Renderer>();
};
