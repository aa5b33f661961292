use std::time::Instant;

use ash::vk;
use glam::{Mat4, Vec2, Vec3};

use super::culling::FrameCulling;
use super::descriptors::DescriptorSet;
use super::executor::{Executor, FrameInput};
use super::far_view::FarView;
use super::frame_input::{eyes_fit, head_is_finite};
use super::masks::MaskShapes;
use super::materials::MaterialSet;
use super::output_targets::OutputTargets;
use super::pipelines::scene_bindings;
use super::record::record_frame;
use super::recorder::FrameDraws;
use super::scene_buffers::SceneBuffers;
use super::setup::{
    check_scene, compile_passes, effect_buffer, make_sampleable, query_pool, sampling_executors,
};
use super::stats::{FrameStats, PassStatistics, StepFragments};
use super::targets::{create_images, CompiledPass};
use super::views::{FrameViews, ViewsBlock};
use super::vulkan_recorder::{BoundStep, FrameObjects, VulkanRecorder};
use crate::foveation::fovea_views;
use crate::gpu::{
    Buffer, CommandPool, Fence, Gpu, GpuError, Image, MemoryLocation, QueryPool, VkResultExt,
};
use crate::plan::{ConfigError, FramePlan, PassPlan, RenderConfig, Step};
use crate::scene::{Draw, Scene};
use crate::view::{EyeParams, HiddenArea};

/// A [`FramePlan`] compiled into Vulkan objects for one scene.
///
/// Frames are rendered one at a time (the CPU waits for each frame's fence), so everything a
/// recorded command buffer uses is alive and idle whenever the renderer is touched again.
pub struct Renderer<'g> {
    pub(super) gpu: &'g Gpu,
    pub(super) plan: FramePlan,
    // Passes (framebuffers, views) go before the images they view.
    /// Each pass compiled.
    passes: Vec<CompiledPass>,
    /// Output images handed in (an OpenXR swapchain's), with their passes.
    output_targets: Option<OutputTargets>,
    /// Each pass's steps as recorded: pipeline, layout and descriptor set (the sets belong to
    /// the fields below).
    steps: Vec<Vec<BoundStep>>,
    /// The steps that sample earlier passes' images (their sets are bound through `steps`).
    /// Each technique's executor the plan calls for (masks, output stage, far composite,
    /// reconstruction), in no particular order: each owns its resources and per-frame uniforms.
    executors: Vec<Box<dyn Executor>>,
    /// Per-frame culling and its id buffer (only when a pass draws a culled set).
    culling: Option<FrameCulling>,
    instance_ids: Option<Buffer>,
    pub(super) images: Vec<Image>,
    /// The scene's descriptor set and layout (used through `steps`).
    _bindings: DescriptorSet,
    /// A lit scene's textures, materials and lights (after the bindings that refer to them).
    _materials: Option<MaterialSet>,
    scene: SceneBuffers,
    views_block: Buffer,
    counter: Option<Buffer>,
    queries: Option<QueryPool>,
    /// Pipeline-statistics queries, one per pass (counting frames on devices that have them).
    statistics: Option<QueryPool>,
    pub(super) readback: Option<Buffer>,
    cmd: vk::CommandBuffer,
    frame_pool: CommandPool,
    fence: Fence,
    light_dir: Vec3,
    /// Each eye's gaze, normalised (−1…1, x right, y up); moves the fovea views.
    gaze: [Vec2; 2],
    /// The eyes the plan was made for: the bounds of [`Renderer::set_eyes`].
    planned_eyes: EyeParams,
    /// Each eye's hidden-area mesh (a runtime's), when handed in.
    hidden_area: Option<[HiddenArea; 2]>,
    pub(super) frames_rendered: u64,
}

impl<'g> Renderer<'g> {
    /// Builds everything `plan` calls for, and nothing else: no counter buffer without fragment
    /// counting, no query pool without timestamps, no MSAA images at 1×.
    pub fn new(gpu: &'g Gpu, plan: &FramePlan, scene: &Scene) -> Result<Self, GpuError> {
        Self::build(gpu, plan, scene, &[])
    }

    /// A renderer whose frames end in one of `output_images` (an OpenXR runtime's swapchain
    /// images, each made as [`super::output_image_desc`] says) instead of an image of its own:
    /// `plan` must have [`RenderConfig::external_output`]; [`Renderer::select_output`] picks
    /// the image before each frame.
    pub fn with_output_images(
        gpu: &'g Gpu,
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
        gpu: &'g Gpu,
        plan: &FramePlan,
        scene: &Scene,
        output_images: &[vk::Image],
    ) -> Result<Self, GpuError> {
        check_scene(plan, scene)?;
        let scene_buffers = SceneBuffers::upload(gpu, scene)?;
        let materials = plan
            .lit
            .then(|| MaterialSet::new(gpu, plan, scene))
            .transpose()?;
        let views_block = Buffer::new(
            gpu,
            "views",
            std::mem::size_of::<ViewsBlock>() as u64,
            vk::BufferUsageFlags::UNIFORM_BUFFER,
            MemoryLocation::CpuToGpu,
        )?;
        let counter = effect_buffer(
            gpu,
            plan.fragment_counter(),
            vk::BufferUsageFlags::STORAGE_BUFFER | vk::BufferUsageFlags::TRANSFER_DST,
            MemoryLocation::GpuToCpu,
        )?;
        let masks = plan
            .passes
            .iter()
            .any(PassPlan::has_masks)
            .then(|| MaskShapes::new(gpu))
            .transpose()?;
        let instance_ids = effect_buffer(
            gpu,
            plan.instance_ids(),
            vk::BufferUsageFlags::STORAGE_BUFFER,
            MemoryLocation::CpuToGpu,
        )?;
        let bindings = scene_bindings(
            gpu,
            &views_block,
            &scene_buffers.instances,
            counter.as_ref(),
            masks.as_ref().map(|m| &m.buffer),
            instance_ids.as_ref(),
            materials.as_ref(),
        )?;
        let images = create_images(gpu, plan, output_images)?;
        let output_targets = plan
            .external_output
            .then(|| OutputTargets::new(gpu, plan, output_images, &images))
            .transpose()?;
        make_sampleable(gpu, plan, &images)?;
        let mut executors = sampling_executors(gpu, plan, &images, counter.as_ref())?;
        executors.extend(masks.map(|m| Box::new(m) as Box<dyn Executor>));
        let sets = |step: &Step| executors.iter().find_map(|e| e.descriptors(step));
        let (passes, steps) = compile_passes(gpu, plan, &images, &bindings, sets)?;
        let queries = query_pool(gpu, vk::QueryType::TIMESTAMP, plan.timestamp_pool_slots())?;
        let statistics = query_pool(
            gpu,
            vk::QueryType::PIPELINE_STATISTICS,
            plan.statistics_pool_slots(),
        )?;
        let frame_pool = gpu.command_pool(vk::CommandPoolCreateFlags::TRANSIENT)?;
        let cmd = gpu.allocate_command_buffer(&frame_pool)?;
        log::debug!(
            "renderer: {} passes, {} attachments, {} instances in {} draws, {} shading",
            plan.passes.len(),
            plan.attachments.len(),
            scene.instance_count(),
            scene.batches.len(),
            scene.shading()
        );
        Ok(Renderer {
            gpu,
            plan: plan.clone(),
            passes,
            output_targets,
            steps,
            executors,
            culling: instance_ids
                .is_some()
                .then(|| FrameCulling::new(scene, &scene_buffers, plan)),
            instance_ids,
            images,
            _bindings: bindings,
            _materials: materials,
            scene: scene_buffers,
            views_block,
            counter,
            queries,
            statistics,
            readback: None,
            cmd,
            frame_pool,
            fence: gpu.fence()?,
            light_dir: scene.light_dir,
            gaze: [Vec2::ZERO; 2],
            planned_eyes: plan.eyes,
            hidden_area: None,
            frames_rendered: 0,
        })
    }

    pub fn plan(&self) -> &FramePlan {
        &self.plan
    }

    /// The image output `id` of the last frame lies in: the selected one of those handed in,
    /// or the renderer's own.
    pub(super) fn output_image(&self, id: usize) -> vk::Image {
        match &self.output_targets {
            Some(t) => t.image().raw,
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
    /// waits for it.
    pub fn render_frame(&mut self, world_from_head: Mat4) -> Result<FrameStats, GpuError> {
        head_is_finite(world_from_head)?;
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
        let input = FrameInput {
            plan,
            fovea: fovea.as_ref(),
            views: &views,
            jitter,
            hidden_area: self.hidden_area.as_ref(),
        };
        for executor in &mut self.executors {
            executor.update(&input);
        }
        let mut cpu_cull_ms = 0.0;
        if let (Some(culling), Some(ids)) = (&mut self.culling, &mut self.instance_ids) {
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
        self.views_block.write(&[views.block]);

        let device = self.gpu.device();
        let start = Instant::now();
        // SAFETY: the previous frame's fence was waited on, so the pool's buffer is idle.
        unsafe {
            device
                .reset_command_pool(self.frame_pool.raw, vk::CommandPoolResetFlags::empty())
                .vk("vkResetCommandPool")?;
            let begin = vk::CommandBufferBeginInfo::default()
                .flags(vk::CommandBufferUsageFlags::ONE_TIME_SUBMIT);
            device
                .begin_command_buffer(self.cmd, &begin)
                .vk("vkBeginCommandBuffer")?;
        }
        let (tally, pass_ends) = {
            let draws = FrameDraws {
                all: &self.scene.draws,
                culled: self.culling.as_ref().map_or(&[][..], |c| &c.sets),
            };
            let objects = FrameObjects {
                device,
                passes: &self.passes,
                retargeted: self.output_targets.as_ref().map_or(&[], |t| t.passes()),
                steps: &self.steps,
                timestamps: self.queries.as_ref().map(|q| q.raw),
                statistics: self.statistics.as_ref().map(|q| q.raw),
                counter: self.counter.as_ref().map(|c| c.raw),
                scene: &self.scene,
            };
            let mut recorder = VulkanRecorder::new(objects, self.cmd);
            record_frame(&self.plan, &draws, &mut recorder);
            (recorder.tally, recorder.pass_ends)
        };
        unsafe { device.end_command_buffer(self.cmd) }.vk("vkEndCommandBuffer")?;
        let recorded = Instant::now();
        // SAFETY: the frame's command buffer was just ended; everything it uses is the
        // renderer's, alive until the wait below.
        unsafe { self.gpu.submit(self.cmd, &self.fence)? };
        let submitted = Instant::now();
        self.gpu.wait(&self.fence)?;
        let done = Instant::now();
        self.frames_rendered += 1;

        let ms = |a: Instant, b: Instant| (b - a).as_secs_f64() * 1e3;
        let (gpu_ms, gpu_pass_ms) = self.read_gpu_times()?;
        let steps = self.read_fragment_counts();
        let pass_statistics = self.read_pass_statistics()?;
        let instances_drawn = self.instances_drawn();
        let mut stats = FrameStats {
            cpu_record_ms: ms(start, recorded),
            cpu_submit_ms: ms(recorded, submitted),
            frame_ms: ms(start, done) + cpu_cull_ms,
            gpu_ms,
            gpu_pass_ms,
            fragments: Vec::new(),
            far_fragments: None,
            steps,
            cpu_cull_ms,
            instances_drawn,
            draw_calls: tally.calls,
            triangles: tally.triangles,
            pass_triangles: {
                let starts = std::iter::once(0).chain(pass_ends.iter().copied());
                pass_ends
                    .iter()
                    .zip(starts)
                    .map(|(end, start)| end - start)
                    .collect()
            },
            pass_statistics,
        };
        if self.counter.is_some() {
            stats.split_scene_fragments(self.plan.views, self.plan.mffr.is_some());
        }
        Ok(stats)
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

    /// Frame and per-pass GPU times from the timestamps.
    fn read_gpu_times(&self) -> Result<(Option<f64>, Vec<f64>), GpuError> {
        let Some(q) = &self.queries else {
            return Ok((None, Vec::new()));
        };
        let mut ticks = vec![0u64; self.plan.timestamp_queries as usize];
        unsafe {
            self.gpu.device().get_query_pool_results(
                q.raw,
                0,
                &mut ticks,
                vk::QueryResultFlags::TYPE_64 | vk::QueryResultFlags::WAIT,
            )
        }
        .vk("vkGetQueryPoolResults")?;
        let ms = |a: u64, b: u64| b.wrapping_sub(a) as f64 * self.gpu.timestamp_period_ns / 1e6;
        let passes = ticks.windows(2).map(|w| ms(w[0], w[1])).collect();
        Ok((Some(ms(ticks[0], ticks[ticks.len() - 1])), passes))
    }

    /// Each pass's pipeline statistics (empty without statistics queries).
    fn read_pass_statistics(&self) -> Result<Vec<PassStatistics>, GpuError> {
        let Some(q) = &self.statistics else {
            return Ok(Vec::new());
        };
        // One [u64; 4] per query: ash derives the query count and stride from the element.
        let mut values = vec![[0u64; 4]; self.plan.statistics_queries as usize];
        unsafe {
            self.gpu.device().get_query_pool_results(
                q.raw,
                0,
                &mut values,
                vk::QueryResultFlags::TYPE_64 | vk::QueryResultFlags::WAIT,
            )
        }
        .vk("vkGetQueryPoolResults")?;
        Ok(values
            .iter()
            .map(|v| PassStatistics {
                assembled: v[0],
                clipped_in: v[1],
                rasterised: v[2],
                fragment_invocations: v[3],
            })
            .collect())
    }

    /// Every counted step's per-view counts (empty without fragment counting).
    fn read_fragment_counts(&mut self) -> Vec<StepFragments> {
        match self.counter.as_mut() {
            Some(counter) => super::counting::read_counts(&self.plan, counter),
            None => Vec::new(),
        }
    }

    /// The draws of a scene step: this frame's cull slot, or every instance.
    pub(super) fn draws(&self, cull_slot: Option<usize>) -> &[Draw] {
        match (cull_slot, &self.culling) {
            (Some(slot), Some(culling)) => &culling.sets[slot],
            _ => &self.scene.draws,
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
    send::<Renderer<'static>>();
};
