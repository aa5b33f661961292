use std::time::Instant;

use ash::vk;
use glam::{Mat4, Vec2, Vec3};

use super::culling::FrameCulling;
use super::executor::{Executor, FrameContext};
use super::far_view::FarView;
use super::frame_input::{eyes_fit, head_is_finite, FrameInput, FrameRecord};
use super::frame_slot::{FrameSlot, SharedBindings, SlotFrame};
use super::masks::MaskShapes;
use super::materials::MaterialSet;
use super::moving::MovingInstances;
use super::output_targets::OutputTargets;
use super::record::record_frame;
use super::recorder::FrameDraws;
use super::scene_buffers::SceneBuffers;
use super::setup::{check_scene, compile_passes, make_sampleable, sampling_executors};
use super::stats::FrameStats;
use super::targets::{create_images, CompiledPass};
use super::views::FrameViews;
use super::vulkan_recorder::{BoundStep, FrameObjects, VulkanRecorder};
use crate::foveation::fovea_views;
use crate::gpu::{Buffer, Gpu, GpuError, Image, VkResultExt};
use crate::plan::{ConfigError, FramePlan, PassPlan, RenderConfig, Step};
use crate::scene::{Draw, Scene};
use crate::view::{EyeParams, HiddenArea};

/// A [`FramePlan`] compiled into Vulkan objects for one scene.
///
/// A renderer records frames into command buffers ([`Renderer::record`]): the caller's, which
/// the caller submits with its own semaphores and fence, or its own ([`Renderer::render_frame`],
/// which submits and waits). It keeps [`FramePlan::frame_slots`] frame slots — uniforms,
/// descriptor sets and query pools of their own — so up to that many frames may be in flight.
/// It holds a handle to its [`Gpu`] (no borrow) and may move to another thread.
pub struct Renderer {
    pub(super) gpu: Gpu,
    pub(super) plan: FramePlan,
    // Passes (framebuffers, views) go before the images they view.
    /// Each pass compiled.
    passes: Vec<CompiledPass>,
    /// The passes touching the history pair compiled with its roles swapped, for odd frames.
    odd_frame_passes: Vec<(usize, CompiledPass)>,
    /// Output images handed in (an OpenXR swapchain's), with their passes.
    output_targets: Option<OutputTargets>,
    /// Each pass's steps as recorded: pipeline, layout and each slot's descriptor set (the sets
    /// belong to the slots and executors below).
    steps: Vec<Vec<BoundStep>>,
    /// Each technique's executor the plan calls for (masks, output stage, far composite,
    /// reconstruction), in no particular order: each owns its resources and per-frame uniforms.
    executors: Vec<Box<dyn Executor>>,
    /// Per-frame culling (only when a pass draws a culled set).
    pub(super) culling: Option<FrameCulling>,
    /// The instances as they stand, when they move between frames.
    pub(super) moving: Option<MovingInstances>,
    /// The draws of the instances in the scene, once some are absent (the scene's draws
    /// otherwise).
    pub(super) present_draws: Option<Vec<Draw>>,
    /// Each frame slot's buffers, bindings and queries.
    pub(super) slots: Vec<FrameSlot>,
    /// The slot the next frame records into.
    next_slot: usize,
    pub(super) images: Vec<Image>,
    /// A lit scene's textures, materials and lights (after the bindings that refer to them).
    _materials: Option<MaterialSet>,
    pub(super) scene: SceneBuffers,
    pub(super) readback: Option<Buffer>,
    light_dir: Vec3,
    /// Each eye's gaze, normalised (−1…1, x right, y up); moves the fovea views.
    gaze: [Vec2; 2],
    /// The eyes the plan was made for: the bounds of [`Renderer::set_eyes`].
    planned_eyes: EyeParams,
    /// Each eye's hidden-area mesh (a runtime's), when handed in.
    hidden_area: Option<[HiddenArea; 2]>,
    pub(super) frames_rendered: u64,
}

impl Renderer {
    /// Builds everything `plan` calls for, and nothing else: no counter buffer without fragment
    /// counting, no query pool without timestamps, no MSAA images at 1×.
    pub fn new(gpu: &Gpu, plan: &FramePlan, scene: &Scene) -> Result<Self, GpuError> {
        Self::build(gpu, plan, scene, &[])
    }

    /// A renderer whose frames end in one of `output_images` (an OpenXR runtime's swapchain
    /// images, each made as [`super::output_image_desc`] says) instead of an image of its own:
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
        let slot_count = plan.frame_slots.max(1) as usize;
        let masks = plan
            .passes
            .iter()
            .any(PassPlan::has_masks)
            .then(|| MaskShapes::new(gpu, slot_count))
            .transpose()?;
        let shared = SharedBindings {
            scene: &scene_buffers,
            materials: materials.as_ref(),
        };
        let slots = (0..slot_count)
            .map(|s| {
                let masks = masks.as_ref().map(|m| &m.buffers[s]);
                FrameSlot::new(gpu, plan, &shared, masks)
            })
            .collect::<Result<Vec<_>, _>>()?;
        let images = create_images(gpu, plan, output_images)?;
        let output_targets = plan
            .external_output
            .then(|| OutputTargets::new(gpu, plan, output_images, &images))
            .transpose()?;
        make_sampleable(gpu, plan, &images)?;
        let counters: Vec<_> = slots.iter().map(|s| s.counter.as_ref()).collect();
        let mut executors = sampling_executors(gpu, plan, &images, &counters)?;
        executors.extend(masks.map(|m| Box::new(m) as Box<dyn Executor>));
        let sets = |step: &Step, slot, parity| {
            executors
                .iter()
                .find_map(|e| e.descriptors(step, slot, parity))
        };
        let bindings: Vec<_> = slots.iter().map(|s| &s.bindings).collect();
        let compiled = compile_passes(gpu, plan, &images, &bindings, sets)?;
        log::debug!(
            "renderer: {} passes, {} attachments, {} instances in {} draws, {} shading, {} frame slots",
            plan.passes.len(),
            plan.attachments.len(),
            scene.instance_count(),
            scene.batches.len(),
            scene.shading(),
            slot_count
        );
        Ok(Renderer {
            gpu: gpu.clone(),
            plan: plan.clone(),
            passes: compiled.passes,
            odd_frame_passes: compiled.odd_frames,
            output_targets,
            steps: compiled.steps,
            executors,
            culling: plan
                .instance_ids()
                .is_some()
                .then(|| FrameCulling::new(scene, &scene_buffers, plan)),
            moving: plan
                .moving_instances()
                .is_some()
                .then(|| MovingInstances::new(scene, own, slot_count)),
            present_draws: None,
            slots,
            next_slot: 0,
            images,
            _materials: materials,
            scene: scene_buffers,
            readback: None,
            light_dir: scene.light_dir,
            gaze: [Vec2::ZERO; 2],
            planned_eyes: plan.eyes,
            hidden_area: None,
            frames_rendered: 0,
        })
    }

    /// The device the renderer records for.
    pub fn gpu(&self) -> &Gpu {
        &self.gpu
    }

    /// The plan the renderer was made from.
    pub fn plan(&self) -> &FramePlan {
        &self.plan
    }

    /// The image output `id` of the last frame lies in: the selected one of those handed in,
    /// or the renderer's own.
    pub(super) fn output_image(&self, id: usize) -> vk::Image {
        match self.output_targets.as_ref().and_then(|t| t.image()) {
            Some(image) => image.raw,
            None => self.images[id].raw,
        }
    }

    /// The output image the next frames end in, by its index among those handed to
    /// [`Renderer::with_output_images`].
    pub fn select_output(&mut self, index: usize) -> Result<(), GpuError> {
        match &mut self.output_targets {
            Some(t) => t.select(index),
            None => Err(GpuError::NoOutputImages),
        }
    }

    /// This frame's eyes (an OpenXR runtime's located views), without replanning: they must
    /// fit the plan's — each field-of-view tangent and the IPD at most the planned ones, the
    /// cant the planned one — so every image size, culling reach and far view the plan fixed
    /// still covers them. Anything else needs a new plan (and renderer); the error says which.
    pub fn set_eyes(&mut self, eyes: EyeParams) -> Result<(), ConfigError> {
        eyes_fit(&eyes, &self.planned_eyes)?;
        self.plan.eyes = eyes;
        Ok(())
    }

    /// Each eye's hidden-area mesh (a runtime's `XR_KHR_visibility_mask`) for the following
    /// frames: the HMD mask drops it. The plan must have taken one
    /// ([`RenderConfig::hidden_area_mesh`]).
    pub fn set_hidden_area(&mut self, areas: [HiddenArea; 2]) -> Result<(), ConfigError> {
        if !self.plan.hidden_area_mesh {
            return Err(ConfigError::new(
                "hidden_area_mesh",
                false,
                "a hidden-area mesh needs a plan that takes one (hmd_mask and hidden_area_mesh on)",
            ));
        }
        self.hidden_area = Some(areas);
        Ok(())
    }

    /// Sets each eye's gaze (normalised −1…1, x right, y up) for the following frames. A gaze
    /// that is not finite or lies outside −1…1 is an error and the previous gaze stays
    /// ([`crate::foveation::check_gaze`]): filter raw tracker samples first
    /// ([`crate::foveation::GazeFilter`]).
    pub fn set_gaze(&mut self, gaze: [Vec2; 2]) -> Result<(), ConfigError> {
        crate::foveation::check_gaze(gaze)?;
        self.gaze = gaze;
        Ok(())
    }

    /// Each eye's gaze for the next frame.
    pub fn gaze(&self) -> [Vec2; 2] {
        self.gaze
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
        let slot = self.next_slot;
        let (pool, cmd) = (self.slots[slot].pool.raw, self.slots[slot].cmd);
        let device = self.gpu.device();
        let start = Instant::now();
        // SAFETY: the slot's last frame through here was waited on, and one recorded by a
        // caller into its own buffer never used this pool: the pool's buffer is idle.
        unsafe {
            device
                .reset_command_pool(pool, vk::CommandPoolResetFlags::empty())
                .vk("vkResetCommandPool")?;
            let begin = vk::CommandBufferBeginInfo::default()
                .flags(vk::CommandBufferUsageFlags::ONE_TIME_SUBMIT);
            device
                .begin_command_buffer(cmd, &begin)
                .vk("vkBeginCommandBuffer")?;
        }
        // SAFETY: the buffer is this device's and recording; the slot's previous frame is done.
        let record = unsafe { self.record(cmd, input)? };
        let device = self.gpu.device();
        unsafe { device.end_command_buffer(cmd) }.vk("vkEndCommandBuffer")?;
        let recorded = Instant::now();
        // SAFETY: the frame's command buffer was just ended; everything it uses is the
        // renderer's, alive until the wait below.
        unsafe { self.gpu.submit(cmd, &self.slots[slot].fence)? };
        let submitted = Instant::now();
        self.gpu.wait(&self.slots[slot].fence)?;
        let done = Instant::now();
        let ms = |a: Instant, b: Instant| (b - a).as_secs_f64() * 1e3;
        let mut stats = self
            .stats_of(record, true)?
            .ok_or(GpuError::FrameSlotReused {
                frame: record.frame,
                slot,
            })?;
        stats.cpu_submit_ms = ms(recorded, submitted);
        stats.frame_ms = ms(start, done);
        Ok(stats)
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
    /// family. The frame this slot held [`FramePlan::frame_slots`] frames ago has finished on
    /// the GPU (its fence signalled), and no frame of this renderer is running when it is
    /// dropped.
    pub unsafe fn record(
        &mut self,
        cmd: vk::CommandBuffer,
        input: &FrameInput,
    ) -> Result<FrameRecord, GpuError> {
        if let (Some(raw), None) = (input.output, &self.output_targets) {
            return Err(ConfigError::new(
                "output",
                format!("{raw:?}"),
                "a plan whose output is handed in (RenderConfig::external_output)",
            )
            .into());
        }
        self.take_input(input)?;
        if let (Some(raw), Some(targets)) = (input.output, &mut self.output_targets) {
            targets.select_image(&self.gpu, &self.plan, raw, &self.images)?;
        }
        let slot = self.next_slot;
        // Decided here alone: the executors' uniforms, passes and sets follow it.
        let parity = (self.frames_rendered % 2) as usize;
        let world_from_head = input.world_from_head;
        let cpu_cull_ms = self.prepare(slot, world_from_head, parity);
        let start = Instant::now();
        let (tally, pass_ends) = {
            let draws = FrameDraws {
                all: self.present_draws.as_ref().unwrap_or(&self.scene.draws),
                culled: self.culling.as_ref().map_or(&[][..], |c| &c.sets),
            };
            let output_passes = self.output_targets.as_ref().map(|t| t.passes(parity));
            let output_passes = output_passes.unwrap_or([&[], &[]]);
            let swapped = [&[][..], &self.odd_frame_passes][parity];
            let frame = &self.slots[slot];
            let objects = FrameObjects {
                device: self.gpu.device(),
                passes: &self.passes,
                // The output image's passes first, then odd frames' swapped pairs.
                retargeted: [output_passes[0], output_passes[1], swapped],
                steps: &self.steps,
                slot,
                parity,
                timestamps: frame.queries.as_ref().map(|q| q.raw),
                statistics: frame.statistics.as_ref().map(|q| q.raw),
                counter: frame.counter.as_ref().map(|c| c.raw),
                scene: &self.scene,
            };
            let mut recorder = VulkanRecorder::new(objects, cmd);
            record_frame(&self.plan, &draws, &mut recorder);
            (recorder.tally, recorder.pass_ends)
        };
        let record = FrameRecord {
            frame: self.frames_rendered,
            slot,
        };
        let starts = std::iter::once(0).chain(pass_ends.iter().copied());
        self.slots[slot].recorded = Some(SlotFrame {
            frame: record.frame,
            cpu_record_ms: start.elapsed().as_secs_f64() * 1e3,
            cpu_cull_ms,
            draw_calls: tally.calls,
            triangles: tally.triangles,
            pass_triangles: pass_ends.iter().zip(starts).map(|(e, s)| e - s).collect(),
            instances_drawn: self.instances_drawn(),
        });
        self.frames_rendered += 1;
        self.next_slot = (slot + 1) % self.slots.len();
        Ok(record)
    }

    /// The figures of a frame [`Renderer::record`] recorded: `Ok(None)` while its GPU queries
    /// are not yet available (it has not finished; read again after its fence), an error once
    /// its slot was recorded into again. A counting frame's counts are read as they lie: ask
    /// for them after the frame's fence.
    pub fn frame_stats(&mut self, record: FrameRecord) -> Result<Option<FrameStats>, GpuError> {
        self.stats_of(record, false)
    }

    fn stats_of(
        &mut self,
        record: FrameRecord,
        wait: bool,
    ) -> Result<Option<FrameStats>, GpuError> {
        let slot = self.slots.get_mut(record.slot);
        let current = slot.as_ref().and_then(|s| s.recorded.as_ref());
        if current.map(|f| f.frame) != Some(record.frame) {
            return Err(GpuError::FrameSlotReused {
                frame: record.frame,
                slot: record.slot,
            });
        }
        let slot = slot.expect("checked above");
        slot.stats(&self.gpu, &self.plan, wait)
    }

    /// Checks a frame's input whole, then keeps its gaze and eyes: a refused input changes
    /// nothing.
    fn take_input(&mut self, input: &FrameInput) -> Result<(), ConfigError> {
        head_is_finite(input.world_from_head)?;
        if let Some(gaze) = input.gaze {
            crate::foveation::check_gaze(gaze)?;
        }
        if let Some(eyes) = &input.eyes {
            eyes_fit(eyes, &self.planned_eyes)?;
        }
        if let Some(gaze) = input.gaze {
            self.gaze = gaze;
        }
        if let Some(eyes) = input.eyes {
            self.plan.eyes = eyes;
        }
        Ok(())
    }

    /// Works out the frame's views, writes slot `slot`'s uniforms and every executor's for a
    /// frame of `parity` (and the instances, when they move), and culls into the slot's id
    /// buffer; returns the culling's CPU time in ms (placing moved instances again included).
    fn prepare(&mut self, slot: usize, world_from_head: Mat4, parity: usize) -> f64 {
        let placing_ms = self.follow_instances(slot);
        let instance_removed = self.moving.as_mut().is_some_and(|m| m.take_removed());
        let plan = &self.plan;
        let fovea = plan.foveation.map(|g| {
            let screen = (plan.eye_resolution.width, plan.eye_resolution.height);
            fovea_views(&plan.eyes, g.ratio, self.gaze, screen)
        });
        let far = plan
            .mffr
            .map(|m| FarView::new(&m, &plan.eyes, world_from_head, self.frames_rendered));
        let jitter = plan
            .foveation
            .and_then(|g| g.temporal)
            .map(|t| t.jitter(self.frames_rendered));
        let views = FrameViews::new(
            plan,
            world_from_head,
            fovea.as_ref(),
            far,
            self.light_dir,
            jitter,
        );
        let context = FrameContext {
            plan,
            fovea: fovea.as_ref(),
            views: &views,
            jitter,
            hidden_area: self.hidden_area.as_ref(),
            instance_removed,
            parity,
        };
        for executor in &mut self.executors {
            executor.update(slot, &context);
        }
        let frame = &mut self.slots[slot];
        let mut cpu_cull_ms = 0.0;
        if let (Some(culling), Some(ids)) = (&mut self.culling, &mut frame.instance_ids) {
            let start = Instant::now();
            culling.cull(
                plan,
                world_from_head,
                self.frames_rendered,
                views.far.as_ref().map(FarView::frustum),
                fovea.as_ref(),
            );
            ids.write(&culling.ids);
            cpu_cull_ms = start.elapsed().as_secs_f64() * 1e3;
        }
        frame.views_block.write(&[views.block]);
        cpu_cull_ms + placing_ms
    }

    /// The number of frame slots: how many frames may be in flight at once.
    pub fn frame_slots(&self) -> usize {
        self.slots.len()
    }

    /// The frame slot the next [`Renderer::record`] records into (slots are taken in turn).
    pub fn next_slot(&self) -> usize {
        self.next_slot
    }

    /// Instances each scene step drew this frame, in plan order.
    fn instances_drawn(&self) -> Vec<u64> {
        let scene_steps = self.plan.passes.iter().flat_map(|p| &p.steps);
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
        self.images.iter().filter(|i| i.lazy).count()
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

// A renderer can move to a render thread (its executors are `Send`, its `Gpu` is shared):
// checked at compile time, so a field that is not fails the build.
const _: () = {
    const fn send<T: Send>() {}
    send::<Renderer>();
};
