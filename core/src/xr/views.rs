//! A runtime's located views in foveate's terms: poses as matrices, OpenXR's field-of-view
//! angles as tangents, and the two eyes as [`EyeParams`] about a head between them. Pure (no
//! OpenXR handle), so the conversions are tested on every host.

use glam::{Mat4, Quat, Vec3};

use crate::view::{Eye, EyeParams, FovTangents};

/// A rigid pose: OpenXR's `XrPosef` (orientation x, y, z, w; position in metres).
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct Pose {
    /// Orientation as a unit quaternion (x, y, z, w).
    pub orientation: [f32; 4],
    /// Position in metres.
    pub position: [f32; 3],
}

impl Pose {
    /// The pose as a matrix from its space to the space it is given in.
    pub fn matrix(self) -> Mat4 {
        let q = Quat::from_array(self.orientation).normalize();
        Mat4::from_rotation_translation(q, Vec3::from_array(self.position))
    }
}

/// OpenXR's `XrFovf` (radians: left and down negative for a view that contains its axis) as
/// foveate's tangents (all positive for such a view).
pub fn fov_tangents(
    angle_left: f32,
    angle_right: f32,
    angle_up: f32,
    angle_down: f32,
) -> FovTangents {
    FovTangents {
        left: (-angle_left).tan(),
        right: angle_right.tan(),
        up: angle_up.tan(),
        down: (-angle_down).tan(),
    }
}

/// The two eyes of a frame as foveate models them, and how far the runtime's eyes lie from
/// that model.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct FittedEyes {
    /// The head: midway between the eyes, looking down their mean forward with their baseline
    /// as +X.
    pub world_from_head: Mat4,
    /// The eye model fitted to the runtime's views.
    pub eyes: EyeParams,
    /// The largest distance from a runtime eye's position to the model's (metres).
    pub position_error_m: f32,
    /// The largest angle between a runtime eye's orientation and the model's (degrees).
    pub angle_error_deg: f32,
}

/// Fits foveate's eye model (half the IPD either side of the head, each yawed outward by the
/// cant) to each eye's pose in world space and field of view, as `xrLocateViews` gives them.
/// Runtimes place the eyes this way (parallel or canted displays); the errors say how far a
/// runtime's eyes are from it (vertical offsets, roll), for the caller to report.
pub fn fit_eyes(world_from_eye: [Mat4; 2], fov: [FovTangents; 2]) -> FittedEyes {
    let origin = world_from_eye.map(|m| m.w_axis.truncate());
    let forward = world_from_eye.map(|m| m.transform_vector3(Vec3::NEG_Z).normalize());
    let centre = (origin[0] + origin[1]) * 0.5;
    let baseline = origin[1] - origin[0];
    let ipd = baseline.length();
    let mean_forward = (forward[0] + forward[1]).normalize();
    // +X along the baseline (or the left eye's +X when the eyes coincide), +Y up from it and
    // the mean forward.
    let x = if ipd > 1e-6 {
        baseline / ipd
    } else {
        world_from_eye[0].transform_vector3(Vec3::X).normalize()
    };
    let y = (-mean_forward).cross(x).normalize();
    let z = x.cross(y);
    let world_from_head = Mat4::from_cols(
        x.extend(0.0),
        y.extend(0.0),
        z.extend(0.0),
        centre.extend(1.0),
    );
    let head_from_world = world_from_head.inverse();
    // Each eye's outward yaw in the head: the left eye turns towards −X, the right towards +X.
    let yaw = |e: Eye| {
        let f = head_from_world.transform_vector3(forward[e.index()]);
        let side = if e == Eye::Left { -1.0 } else { 1.0 };
        (side * f.x).atan2(-f.z)
    };
    let eyes = EyeParams {
        left_fov: fov[0],
        right_fov: fov[1],
        ipd_m: ipd,
        cant_rad: (yaw(Eye::Left) + yaw(Eye::Right)) * 0.5,
    };
    let mut position_error_m: f32 = 0.0;
    let mut angle_error_deg: f32 = 0.0;
    for e in Eye::BOTH {
        let model = world_from_head * eyes.head_from_eye(e);
        let actual = world_from_eye[e.index()];
        position_error_m = position_error_m.max(model.w_axis.distance(actual.w_axis));
        let (q_model, q_actual) = (
            Quat::from_mat4(&model).normalize(),
            Quat::from_mat4(&actual).normalize(),
        );
        angle_error_deg = angle_error_deg.max(q_model.angle_between(q_actual).to_degrees());
    }
    FittedEyes {
        world_from_head,
        eyes,
        position_error_m,
        angle_error_deg,
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    fn fov() -> [FovTangents; 2] {
        let left = fov_tangents(-0.9, 0.8, 0.85, -0.95);
        [left, left.mirrored()]
    }

    #[test]
    fn openxr_angles_become_positive_tangents() {
        let t = fov_tangents(-0.9, 0.8, 0.85, -0.95);
        let expected = [0.9f32.tan(), 0.8f32.tan(), 0.85f32.tan(), 0.95f32.tan()];
        for (a, b) in t.as_array().iter().zip(expected) {
            assert!((a - b).abs() < 1e-6, "{:?}", t.as_array());
        }
    }

    /// Eyes built by foveate's own model, anywhere in the world, are fitted back exactly.
    #[test]
    fn the_model_s_own_eyes_fit_back_exactly() {
        let head = Mat4::from_rotation_translation(
            Quat::from_euler(glam::EulerRot::YXZ, 0.7, -0.3, 0.2),
            Vec3::new(1.5, 1.7, -2.0),
        );
        for (ipd, cant_deg) in [(0.064f32, 0.0f32), (0.058, 10.0), (0.07, -5.0)] {
            let eyes = EyeParams {
                left_fov: fov()[0],
                right_fov: fov()[1],
                ipd_m: ipd,
                cant_rad: cant_deg.to_radians(),
            };
            let poses = Eye::BOTH.map(|e| head * eyes.head_from_eye(e));
            let fit = fit_eyes(poses, fov());
            assert!(
                (fit.eyes.ipd_m - ipd).abs() < 1e-5,
                "ipd {}",
                fit.eyes.ipd_m
            );
            assert!(
                (fit.eyes.cant_rad.to_degrees() - cant_deg).abs() < 1e-3,
                "cant {}",
                fit.eyes.cant_rad.to_degrees()
            );
            assert!(fit.position_error_m < 1e-5 && fit.angle_error_deg < 0.05);
            assert!(
                fit.world_from_head.abs_diff_eq(head, 1e-4),
                "{} against {head}",
                fit.world_from_head
            );
        }
    }

    /// A runtime eye the model cannot express (one eye 3 mm higher: the baseline rolls 2.7°
    /// while the eyes do not) is reported, not hidden.
    #[test]
    fn eyes_off_the_model_report_their_error() {
        let eyes = EyeParams {
            left_fov: fov()[0],
            right_fov: fov()[1],
            ipd_m: 0.064,
            cant_rad: 0.0,
        };
        let mut poses = Eye::BOTH.map(|e| eyes.head_from_eye(e));
        poses[1].w_axis.y += 0.003;
        let fit = fit_eyes(poses, fov());
        assert!(
            fit.angle_error_deg > 2.0 || fit.position_error_m > 1e-3,
            "{} m, {}°",
            fit.position_error_m,
            fit.angle_error_deg
        );
    }

    #[test]
    fn a_pose_is_its_rotation_then_its_translation() {
        let q = Quat::from_rotation_y(0.5);
        let pose = Pose {
            orientation: q.to_array(),
            position: [1.0, 2.0, 3.0],
        };
        let p = pose.matrix().transform_point3(Vec3::NEG_Z);
        let expected = q * Vec3::NEG_Z + Vec3::new(1.0, 2.0, 3.0);
        assert!(p.abs_diff_eq(expected, 1e-6));
    }
}
