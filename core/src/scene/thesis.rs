//! The benchmark scene of the Tachyon thesis (Preißner 2020 §5.1) and its camera rails.
//!
//! 711 × 22 × 711 grid counts at spacing 3.6, each position jittered by the thesis' sin/cos/tan
//! entropy; a cube everywhere except where the x+z, y−z and z counts are all multiples of 11,
//! where a high-poly object goes, cycling through the high-poly types: 11,121,462 instances at
//! full size. `scale` shrinks the two horizontal counts for small copies.

use glam::{Mat4, Quat, Vec3};
use rayon::prelude::*;

use super::default_scene::palette;
use super::{cube, uv_sphere, DrawBatch, Instance, Scene};
use crate::cull::Sphere;
use crate::vocab::ConfigError;

/// The thesis scene's grid: 711 × 22 × 711 positions.
pub const THESIS_COUNTS: [u32; 3] = [711, 22, 711];
/// Metres between grid positions.
pub const THESIS_SPACING: f32 = 3.6;
/// Frames of one rails loop (the thesis ran two loops in 5400 frames).
pub const RAIL_LOOP_FRAMES: u64 = 2700;

/// What stands at a grid position.
#[derive(Clone, Copy, Debug, PartialEq, Eq, Hash)]
pub enum ThesisObject {
    /// A unit cube.
    Cube,
    /// High-poly type 0, 1 or 2 (the thesis: robot, material sphere, helmet).
    HighPoly(u8),
}

impl ThesisObject {
    /// Bounding radius: the unit cube's half-diagonal; the high-poly stand-ins' own spheres.
    pub fn radius(self) -> f32 {
        match self {
            ThesisObject::Cube => 0.5 * 3f32.sqrt(),
            ThesisObject::HighPoly(t) => [1.2, 1.0, 0.8][t as usize % 3],
        }
    }
}

/// The thesis' entropy, evaluated as its pseudo-code reads: three assignments in sequence, each
/// using the values already updated.
pub fn entropy(x: f32, y: f32, z: f32) -> Vec3 {
    let x1 = (x.sin() + y.cos() + z.tan()).sin();
    let y1 = (y.sin() + z.cos() + x1.tan()).cos();
    let z1 = (z.sin().cos() + x1.cos() + y1.tan()).sin();
    Vec3::new(x1, y1, z1)
}

/// The scene's instances, generated deterministically.
pub struct ThesisScene {
    /// The grid's counts along x, y and z.
    pub counts: [u32; 3],
    /// Each object's position.
    pub positions: Vec<Vec3>,
    /// What stands at each position.
    pub objects: Vec<ThesisObject>,
}

impl ThesisScene {
    /// Grid counts at `scale` (horizontal counts scaled, at least 1; the 22 levels kept).
    pub fn counts(scale: f32) -> Result<[u32; 3], ConfigError> {
        if !scale.is_finite() || scale <= 0.0 || scale > 1.0 {
            return Err(ConfigError::new(
                "scale",
                scale,
                "0 < scale ≤ 1 (1 = the full 711 × 22 × 711 scene)",
            ));
        }
        let h = ((THESIS_COUNTS[0] as f32 * scale).round() as u32).max(1);
        Ok([h, THESIS_COUNTS[1], h])
    }

    /// How many objects the scene has at `scale`.
    pub fn instance_count(scale: f32) -> Result<u64, ConfigError> {
        Ok(Self::counts(scale)?.iter().map(|&c| c as u64).product())
    }

    /// The scene at `scale` (0 < scale ≤ 1), generated deterministically.
    pub fn new(scale: f32) -> Result<Self, ConfigError> {
        let counts = Self::counts(scale)?;
        let [nx, ny, nz] = counts;
        let per_x = (ny * nz) as usize;
        let cells: Vec<(Vec3, ThesisObject)> = (0..nx)
            .into_par_iter()
            .flat_map_iter(|x| {
                (0..ny).flat_map(move |y| {
                    (0..nz).map(move |z| {
                        let grid = Vec3::new(x as f32, y as f32, z as f32) * THESIS_SPACING;
                        let position = grid + entropy(x as f32, y as f32, z as f32);
                        (position, object_at(x, y, z, nz))
                    })
                })
            })
            .collect();
        debug_assert_eq!(cells.len(), per_x * nx as usize);
        let (positions, objects) = cells.into_iter().unzip();
        Ok(ThesisScene {
            counts,
            positions,
            objects,
        })
    }

    /// How many objects it has.
    pub fn len(&self) -> usize {
        self.positions.len()
    }

    /// Whether it has none.
    pub fn is_empty(&self) -> bool {
        self.positions.is_empty()
    }

    /// Bounding spheres, in instance order.
    pub fn bounds(&self) -> Vec<Sphere> {
        self.positions
            .par_iter()
            .zip(&self.objects)
            .map(|(&p, o)| Sphere::new(p, o.radius()))
            .collect()
    }

    /// The scene to render: unit cubes, and for the high-poly objects spheres of their radius
    /// at three tessellations (the thesis' robot, material sphere and helmet are not ours to
    /// ship), the head at the rails' first pose.
    pub fn to_scene(&self) -> Scene {
        let meshes = vec![
            cube(),
            uv_sphere(64, 32),
            uv_sphere(48, 24),
            uv_sphere(40, 20),
        ];
        let mut batches: Vec<DrawBatch> = (0..meshes.len())
            .map(|mesh| DrawBatch {
                mesh,
                instances: Vec::new(),
            })
            .collect();
        for (i, (&p, &o)) in self.positions.iter().zip(&self.objects).enumerate() {
            let (mesh, scale, colour) = match o {
                ThesisObject::Cube => (0, 1.0, palette(i as u32 % 97) * 0.8),
                ThesisObject::HighPoly(t) => (1 + t as usize, o.radius(), palette(200 + t as u32)),
            };
            batches[mesh].instances.push(Instance::new(
                Mat4::from_scale_rotation_translation(Vec3::splat(scale), Quat::IDENTITY, p),
                colour,
            ));
        }
        Scene {
            meshes,
            batches,
            head: rail_pose(0, self.extent()),
            light_dir: Vec3::new(0.3, -1.0, 0.2).normalize(),
            materials: Vec::new(),
            lights: Vec::new(),
            reach: None,
        }
    }

    /// The scene's extent (grid counts × spacing).
    pub fn extent(&self) -> Vec3 {
        Vec3::new(
            self.counts[0] as f32,
            self.counts[1] as f32,
            self.counts[2] as f32,
        ) * THESIS_SPACING
    }
}

fn object_at(x: u32, y: u32, z: u32, nz: u32) -> ThesisObject {
    let multiple = |v: i64| v.rem_euclid(11) == 0;
    if multiple(x as i64 + z as i64) && multiple(y as i64 - z as i64) && multiple(z as i64) {
        // Cycle the types in placement order ("modulo-index-incremented").
        let index =
            (x / 11) as u64 * (nz as u64 / 11 + 1) * 2 + (z / 11) as u64 * 2 + (y / 11) as u64;
        ThesisObject::HighPoly((index % 3) as u8)
    } else {
        ThesisObject::Cube
    }
}

/// The head pose at `frame` along the rails: a circle around the scene's centre for position
/// and another, faster one for the view direction, both from sin/cos of the frame number as in
/// the thesis (which does not print its constants; these are ours). Same frame, same pose.
pub fn rail_pose(frame: u64, extent: Vec3) -> Mat4 {
    let loop_phase =
        std::f32::consts::TAU * (frame % RAIL_LOOP_FRAMES) as f32 / RAIL_LOOP_FRAMES as f32;
    let centre = extent * 0.5;
    let radius = 0.3 * extent.x.min(extent.z);
    let position = centre
        + Vec3::new(
            radius * loop_phase.cos(),
            0.25 * extent.y * (2.0 * loop_phase).sin(),
            radius * loop_phase.sin(),
        );
    let yaw = -3.0 * loop_phase;
    let pitch = 0.15 * (5.0 * loop_phase).sin();
    Mat4::from_rotation_translation(
        Quat::from_euler(glam::EulerRot::YXZ, yaw, pitch, 0.0),
        position,
    )
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn full_size_is_the_thesis_count() {
        assert_eq!(ThesisScene::instance_count(1.0).unwrap(), 11_121_462);
        assert_eq!(ThesisScene::counts(1.0).unwrap(), [711, 22, 711]);
        assert_eq!(ThesisScene::counts(0.05).unwrap(), [36, 22, 36]);
        assert_eq!(ThesisScene::counts(0.0).unwrap_err().field, "scale");
        assert_eq!(ThesisScene::counts(f32::NAN).unwrap_err().field, "scale");
    }

    #[test]
    fn small_copy_is_generated_as_specified() {
        let scene = ThesisScene::new(0.05).unwrap();
        assert_eq!(
            scene.len() as u64,
            ThesisScene::instance_count(0.05).unwrap()
        );
        // Position of grid cell (x, y, z) is the grid point plus the entropy.
        let (x, y, z) = (3u32, 5u32, 7u32);
        let i = ((x * 22 + y) * 36 + z) as usize;
        let expected = Vec3::new(3.0, 5.0, 7.0) * 3.6 + entropy(3.0, 5.0, 7.0);
        assert!((scene.positions[i] - expected).length() < 1e-5);
        // High-poly objects sit where x+z, y−z and z are multiples of 11.
        let high: Vec<usize> = (0..scene.len())
            .filter(|&i| scene.objects[i] != ThesisObject::Cube)
            .collect();
        assert!(!high.is_empty());
        assert_eq!(scene.objects[0], ThesisObject::HighPoly(0));
        let types: std::collections::HashSet<_> = high.iter().map(|&i| scene.objects[i]).collect();
        assert_eq!(types.len(), 3, "cycles through all high-poly types");
        assert!(scene.positions.iter().all(|p| p.is_finite()));
    }

    #[test]
    fn rails_repeat_per_frame() {
        let extent = Vec3::new(2559.6, 79.2, 2559.6);
        assert_eq!(rail_pose(17, extent), rail_pose(17, extent));
        assert_eq!(
            rail_pose(5, extent),
            rail_pose(5 + RAIL_LOOP_FRAMES, extent)
        );
        assert_ne!(rail_pose(5, extent), rail_pose(6, extent));
        let p = rail_pose(100, extent).transform_point3(Vec3::ZERO);
        assert!(p.x > 0.0 && p.x < extent.x && p.z > 0.0 && p.z < extent.z);
    }
}
