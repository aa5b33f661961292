//! Recording the stencil masks (the HMD mask's lens ellipse, foveation's inset and outset
//! circles) and the shapes they draw this frame.

use glam::Vec4;

use super::descriptors::DescriptorSet;
use super::executor::{Executor, FrameContext};
use super::recorder::{Recorder, Rect};
use crate::foveation::{mask_shapes, MASK_SHAPES};
use crate::gpu::{Buffer, Gpu, GpuError, MemoryLocation};
use crate::plan::{FramePlan, PassPlan, StencilState, Step};
use crate::shaders::MASK_VERTICES;
use crate::view::{Eye, FovTangents, HiddenArea, MAX_HIDDEN_TRIANGLES};

/// Each eye's hidden triangles' corners in NDC, two corners per element (`Masks.hidden`).
const HIDDEN_ELEMENTS: usize = MAX_HIDDEN_TRIANGLES * 3;

/// The stencil masks' uniform block (`Masks` in `shaders/mask.vert`, std140).
#[repr(C)]
#[derive(Clone, Copy)]
struct MasksBlock {
    shapes: [Vec4; MASK_SHAPES],
    hidden: [Vec4; HIDDEN_ELEMENTS],
}

/// The stencil masks' shapes, rewritten each frame from the gaze (the scene's bindings read
/// them as binding 3).
pub(crate) struct MaskShapes {
    /// One per frame slot.
    pub buffers: Vec<Buffer>,
}

impl MaskShapes {
    pub fn new(gpu: &Gpu, slots: usize) -> Result<Self, GpuError> {
        let bytes = std::mem::size_of::<MasksBlock>() as u64;
        let usage = ash::vk::BufferUsageFlags::UNIFORM_BUFFER;
        let buffer = || Buffer::new(gpu, "stencil masks", bytes, usage, MemoryLocation::CpuToGpu);
        Ok(MaskShapes {
            buffers: (0..slots).map(|_| buffer()).collect::<Result<_, _>>()?,
        })
    }
}

impl Executor for MaskShapes {
    fn update(&mut self, slot: usize, frame: &FrameContext) {
        let block = MasksBlock {
            shapes: stencil_shapes(frame.plan, frame.fovea, frame.views.ring.as_ref()),
            hidden: hidden_corners(frame.plan, frame.hidden_area),
        };
        self.buffers[slot].write(&[block]);
    }

    fn descriptors(&self, _step: &Step, _slot: usize, _parity: usize) -> Option<&DescriptorSet> {
        None
    }
}

/// The mask fans step: every view's keep shapes set the bits the step writes, then its drop
/// shapes clear them, then a runtime's hidden triangles clear them too (when planned).
pub(super) fn record_mask_fans(
    pass: &PassPlan,
    stencil: StencilState,
    hidden_area: bool,
    area: Rect,
    rec: &mut dyn Recorder,
) {
    rec.set_viewport(area, pass.guard_band);
    for (shape_set, reference) in [(0u32, stencil.write_mask), (1, 0)] {
        rec.stencil_reference(reference);
        rec.push_vertex(shape_set);
        rec.draw(MASK_VERTICES);
    }
    if hidden_area {
        rec.push_vertex(2);
        rec.draw(HIDDEN_ELEMENTS as u32);
    }
}

/// The hidden triangles of each eye in its view's NDC (none until a mesh is handed in).
fn hidden_corners(plan: &FramePlan, hidden: Option<&[HiddenArea; 2]>) -> [Vec4; HIDDEN_ELEMENTS] {
    let mut out = [Vec4::ZERO; HIDDEN_ELEMENTS];
    let Some(areas) = hidden else {
        return out;
    };
    for eye in Eye::BOTH {
        let corners: Vec<glam::Vec2> = areas[eye.index()]
            .ndc(plan.eyes.fov(eye))
            .into_iter()
            .flatten()
            .collect();
        let half = HIDDEN_ELEMENTS / 2;
        for (slot, pair) in out[eye.index() * half..][..half]
            .iter_mut()
            .zip(corners.chunks(2))
        {
            let second = pair.get(1).copied().unwrap_or(glam::Vec2::ZERO);
            *slot = Vec4::new(pair[0].x, pair[0].y, second.x, second.y);
        }
    }
    out
}

/// The stencil shapes of a frame (see `shaders/mask.vert`): per view, what it keeps ([0..6)) and
/// then drops ([6..12)). The eye (periphery) views keep the lens-visible ellipse with the HMD
/// mask, everything without; foveation's inset and outset masks go on top.
fn stencil_shapes(
    plan: &FramePlan,
    fovea: Option<&[FovTangents; 2]>,
    ring: Option<&[FovTangents; 2]>,
) -> [Vec4; MASK_SHAPES] {
    let full = Vec4::new(0.0, 0.0, 2.0, 2.0);
    let mut shapes = [Vec4::ZERO; MASK_SHAPES];
    if let (Some(g), Some(fovea)) = (&plan.foveation, fovea) {
        if g.stencil {
            shapes = mask_shapes(g, &plan.eyes, fovea, ring);
        } else {
            shapes[2..6].fill(full);
        }
    }
    for eye in Eye::BOTH {
        shapes[eye.index()] = match &plan.hmd_mask {
            // A runtime's mesh drops what it hides; the eye keeps everything else.
            Some(_) if plan.hidden_area_mesh => full,
            Some(lens) => lens[eye.index()].ndc_ellipse(),
            None => full,
        };
    }
    shapes
}
