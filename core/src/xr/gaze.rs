//! An eye tracker's gaze ray (OpenXR `XR_EXT_eye_gaze_interaction`: one combined pose whose −Z
//! is the gaze) as each eye's normalised gaze, the coordinates the foveation windows follow.
//! The ray's direction is taken for both eyes (a gaze at infinity: vergence ignored, which
//! moves a near target by at most half the IPD's angle). Pure, tested on every host.

use glam::{Vec2, Vec3};

use crate::view::{Eye, EyeParams};

/// Each eye's normalised gaze (−1…1, x right, y up; clamped to the view) for a gaze looking
/// along `direction` in head space; `None` for a ray that does not point ahead of both eyes
/// (or is not finite), which the caller treats as a lost sample.
pub fn eye_gazes(eyes: &EyeParams, direction: Vec3) -> Option<[Vec2; 2]> {
    if !direction.is_finite() || direction.length_squared() == 0.0 {
        return None;
    }
    let gaze = |eye: Eye| {
        let d = eyes
            .head_from_eye(eye)
            .inverse()
            .transform_vector3(direction);
        if d.z >= -1e-6 {
            return None;
        }
        let t = Vec2::new(d.x / -d.z, d.y / -d.z);
        let fov = eyes.fov(eye);
        let centre = Vec2::new((fov.right - fov.left) / 2.0, (fov.up - fov.down) / 2.0);
        let half = Vec2::new((fov.left + fov.right) / 2.0, (fov.up + fov.down) / 2.0);
        Some(((t - centre) / half).clamp(Vec2::NEG_ONE, Vec2::ONE))
    };
    Some([gaze(Eye::Left)?, gaze(Eye::Right)?])
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::foveation::gaze_tangent;
    use crate::view::FovTangents;

    fn eyes(cant_deg: f32) -> EyeParams {
        let left = FovTangents::from_angles_deg(50.0, 42.0, 45.0, 50.0);
        EyeParams {
            left_fov: left,
            right_fov: left.mirrored(),
            ipd_m: 0.064,
            cant_rad: cant_deg.to_radians(),
        }
    }

    /// A gaze built from an eye's normalised coordinates (through `gaze_tangent`, as the
    /// fovea windows place it) comes back as those coordinates, asymmetric fields and canted
    /// eyes included. Mutation: y measured downwards, or the centre left out, fails it.
    #[test]
    fn a_gaze_ray_comes_back_as_the_point_it_was_built_from() {
        for cant in [0.0, 10.0] {
            let e = eyes(cant);
            for g in [Vec2::ZERO, Vec2::new(0.5, -0.3), Vec2::new(-0.8, 0.6)] {
                let t = gaze_tangent(e.fov(Eye::Left), g);
                let direction = e.head_from_eye(Eye::Left).transform_vector3(t.extend(-1.0));
                let [left, _] = eye_gazes(&e, direction).unwrap();
                assert!(left.abs_diff_eq(g, 1e-5), "cant {cant}: {left} for {g}");
            }
        }
    }

    #[test]
    fn straight_ahead_is_each_eye_s_own_centre_offset() {
        // An asymmetric field puts the straight-ahead ray off the image centre, mirrored
        // between the eyes.
        let [l, r] = eye_gazes(&eyes(0.0), Vec3::NEG_Z).unwrap();
        assert!(l.x.abs() > 0.01 && (l.x + r.x).abs() < 1e-6 && (l.y - r.y).abs() < 1e-6);
    }

    #[test]
    fn a_ray_behind_or_broken_is_no_gaze() {
        assert!(eye_gazes(&eyes(0.0), Vec3::Z).is_none());
        assert!(eye_gazes(&eyes(0.0), Vec3::ZERO).is_none());
        assert!(eye_gazes(&eyes(0.0), Vec3::new(f32::NAN, 0.0, -1.0)).is_none());
        // Far outside the view: clamped to its edge.
        let [l, _] = eye_gazes(&eyes(0.0), Vec3::new(5.0, 0.0, -1.0)).unwrap();
        assert_eq!(l.x, 1.0);
    }
}
