//! Level of detail: simplified versions of a mesh, each with how far its surface strays from the
//! full mesh, so that a draw set whose pixels cannot resolve that distance draws the coarser one
//! (a foveated frame's periphery has about a third of the fovea's pixels per degree).
//!
//! meshoptimizer simplifies by edge collapse on positions and normals, keeping the original
//! vertices (with their normals, UVs and tangents) and the mesh's attribute seams. Its own error
//! estimate measures how far kept vertices move from the collapsed triangles' planes, not how far
//! a coarse triangle sags below a curved surface (on a cylinder the sag is 3.5× its estimate), so
//! each level's error is measured: the largest distance, sampled both ways, between its surface
//! and the full mesh's, in the mesh's units. The selection projects it to pixels. Shading is
//! weighed by the simplifier (normals) but not bounded in pixels: a texture stretched across a
//! collapsed edge or a normal interpolated over a larger triangle is priced by eFLIP against the
//! full mesh.

use std::ops::RangeInclusive;

use super::{Mesh, Scene};
use crate::vocab::ConfigError;

pub use super::clusters::ClusterError as LodError;

/// Meshes of fewer triangles keep one level: a cube or a quad has nothing to drop.
pub const LOD_MIN_TRIANGLES: usize = 64;
/// Levels per mesh past the full one, each asking for half the previous one's triangles.
pub const MAX_LOD_LEVELS: usize = 4;
/// The projected error a draw set accepts when asked without a bound: one of its pixels.
pub const DEFAULT_LOD_ERROR_PX: f32 = 1.0;
/// The bounds `--lod` accepts, in the draw set's pixels.
pub const LOD_ERROR_PX_RANGE: RangeInclusive<f32> = 0.125..=8.0;

/// One simplified version of a mesh.
#[derive(Clone, Debug, PartialEq)]
pub struct LodLevel {
    /// Its triangles, indexing the mesh's own vertices.
    pub indices: Vec<u32>,
    /// How far its surface lies from the full mesh's, in the mesh's units: measured both ways
    /// (sampled), and never less than the simplifier's estimate or a finer level's.
    pub error: f32,
}

impl LodLevel {
    /// Its triangles.
    pub fn triangle_count(&self) -> usize {
        self.indices.len() / 3
    }
}

/// How much error a draw set accepts from a coarser level.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct LodSettings {
    /// The most a level's error may project to, in the pixels of each view that draws it.
    pub max_error_px: f32,
}

impl LodSettings {
    /// At most `max_error_px` pixels of projected error, in the range the error names.
    pub fn new(max_error_px: f32) -> Result<Self, ConfigError> {
        if !LOD_ERROR_PX_RANGE.contains(&max_error_px) {
            return Err(ConfigError::new(
                "lod",
                max_error_px,
                format!(
                    "an error bound in {}..={} pixels",
                    LOD_ERROR_PX_RANGE.start(),
                    LOD_ERROR_PX_RANGE.end()
                ),
            ));
        }
        Ok(LodSettings { max_error_px })
    }
}

impl Default for LodSettings {
    fn default() -> Self {
        LodSettings {
            max_error_px: DEFAULT_LOD_ERROR_PX,
        }
    }
}

impl Scene {
    /// The scene with simplified levels for every mesh of at least [`LOD_MIN_TRIANGLES`]
    /// triangles. The full meshes are untouched: a frame planned without level of detail draws
    /// exactly what it drew before.
    pub fn with_lod(mut self) -> Result<Scene, LodError> {
        for mesh in &mut self.meshes {
            if mesh.lods.is_empty() && mesh.triangle_count() >= LOD_MIN_TRIANGLES {
                mesh.lods = build::levels(mesh)?;
            }
        }
        Ok(self)
    }

    /// Levels over all meshes, and the meshes that have them.
    pub fn lod_counts(&self) -> (usize, usize) {
        let with = self.meshes.iter().filter(|m| !m.lods.is_empty());
        (with.clone().map(|m| m.lods.len()).sum(), with.count())
    }
}

#[cfg(feature = "clusters")]
mod build {
    use glam::Vec3;

    use super::*;
    use crate::scene::deviation::surface_distance;

    /// A level kept must have at most this fraction of the previous one's triangles; past it the
    /// simplifier is stuck (locked seams, a mesh already minimal) and a level would only cost a draw.
    const MIN_REDUCTION: f32 = 0.8;

    /// How much a collapse's change in normals counts against it, beside its change in
    /// position (meshoptimizer weighs attributes against positions scaled to the mesh's
    /// extent). Positions alone keep silhouettes within the bound but let a collapse spread one
    /// vertex's normal over a face it did not shade: on the assimp engine the fovea's eFLIP p99
    /// was 0.176 at 1 px with positions only and 0.011 with normals at this weight, for the
    /// same frame time (BENCHMARKS, "Level of detail per draw set").
    const NORMAL_WEIGHT: f32 = 0.5;

    pub(super) fn levels(mesh: &Mesh) -> Result<Vec<LodLevel>, LodError> {
        let positions = super::super::clusters::positions(mesh);
        let points: Vec<Vec3> = mesh.vertices.iter().map(|v| v.position.into()).collect();
        let normals: Vec<f32> = mesh.vertices.iter().flat_map(|v| v.normal).collect();
        let unlocked = vec![false; mesh.vertices.len()];
        let mut levels: Vec<LodLevel> = Vec::new();
        let mut index_count = mesh.indices.len();
        for _ in 0..MAX_LOD_LEVELS {
            let target = index_count / 6 * 3;
            let mut error = 0.0;
            // Each level from the full mesh, so its error is against the full mesh.
            let indices = meshopt::simplify_with_attributes_and_locks(
                &mesh.indices,
                &positions,
                &normals,
                &[NORMAL_WEIGHT; 3],
                3 * std::mem::size_of::<f32>(),
                &unlocked,
                target,
                f32::MAX,
                meshopt::SimplifyOptions::ErrorAbsolute,
                Some(&mut error),
            );
            if indices.is_empty() || indices.len() as f32 > MIN_REDUCTION * index_count as f32 {
                break;
            }
            let finer = levels.last().map_or(0.0, |l| l.error);
            let measured = surface_distance(&points, &mesh.indices, &indices);
            index_count = indices.len();
            levels.push(LodLevel {
                indices,
                error: error.max(measured).max(finer),
            });
        }
        Ok(levels)
    }
}

#[cfg(not(feature = "clusters"))]
mod build {
    use super::*;

    pub(super) fn levels(_: &Mesh) -> Result<Vec<LodLevel>, LodError> {
        Err(LodError::NotBuilt)
    }
}

#[cfg(all(test, feature = "clusters"))]
mod tests {
    use glam::Vec3;

    use super::*;
    use crate::scene::{cube, cylinder, uv_sphere};

    /// How much deeper than its measured error a level's surface may lie between the
    /// measurement's samples.
    const SAMPLING_SLACK: f32 = 1.02;

    /// How deep inside a shape's true surface a point lies.
    type Depth<'a> = dyn Fn(Vec3) -> f32 + 'a;

    fn with_lod(mesh: Mesh) -> Mesh {
        let scene = Scene {
            meshes: vec![mesh],
            ..Scene::empty()
        };
        scene.with_lod().unwrap().meshes.remove(0)
    }

    /// Each level has fewer triangles and no smaller an error than the one before, indexes the
    /// mesh's own vertices, and leaves the full mesh as it was. Mutation: a level written over
    /// the mesh's own indices fails the first assertion.
    #[test]
    fn levels_coarsen_and_keep_the_full_mesh() {
        for mesh in [uv_sphere(32, 16), cylinder(64)] {
            let l = with_lod(mesh.clone());
            assert_eq!(
                l.indices, mesh.indices,
                "{}: full mesh untouched",
                mesh.name
            );
            assert!(l.lods.len() >= 2, "{}: {} levels", mesh.name, l.lods.len());
            let mut triangles = mesh.triangle_count();
            let mut error = 0.0;
            for level in &l.lods {
                assert!(level.triangle_count() < triangles, "{}", mesh.name);
                assert!(level.error >= error && level.error.is_finite());
                assert!(level
                    .indices
                    .iter()
                    .all(|&i| (i as usize) < mesh.vertices.len()));
                triangles = level.triangle_count();
                error = level.error;
            }
        }
        assert!(with_lod(cube()).lods.is_empty(), "too small to simplify");
    }

    /// A level's error bounds how far its surface lies from the full mesh: on a sphere and a
    /// cylinder of radius 5, no point of a level's triangles (sampled twice as finely as the
    /// measurement) lies deeper inside the true surface than its error plus the full mesh's own
    /// deepest point, within the measurement's sampling ([`SAMPLING_SLACK`]: a coarse level's
    /// skewed triangles sag deepest between samples, 1.1 % deeper on the sphere). Mutation:
    /// meshoptimizer's estimate alone fails (1.65× deeper on the sphere, 3.5× on the cylinder).
    #[test]
    fn level_error_bounds_the_surface() {
        let radius = 5.0;
        // How deep inside the surface a point lies: the sphere's, or the cylinder's (axis y,
        // height 1, flat caps).
        let sphere = |p: Vec3| radius - p.length();
        let cylinder_depth =
            |p: Vec3| (radius - Vec3::new(p.x, 0.0, p.z).length()).min(0.5 - p.y.abs());
        let shapes: [(Mesh, Vec3, &Depth); 2] = [
            (uv_sphere(48, 24), Vec3::splat(radius), &sphere),
            (
                cylinder(96),
                Vec3::new(2.0 * radius, 1.0, 2.0 * radius),
                &cylinder_depth,
            ),
        ];
        for (mut mesh, scale, depth) in shapes {
            for v in &mut mesh.vertices {
                v.position = (Vec3::from(v.position) * scale).into();
            }
            let deepest = |indices: &[u32]| {
                indices
                    .chunks(3)
                    .flat_map(|t| {
                        let [a, b, c] =
                            [0, 1, 2].map(|k| Vec3::from(mesh.vertices[t[k] as usize].position));
                        (0..=12).flat_map(move |i| {
                            (0..=12 - i).map(move |j| {
                                a + (b - a) * (i as f32 / 12.0) + (c - a) * (j as f32 / 12.0)
                            })
                        })
                    })
                    .map(depth)
                    .fold(0.0, f32::max)
            };
            let facets = deepest(&mesh.indices);
            for level in with_lod(mesh.clone()).lods {
                let deep = deepest(&level.indices);
                assert!(
                    deep <= level.error * SAMPLING_SLACK + facets + 1e-4,
                    "{} of {} triangles: {deep} deep, error {}",
                    mesh.name,
                    level.triangle_count(),
                    level.error
                );
            }
        }
    }

    #[test]
    fn lod_bounds_are_checked() {
        for bad in [0.0, -1.0, 0.1, 9.0, f32::NAN, f32::INFINITY] {
            let e = LodSettings::new(bad).unwrap_err().to_string();
            assert!(e.contains("lod"), "{e}");
        }
        assert!(LodSettings::new(1.0).is_ok());
    }
}
