//! Eyes, their poses and projections.
//!
//! Conventions: right-handed view space, +X right, +Y up, looking down −Z (as OpenXR and
//! OpenVR). Clip space is Vulkan's (NDC y points down, depth 0..1) with **reverse-Z**: the
//! near plane maps to depth 1 and the far plane to 0, so depth precision is spent far away
//! where f32 needs it; the depth test is `GREATER` and depth clears to 0.

mod distortion;
mod hidden_area;
mod hmd;
mod lens;
mod polygon;
mod projection;

pub use distortion::RadialDistortion;
pub use hidden_area::{HiddenArea, MAX_HIDDEN_TRIANGLES};
pub use hmd::{EyeTracker, HmdProfile, CARDBOARD_2015_LENS, DEFAULT_IPD_M, HMD_PROFILES};
pub use lens::LensRegion;
pub use projection::reverse_z_projection;

use glam::{Mat4, Quat, Vec3};

/// Which eye of a stereo pair.
#[derive(Clone, Copy, Debug, PartialEq, Eq, Hash)]
pub enum Eye {
    /// The left eye.
    Left,
    /// The right eye.
    Right,
}

impl Eye {
    /// Both eyes, left first.
    pub const BOTH: [Eye; 2] = [Eye::Left, Eye::Right];

    /// Its name in the printout.
    pub fn name(self) -> &'static str {
        match self {
            Eye::Left => "left",
            Eye::Right => "right",
        }
    }

    /// 0 for the left eye, 1 for the right.
    pub fn index(self) -> usize {
        match self {
            Eye::Left => 0,
            Eye::Right => 1,
        }
    }

    /// −1 for the left eye, +1 for the right: the side of the head the eye sits on.
    fn side(self) -> f32 {
        match self {
            Eye::Left => -1.0,
            Eye::Right => 1.0,
        }
    }
}

/// The four half-angle tangents of an eye's field of view, all positive for a view that
/// contains its own axis: the edges sit at x/−z = −left, +right and y/−z = +up, −down.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct FovTangents {
    /// Tangent of the angle to the left edge.
    pub left: f32,
    /// Tangent of the angle to the right edge.
    pub right: f32,
    /// Tangent of the angle to the top edge.
    pub up: f32,
    /// Tangent of the angle to the bottom edge.
    pub down: f32,
}

impl FovTangents {
    /// A symmetric field of view from full horizontal and vertical angles in degrees.
    pub fn symmetric_deg(horizontal: f32, vertical: f32) -> Self {
        let h = (horizontal.to_radians() * 0.5).tan();
        let v = (vertical.to_radians() * 0.5).tan();
        Self {
            left: h,
            right: h,
            up: v,
            down: v,
        }
    }

    /// From the four half-angles in degrees (left, right, up, down), each measured from the
    /// eye's axis and positive outwards.
    pub fn from_angles_deg(left: f32, right: f32, up: f32, down: f32) -> Self {
        let t = |a: f32| a.to_radians().tan();
        Self {
            left: t(left),
            right: t(right),
            up: t(up),
            down: t(down),
        }
    }

    /// The mirror image (left and right swapped): a right eye from a left eye's tangents.
    pub fn mirrored(self) -> Self {
        Self {
            left: self.right,
            right: self.left,
            ..self
        }
    }

    /// Left, right, up, down.
    pub fn as_array(self) -> [f32; 4] {
        [self.left, self.right, self.up, self.down]
    }

    /// Pixels per degree at this view's axis when it is `pixels` wide: one pixel there spans
    /// `atan(tangent width / pixels)`, so `ppd = 1 / degrees(atan((left + right) / pixels))`.
    pub fn pixels_per_degree(self, pixels: u32) -> f64 {
        let width = self.left as f64 + self.right as f64;
        1.0 / (width / pixels as f64).atan().to_degrees()
    }

    /// Where a tangent-space point (x right, y up) lands in this view's NDC (Vulkan: y down).
    pub fn ndc(self, t: glam::Vec2) -> glam::Vec2 {
        glam::Vec2::new(
            (t.x + self.left) / (self.left + self.right) * 2.0 - 1.0,
            1.0 - (t.y + self.down) / (self.up + self.down) * 2.0,
        )
    }
}

/// The eye pair: per-eye FOV tangents, interpupillary distance and an optional outward cant
/// (each eye yawed away from the nose by `cant_rad`, as on headsets with canted displays).
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct EyeParams {
    /// The left eye's field.
    pub left_fov: FovTangents,
    /// The right eye's field.
    pub right_fov: FovTangents,
    /// Interpupillary distance in metres.
    pub ipd_m: f32,
    /// Outward yaw of each eye in radians (0 for parallel eyes).
    pub cant_rad: f32,
}

impl EyeParams {
    /// The field of `eye`.
    pub fn fov(&self, eye: Eye) -> FovTangents {
        match eye {
            Eye::Left => self.left_fov,
            Eye::Right => self.right_fov,
        }
    }

    /// The eye's pose in head space: half the IPD to its side, yawed outward by the cant.
    pub fn head_from_eye(&self, eye: Eye) -> Mat4 {
        let offset = Vec3::new(eye.side() * self.ipd_m * 0.5, 0.0, 0.0);
        // Yaw about +Y by a positive angle turns −Z towards −X, i.e. to the left: the left eye
        // cants by +cant, the right by −cant.
        let yaw = Quat::from_rotation_y(-eye.side() * self.cant_rad);
        Mat4::from_rotation_translation(yaw, offset)
    }

    /// View matrix of `eye` for a head at pose `world_from_head`.
    pub fn view(&self, eye: Eye, world_from_head: Mat4) -> Mat4 {
        (world_from_head * self.head_from_eye(eye)).inverse()
    }

    /// Reverse-Z projection of `eye` (see the module docs).
    pub fn projection(&self, eye: Eye, near: f32, far: f32) -> Mat4 {
        reverse_z_projection(self.fov(eye), near, far)
    }
}

/// A head pose looking from `eye` at `target` with +Y up.
pub fn look_at_head(eye: Vec3, target: Vec3) -> Mat4 {
    Mat4::look_at_rh(eye, target, Vec3::Y).inverse()
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn parallel_eyes_sit_half_an_ipd_either_side() {
        let p = EyeParams {
            left_fov: FovTangents::symmetric_deg(90.0, 90.0),
            right_fov: FovTangents::symmetric_deg(90.0, 90.0),
            ipd_m: 0.064,
            cant_rad: 0.0,
        };
        let l = p.head_from_eye(Eye::Left).transform_point3(Vec3::ZERO);
        let r = p.head_from_eye(Eye::Right).transform_point3(Vec3::ZERO);
        assert!((l.x + 0.032).abs() < 1e-7 && (r.x - 0.032).abs() < 1e-7);
    }

    #[test]
    fn cant_turns_each_eye_outward() {
        let p = EyeParams {
            left_fov: FovTangents::symmetric_deg(90.0, 90.0),
            right_fov: FovTangents::symmetric_deg(90.0, 90.0),
            ipd_m: 0.064,
            cant_rad: 10f32.to_radians(),
        };
        let l = p.head_from_eye(Eye::Left).transform_vector3(-Vec3::Z);
        let r = p.head_from_eye(Eye::Right).transform_vector3(-Vec3::Z);
        assert!(l.x < -0.17 && r.x > 0.17, "left {l}, right {r}");
    }
}
