//! MFFR's far view of a frame: one view covering both eyes from beyond the split, computed once
//! per frame and read by the views block, the far composite and culling.

use glam::Mat4;

use crate::cull::Frustum;
use crate::mffr::MffrGeometry;
use crate::plan::Resolution;
use crate::view::{reverse_z_projection, EyeParams, FovTangents};

/// This frame's far view: one view covering both eyes, from beyond the split (its pose moves
/// with the frame as the MFFR variant says).
pub(crate) struct FarView {
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
