//! Recording one frame: the plan's passes and their steps, in order, through [`Recorder`] —
//! one narrow interface, implemented by Vulkan ([`VulkanRecorder`]) and by a command log
//! (`render::CommandLog`) that tests read without a GPU. The executor decides nothing: what it
//! records follows from the plan and the frame's draws.

use ash::vk;

use super::renderer::{DrawTally, Renderer};
use crate::plan::{Barrier, ClearValue, FramePlan, PassPlan, Step};
use crate::scene::Draw;

/// A rectangle of a pass's render area: x, y, width, height in pixels.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub struct Rect {
    pub x: u32,
    pub y: u32,
    pub width: u32,
    pub height: u32,
}

/// What recording a frame does, in the renderer's own terms.
pub trait Recorder {
    /// Before the frame: reset `count` timestamp queries (the whole pool, spare slots too).
    fn reset_queries(&mut self, count: u32);
    /// A timestamp after everything recorded so far.
    fn timestamp(&mut self, index: u32);
    /// Counting frames: zero the fragment counters, visible to the fragment shaders, and reset
    /// `statistics` pipeline-statistics queries.
    fn clear_counters(&mut self, statistics: u32);
    /// Counting frames: a pipeline-statistics query around pass `pass` (outside the render
    /// pass, so a multiview pass's views land in one query).
    fn begin_statistics(&mut self, pass: usize);
    fn end_statistics(&mut self, pass: usize);
    /// Counting frames: one pass's counting atomics before the next pass's.
    fn counters_barrier(&mut self);
    /// Counting frames: the counters, visible to the host.
    fn counters_to_host(&mut self);
    /// Pass `pass` begins, clearing as `clears` says, once what it waits on is done (`wait`:
    /// the plan's barriers, which Vulkan executes as the render pass's external dependency).
    fn begin_pass(&mut self, pass: usize, clears: &[ClearValue], wait: &[Barrier]);
    /// Pass `pass` ends; later work that touches its images waits for it as `signal` says.
    fn end_pass(&mut self, pass: usize, signal: &[Barrier]);
    /// Step `step` of pass `pass`: its pipeline and the resources it reads.
    fn bind_step(&mut self, pass: usize, step: usize);
    /// The scene's vertex and index buffers.
    fn bind_geometry(&mut self);
    /// Viewport `guard_band` times larger than `area`, centred on it, scissored to it.
    fn set_viewport(&mut self, area: Rect, guard_band: u32);
    /// The vertex stage's push constant: the view index or the mask fans' shape set.
    fn push_vertex(&mut self, value: u32);
    /// The fragment stage's push constant (the far composite's view in a single-eye pass).
    fn push_fragment(&mut self, value: u32);
    fn stencil_reference(&mut self, reference: u32);
    /// `vertices` generated vertices (full-view triangles, mask fans).
    fn draw(&mut self, vertices: u32);
    /// Mesh `mesh` for `instance_count` instances from `first_instance`.
    fn draw_indexed(&mut self, mesh: usize, instance_count: u32, first_instance: u32);
}

/// What one frame draws: every instance, and each cull slot's culled draws.
pub struct FrameDraws<'a> {
    pub all: &'a [Draw],
    pub culled: &'a [Vec<Draw>],
}

impl FrameDraws<'_> {
    fn of(&self, cull_slot: Option<usize>) -> &[Draw] {
        cull_slot.map_or(self.all, |slot| &self.culled[slot])
    }
}

/// Records the frame `plan` describes into `rec`.
pub fn record_frame(plan: &FramePlan, draws: &FrameDraws, rec: &mut dyn Recorder) {
    let timestamps = plan.timestamp_queries > 0;
    let counting = plan.count_fragments();
    if timestamps {
        rec.reset_queries(plan.timestamp_pool_slots());
        rec.timestamp(0);
    }
    let statistics = plan.statistics_queries > 0;
    if counting {
        rec.clear_counters(plan.statistics_pool_slots());
    }
    for (index, pass) in plan.passes.iter().enumerate() {
        if statistics {
            rec.begin_statistics(index);
        }
        // One clear value per attachment, in `uses()` order (the render pass's), up to the
        // last one the plan clears: none for a pass that clears nothing.
        let uses: Vec<_> = pass.uses().collect();
        let cleared = uses
            .iter()
            .rposition(|u| u.clear.is_some())
            .map_or(0, |i| i + 1);
        let clears: Vec<ClearValue> = uses[..cleared]
            .iter()
            .map(|u| {
                u.clear.unwrap_or(ClearValue::DepthStencil {
                    depth: 0.0,
                    stencil: 0,
                })
            })
            .collect();
        rec.begin_pass(index, &clears, &pass.barriers.wait);
        let area = pass_area(plan, pass);
        for (step_index, step) in pass.steps.iter().enumerate() {
            rec.bind_step(index, step_index);
            match *step {
                Step::MaskFans { .. } => super::masks::record_mask_fans(pass, area, rec),
                Step::FarComposite { .. } => super::mffr::record_far_composite(pass, area, rec),
                Step::Scene { cull_slot, .. } => {
                    super::stereo_scene::record_scene(plan, pass, area, draws.of(cull_slot), rec)
                }
                Step::Probe { .. } => super::probe::record_probe(pass, area, rec),
                Step::Output(_) => super::output::record_output(pass, area, rec),
                Step::RadialMask { .. } => {
                    super::radial_density::record_radial_mask(pass, area, rec)
                }
                Step::Reconstruct => super::radial_density::record_reconstruction(pass, area, rec),
            }
        }
        rec.end_pass(index, &pass.barriers.signal);
        if statistics {
            rec.end_statistics(index);
        }
        if counting {
            rec.counters_barrier();
        }
        if timestamps {
            rec.timestamp(index as u32 + 1);
        }
    }
    if counting {
        rec.counters_to_host();
    }
}

/// A pass's render area: its colour attachment's extent.
fn pass_area(plan: &FramePlan, pass: &PassPlan) -> Rect {
    let a = &plan.attachments[pass.color.attachment];
    Rect {
        x: 0,
        y: 0,
        width: a.width,
        height: a.height,
    }
}

/// Records into a Vulkan command buffer with a renderer's objects, tallying what it draws.
pub(super) struct VulkanRecorder<'r> {
    pub r: &'r Renderer<'r>,
    pub cmd: vk::CommandBuffer,
    pub tally: DrawTally,
    /// The running triangle tally at the end of each pass.
    pub pass_ends: Vec<u64>,
    /// The layout the current step's resources were bound with (for push constants).
    layout: vk::PipelineLayout,
}

impl<'r> VulkanRecorder<'r> {
    pub fn new(r: &'r Renderer<'r>, cmd: vk::CommandBuffer) -> Self {
        Self {
            r,
            cmd,
            tally: DrawTally::default(),
            pass_ends: Vec::new(),
            layout: vk::PipelineLayout::null(),
        }
    }

    fn device(&self) -> &ash::Device {
        self.r.gpu.device()
    }

    fn count(&mut self, triangles: u64) {
        self.tally.calls += 1;
        self.tally.triangles += triangles;
    }

    fn barrier(
        &self,
        src: (vk::PipelineStageFlags, vk::AccessFlags),
        dst: (vk::PipelineStageFlags, vk::AccessFlags),
    ) {
        // SAFETY: recording into this renderer's command buffer.
        unsafe { memory_barrier(self.device(), self.cmd, src, dst) }
    }
}

// SAFETY (every method): the handles recorded belong to the renderer, which waits for the
// frame's fence before anything it owns can be dropped or touched again.
impl Recorder for VulkanRecorder<'_> {
    fn reset_queries(&mut self, count: u32) {
        if let Some(q) = &self.r.queries {
            unsafe {
                self.device()
                    .cmd_reset_query_pool(self.cmd, q.raw, 0, count)
            };
        }
    }

    fn timestamp(&mut self, index: u32) {
        if let Some(q) = &self.r.queries {
            let stage = if index == 0 {
                vk::PipelineStageFlags::TOP_OF_PIPE
            } else {
                vk::PipelineStageFlags::BOTTOM_OF_PIPE
            };
            unsafe {
                self.device()
                    .cmd_write_timestamp(self.cmd, stage, q.raw, index)
            };
        }
    }

    fn clear_counters(&mut self, statistics: u32) {
        if let Some(q) = &self.r.statistics {
            unsafe {
                self.device()
                    .cmd_reset_query_pool(self.cmd, q.raw, 0, statistics)
            };
        }
        if let Some(counter) = &self.r.counter {
            unsafe {
                self.device()
                    .cmd_fill_buffer(self.cmd, counter.raw, 0, vk::WHOLE_SIZE, 0)
            };
            self.barrier(
                (
                    vk::PipelineStageFlags::TRANSFER,
                    vk::AccessFlags::TRANSFER_WRITE,
                ),
                (
                    vk::PipelineStageFlags::FRAGMENT_SHADER,
                    vk::AccessFlags::SHADER_READ | vk::AccessFlags::SHADER_WRITE,
                ),
            );
        }
    }

    fn begin_statistics(&mut self, pass: usize) {
        if let Some(q) = &self.r.statistics {
            unsafe {
                self.device().cmd_begin_query(
                    self.cmd,
                    q.raw,
                    pass as u32,
                    vk::QueryControlFlags::empty(),
                )
            };
        }
    }

    fn end_statistics(&mut self, pass: usize) {
        if let Some(q) = &self.r.statistics {
            unsafe { self.device().cmd_end_query(self.cmd, q.raw, pass as u32) };
        }
    }

    fn counters_barrier(&mut self) {
        let atomics = (
            vk::PipelineStageFlags::FRAGMENT_SHADER,
            vk::AccessFlags::SHADER_READ | vk::AccessFlags::SHADER_WRITE,
        );
        self.barrier(atomics, atomics);
    }

    fn counters_to_host(&mut self) {
        self.barrier(
            (
                vk::PipelineStageFlags::FRAGMENT_SHADER,
                vk::AccessFlags::SHADER_WRITE,
            ),
            (vk::PipelineStageFlags::HOST, vk::AccessFlags::HOST_READ),
        );
    }

    // The barriers are the compiled render pass's external dependencies (`targets.rs`):
    // beginning and ending it executes them.
    fn begin_pass(&mut self, pass: usize, clears: &[ClearValue], _wait: &[Barrier]) {
        let compiled = &self.r.passes[pass].0;
        let clears: Vec<vk::ClearValue> = clears
            .iter()
            .map(|c| match *c {
                ClearValue::DepthStencil { depth, stencil } => vk::ClearValue {
                    depth_stencil: vk::ClearDepthStencilValue { depth, stencil },
                },
                ClearValue::Color(float32) => vk::ClearValue {
                    color: vk::ClearColorValue { float32 },
                },
            })
            .collect();
        let begin = vk::RenderPassBeginInfo::default()
            .render_pass(compiled.render_pass.raw)
            .framebuffer(compiled.framebuffer.raw)
            .render_area(vk::Rect2D {
                offset: vk::Offset2D::default(),
                extent: compiled.extent,
            })
            .clear_values(&clears);
        unsafe {
            self.device()
                .cmd_begin_render_pass(self.cmd, &begin, vk::SubpassContents::INLINE)
        };
    }

    fn end_pass(&mut self, _pass: usize, _signal: &[Barrier]) {
        unsafe { self.device().cmd_end_render_pass(self.cmd) };
        self.pass_ends.push(self.tally.triangles);
    }

    fn bind_step(&mut self, pass: usize, step: usize) {
        let r = self.r;
        let pipeline = &r.passes[pass].1[step];
        // The composites read their sampled sets; every other step the scene's bindings.
        let (layout, set) = match r.plan.passes[pass].steps[step] {
            Step::Output(_) => {
                let c = &r.output.as_ref().expect("planned with an output pass").set;
                (c.layout.raw, c.set)
            }
            Step::FarComposite { .. } => {
                let f = &r.far_composite.as_ref().expect("planned with MFFR").set;
                (f.layout.raw, f.set)
            }
            Step::Reconstruct => {
                let s = &r
                    .reconstruction
                    .as_ref()
                    .expect("planned with radial density")
                    .set;
                (s.layout.raw, s.set)
            }
            _ => (r.bindings.layout.raw, r.bindings.set),
        };
        self.layout = layout;
        unsafe {
            let device = self.device();
            device.cmd_bind_pipeline(self.cmd, vk::PipelineBindPoint::GRAPHICS, pipeline.raw);
            device.cmd_bind_descriptor_sets(
                self.cmd,
                vk::PipelineBindPoint::GRAPHICS,
                layout,
                0,
                &[set],
                &[],
            );
        }
    }

    fn bind_geometry(&mut self) {
        let scene = &self.r.scene;
        unsafe {
            let device = self.device();
            device.cmd_bind_vertex_buffers(self.cmd, 0, &[scene.vertices.raw], &[0]);
            device.cmd_bind_index_buffer(self.cmd, scene.indices.raw, 0, vk::IndexType::UINT32);
        }
    }

    fn set_viewport(&mut self, area: Rect, guard_band: u32) {
        let k = guard_band as f32;
        let (w, h) = (area.width as f32, area.height as f32);
        let viewport = vk::Viewport {
            x: area.x as f32 - (k - 1.0) * 0.5 * w,
            y: area.y as f32 - (k - 1.0) * 0.5 * h,
            width: k * w,
            height: k * h,
            min_depth: 0.0,
            max_depth: 1.0,
        };
        let scissor = vk::Rect2D {
            offset: vk::Offset2D {
                x: area.x as i32,
                y: area.y as i32,
            },
            extent: vk::Extent2D {
                width: area.width,
                height: area.height,
            },
        };
        unsafe {
            let device = self.device();
            device.cmd_set_viewport(self.cmd, 0, &[viewport]);
            device.cmd_set_scissor(self.cmd, 0, &[scissor]);
        }
    }

    fn push_vertex(&mut self, value: u32) {
        unsafe {
            self.device().cmd_push_constants(
                self.cmd,
                self.layout,
                vk::ShaderStageFlags::VERTEX,
                0,
                &value.to_le_bytes(),
            )
        };
    }

    fn push_fragment(&mut self, value: u32) {
        unsafe {
            self.device().cmd_push_constants(
                self.cmd,
                self.layout,
                vk::ShaderStageFlags::FRAGMENT,
                0,
                &value.to_le_bytes(),
            )
        };
    }

    fn stencil_reference(&mut self, reference: u32) {
        unsafe {
            self.device().cmd_set_stencil_reference(
                self.cmd,
                vk::StencilFaceFlags::FRONT_AND_BACK,
                reference,
            )
        };
    }

    fn draw(&mut self, vertices: u32) {
        unsafe { self.device().cmd_draw(self.cmd, vertices, 1, 0, 0) };
        self.count(vertices as u64 / 3);
    }

    fn draw_indexed(&mut self, mesh: usize, instance_count: u32, first_instance: u32) {
        let m = self.r.scene.meshes[mesh];
        unsafe {
            self.device().cmd_draw_indexed(
                self.cmd,
                m.index_count,
                instance_count,
                m.first_index,
                m.vertex_offset,
                first_instance,
            )
        };
        self.count(m.index_count as u64 / 3 * instance_count as u64);
    }
}

pub(super) unsafe fn memory_barrier(
    device: &ash::Device,
    cmd: vk::CommandBuffer,
    src: (vk::PipelineStageFlags, vk::AccessFlags),
    dst: (vk::PipelineStageFlags, vk::AccessFlags),
) {
    let barrier = [vk::MemoryBarrier::default()
        .src_access_mask(src.1)
        .dst_access_mask(dst.1)];
    device.cmd_pipeline_barrier(
        cmd,
        src.0,
        dst.0,
        vk::DependencyFlags::empty(),
        &barrier,
        &[],
        &[],
    );
}
