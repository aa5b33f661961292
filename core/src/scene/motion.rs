//! Motion for temporal measurements: the head walking, and a walker crossing the view.

use glam::{Mat4, Vec3};

use super::{cube, DrawBatch, Instance, Scene};

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

/// A walker crossing the view from left to right in front of the head: a person-sized box
/// (0.5 × 1.8 × 0.3 m, red) on the ground, so accumulation over frames meets a surface that
/// moves on its own (a trail behind it, what it uncovers) and not only the head's motion.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct Walker {
    /// Its instance, numbered as `Renderer::move_instance` takes it: the scene's last.
    pub instance: usize,
    /// Where it starts (its centre) and the way it walks (unit, horizontal).
    start: Vec3,
    direction: Vec3,
}

impl Walker {
    /// Walking speed (m/s).
    pub const SPEED_M_S: f32 = 1.4;

    /// Adds a walker to `scene`, `ahead_m` in front of the head and starting 2 m to its left,
    /// walking across at [`Walker::SPEED_M_S`] (a mesh and a batch of its own, last).
    pub fn add(scene: &mut Scene, ahead_m: f32) -> Walker {
        let head = scene.head;
        let flat = |v: Vec3| Vec3::new(v.x, 0.0, v.z).normalize_or_zero();
        let right = flat(head.x_axis.truncate());
        let forward = flat(-head.z_axis.truncate());
        let eye = head.w_axis.truncate();
        let start = Vec3::new(eye.x, 0.9, eye.z) + forward * ahead_m - right * 2.0;
        let walker = Walker {
            instance: scene.instance_count(),
            start,
            direction: right,
        };
        scene.meshes.push(cube());
        scene.batches.push(DrawBatch {
            mesh: scene.meshes.len() - 1,
            instances: vec![Instance::new(walker.model(0.0), Vec3::new(0.8, 0.1, 0.1))],
        });
        walker
    }

    /// Its model matrix `seconds` into its walk.
    pub fn model(&self, seconds: f32) -> Mat4 {
        let at = self.start + self.direction * Self::SPEED_M_S * seconds;
        Mat4::from_translation(at) * Mat4::from_scale(Vec3::new(0.5, 1.8, 0.3))
    }
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
