//! The foveation layer: a [`FramePlan`] compiled into everything but the scene — the passes and
//! their images, the views placed each frame, the stencil masks, the output stage (composition,
//! accumulation, lens), the frame slots and their queries — recording whole frames whose scene
//! steps someone else draws: foveate's own scene (`Renderer`, built on this layer) or
//! an engine's draws (`layer_engine.rs`). It knows nothing of foveate's scene model.

use std::time::Instant;

use ash::vk;
use glam::{Mat4, Vec2, Vec3};

use super::executor::{Executor, FrameContext};
use super::far_view::FarView;
use super::frame_input::{eyes_fit, FrameInput, FrameRecord};
use super::frame_slot::{FrameSlot, SharedBindings, SlotFrame};
use super::masks::MaskShapes;
use super::output_targets::OutputTargets;
use super::record::record_frame;
use super::recorder::FrameDraws;
use super::setup::{compile_passes, make_sampleable, sampling_executors};
use super::stats::FrameStats;
use super::targets::{create_images, CompiledPass};
use super::views::FrameViews;
use super::vulkan_recorder::{BoundStep, FrameObjects, SceneSteps, VulkanRecorder};
use crate::foveation::fovea_views;
use crate::gpu::{Buffer, Gpu, GpuError, Image, VkResultExt};
use crate::plan::{AttachmentId, ConfigError, FramePlan, PassPlan, Step};
use crate::view::{EyeParams, FovTangents, HiddenArea};

/// A [`FramePlan`] compiled into the Vulkan objects of everything a frame does around its scene
/// steps, recording frames whose scene steps an engine draws.
///
/// A layer records frames into command buffers: the caller's ([`FoveationLayer::record`]), which
/// the caller submits with its own semaphores and fence, or its own
/// ([`FoveationLayer::render`], which submits and waits). It keeps
/// [`FramePlan::frame_slots`] frame slots — uniforms, descriptor sets and query pools of their
/// own — so up to that many frames may be in flight. It holds a handle to its [`Gpu`] (no
/// borrow) and may move to another thread.
pub struct FoveationLayer {
    pub(crate) gpu: Gpu,
    pub(crate) plan: FramePlan,
    // Passes (framebuffers, views) go before the images they view.
    /// Each pass compiled.
    pub(super) passes: Vec<CompiledPass>,
    /// The passes touching the history pair compiled with its roles swapped, for odd frames.
    odd_frame_passes: Vec<(usize, CompiledPass)>,
    /// Output images handed in (an OpenXR swapchain's), with their passes.
    output_targets: Option<OutputTargets>,
    /// Each pass's steps as recorded: pipeline, layout and each slot's descriptor set (the sets
    /// belong to the slots and executors below). An engine's scene steps have no pipeline.
    pub(super) steps: Vec<Vec<BoundStep>>,
    /// Each technique's executor the plan calls for (masks, output stage, far composite,
    /// reconstruction), in no particular order: each owns its resources and per-frame uniforms.
    executors: Vec<Box<dyn Executor>>,
    /// Each frame slot's buffers, bindings and queries.
    pub(crate) slots: Vec<FrameSlot>,
    /// The slot the next frame records into.
    next_slot: usize,
    pub(super) images: Vec<Image>,
    pub(super) readback: Option<Buffer>,
    /// The scene's light, as the views block carries it to foveate's scene shaders.
    pub(crate) light_dir: Vec3,
    /// Each eye's gaze, normalised (−1…1, x right, y up); moves the fovea views.
    gaze: [Vec2; 2],
    /// The eyes the plan was made for: the bounds of [`FoveationLayer::set_eyes`].
    planned_eyes: EyeParams,
    /// Each eye's hidden-area mesh (a runtime's), when handed in.
    hidden_area: Option<[HiddenArea; 2]>,
    pub(crate) frames_rendered: u64,
}

/// A frame about to be recorded: its slot and parity, and the views placed for it.
pub(crate) struct PreparedFrame {
    pub slot: usize,
    pub parity: usize,
    pub world_from_head: Mat4,
    /// Each eye's fovea window around its gaze, when foveated.
    pub fovea: Option<[FovTangents; 2]>,
    pub views: FrameViews,
}

/// A slot's own command buffer, begun for a frame that is submitted and waited on.
pub(crate) struct OwnBuffer {
    slot: usize,
    pub cmd: vk::CommandBuffer,
    start: Instant,
}

/// What the scene's side of a frame measured, for its figures.
#[derive(Default)]
pub(crate) struct SceneFigures {
    pub cpu_cull_ms: f64,
    pub instances_drawn: Vec<u64>,
}

impl FoveationLayer {
    /// Builds everything `plan` calls for around its scene steps, and nothing else, with the
    /// frame slots' descriptor sets binding `shared` (foveate's scene's, or nothing of an
    /// engine's); its frames end in one of `output_images` when handed in, and the attachments
    /// `view_images` names are an engine's images.
    pub(crate) fn build(
        gpu: &Gpu,
        plan: &FramePlan,
        shared: SharedBindings,
        output_images: &[vk::Image],
        view_images: &[(AttachmentId, vk::Image)],
    ) -> Result<Self, GpuError> {
        let slot_count = plan.frame_slots.max(1) as usize;
        let masks = plan
            .passes
            .iter()
            .any(PassPlan::has_masks)
            .then(|| MaskShapes::new(gpu, slot_count))
            .transpose()?;
        let slots = (0..slot_count)
            .map(|s| {
                let masks = masks.as_ref().map(|m| &m.buffers[s]);
                FrameSlot::new(gpu, plan, &shared, masks)
            })
            .collect::<Result<Vec<_>, _>>()?;
        let images = create_images(gpu, plan, output_images, view_images)?;
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
        Ok(FoveationLayer {
            gpu: gpu.clone(),
            plan: plan.clone(),
            passes: compiled.passes,
            odd_frame_passes: compiled.odd_frames,
            output_targets,
            steps: compiled.steps,
            executors,
            slots,
            next_slot: 0,
            images,
            readback: None,
            light_dir: Vec3::NEG_Y,
            gaze: [Vec2::ZERO; 2],
            planned_eyes: plan.eyes,
            hidden_area: None,
            frames_rendered: 0,
        })
    }

    /// The device the layer records for.
    pub fn gpu(&self) -> &Gpu {
        &self.gpu
    }

    /// The plan the layer was made from.
    pub fn plan(&self) -> &FramePlan {
        &self.plan
    }

    /// The image output `id` of the last frame lies in: the selected one of those handed in,
    /// or the layer's own.
    pub(super) fn output_image(&self, id: usize) -> vk::Image {
        match self.output_targets.as_ref().and_then(|t| t.image()) {
            Some(image) => image.raw,
            None => self.images[id].raw,
        }
    }

    /// The output image the next frames end in, by its index among those handed in when the
    /// layer was made.
    pub fn select_output(&mut self, index: usize) -> Result<(), GpuError> {
        match &mut self.output_targets {
            Some(t) => t.select(index),
            None => Err(GpuError::NoOutputImages),
        }
    }

    /// This frame's eyes (an OpenXR runtime's located views), without replanning: they must
    /// fit the plan's — each field-of-view tangent and the IPD at most the planned ones, the
    /// cant the planned one — so every image size, culling reach and far view the plan fixed
    /// still covers them. Anything else needs a new plan; the error says which.
    pub fn set_eyes(&mut self, eyes: EyeParams) -> Result<(), ConfigError> {
        eyes_fit(&eyes, &self.planned_eyes)?;
        self.plan.eyes = eyes;
        Ok(())
    }

    /// Each eye's hidden-area mesh (a runtime's `XR_KHR_visibility_mask`) for the following
    /// frames: the HMD mask drops it. The plan must have taken one
    /// ([`crate::plan::RenderConfig::hidden_area_mesh`]).
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

    /// `Ok` when the next frame slot may take a frame: its last frame (if any) has run to its
    /// end on the GPU; else an error naming that frame ([`GpuError::SlotInFlight`]).
    pub fn check_next_slot(&self) -> Result<(), GpuError> {
        self.gpu.check_alive()?;
        self.slots[self.next_slot].check_free(&self.gpu, self.next_slot)
    }

    /// The number of frame slots: how many frames may be in flight at once.
    pub fn frame_slots(&self) -> usize {
        self.slots.len()
    }

    /// How many frames the layer has recorded: the number the next frame will have.
    pub fn frames_recorded(&self) -> u64 {
        self.frames_rendered
    }

    /// The frame slot the next frame records into (slots are taken in turn).
    pub fn next_slot(&self) -> usize {
        self.next_slot
    }

    /// How many transient attachments got lazily allocated memory (tile GPUs; 0 on lavapipe).
    pub fn lazy_attachments(&self) -> usize {
        self.images.iter().filter(|i| i.lazy).count()
    }

    /// The figures of a frame recorded before: `Ok(None)` while its GPU queries are not yet
    /// available (it has not finished; read again after its fence), an error once its slot
    /// was recorded into again. A counting frame's counts are read as they lie: ask for them
    /// after the frame's fence.
    pub fn frame_stats(&mut self, record: FrameRecord) -> Result<Option<FrameStats>, GpuError> {
        self.stats_of(record, false)
    }

    pub(super) fn stats_of(
        &mut self,
        record: FrameRecord,
        wait: bool,
    ) -> Result<Option<FrameStats>, GpuError> {
        self.gpu.check_alive()?;
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

    /// Begins the next slot's own command buffer, for a frame that is submitted and waited on
    /// ([`OwnBuffer`], then [`FoveationLayer::submit_own_buffer`]).
    pub(crate) fn begin_own_buffer(&mut self) -> Result<OwnBuffer, GpuError> {
        self.gpu.check_alive()?;
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
        Ok(OwnBuffer { slot, cmd, start })
    }

    /// Ends, submits and waits for `own`, into which `frame` was recorded: the frame's figures,
    /// with the CPU's times around it.
    pub(crate) fn submit_own_buffer(
        &mut self,
        own: OwnBuffer,
        frame: FrameRecord,
    ) -> Result<FrameStats, GpuError> {
        let (slot, cmd) = (own.slot, own.cmd);
        // SAFETY: the buffer is recording.
        unsafe { self.gpu.device().end_command_buffer(cmd) }.vk("vkEndCommandBuffer")?;
        let recorded = Instant::now();
        // SAFETY: the frame's command buffer was just ended; everything it uses is the
        // layer's (or its caller's), alive until the wait below.
        unsafe { self.gpu.submit(cmd, &self.slots[slot].fence)? };
        let submitted = Instant::now();
        self.gpu.wait(&self.slots[slot].fence)?;
        let done = Instant::now();
        let ms = |a: Instant, b: Instant| (b - a).as_secs_f64() * 1e3;
        let mut stats = self
            .stats_of(frame, true)?
            .ok_or(GpuError::FrameSlotReused {
                frame: frame.frame,
                slot,
            })?;
        stats.cpu_submit_ms = ms(recorded, submitted);
        stats.frame_ms = ms(own.start, done);
        Ok(stats)
    }

    /// Checks a frame's input whole, keeps its gaze and eyes (a refused input changes
    /// nothing), picks its output image, and places its views: the frame's slot and parity,
    /// every executor's uniforms written for it. The caller has checked the slot free
    /// ([`FoveationLayer::check_next_slot`]) before writing anything of it.
    /// `instance_removed`: whether the scene lost an instance since the frame before (the
    /// accumulation clips everywhere once).
    pub(crate) fn prepare(
        &mut self,
        input: &FrameInput,
        instance_removed: bool,
    ) -> Result<PreparedFrame, GpuError> {
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
        let (fovea, views) = self.place_views(world_from_head);
        let context = FrameContext {
            plan: &self.plan,
            fovea: fovea.as_ref(),
            views: &views,
            jitter: views.jitter,
            hidden_area: self.hidden_area.as_ref(),
            instance_removed,
            parity,
        };
        for executor in &mut self.executors {
            executor.update(slot, &context);
        }
        self.slots[slot].views_block.write(&[views.block]);
        Ok(PreparedFrame {
            slot,
            parity,
            world_from_head,
            fovea,
            views,
        })
    }

    /// The next frame's views with the head at `world_from_head`: each eye, each eye's fovea
    /// window around its gaze when foveated, the MFFR far view, the accumulation's jitter.
    pub(super) fn place_views(
        &self,
        world_from_head: Mat4,
    ) -> (Option<[FovTangents; 2]>, FrameViews) {
        self.place_views_for(&self.plan, self.gaze, world_from_head)
    }

    /// [`FoveationLayer::place_views`] with `plan`'s eyes and `gaze`.
    pub(super) fn place_views_for(
        &self,
        plan: &FramePlan,
        gaze: [Vec2; 2],
        world_from_head: Mat4,
    ) -> (Option<[FovTangents; 2]>, FrameViews) {
        let fovea = plan.foveation.map(|g| {
            let screen = (plan.eye_resolution.width, plan.eye_resolution.height);
            fovea_views(&plan.eyes, g.ratio, gaze, screen)
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
        (fovea, views)
    }

    /// Checks a frame's input whole, then keeps its gaze and eyes: a refused input changes
    /// nothing.
    fn take_input(&mut self, input: &FrameInput) -> Result<(), ConfigError> {
        self.check_input(input)?;
        if let Some(gaze) = input.gaze {
            self.gaze = gaze;
        }
        if let Some(eyes) = input.eyes {
            self.plan.eyes = eyes;
        }
        Ok(())
    }

    /// The eyes the plan was made for.
    pub(super) fn planned_eyes(&self) -> crate::view::EyeParams {
        self.planned_eyes
    }

    /// Records the prepared frame into `cmd`: every pass and step of the plan, each scene step
    /// drawn by `scene`, the figures the scene measured kept with the slot's; last, the slot's
    /// word that the frame has run.
    pub(crate) fn record_prepared(
        &mut self,
        cmd: vk::CommandBuffer,
        frame: &PreparedFrame,
        draws: &FrameDraws,
        scene: SceneSteps,
        figures: SceneFigures,
    ) -> Result<FrameRecord, GpuError> {
        let (slot, parity) = (frame.slot, frame.parity);
        self.slots[slot].unset_finished(&self.gpu)?;
        let start = Instant::now();
        let (tally, pass_ends) = {
            let output_passes = self.output_targets.as_ref().map(|t| t.passes(parity));
            let output_passes = output_passes.unwrap_or([&[], &[]]);
            let swapped = [&[][..], &self.odd_frame_passes][parity];
            let slot_objects = &self.slots[slot];
            let objects = FrameObjects {
                device: self.gpu.device(),
                passes: &self.passes,
                // The output image's passes first, then odd frames' swapped pairs.
                retargeted: [output_passes[0], output_passes[1], swapped],
                steps: &self.steps,
                slot,
                parity,
                timestamps: slot_objects.queries.as_ref().map(|q| q.raw),
                statistics: slot_objects.statistics.as_ref().map(|q| q.raw),
                counter: slot_objects.counter.as_ref().map(|c| c.raw),
                scene,
            };
            let mut recorder = VulkanRecorder::new(objects, cmd);
            record_frame(&self.plan, draws, &mut recorder);
            (recorder.tally, recorder.pass_ends)
        };
        self.slots[slot].record_finished(&self.gpu, cmd);
        let record = FrameRecord {
            frame: self.frames_rendered,
            slot,
        };
        let starts = std::iter::once(0).chain(pass_ends.iter().copied());
        self.slots[slot].recorded = Some(SlotFrame {
            frame: record.frame,
            cpu_record_ms: start.elapsed().as_secs_f64() * 1e3,
            cpu_cull_ms: figures.cpu_cull_ms,
            draw_calls: tally.calls,
            triangles: tally.triangles,
            pass_triangles: pass_ends.iter().zip(starts).map(|(e, s)| e - s).collect(),
            instances_drawn: figures.instances_drawn,
        });
        self.frames_rendered += 1;
        self.next_slot = (slot + 1) % self.slots.len();
        Ok(record)
    }
}

impl Drop for FoveationLayer {
    /// Waits for the frames still running before their images, buffers and passes go: when a
    /// slot's last frame has not run to its end, the device is waited idle (a frame recorded
    /// but never submitted is not waited for).
    fn drop(&mut self) {
        if self.gpu.device_lost().is_some() {
            return; // Nothing runs on a lost device: its objects go as they are.
        }
        let running =
            (self.slots.iter().enumerate()).any(|(k, s)| s.check_free(&self.gpu, k).is_err());
        if running {
            if let Err(e) = self.gpu.wait_idle() {
                log::warn!("foveation layer: waiting for its frames on drop failed: {e}");
            }
        }
    }
}

// A layer can move to a render thread (its executors are `Send`, its `Gpu` is shared):
// checked at compile time, so a field that is not fails the build.
const _: () = {
    const fn send<T: Send>() {}
    send::<FoveationLayer>();
};
