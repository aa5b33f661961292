//! Recording the stencil masks (the HMD mask's lens ellipse, foveation's inset and outset
//! circles) and the shapes they draw this frame.

use glam::Vec4;

use super::descriptors::DescriptorSet;
use super::executor::{Executor, FrameInput};
use super::recorder::{Recorder, Rect};
use crate::foveation::mask_shapes;
use crate::gpu::{Buffer, Gpu, GpuError, MemoryLocation};
use crate::plan::{FramePlan, PassPlan, StencilState, Step};
use crate::shaders::MASK_VERTICES;
use crate::view::{Eye, FovTangents};

/// The stencil masks' shapes, rewritten each frame from the gaze (the scene's bindings read
/// them as binding 3).
pub(crate) struct MaskShapes {
    pub buffer: Buffer,
}

impl MaskShapes {
    pub fn new(gpu: &Gpu) -> Result<Self, GpuError> {
        let bytes = std::mem::size_of::<[Vec4; 8]>() as u64;
        let usage = ash::vk::BufferUsageFlags::UNIFORM_BUFFER;
        Ok(MaskShapes {
            buffer: Buffer::new(gpu, "stencil masks", bytes, usage, MemoryLocation::CpuToGpu)?,
        })
    }
}

impl Executor for MaskShapes {
    fn update(&mut self, frame: &FrameInput) {
        self.buffer.write(&stencil_shapes(frame.plan, frame.fovea));
    }

    fn descriptors(&self, _step: &Step) -> Option<&DescriptorSet> {
        None
    }
}

/// The mask fans step: every view's keep shapes set the bits the step writes, then its drop
/// shapes clear them.
pub(super) fn record_mask_fans(
    pass: &PassPlan,
    stencil: StencilState,
    area: Rect,
    rec: &mut dyn Recorder,
) {
    rec.set_viewport(area, pass.guard_band);
    for (shape_set, reference) in [(0u32, stencil.write_mask), (1, 0)] {
        rec.stencil_reference(reference);
        rec.push_vertex(shape_set);
        rec.draw(MASK_VERTICES);
    }
}

/// The stencil shapes of a frame (see `shaders/mask.vert`): per view, what it keeps ([0..4)) and
/// then drops ([4..8)). The eye (periphery) views keep the lens-visible ellipse with the HMD
/// mask, everything without; foveation's inset and outset masks go on top.
fn stencil_shapes(plan: &FramePlan, fovea: Option<&[FovTangents; 2]>) -> [Vec4; 8] {
    let full = Vec4::new(0.0, 0.0, 2.0, 2.0);
    let mut shapes = [Vec4::ZERO; 8];
    if let (Some(g), Some(fovea)) = (&plan.foveation, fovea) {
        if g.stencil {
            shapes = mask_shapes(g, &plan.eyes, fovea);
        } else {
            shapes[2..4].fill(full);
        }
    }
    for eye in Eye::BOTH {
        shapes[eye.index()] = match &plan.hmd_mask {
            Some(lens) => lens[eye.index()].ndc_ellipse(),
            None => full,
        };
    }
    shapes
}
