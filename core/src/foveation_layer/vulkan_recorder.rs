//! The Vulkan [`Recorder`]: the frame's commands into a command buffer, with the objects the
//! renderer compiled from the plan ([`FrameObjects`]), tallying what it draws.

use std::sync::Arc;

use ash::vk;

use super::recorder::{Recorder, Rect};
use super::stats::DrawTally;
use super::targets::CompiledPass;
use crate::gpu::{memory_barrier, Pipeline};
use crate::plan::{Barrier, ClearValue};

/// A step as recorded: its pipeline, and the layout and descriptor sets it binds (the scene's
/// bindings, or its technique's sampled set): one set per frame slot. An engine's scene step
/// has no pipeline of foveate's: the engine binds its own.
pub(super) struct BoundStep {
    pub pipeline: Option<Arc<Pipeline>>,
    pub layout: vk::PipelineLayout,
    /// Per frame slot, the set even and odd frames bind.
    pub sets: Vec<[vk::DescriptorSet; 2]>,
}

/// Everything a frame's commands use, borrowed from the renderer that owns it.
pub(super) struct FrameObjects<'r, 's> {
    pub device: &'r ash::Device,
    pub passes: &'r [CompiledPass],
    /// Passes replacing the plan's: those compiled for this frame's output image (an OpenXR
    /// swapchain's image: see `OutputTargets`), then on odd frames those with the history
    /// pairs swapped; searched in order, the first that has a pass decides.
    pub retargeted: [&'r [(usize, CompiledPass)]; 3],
    /// Each pass's steps, in plan order.
    pub steps: &'r [Vec<BoundStep>],
    /// The frame slot recorded: whose descriptor sets the steps bind.
    pub slot: usize,
    /// The frame's parity (0 even, 1 odd): which of a step's sets for its slot it binds.
    pub parity: usize,
    pub timestamps: Option<vk::QueryPool>,
    pub statistics: Option<vk::QueryPool>,
    pub counter: Option<vk::Buffer>,
    pub scene: SceneSteps<'s>,
}

/// Where one mesh lives in a scene's shared vertex and index buffers.
#[derive(Clone, Copy, Debug)]
pub(crate) struct MeshRange {
    pub first_index: u32,
    pub index_count: u32,
    pub vertex_offset: i32,
}

/// A scene's geometry as the layer draws its meshes: one vertex buffer, one `u32` index
/// buffer, and the ranges a draw's `mesh` names.
#[derive(Clone, Copy)]
pub(crate) struct SceneGeometry<'r> {
    pub vertices: vk::Buffer,
    pub indices: vk::Buffer,
    pub meshes: &'r [MeshRange],
}

/// Who draws the frame's scene steps.
pub(crate) enum SceneSteps<'r> {
    /// foveate's scene renderer, whose draws the layer records from its geometry.
    Foveate(SceneGeometry<'r>),
    /// The engine, called with the command buffer and the pass's index at each scene step,
    /// inside the pass.
    Engine(&'r mut dyn FnMut(vk::CommandBuffer, usize)),
}

impl SceneSteps<'_> {
    fn geometry(&self) -> &SceneGeometry<'_> {
        match self {
            SceneSteps::Foveate(geometry) => geometry,
            SceneSteps::Engine(_) => {
                unreachable!("record_frame draws no mesh of an engine's frame")
            }
        }
    }
}

/// Records into a Vulkan command buffer with a renderer's objects, tallying what it draws.
pub(super) struct VulkanRecorder<'r, 's> {
    pub objects: FrameObjects<'r, 's>,
    pub cmd: vk::CommandBuffer,
    pub tally: DrawTally,
    /// The running triangle tally at the end of each pass.
    pub pass_ends: Vec<u64>,
    /// The layout the current step's resources were bound with (for push constants).
    layout: vk::PipelineLayout,
}

impl<'r, 's> VulkanRecorder<'r, 's> {
    pub fn new(objects: FrameObjects<'r, 's>, cmd: vk::CommandBuffer) -> Self {
        Self {
            objects,
            cmd,
            tally: DrawTally::default(),
            pass_ends: Vec::new(),
            layout: vk::PipelineLayout::null(),
        }
    }

    fn device(&self) -> &ash::Device {
        self.objects.device
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
impl Recorder for VulkanRecorder<'_, '_> {
    fn reset_queries(&mut self, count: u32) {
        if let Some(q) = self.objects.timestamps {
            unsafe { self.device().cmd_reset_query_pool(self.cmd, q, 0, count) };
        }
    }

    fn timestamp(&mut self, index: u32) {
        if let Some(q) = self.objects.timestamps {
            let stage = if index == 0 {
                vk::PipelineStageFlags::TOP_OF_PIPE
            } else {
                vk::PipelineStageFlags::BOTTOM_OF_PIPE
            };
            unsafe { self.device().cmd_write_timestamp(self.cmd, stage, q, index) };
        }
    }

    fn clear_counters(&mut self, statistics: u32) {
        if let Some(q) = self.objects.statistics {
            unsafe {
                self.device()
                    .cmd_reset_query_pool(self.cmd, q, 0, statistics)
            };
        }
        if let Some(counter) = self.objects.counter {
            unsafe {
                self.device()
                    .cmd_fill_buffer(self.cmd, counter, 0, vk::WHOLE_SIZE, 0)
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
        if let Some(q) = self.objects.statistics {
            unsafe {
                self.device().cmd_begin_query(
                    self.cmd,
                    q,
                    pass as u32,
                    vk::QueryControlFlags::empty(),
                )
            };
        }
    }

    fn end_statistics(&mut self, pass: usize) {
        if let Some(q) = self.objects.statistics {
            unsafe { self.device().cmd_end_query(self.cmd, q, pass as u32) };
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
        let objects = &self.objects;
        let compiled = objects
            .retargeted
            .iter()
            .flat_map(|list| list.iter())
            .find(|(i, _)| *i == pass)
            .map_or(&objects.passes[pass], |(_, c)| c);
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
        let bound = &self.objects.steps[pass][step];
        self.layout = bound.layout;
        let Some(pipeline) = &bound.pipeline else {
            return; // the engine's step: it binds its own
        };
        unsafe {
            let device = self.device();
            device.cmd_bind_pipeline(self.cmd, vk::PipelineBindPoint::GRAPHICS, pipeline.raw);
            device.cmd_bind_descriptor_sets(
                self.cmd,
                vk::PipelineBindPoint::GRAPHICS,
                bound.layout,
                0,
                &[bound.sets[self.objects.slot][self.objects.parity]],
                &[],
            );
        }
    }

    fn bind_geometry(&mut self) {
        let scene = *self.objects.scene.geometry();
        unsafe {
            let device = self.device();
            device.cmd_bind_vertex_buffers(self.cmd, 0, &[scene.vertices], &[0]);
            device.cmd_bind_index_buffer(self.cmd, scene.indices, 0, vk::IndexType::UINT32);
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
        let m = self.objects.scene.geometry().meshes[mesh];
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

    fn engine_draws(&mut self, pass: usize, _step: usize) {
        if let SceneSteps::Engine(draw) = &mut self.objects.scene {
            draw(self.cmd, pass);
        }
    }
}
