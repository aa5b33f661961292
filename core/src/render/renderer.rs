use std::time::Instant;

use ash::vk;
use glam::{Mat4, Vec2, Vec4};

use super::composite::Composite;
use super::pipelines::{pass_pipeline, PipelineKind, SceneBindings};
use super::record::memory_barrier;
use super::scene_buffers::SceneBuffers;
use super::targets::{compile_pass, create_images, CompiledPass};
use crate::foveation::{fovea_views, mask_shapes};
use crate::gpu::{
    Buffer, CommandPool, Fence, Gpu, GpuError, Image, MemoryLocation, Pipeline, QueryPool,
    VkResultExt,
};
use crate::metrics::RgbaImage;
use crate::plan::{FramePlan, PassKind, TargetLayout, MAX_VIEWS};
use crate::scene::Scene;
use crate::view::reverse_z_projection;
use crate::view::Eye;

/// The per-frame uniform block (`Views` in the shaders, std140).
#[repr(C)]
#[derive(Clone, Copy)]
struct ViewsBlock {
    view_proj: [Mat4; MAX_VIEWS as usize],
    light_dir: Vec4,
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
    /// Fragments shaded per view (when fragment counting is planned; empty otherwise).
    pub fragments: Vec<u64>,
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

    pub fn side_by_side(&self) -> RgbaImage {
        RgbaImage::side_by_side(&self.left, &self.right)
    }
}

/// The pipelines of one planned pass: mask and coverage pipelines exist only when the pass has
/// masks or a coverage probe.
pub(super) struct PassPipelines {
    /// `None` for a composite pass (its pipeline lives in [`Composite`]).
    pub scene: Option<Pipeline>,
    pub mask: Option<Pipeline>,
    pub coverage: Option<Pipeline>,
}

/// A [`FramePlan`] compiled into Vulkan objects for one scene.
///
/// Frames are rendered one at a time (the CPU waits for each frame's fence), so everything a
/// recorded command buffer uses is alive and idle whenever the renderer is touched again.
pub struct Renderer<'g> {
    pub(super) gpu: &'g Gpu,
    pub(super) plan: FramePlan,
    // Passes (framebuffers, views) go before the images they view.
    pub(super) passes: Vec<(CompiledPass, PassPipelines)>,
    /// Composition of a foveated frame, when planned.
    pub(super) composite: Option<Composite>,
    images: Vec<Image>,
    pub(super) bindings: SceneBindings,
    pub(super) scene: SceneBuffers,
    views_block: Buffer,
    pub(super) counter: Option<Buffer>,
    /// Stencil mask shapes (only when a pass has masks), rewritten each frame from the gaze.
    masks: Option<Buffer>,
    pub(super) queries: Option<QueryPool>,
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
        let scene_buffers = SceneBuffers::upload(gpu, scene)?;
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
            .any(|p| p.stencil_masks)
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
        let bindings = SceneBindings::new(
            gpu,
            &views_block,
            &scene_buffers.instances,
            counter.as_ref(),
            masks.as_ref(),
        )?;
        let images = create_images(gpu, plan)?;
        let mut composite = None;
        let mut passes = Vec::with_capacity(plan.passes.len());
        for (i, p) in plan.passes.iter().enumerate() {
            let compiled = compile_pass(gpu, plan, i, &images)?;
            let pipeline = |kind| {
                pass_pipeline(
                    gpu,
                    plan,
                    p,
                    kind,
                    compiled.render_pass.raw,
                    &bindings.layout,
                )
            };
            let pipelines = match p.kind {
                PassKind::Scene => PassPipelines {
                    scene: Some(pipeline(PipelineKind::Scene)?),
                    mask: p
                        .stencil_masks
                        .then(|| pipeline(PipelineKind::Mask))
                        .transpose()?,
                    coverage: p
                        .coverage_probe
                        .then(|| pipeline(PipelineKind::Coverage))
                        .transpose()?,
                },
                PassKind::Composite => {
                    let views = &images[p.samples[0]];
                    composite = Some(Composite::new(
                        gpu,
                        plan,
                        p,
                        compiled.render_pass.raw,
                        views,
                    )?);
                    PassPipelines {
                        scene: None,
                        mask: None,
                        coverage: None,
                    }
                }
            };
            passes.push((compiled, pipelines));
        }
        let queries = (plan.timestamp_queries > 0)
            .then(|| {
                let info = vk::QueryPoolCreateInfo::default()
                    .query_type(vk::QueryType::TIMESTAMP)
                    .query_count(plan.timestamp_queries);
                unsafe { gpu.device().create_query_pool(&info, None) }
                    .vk("vkCreateQueryPool")
                    .map(|raw| QueryPool::from_raw(&gpu.dev, raw))
            })
            .transpose()?;
        let frame_pool = gpu.command_pool(vk::CommandPoolCreateFlags::TRANSIENT)?;
        let cmd = gpu.allocate_command_buffer(&frame_pool)?;
        Ok(Renderer {
            gpu,
            plan: plan.clone(),
            passes,
            composite,
            images,
            bindings,
            scene: scene_buffers,
            views_block,
            counter,
            masks,
            queries,
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

    /// Renders one frame with the head at `world_from_head` and waits for it.
    pub fn render_frame(&mut self, world_from_head: Mat4) -> Result<FrameStats, GpuError> {
        let plan = &self.plan;
        let mut view_proj = [Mat4::IDENTITY; MAX_VIEWS as usize];
        for eye in Eye::BOTH {
            view_proj[eye.index()] = plan.eyes.projection(eye, plan.near, plan.far)
                * plan.eyes.view(eye, world_from_head);
        }
        if let Some(g) = &plan.foveation {
            // Views 2 and 3: each eye's fovea window around its gaze, from the same eye centre.
            let screen = (plan.eye_resolution.width, plan.eye_resolution.height);
            let fovea = fovea_views(&plan.eyes, g.ratio, self.gaze, screen);
            for eye in Eye::BOTH {
                view_proj[2 + eye.index()] =
                    reverse_z_projection(fovea[eye.index()], plan.near, plan.far)
                        * plan.eyes.view(eye, world_from_head);
            }
            if let Some(masks) = &mut self.masks {
                masks.write(&mask_shapes(g, &plan.eyes, &fovea));
            }
            if let Some(composite) = &mut self.composite {
                composite.update(plan, &fovea);
            }
        }
        self.views_block.write(&[ViewsBlock {
            view_proj,
            light_dir: self.light_dir,
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
        self.record(self.cmd);
        unsafe { device.end_command_buffer(self.cmd) }.vk("vkEndCommandBuffer")?;
        let recorded = Instant::now();
        self.gpu.submit(self.cmd, &self.fence)?;
        let submitted = Instant::now();
        self.gpu.wait(&self.fence)?;
        let done = Instant::now();
        self.frames_rendered += 1;

        let ms = |a: Instant, b: Instant| (b - a).as_secs_f64() * 1e3;
        let (gpu_ms, gpu_pass_ms) = self.read_gpu_times()?;
        Ok(FrameStats {
            cpu_record_ms: ms(start, recorded),
            cpu_submit_ms: ms(recorded, submitted),
            frame_ms: ms(start, done),
            gpu_ms,
            gpu_pass_ms,
            fragments: self.read_fragment_counts(),
        })
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

    fn read_fragment_counts(&mut self) -> Vec<u64> {
        let views = self.plan.views as usize;
        self.counter
            .as_mut()
            .map(|c| c.read_u32s(views).into_iter().map(u64::from).collect())
            .unwrap_or_default()
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
        Ok(match self.plan.layout {
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

    /// How many transient attachments got lazily allocated memory (tile GPUs; 0 on lavapipe).
    pub fn lazy_attachments(&self) -> usize {
        self.images.iter().filter(|i| i.lazy).count()
    }
}
