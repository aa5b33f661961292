//! MFFR in the renderer (seed 000 §4.3): the per-frame near/far split of the scene's instances,
//! and the far composite's resources. The far pass itself is a scene pass drawn from the far
//! view; the composite is a full-view draw inside each eye pass.

use glam::{Mat4, Vec4};

use super::recorder::{Recorder, Rect};
use super::sampled_set::SampledSet;
use crate::cull::Frustum;
use crate::gpu::{Buffer, Gpu, GpuError, Image};
use crate::mffr::{FarReprojection, MffrGeometry};
use crate::plan::{PassPlan, Resolution, Submission, MAX_VIEWS};
use crate::view::{reverse_z_projection, EyeParams, FovTangents};

/// This frame's far view: one view covering both eyes, from beyond the split (its pose moves
/// with the frame as the MFFR variant says).
pub(super) struct FarView {
    pub world_from_far: Mat4,
    pub view_proj: Mat4,
    pub fov: FovTangents,
    /// The far pass's near plane (its depth-in-alpha numerator).
    pub near: f32,
    /// Where the eye views end.
    pub split_m: f32,
    pub resolution: Resolution,
    frustum: Frustum,
}

impl FarView {
    pub fn new(m: &MffrGeometry, eyes: &EyeParams, world_from_head: Mat4, frame: u64) -> Self {
        let world_from_far = world_from_head * m.head_from_far(eyes, frame);
        FarView {
            world_from_far,
            view_proj: reverse_z_projection(m.far_fov, m.far_near, m.far)
                * world_from_far.inverse(),
            fov: m.far_fov,
            near: m.far_near,
            split_m: m.split_m,
            resolution: m.resolution,
            frustum: Frustum::from_eye(world_from_far, m.far_fov, m.far_near, m.far),
        }
    }

    /// What the far pass sees (its instances are culled against it).
    pub fn frustum(&self) -> &Frustum {
        &self.frustum
    }
}

/// The far composite's uniform block (`FarComposite` in `shaders/far_composite.frag`, std140).
#[repr(C)]
#[derive(Clone, Copy)]
struct FarCompositeBlock {
    direction: [Mat4; MAX_VIEWS as usize],
    origin: [Vec4; MAX_VIEWS as usize],
    params: Vec4,
}

pub(crate) struct FarComposite {
    pub set: SampledSet,
}

impl FarComposite {
    /// Sets up sampling of `far_image`, the far pass's resolved colour, counting into
    /// `counter` in counting frames.
    pub fn new(gpu: &Gpu, far_image: &Image, counter: Option<&Buffer>) -> Result<Self, GpuError> {
        let bytes = std::mem::size_of::<FarCompositeBlock>() as u64;
        Ok(FarComposite {
            set: SampledSet::new(gpu, &[far_image], false, bytes, 4, counter)?,
        })
    }

    /// This frame's reprojection of each view (its pose and field of view) into the far view.
    pub fn update(&mut self, views: &[(Mat4, FovTangents)], far: &FarView) {
        let mut block = FarCompositeBlock {
            direction: [Mat4::ZERO; MAX_VIEWS as usize],
            origin: [Vec4::ZERO; MAX_VIEWS as usize],
            params: Vec4::new(far.near, 0.0, 0.0, 0.0),
        };
        for (i, &(world_from_view, fov)) in views.iter().enumerate() {
            let r = FarReprojection::new(world_from_view, fov, far.view_proj);
            block.direction[i] = r.direction;
            block.origin[i] = r.origin;
        }
        self.set.uniforms.write(&[block]);
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
