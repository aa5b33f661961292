//! Head motion for temporal measurements.

use glam::{Mat4, Vec3};

/// Walking speed (m/s) and head turn (degrees/s) of [`walking_pose`]: an unhurried walk while
/// looking around.
pub const WALK_SPEED_M_S: f32 = 1.4;
/// Head turn in degrees per second (see [`WALK_SPEED_M_S`]).
pub const TURN_DEG_S: f32 = 20.0;

/// The head `seconds` into a walk from `start`: forward (the head's -z) at walking speed, turning
/// left at a steady rate.
pub fn walking_pose(start: Mat4, seconds: f32) -> Mat4 {
    let yaw = (TURN_DEG_S * seconds).to_radians();
    start
        * Mat4::from_translation(Vec3::new(0.0, 0.0, -WALK_SPEED_M_S * seconds))
        * Mat4::from_rotation_y(yaw)
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn the_walk_starts_at_the_start_and_moves_at_walking_speed() {
        let start = Mat4::from_translation(Vec3::new(1.0, 1.6, 2.0));
        assert_eq!(walking_pose(start, 0.0), start);
        let after = walking_pose(start, 1.0).transform_point3(Vec3::ZERO);
        assert!((after.distance(Vec3::new(1.0, 1.6, 2.0)) - WALK_SPEED_M_S).abs() < 1e-5);
    }
}
