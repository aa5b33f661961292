//! Recording one frame: the plan's passes with the scene submitted as each pass's
//! [`Submission`] says.

use ash::vk;

use super::renderer::{DrawTally, Renderer};
use super::sampled_set::SampledSet;
use crate::gpu::Pipeline;
use crate::mffr::FAR_VIEW_INDEX;
use crate::plan::{ClearValue, PassPlan, Step, Submission};
use crate::scene::Draw;
use crate::view::Eye;

impl Renderer<'_> {
    /// Records the whole frame into `cmd` (already begun).
    pub(super) fn record(&self, cmd: vk::CommandBuffer) {
        let device = self.gpu.device();
        // SAFETY (whole function): every handle recorded belongs to this renderer, which waits
        // for the frame's fence before anything it owns can be dropped.
        unsafe {
            if let Some(q) = &self.queries {
                device.cmd_reset_query_pool(cmd, q.raw, 0, self.plan.timestamp_queries);
                device.cmd_write_timestamp(cmd, vk::PipelineStageFlags::TOP_OF_PIPE, q.raw, 0);
            }
            if let Some(counter) = &self.counter {
                device.cmd_fill_buffer(cmd, counter.raw, 0, vk::WHOLE_SIZE, 0);
                memory_barrier(
                    device,
                    cmd,
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
            for (index, (pass_plan, (pass, pipelines))) in
                self.plan.passes.iter().zip(&self.passes).enumerate()
            {
                // One clear value per attachment, in `uses()` order (the render pass's), up to
                // the last one the plan clears: none for a pass that clears nothing.
                let uses: Vec<_> = pass_plan.uses().collect();
                let cleared = uses
                    .iter()
                    .rposition(|u| u.clear.is_some())
                    .map_or(0, |i| i + 1);
                let clears: Vec<vk::ClearValue> = uses[..cleared]
                    .iter()
                    .map(|u| match u.clear {
                        Some(ClearValue::DepthStencil { depth, stencil }) => vk::ClearValue {
                            depth_stencil: vk::ClearDepthStencilValue { depth, stencil },
                        },
                        Some(ClearValue::Color(float32)) => vk::ClearValue {
                            color: vk::ClearColorValue { float32 },
                        },
                        None => vk::ClearValue::default(),
                    })
                    .collect();
                let begin = vk::RenderPassBeginInfo::default()
                    .render_pass(pass.render_pass.raw)
                    .framebuffer(pass.framebuffer.raw)
                    .render_area(vk::Rect2D {
                        offset: vk::Offset2D::default(),
                        extent: pass.extent,
                    })
                    .clear_values(&clears);
                device.cmd_begin_render_pass(cmd, &begin, vk::SubpassContents::INLINE);
                // The plan's steps in the plan's order, each with its own pipeline.
                for (step, pipeline) in pass_plan.steps.iter().zip(pipelines) {
                    match *step {
                        Step::MaskFans { .. } => {
                            self.bind_scene_set(cmd);
                            self.record_masks(cmd, pipeline, pass_plan, pass.extent);
                        }
                        Step::FarComposite { .. } => {
                            let far = self.far_composite.as_ref().expect("planned with MFFR");
                            self.record_full_view(cmd, pipeline, &far.set, pass_plan, pass.extent);
                        }
                        Step::Scene { cull_slot, .. } => {
                            self.bind_scene_set(cmd);
                            device.cmd_bind_pipeline(
                                cmd,
                                vk::PipelineBindPoint::GRAPHICS,
                                pipeline.raw,
                            );
                            device.cmd_bind_vertex_buffers(
                                cmd,
                                0,
                                &[self.scene.vertices.raw],
                                &[0],
                            );
                            device.cmd_bind_index_buffer(
                                cmd,
                                self.scene.indices.raw,
                                0,
                                vk::IndexType::UINT32,
                            );
                            self.record_submission(cmd, pass_plan, pass.extent, cull_slot);
                        }
                        Step::Probe { .. } => {
                            // Full-view triangle, counted per view under its stencil state.
                            self.bind_scene_set(cmd);
                            device.cmd_bind_pipeline(
                                cmd,
                                vk::PipelineBindPoint::GRAPHICS,
                                pipeline.raw,
                            );
                            self.full_view_draw(cmd);
                        }
                        Step::Composite => {
                            let composite =
                                self.composite.as_ref().expect("planned with foveation");
                            self.record_full_view(
                                cmd,
                                pipeline,
                                &composite.set,
                                pass_plan,
                                pass.extent,
                            );
                        }
                    }
                }
                device.cmd_end_render_pass(cmd);
                self.pass_ends.borrow_mut().push(self.tally.get().triangles);
                if self.counter.is_some() {
                    // The next pass's counting atomics follow this one's.
                    let atomics = (
                        vk::PipelineStageFlags::FRAGMENT_SHADER,
                        vk::AccessFlags::SHADER_READ | vk::AccessFlags::SHADER_WRITE,
                    );
                    memory_barrier(device, cmd, atomics, atomics);
                }
                if let Some(q) = &self.queries {
                    device.cmd_write_timestamp(
                        cmd,
                        vk::PipelineStageFlags::BOTTOM_OF_PIPE,
                        q.raw,
                        index as u32 + 1,
                    );
                }
            }
            if self.counter.is_some() {
                memory_barrier(
                    device,
                    cmd,
                    (
                        vk::PipelineStageFlags::FRAGMENT_SHADER,
                        vk::AccessFlags::SHADER_WRITE,
                    ),
                    (vk::PipelineStageFlags::HOST, vk::AccessFlags::HOST_READ),
                );
            }
        }
    }

    unsafe fn record_submission(
        &self,
        cmd: vk::CommandBuffer,
        pass: &PassPlan,
        extent: vk::Extent2D,
        cull_slot: Option<usize>,
    ) {
        let eye_width = self.plan.eye_resolution.width;
        let full = rect(0, extent.width, extent.height);
        let submission = pass.submission;
        let draws = self.draws(cull_slot);
        match submission {
            Submission::Multiview | Submission::Instanced => {
                self.set_view(cmd, full, 0, pass.guard_band);
                let doubled = submission == Submission::Instanced;
                for draw in draws {
                    self.draw(cmd, draw, doubled);
                }
            }
            Submission::SingleEye(_) | Submission::FarView => {
                let view = match submission {
                    Submission::SingleEye(eye) => eye.index() as u32,
                    _ => FAR_VIEW_INDEX,
                };
                self.set_view(cmd, full, view, pass.guard_band);
                for draw in draws {
                    self.draw(cmd, draw, false);
                }
            }
            Submission::PerObject => {
                for draw in draws {
                    for i in 0..draw.instance_count {
                        let one = Draw {
                            first_instance: draw.first_instance + i,
                            instance_count: 1,
                            ..*draw
                        };
                        for eye in Eye::BOTH {
                            let x = eye.index() as u32 * eye_width;
                            self.set_view(
                                cmd,
                                rect(x, eye_width, extent.height),
                                eye.index() as u32,
                                pass.guard_band,
                            );
                            self.draw(cmd, &one, false);
                        }
                    }
                }
            }
        }
    }

    /// The stencil masks of a pass, written before anything else: every view's keep shape as
    /// 1, then its drop shape as 0. Leaves the reference at 1, which scene draws test against.
    unsafe fn record_masks(
        &self,
        cmd: vk::CommandBuffer,
        mask: &Pipeline,
        pass: &PassPlan,
        extent: vk::Extent2D,
    ) {
        let device = self.gpu.device();
        device.cmd_bind_pipeline(cmd, vk::PipelineBindPoint::GRAPHICS, mask.raw);
        self.set_view(
            cmd,
            rect(0, extent.width, extent.height),
            0,
            pass.guard_band,
        );
        for (shape_set, reference) in [(0u32, 1u32), (1, 0)] {
            device.cmd_set_stencil_reference(cmd, vk::StencilFaceFlags::FRONT_AND_BACK, reference);
            device.cmd_push_constants(
                cmd,
                self.bindings.layout.raw,
                vk::ShaderStageFlags::VERTEX,
                0,
                &shape_set.to_le_bytes(),
            );
            device.cmd_draw(cmd, crate::shaders::MASK_VERTICES, 1, 0, 0);
            self.count_draw(crate::shaders::MASK_VERTICES as u64 / 3);
        }
    }

    /// The scene shaders' descriptor set (masks and the coverage probe use it too).
    unsafe fn bind_scene_set(&self, cmd: vk::CommandBuffer) {
        self.gpu.device().cmd_bind_descriptor_sets(
            cmd,
            vk::PipelineBindPoint::GRAPHICS,
            self.bindings.layout.raw,
            0,
            &[self.bindings.set],
            &[],
        );
    }

    /// A full-view triangle sampling an earlier pass's image: foveated composition, or the MFFR
    /// far composite (which in a single-eye pass learns its view from a push constant).
    unsafe fn record_full_view(
        &self,
        cmd: vk::CommandBuffer,
        pipeline: &Pipeline,
        set: &SampledSet,
        pass: &PassPlan,
        extent: vk::Extent2D,
    ) {
        let device = self.gpu.device();
        device.cmd_bind_pipeline(cmd, vk::PipelineBindPoint::GRAPHICS, pipeline.raw);
        device.cmd_bind_descriptor_sets(
            cmd,
            vk::PipelineBindPoint::GRAPHICS,
            set.layout.raw,
            0,
            &[set.set],
            &[],
        );
        if set.push_bytes > 0 {
            let view = match pass.submission {
                Submission::SingleEye(eye) => eye.index() as u32,
                _ => 0, // multiview: the shader reads gl_ViewIndex
            };
            device.cmd_push_constants(
                cmd,
                set.layout.raw,
                vk::ShaderStageFlags::FRAGMENT,
                0,
                &view.to_le_bytes(),
            );
        }
        self.set_viewport(cmd, rect(0, extent.width, extent.height), pass.guard_band);
        self.full_view_draw(cmd);
    }

    /// One triangle covering the viewport (the pipeline bound makes it a composite or a probe).
    unsafe fn full_view_draw(&self, cmd: vk::CommandBuffer) {
        self.gpu.device().cmd_draw(cmd, 3, 1, 0, 0);
        self.count_draw(1);
    }

    fn count_draw(&self, triangles: u64) {
        let t = self.tally.get();
        self.tally.set(DrawTally {
            calls: t.calls + 1,
            triangles: t.triangles + triangles,
        });
    }

    /// Viewport, scissor and the eye index the vertex shader reads in push-constant modes.
    unsafe fn set_view(&self, cmd: vk::CommandBuffer, area: vk::Rect2D, eye: u32, guard_band: u32) {
        self.set_viewport(cmd, area, guard_band);
        let device = self.gpu.device();
        device.cmd_push_constants(
            cmd,
            self.bindings.layout.raw,
            vk::ShaderStageFlags::VERTEX,
            0,
            &eye.to_le_bytes(),
        );
    }

    /// A viewport `guard_band` times larger than `area`, centred on it, scissored to it.
    unsafe fn set_viewport(&self, cmd: vk::CommandBuffer, area: vk::Rect2D, guard_band: u32) {
        let device = self.gpu.device();
        let k = guard_band as f32;
        let (w, h) = (area.extent.width as f32, area.extent.height as f32);
        let viewport = vk::Viewport {
            x: area.offset.x as f32 - (k - 1.0) * 0.5 * w,
            y: -(k - 1.0) * 0.5 * h,
            width: k * w,
            height: k * h,
            min_depth: 0.0,
            max_depth: 1.0,
        };
        device.cmd_set_viewport(cmd, 0, &[viewport]);
        device.cmd_set_scissor(cmd, 0, &[area]);
    }

    /// One indexed draw; `doubled` doubles instance count and first instance for instanced
    /// stereo, so instance 2k is object k's left eye and 2k+1 its right.
    unsafe fn draw(&self, cmd: vk::CommandBuffer, draw: &Draw, doubled: bool) {
        let mesh = self.scene.meshes[draw.mesh];
        let k = if doubled { 2 } else { 1 };
        self.count_draw(mesh.index_count as u64 / 3 * (draw.instance_count * k) as u64);
        self.gpu.device().cmd_draw_indexed(
            cmd,
            mesh.index_count,
            draw.instance_count * k,
            mesh.first_index,
            mesh.vertex_offset,
            draw.first_instance * k,
        );
    }
}

fn rect(x: u32, width: u32, height: u32) -> vk::Rect2D {
    vk::Rect2D {
        offset: vk::Offset2D { x: x as i32, y: 0 },
        extent: vk::Extent2D { width, height },
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
