use std::sync::Arc;
use std::time::Instant;

use ash::vk;
use glam::{Mat4, Vec2, Vec4};

use super::culling::FrameCulling;
use super::materials::MaterialSet;
use super::mffr::FarComposite;
use super::output::OutputStage;
use super::pipelines::{compile_pipeline, SceneBindings};
use super::radial_density::Reconstruction;
use super::record::{memory_barrier, record_frame, FrameDraws, VulkanRecorder};
use super::scene_buffers::SceneBuffers;
use super::targets::{compile_pass, create_images, CompiledPass};
use crate::cull::Frustum;
use crate::foveation::fovea_views;
use crate::gpu::{
    BlitSource, Buffer, CommandPool, Fence, Gpu, GpuError, Image, MemoryLocation, Pipeline,
    QueryPool, VkResultExt,
};
use crate::metrics::RgbaImage;
use crate::mffr::FAR_VIEW_INDEX;
use crate::plan::{
    AttachmentId, CountedStep, FramePlan, PassKind, PassPlan, RenderConfig, Step, TargetLayout,
    COUNTER_SLOTS_PER_STEP, MAX_VIEWS,
};
use crate::scene::{Draw, Scene, Shading};
use crate::view::{reverse_z_projection, Eye, FovTangents};

/// The per-frame uniform block (`Views` in the shaders, std140).
#[repr(C)]
#[derive(Clone, Copy)]
struct ViewsBlock {
    /// The eye views, then the MFFR far view at [`FAR_VIEW_INDEX`].
    view_proj: [Mat4; MAX_VIEWS as usize + 1],
    /// xyz: light direction; w: the far pass's near plane (its depth-in-alpha numerator).
    light_dir: Vec4,
    /// Each view's eye in world space, the MFFR far view's at [`FAR_VIEW_INDEX`].
    eye_pos: [Vec4; MAX_VIEWS as usize + 1],
    /// How each view's ray at unit depth moves per pixel right and down (world space): lit
    /// shading's analytic texture gradients.
    ray_dx: [Vec4; MAX_VIEWS as usize + 1],
    ray_dy: [Vec4; MAX_VIEWS as usize + 1],
}

/// One pixel's step of a view's ray at unit depth, right and down, in world space.
fn ray_steps(world_from_view: Mat4, fov: FovTangents, pixels: (u32, u32)) -> (Vec4, Vec4) {
    let right = world_from_view.transform_vector3(glam::Vec3::X);
    let down = world_from_view.transform_vector3(glam::Vec3::NEG_Y);
    (
        (right * (fov.left + fov.right) / pixels.0 as f32).extend(0.0),
        (down * (fov.up + fov.down) / pixels.1 as f32).extend(0.0),
    )
}

/// What one frame cost, measured.
#[derive(Clone, Debug, Default, PartialEq)]
pub struct FrameStats {
    /// CPU time recording the command buffer.
    pub cpu_record_ms: f64,
    /// CPU time of the `vkQueueSubmit` call.
    pub cpu_submit_ms: f64,
    /// Wall time from the start of recording to the frame's fence signalling.
    pub frame_ms: f64,
    /// GPU time between the frame's first and last timestamp (when timestamps are planned).
    pub gpu_ms: Option<f64>,
    /// GPU time of each planned pass, in plan order (when timestamps are planned).
    pub gpu_pass_ms: Vec<f64>,
    /// Fragments the scene draws shaded per eye view, over every eye pass (when fragment
    /// counting is planned; empty otherwise). Masks, composites and probes are in
    /// [`FrameStats::steps`].
    pub fragments: Vec<u64>,
    /// Fragments the MFFR far pass's scene draws shaded (when both are planned).
    pub far_fragments: Option<u64>,
    /// Every counted step's fragments, per view, in recording order (counting frames only).
    pub steps: Vec<StepFragments>,
    /// CPU time splitting the instances into the MFFR near and far sets (0 without MFFR).
    pub cpu_cull_ms: f64,
    /// Instances drawn by each scene pass, in plan order (every instance without culling).
    pub instances_drawn: Vec<u64>,
    /// Draw commands the frame recorded (scene draws, masks, composites).
    pub draw_calls: u64,
    /// Triangles those draw commands submitted (per draw: triangles × instances).
    pub triangles: u64,
    /// Of those, the triangles each pass submitted, in plan order.
    pub pass_triangles: Vec<u64>,
    /// Primitives and fragment-shader invocations each pass's pipelines processed, measured by
    /// pipeline-statistics queries (counting frames on devices that have them; empty
    /// otherwise), in plan order.
    pub pass_statistics: Vec<PassStatistics>,
}

/// A pass's work as pipeline-statistics queries measure it, summed over its views. Lavapipe
/// runs a multiview pass's views one after another and counts each view's primitives; a tile
/// GPU may count a multiview draw once. Full-view passes count their one triangle per view.
#[derive(Clone, Copy, Debug, Default, PartialEq, Eq)]
pub struct PassStatistics {
    /// Primitives input assembly produced.
    pub assembled: u64,
    /// Primitives that reached the clipper.
    pub clipped_in: u64,
    /// Primitives the clipper passed on to rasterisation (culled and degenerate ones gone).
    pub rasterised: u64,
    /// Fragment shader invocations as the driver counts them: helper invocations may or may
    /// not count, and lavapipe 22.3 counts whole raster blocks, so the exact per-view figures
    /// are the counting frame's atomics ([`FrameStats::steps`]).
    pub fragment_invocations: u64,
}

/// The pipeline statistics counting frames query, in the order Vulkan returns them.
const PASS_STATISTICS: vk::QueryPipelineStatisticFlags = vk::QueryPipelineStatisticFlags::from_raw(
    vk::QueryPipelineStatisticFlags::INPUT_ASSEMBLY_PRIMITIVES.as_raw()
        | vk::QueryPipelineStatisticFlags::CLIPPING_INVOCATIONS.as_raw()
        | vk::QueryPipelineStatisticFlags::CLIPPING_PRIMITIVES.as_raw()
        | vk::QueryPipelineStatisticFlags::FRAGMENT_SHADER_INVOCATIONS.as_raw(),
);

/// Fragments one step of a pass shaded, measured by the counting frame's atomics.
#[derive(Clone, Debug, PartialEq)]
pub struct StepFragments {
    /// The pass's name, as the plan prints it.
    pub pass: &'static str,
    pub step: CountedStep,
    /// Per view: views 0–3, then the MFFR far view.
    pub views: [u64; COUNTER_SLOTS_PER_STEP as usize],
}

impl StepFragments {
    pub fn total(&self) -> u64 {
        self.views.iter().sum()
    }
}

impl FrameStats {
    /// Fragments every counted step shaded: the frame's whole fragment work.
    pub fn total_fragments(&self) -> u64 {
        self.steps.iter().map(StepFragments::total).sum()
    }

    /// Fragments the scene draws shaded, eye views and MFFR far view together.
    pub fn scene_fragments(&self) -> u64 {
        self.fragments_of(CountedStep::Scene)
    }

    /// Fragments the steps of one kind shaded, over passes and views.
    pub fn fragments_of(&self, step: CountedStep) -> u64 {
        self.per_view(step).iter().sum()
    }

    /// Fragments the steps of one kind shaded per view (0–3, then the far view), over passes.
    pub fn per_view(&self, step: CountedStep) -> [u64; COUNTER_SLOTS_PER_STEP as usize] {
        let mut views = [0; COUNTER_SLOTS_PER_STEP as usize];
        for s in self.steps.iter().filter(|s| s.step == step) {
            for (sum, n) in views.iter_mut().zip(s.views) {
                *sum += n;
            }
        }
        views
    }
}

/// Draw commands and triangles recorded into the current frame.
#[derive(Clone, Copy, Debug, Default)]
pub(super) struct DrawTally {
    pub calls: u64,
    pub triangles: u64,
}

/// The two eyes' images of the last frame.
#[derive(Clone, Debug, PartialEq)]
pub struct StereoImage {
    pub left: RgbaImage,
    pub right: RgbaImage,
}

impl StereoImage {
    pub fn eye(&self, eye: Eye) -> &RgbaImage {
        match eye {
            Eye::Left => &self.left,
            Eye::Right => &self.right,
        }
    }

    /// Left, right.
    pub fn eyes(&self) -> [&RgbaImage; 2] {
        [&self.left, &self.right]
    }

    pub fn side_by_side(&self) -> RgbaImage {
        RgbaImage::side_by_side(&self.left, &self.right)
    }
}

/// A [`FramePlan`] compiled into Vulkan objects for one scene.
///
/// Frames are rendered one at a time (the CPU waits for each frame's fence), so everything a
/// recorded command buffer uses is alive and idle whenever the renderer is touched again.
pub struct Renderer<'g> {
    pub(super) gpu: &'g Gpu,
    pub(super) plan: FramePlan,
    // Passes (framebuffers, views) go before the images they view.
    /// Each pass compiled, with one pipeline per step of the plan's, in step order.
    pub(super) passes: Vec<(CompiledPass, Vec<Arc<Pipeline>>)>,
    /// The output stage (a foveated frame's composition, lens distortion), when planned.
    pub(super) output: Option<OutputStage>,
    /// The MFFR far composite, when planned.
    pub(super) far_composite: Option<FarComposite>,
    /// Radial density reconstruction, when planned.
    pub(super) reconstruction: Option<Reconstruction>,
    /// Per-frame culling and its id buffer (only when a pass draws a culled set).
    pub(super) culling: Option<FrameCulling>,
    pub(super) instance_ids: Option<Buffer>,
    images: Vec<Image>,
    pub(super) bindings: SceneBindings,
    /// A lit scene's textures, materials and lights (after the bindings that refer to them).
    _materials: Option<MaterialSet>,
    pub(super) scene: SceneBuffers,
    views_block: Buffer,
    pub(super) counter: Option<Buffer>,
    /// Stencil mask shapes (only when a pass has masks), rewritten each frame from the gaze.
    masks: Option<Buffer>,
    pub(super) queries: Option<QueryPool>,
    /// Pipeline-statistics queries, one per pass (counting frames on devices that have them).
    pub(super) statistics: Option<QueryPool>,
    readback: Option<Buffer>,
    cmd: vk::CommandBuffer,
    frame_pool: CommandPool,
    fence: Fence,
    light_dir: Vec4,
    /// Each eye's gaze, normalised (−1…1, x right, y up); moves the fovea views.
    gaze: [Vec2; 2],
    frames_rendered: u64,
}

impl<'g> Renderer<'g> {
    /// Builds everything `plan` calls for, and nothing else: no counter buffer without fragment
    /// counting, no query pool without timestamps, no MSAA images at 1×.
    pub fn new(gpu: &'g Gpu, plan: &FramePlan, scene: &Scene) -> Result<Self, GpuError> {
        if scene.instance_count() != plan.scene_instances {
            return Err(crate::vocab::ConfigError::new(
                "scene",
                format!("{} instances", scene.instance_count()),
                format!(
                    "the scene the plan was made for ({} instances): plan the frame for this scene",
                    plan.scene_instances
                ),
            )
            .into());
        }
        if scene.shading() == Shading::Lit && !plan.lit
            || scene.shading() == Shading::Flat && plan.lit
        {
            return Err(crate::vocab::ConfigError::new(
                "scene",
                format!("{} shading", scene.shading()),
                "the shading the plan was made for: plan the frame for this scene",
            )
            .into());
        }
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
        let counter = plan
            .fragment_counter()
            .map(|b| {
                Buffer::new(
                    gpu,
                    b.name,
                    b.bytes,
                    vk::BufferUsageFlags::STORAGE_BUFFER | vk::BufferUsageFlags::TRANSFER_DST,
                    MemoryLocation::GpuToCpu,
                )
            })
            .transpose()?;
        let masks = plan
            .passes
            .iter()
            .any(PassPlan::has_masks)
            .then(|| {
                let bytes = std::mem::size_of::<[Vec4; 8]>() as u64;
                Buffer::new(
                    gpu,
                    "stencil masks",
                    bytes,
                    vk::BufferUsageFlags::UNIFORM_BUFFER,
                    MemoryLocation::CpuToGpu,
                )
            })
            .transpose()?;
        let instance_ids = plan
            .instance_ids()
            .map(|b| {
                Buffer::new(
                    gpu,
                    b.name,
                    b.bytes,
                    vk::BufferUsageFlags::STORAGE_BUFFER,
                    MemoryLocation::CpuToGpu,
                )
            })
            .transpose()?;
        let bindings = SceneBindings::new(
            gpu,
            &views_block,
            &scene_buffers.instances,
            counter.as_ref(),
            masks.as_ref(),
            instance_ids.as_ref(),
            materials.as_ref(),
        )?;
        let images = create_images(gpu, plan)?;
        let output = plan
            .passes
            .iter()
            .find(|p| p.kind == PassKind::Output)
            .map(|p| {
                // Two images always: the shader declares both (a one-image source twice).
                let first = &images[p.samples[0]];
                let second = &images[p.samples[p.samples.len() - 1]];
                OutputStage::new(gpu, &[first, second], counter.as_ref())
            })
            .transpose()?;
        let reconstruction = plan
            .passes
            .iter()
            .find(|p| p.steps.contains(&Step::Reconstruct))
            .map(|p| Reconstruction::new(gpu, &images[p.samples[0]], counter.as_ref()))
            .transpose()?;
        let far_composite = plan
            .far_pass()
            .map(|p| {
                let far_image = &images[p.resolve.unwrap_or(p.color).attachment];
                FarComposite::new(gpu, far_image, counter.as_ref())
            })
            .transpose()?;
        let mut passes = Vec::with_capacity(plan.passes.len());
        for (i, p) in plan.passes.iter().enumerate() {
            let compiled = compile_pass(gpu, plan, i, &images)?;
            // Each step's pipeline, with the layout of the resources it reads: the composites
            // their sampled sets, everything else the scene's bindings.
            let samples = plan.attachments[p.color.attachment].samples;
            let pipelines = p
                .steps
                .iter()
                .zip(&p.pipelines)
                .map(|(step, desc)| {
                    let set = match step {
                        Step::Output(_) => output.as_ref().map(|c| &c.set),
                        Step::FarComposite { .. } => far_composite.as_ref().map(|f| &f.set),
                        Step::Reconstruct => reconstruction.as_ref().map(|r| &r.set),
                        _ => None,
                    };
                    let (layout, description) = match set {
                        Some(set) => (&set.layout, &set.layout_description),
                        None => (&bindings.layout, &bindings.layout_description),
                    };
                    compile_pipeline(gpu, desc, samples, &compiled, layout, description)
                })
                .collect::<Result<Vec<_>, _>>()?;
            passes.push((compiled, pipelines));
        }
        let queries = (plan.timestamp_queries > 0)
            .then(|| {
                let info = vk::QueryPoolCreateInfo::default()
                    .query_type(vk::QueryType::TIMESTAMP)
                    .query_count(plan.timestamp_pool_slots());
                unsafe { gpu.device().create_query_pool(&info, None) }
                    .vk("vkCreateQueryPool")
                    .map(|raw| QueryPool::from_raw(&gpu.dev, raw))
            })
            .transpose()?;
        let statistics = (plan.statistics_queries > 0)
            .then(|| {
                let info = vk::QueryPoolCreateInfo::default()
                    .query_type(vk::QueryType::PIPELINE_STATISTICS)
                    .query_count(plan.statistics_pool_slots())
                    .pipeline_statistics(PASS_STATISTICS);
                unsafe { gpu.device().create_query_pool(&info, None) }
                    .vk("vkCreateQueryPool")
                    .map(|raw| QueryPool::from_raw(&gpu.dev, raw))
            })
            .transpose()?;
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
            output,
            far_composite,
            reconstruction,
            culling: instance_ids
                .is_some()
                .then(|| FrameCulling::new(scene, &scene_buffers.draws, plan)),
            instance_ids,
            images,
            bindings,
            _materials: materials,
            scene: scene_buffers,
            views_block,
            counter,
            masks,
            queries,
            statistics,
            readback: None,
            cmd,
            frame_pool,
            fence: gpu.fence()?,
            light_dir: scene.light_dir.extend(0.0),
            gaze: [Vec2::ZERO; 2],
            frames_rendered: 0,
        })
    }

    pub fn plan(&self) -> &FramePlan {
        &self.plan
    }

    /// Sets each eye's gaze (normalised −1…1, x right, y up) for the following frames. Filter
    /// raw tracker samples first ([`crate::foveation::GazeFilter`]).
    pub fn set_gaze(&mut self, gaze: [Vec2; 2]) {
        self.gaze = gaze;
    }

    /// Each eye's gaze for the next frame.
    pub fn gaze(&self) -> [Vec2; 2] {
        self.gaze
    }

    /// Renders one frame with the head at `world_from_head` and waits for it.
    pub fn render_frame(&mut self, world_from_head: Mat4) -> Result<FrameStats, GpuError> {
        let plan = &self.plan;
        // Every view (pose, field of view): the eyes, then the fovea windows around the gaze.
        let world_from_eye = Eye::BOTH.map(|e| world_from_head * plan.eyes.head_from_eye(e));
        let mut views: Vec<(Mat4, FovTangents)> = Eye::BOTH
            .iter()
            .map(|&e| (world_from_eye[e.index()], plan.eyes.fov(e)))
            .collect();
        let fovea = plan.foveation.map(|g| {
            let screen = (plan.eye_resolution.width, plan.eye_resolution.height);
            fovea_views(&plan.eyes, g.ratio, self.gaze, screen)
        });
        if let Some(fovea) = &fovea {
            views.extend(Eye::BOTH.map(|e| (world_from_eye[e.index()], fovea[e.index()])));
        }
        // With MFFR the eye views end at the split.
        let eye_far = plan.mffr.map_or(plan.far, |m| m.split_m);
        let mut view_proj = [Mat4::IDENTITY; MAX_VIEWS as usize + 1];
        let mut eye_pos = [Vec4::ZERO; MAX_VIEWS as usize + 1];
        let (mut ray_dx, mut ray_dy) = ([Vec4::ZERO; 5], [Vec4::ZERO; 5]);
        let view_pixels = plan.foveation.map_or(plan.eye_resolution, |f| f.view);
        for (i, &(world_from_view, fov)) in views.iter().enumerate() {
            view_proj[i] =
                reverse_z_projection(fov, plan.near, eye_far) * world_from_view.inverse();
            eye_pos[i] = world_from_view.w_axis;
            (ray_dx[i], ray_dy[i]) = ray_steps(
                world_from_view,
                fov,
                (view_pixels.width, view_pixels.height),
            );
        }
        if let Some(masks) = &mut self.masks {
            masks.write(&super::masks::stencil_shapes(plan, fovea.as_ref()));
        }
        if let Some(output) = &mut self.output {
            output.update(plan, fovea.as_ref());
        }
        let mut light_dir = self.light_dir;
        let mut far_frustum = None;
        if let Some(m) = &plan.mffr {
            let world_from_far =
                world_from_head * m.head_from_far(&plan.eyes, self.frames_rendered);
            let far_view_proj =
                reverse_z_projection(m.far_fov, m.far_near, m.far) * world_from_far.inverse();
            view_proj[FAR_VIEW_INDEX as usize] = far_view_proj;
            eye_pos[FAR_VIEW_INDEX as usize] = world_from_far.w_axis;
            let far = FAR_VIEW_INDEX as usize;
            (ray_dx[far], ray_dy[far]) = ray_steps(
                world_from_far,
                m.far_fov,
                (m.resolution.width, m.resolution.height),
            );
            light_dir.w = m.far_near;
            if let Some(far) = &mut self.far_composite {
                far.update(&views, far_view_proj, m.far_near);
            }
            far_frustum = Some(Frustum::from_eye(
                world_from_far,
                m.far_fov,
                m.far_near,
                m.far,
            ));
        }
        let mut cpu_cull_ms = 0.0;
        if let (Some(culling), Some(ids)) = (&mut self.culling, &mut self.instance_ids) {
            let start = Instant::now();
            culling.cull(
                plan,
                world_from_head,
                self.frames_rendered,
                far_frustum.as_ref(),
                fovea.as_ref(),
                &self.scene.draws,
            );
            ids.write(&culling.ids);
            cpu_cull_ms = start.elapsed().as_secs_f64() * 1e3;
        }
        self.views_block.write(&[ViewsBlock {
            view_proj,
            light_dir,
            eye_pos,
            ray_dx,
            ray_dy,
        }]);

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
            let mut recorder = VulkanRecorder::new(self, self.cmd);
            record_frame(&self.plan, &draws, &mut recorder);
            (recorder.tally, recorder.pass_ends)
        };
        unsafe { device.end_command_buffer(self.cmd) }.vk("vkEndCommandBuffer")?;
        let recorded = Instant::now();
        self.gpu.submit(self.cmd, &self.fence)?;
        let submitted = Instant::now();
        self.gpu.wait(&self.fence)?;
        let done = Instant::now();
        self.frames_rendered += 1;

        let ms = |a: Instant, b: Instant| (b - a).as_secs_f64() * 1e3;
        let (gpu_ms, gpu_pass_ms) = self.read_gpu_times()?;
        let steps = self.read_fragment_counts();
        let pass_statistics = self.read_pass_statistics()?;
        let instances_drawn = self
            .plan
            .passes
            .iter()
            .flat_map(|p| &p.steps)
            .filter_map(|s| match *s {
                Step::Scene { cull_slot, .. } => Some(
                    self.draws(cull_slot)
                        .iter()
                        .map(|d| d.instance_count as u64)
                        .sum(),
                ),
                _ => None,
            })
            .collect();
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
            let scene = stats.per_view(CountedStep::Scene);
            stats.fragments = scene[..self.plan.views as usize].to_vec();
            stats.far_fragments = self
                .plan
                .mffr
                .is_some()
                .then_some(scene[FAR_VIEW_INDEX as usize]);
        }
        Ok(stats)
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

    /// Copies the last frame's stereo image back to the CPU.
    pub fn readback(&mut self) -> Result<StereoImage, GpuError> {
        if self.frames_rendered == 0 {
            return Err(GpuError::NoFrameRendered);
        }
        let outputs = self.plan.outputs();
        let size: u64 = outputs
            .iter()
            .map(|&i| self.plan.attachments[i].bytes())
            .sum();
        if self.readback.as_ref().is_none_or(|b| b.size < size) {
            self.readback = Some(Buffer::new(
                self.gpu,
                "readback",
                size,
                vk::BufferUsageFlags::TRANSFER_DST,
                MemoryLocation::GpuToCpu,
            )?);
        }
        let buffer = self.readback.as_mut().expect("created above");
        // Every layer of every output, one after the other.
        let mut copies = Vec::new();
        let mut offset = 0;
        for &id in &outputs {
            let a = &self.plan.attachments[id];
            let region = vk::BufferImageCopy::default()
                .buffer_offset(offset)
                .image_subresource(vk::ImageSubresourceLayers {
                    aspect_mask: vk::ImageAspectFlags::COLOR,
                    mip_level: 0,
                    base_array_layer: 0,
                    layer_count: a.layers,
                })
                .image_extent(vk::Extent3D {
                    width: a.width,
                    height: a.height,
                    depth: 1,
                });
            copies.push((self.images[id].raw, region));
            offset += a.bytes();
        }
        let device = self.gpu.device();
        let buffer_raw = buffer.raw;
        self.gpu.one_shot(|cmd| unsafe {
            for (image, region) in &copies {
                // The outputs' render passes left them in TRANSFER_SRC_OPTIMAL.
                device.cmd_copy_image_to_buffer(
                    cmd,
                    *image,
                    vk::ImageLayout::TRANSFER_SRC_OPTIMAL,
                    buffer_raw,
                    &[*region],
                );
            }
            memory_barrier(
                device,
                cmd,
                (
                    vk::PipelineStageFlags::TRANSFER,
                    vk::AccessFlags::TRANSFER_WRITE,
                ),
                (vk::PipelineStageFlags::HOST, vk::AccessFlags::HOST_READ),
            );
        })?;
        let bytes = &buffer.mapped()[..size as usize];
        let first = &self.plan.attachments[outputs[0]];
        let (w, h) = (first.width, first.height);
        let mut slices = bytes
            .chunks_exact((w * h * 4) as usize)
            .map(|data| RgbaImage {
                width: w,
                height: h,
                data: data.to_vec(),
            });
        let mut next = || slices.next().expect("two eyes' worth of layers");
        Ok(match self.plan.output_layout() {
            TargetLayout::Layered | TargetLayout::PerEye => StereoImage {
                left: next(),
                right: next(),
            },
            TargetLayout::SideBySide => {
                let both = next();
                StereoImage {
                    left: both.crop(0, 0, w / 2, h),
                    right: both.crop(w / 2, 0, w / 2, h),
                }
            }
        })
    }

    /// The last frame's eye images where they lie (left, right) for a swapchain to show
    /// ([`crate::gpu::Swapchain::present`]); the outputs stay in `TRANSFER_SRC_OPTIMAL`.
    pub fn present_sources(&self) -> Result<[BlitSource; 2], GpuError> {
        if self.frames_rendered == 0 {
            return Err(GpuError::NoFrameRendered);
        }
        let outputs = self.plan.outputs();
        let first = &self.plan.attachments[outputs[0]];
        let source = |id: AttachmentId, layer, x, width| BlitSource {
            image: self.images[id].raw,
            layer,
            x,
            width,
            height: first.height,
        };
        let w = first.width;
        Ok(match self.plan.output_layout() {
            TargetLayout::Layered => [source(outputs[0], 0, 0, w), source(outputs[0], 1, 0, w)],
            TargetLayout::PerEye => [source(outputs[0], 0, 0, w), source(outputs[1], 0, 0, w)],
            TargetLayout::SideBySide => [
                source(outputs[0], 0, 0, w / 2),
                source(outputs[0], 0, w / 2, w / 2),
            ],
        })
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
    renderer.set_gaze(gaze);
    renderer.render_frame(world_from_head)
}
