//! MFFR in the renderer (Preißner 2020 §4.3): the per-frame near/far split of the scene's instances,
//! and the far composite's resources. The far pass itself is a scene pass drawn from the far
//! view; the composite is a full-view draw inside each eye pass.

use glam::{Mat4, Vec4};

use super::descriptors::DescriptorSet;
use super::executor::{Executor, FrameContext};
use super::recorder::{Recorder, Rect};
use super::sampled_set::SampledSet;
use crate::gpu::{Buffer, Gpu, GpuError, Image};
use crate::mffr::FarReprojection;
use crate::plan::{PassPlan, Step, Submission, MAX_VIEWS};

/// The far composite's uniform block (`FarComposite` in `shaders/far_composite.frag`, std140).
#[repr(C)]
#[derive(Clone, Copy)]
struct FarCompositeBlock {
    direction: [Mat4; MAX_VIEWS as usize],
    origin: [Vec4; MAX_VIEWS as usize],
    params: Vec4,
}

pub(crate) struct FarComposite {
    /// One per frame slot.
    sets: Vec<SampledSet>,
}

impl FarComposite {
    /// Sets up sampling of `far_image`, the far pass's resolved colour, counting into
    /// each frame slot's counter (`counters`) in counting frames.
    pub fn new(
        gpu: &Gpu,
        far_image: &Image,
        counters: &[Option<&Buffer>],
    ) -> Result<Self, GpuError> {
        let bytes = std::mem::size_of::<FarCompositeBlock>() as u64;
        Ok(FarComposite {
            sets: SampledSet::per_slot(gpu, &[far_image], false, bytes, 4, counters)?,
        })
    }
}

impl Executor for FarComposite {
    /// This frame's reprojection of each view (its pose and field of view) into the far view.
    fn update(&mut self, slot: usize, frame: &FrameContext) {
        let Some(far) = frame.views.far.as_ref() else {
            return;
        };
        let mut block = FarCompositeBlock {
            direction: [Mat4::ZERO; MAX_VIEWS as usize],
            origin: [Vec4::ZERO; MAX_VIEWS as usize],
            params: Vec4::new(far.near, 0.0, 0.0, 0.0),
        };
        for (i, &(world_from_view, fov)) in frame.views.views.iter().enumerate() {
            let r = FarReprojection::new(world_from_view, fov, far.view_proj);
            block.direction[i] = r.direction;
            block.origin[i] = r.origin;
        }
        self.sets[slot].uniforms.write(&[block]);
    }

    fn descriptors(&self, step: &Step, slot: usize, _parity: usize) -> Option<&DescriptorSet> {
        matches!(step, Step::FarComposite { .. }).then_some(&self.sets[slot].descriptors)
    }
}

/// The far composite step: a full-view triangle reprojecting the far image into each view; a
/// single-eye pass tells the shader its view, multiview reads `gl_ViewIndex`.
pub(super) fn record_far_composite(pass: &PassPlan, area: Rect, rec: &mut dyn Recorder) {
    let view = match pass.submission {
        Submission::SingleEye(eye) => eye.index() as u32,
        _ => 0,
    };
    rec.push_fragment(view);
    rec.set_viewport(area, pass.guard_band);
    rec.draw(3);
}
