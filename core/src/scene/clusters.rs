//! Clusters: a mesh's triangles in runs of at most 32 to 256 (124 by default), each with a bounding sphere and a cone of its normals, so that a draw set culls the parts of
//! a large mesh its views cannot see (Di Donato 2017 §3.2: four views raise the vertex load until the
//! GPU is vertex-bound). meshoptimizer builds them: its greedy builder keeps a cluster's
//! triangles adjacent and facing alike, which is what makes the bounds tight.
//!
//! A clustered mesh's index buffer is reordered so that each cluster is one contiguous range:
//! drawn whole, the mesh draws the same triangles as before, in cluster order.

use glam::{DMat4, DVec3, Mat4, Vec3};

use super::{Instance, Mesh, Scene};
use crate::cull::Sphere;
use crate::vocab::ConfigError;

/// The triangles per cluster foveate builds when asked without a size: meshoptimizer's
/// recommendation for 64 vertices (its builder wants a multiple of four).
pub const DEFAULT_CLUSTER_TRIANGLES: u32 = 124;
/// The sizes `--clusters` accepts: meshoptimizer's limit is 512 triangles and 256 vertices; below
/// 32 a cluster's draw costs more than the triangles it can save.
pub const CLUSTER_TRIANGLES_RANGE: std::ops::RangeInclusive<u32> = 32..=256;

/// One run of a mesh's triangles, culled as a unit.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct Cluster {
    /// Where the run starts in the mesh's index buffer, and how long it is (three per triangle).
    pub first_index: u32,
    /// Indices in the run (three per triangle).
    pub index_count: u32,
    /// A sphere around its vertices, in the mesh's space.
    pub bounds: Sphere,
    /// The cone its triangles' normals fall in; `None` when they point too many ways to ever
    /// all face away.
    pub normals: Option<NormalCone>,
}

/// A cone around a cluster's triangles' normals, as meshoptimizer states it: seen from a point p
/// with `dot(c − p, axis) ≥ cutoff·|c − p| + r` (c, r the cluster's bounding sphere), every
/// triangle faces away (Real-Time Rendering 4th ed. §19.3).
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct NormalCone {
    /// The cone's unit axis, in the mesh's space.
    pub axis: Vec3,
    /// The cone's cutoff (see above).
    pub cutoff: f32,
}

/// How a scene's large meshes are split.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub struct ClusterSettings {
    /// At most this many triangles per cluster; meshes with no more stay whole.
    pub max_triangles: u32,
}

impl ClusterSettings {
    /// At most `max_triangles` per cluster: a multiple of 4 in the range the error names.
    pub fn new(max_triangles: u32) -> Result<Self, ConfigError> {
        if !CLUSTER_TRIANGLES_RANGE.contains(&max_triangles) || !max_triangles.is_multiple_of(4) {
            return Err(ConfigError::new(
                "clusters",
                max_triangles,
                format!(
                    "a multiple of 4 in {}..={} triangles per cluster",
                    CLUSTER_TRIANGLES_RANGE.start(),
                    CLUSTER_TRIANGLES_RANGE.end()
                ),
            ));
        }
        Ok(ClusterSettings { max_triangles })
    }
}

impl Default for ClusterSettings {
    fn default() -> Self {
        ClusterSettings {
            max_triangles: DEFAULT_CLUSTER_TRIANGLES,
        }
    }
}

/// Why a scene could not be clustered.
#[derive(Debug, thiserror::Error)]
pub enum ClusterError {
    #[error("clusters and level of detail: this build of foveate has no meshoptimizer to build them (the `clusters` feature is off; the Android library is built without it)")]
    /// Built without the `clusters` feature.
    NotBuilt,
}

impl Scene {
    /// The scene with every mesh of more than `settings.max_triangles` triangles split into
    /// clusters (its index buffer reordered cluster by cluster); smaller meshes stay whole, as
    /// instance culling already culls them as a unit.
    pub fn with_clusters(mut self, settings: ClusterSettings) -> Result<Scene, ClusterError> {
        for mesh in &mut self.meshes {
            if mesh.clusters.is_empty() && mesh.triangle_count() > settings.max_triangles as usize {
                build::cluster(mesh, settings)?;
            }
        }
        Ok(self)
    }

    /// The most ids one culled draw set can hold: each instance once, or once per cluster of
    /// a clustered mesh.
    pub fn cull_entries(&self) -> usize {
        self.batches
            .iter()
            .map(|b| b.instances.len() * self.meshes[b.mesh].clusters.len().max(1))
            .sum()
    }

    /// Clusters over all meshes, and the meshes that have them.
    pub fn cluster_counts(&self) -> (usize, usize) {
        let clustered = self.meshes.iter().filter(|m| !m.clusters.is_empty());
        (
            clustered.clone().map(|m| m.clusters.len()).sum(),
            clustered.count(),
        )
    }
}

/// Where an instance's clusters are: its model matrix, and the inverse that takes a viewpoint
/// into the mesh's space, where the cones are. Whether a triangle faces a point is kept by any
/// affine map of positive determinant (the sign of det[v1 − v0, v2 − v0, p − v0] is), so the
/// cones hold under rotation and non-uniform scale alike; a mirror swaps front and back, so a
/// mirrored instance's clusters are never dropped for their back faces.
#[derive(Clone, Copy, Debug)]
pub struct PlacedClusters {
    model: Mat4,
    scale: f32,
    mesh_from_world: Option<DMat4>,
}

impl PlacedClusters {
    /// The clusters of `instance`.
    pub fn new(instance: &Instance) -> Self {
        let model = instance.model;
        let model64 = model.as_dmat4();
        PlacedClusters {
            model,
            scale: instance.max_scale(),
            mesh_from_world: (model64.determinant() > 0.0).then(|| model64.inverse()),
        }
    }

    /// The cluster's bounding sphere in the world.
    pub fn bounds(&self, c: &Cluster) -> Sphere {
        Sphere::new(
            self.model.transform_point3(c.bounds.center),
            c.bounds.radius * self.scale,
        )
    }

    /// The viewpoints `eyes` in the mesh's space, for [`PlacedClusters::faces_away`]; `None`
    /// when the instance is mirrored.
    pub fn local_eyes(&self, eyes: &[Vec3; 2]) -> Option<[DVec3; 2]> {
        let m = self.mesh_from_world?;
        Some(eyes.map(|e| m.transform_point3(e.as_dvec3())))
    }

    /// Whether every triangle of the cluster faces away from both viewpoints (from
    /// [`PlacedClusters::local_eyes`]), so back-face culling would discard all of it:
    /// conservative, never true when a triangle may face one.
    pub fn faces_away(c: &Cluster, local_eyes: &Option<[DVec3; 2]>) -> bool {
        let (Some(cone), Some(eyes)) = (c.normals, local_eyes) else {
            return false;
        };
        let centre = c.bounds.center.as_dvec3();
        let axis = cone.axis.as_dvec3();
        let cutoff = cone.cutoff as f64 + CONE_SLACK;
        eyes.iter().all(|&eye| {
            let to_centre = centre - eye;
            to_centre.dot(axis) >= cutoff * to_centre.length() + c.bounds.radius as f64
        })
    }
}

/// Added to a cone's cutoff: meshoptimizer derives cones from `f32` normals, so a triangle at
/// the cone's edge may lean this much further (about 0.06°) than the cone says.
const CONE_SLACK: f64 = 1e-3;

#[cfg(feature = "clusters")]
pub(super) use build::positions;

#[cfg(feature = "clusters")]
mod build {
    use super::*;
    use crate::scene::Vertex;

    pub(super) fn cluster(mesh: &mut Mesh, settings: ClusterSettings) -> Result<(), ClusterError> {
        let positions = positions(mesh);
        let meshlets = meshopt::build_meshlets(
            &mesh.indices,
            &positions,
            max_vertices(settings),
            settings.max_triangles as usize,
            CONE_WEIGHT,
        );
        let mut indices = Vec::with_capacity(mesh.indices.len());
        let mut clusters = Vec::with_capacity(meshlets.len());
        for meshlet in meshlets.iter() {
            let first_index = indices.len() as u32;
            indices.extend(
                meshlet
                    .triangles
                    .iter()
                    .map(|&t| meshlet.vertices[t as usize]),
            );
            let run = &indices[first_index as usize..];
            let b = meshopt::compute_cluster_bounds(run, &positions);
            let centre = Vec3::from(b.center);
            // At least the farthest vertex as `f32` measures it, whatever meshoptimizer rounded.
            let reach = run
                .iter()
                .map(|&i| Vec3::from(mesh.vertices[i as usize].position).distance(centre))
                .fold(b.radius, f32::max);
            clusters.push(Cluster {
                first_index,
                index_count: run.len() as u32,
                bounds: Sphere::new(centre, reach * (1.0 + 4.0 * f32::EPSILON)),
                // meshoptimizer's cutoff of 1: the normals span more than a half-space.
                normals: (b.cone_cutoff < 1.0).then(|| NormalCone {
                    axis: Vec3::from(b.cone_axis),
                    cutoff: b.cone_cutoff,
                }),
            });
        }
        mesh.indices = indices;
        mesh.clusters = clusters;
        Ok(())
    }

    /// The mesh's vertex positions as meshoptimizer reads them.
    pub(in crate::scene) fn positions(mesh: &Mesh) -> meshopt::VertexDataAdapter<'_> {
        let bytes = meshopt::typed_to_bytes(&mesh.vertices);
        meshopt::VertexDataAdapter::new(bytes, std::mem::size_of::<Vertex>(), 0)
            .expect("Vertex is a whole number of strides with its position first")
    }

    /// The vertices a cluster may reference: about what a patch of `max_triangles` on a
    /// regular grid needs, at least meshoptimizer's recommended 64.
    fn max_vertices(settings: ClusterSettings) -> usize {
        (settings.max_triangles as usize / 2 + 2).clamp(64, 255)
    }

    /// How much meshoptimizer's builder favours triangles facing alike over compact clusters:
    /// its documentation's value for back-face culling.
    const CONE_WEIGHT: f32 = 0.25;
}

#[cfg(not(feature = "clusters"))]
mod build {
    use super::*;

    pub(super) fn cluster(_: &mut Mesh, _: ClusterSettings) -> Result<(), ClusterError> {
        Err(ClusterError::NotBuilt)
    }
}

#[cfg(all(test, feature = "clusters"))]
mod tests {
    use glam::Quat;
    use proptest::prelude::*;

    use super::*;
    use crate::scene::{cylinder, ground_grid, uv_sphere};

    fn clustered(mesh: Mesh) -> Mesh {
        let scene = Scene {
            meshes: vec![mesh],
            ..Scene::empty()
        };
        let mut scene = scene.with_clusters(ClusterSettings::default()).unwrap();
        scene.meshes.remove(0)
    }

    /// Each triangle with its vertex order rotated to start at its smallest index: the same
    /// triangle, wound the same way.
    fn triangles(indices: &[u32]) -> Vec<[u32; 3]> {
        let mut t: Vec<[u32; 3]> = indices
            .chunks(3)
            .map(|t| {
                let k = (0..3).min_by_key(|&k| t[k]).unwrap();
                [t[k], t[(k + 1) % 3], t[(k + 2) % 3]]
            })
            .collect();
        t.sort();
        t
    }

    /// Clustering reorders triangles and nothing else: the same triangles, wound the same way,
    /// each in exactly one cluster of at most the asked size, inside its cluster's sphere.
    /// Mutation: a triangle's vertices reversed in the reorder fails the winding.
    #[test]
    fn clusters_partition_the_mesh() {
        for mesh in [uv_sphere(32, 16), ground_grid(26.0, 0.25), cylinder(64)] {
            let c = clustered(mesh.clone());
            assert!(
                c.clusters.len() > 1,
                "{}: {} clusters",
                mesh.name,
                c.clusters.len()
            );
            assert_eq!(
                triangles(&c.indices),
                triangles(&mesh.indices),
                "{}",
                mesh.name
            );
            let mut next = 0;
            for cluster in &c.clusters {
                assert_eq!(cluster.first_index, next, "contiguous, in order");
                assert!(cluster.index_count / 3 <= DEFAULT_CLUSTER_TRIANGLES);
                next += cluster.index_count;
                let run = &c.indices[cluster.first_index as usize..next as usize];
                for &i in run {
                    let p = Vec3::from(c.vertices[i as usize].position);
                    assert!(p.distance(cluster.bounds.center) <= cluster.bounds.radius);
                }
            }
            assert_eq!(next as usize, c.indices.len());
        }
    }

    #[test]
    fn cluster_sizes_are_checked() {
        for bad in [0, 30, 126, 260, 512] {
            let e = ClusterSettings::new(bad).unwrap_err().to_string();
            assert!(
                e.contains("clusters") && e.contains(&bad.to_string()),
                "{e}"
            );
        }
        assert!(ClusterSettings::new(64).is_ok());
    }

    /// Whether a triangle of the placed mesh faces `eye` (f64): the oracle of back-face culling.
    fn faces(model: Mat4, mesh: &Mesh, t: &[u32], eye: Vec3) -> bool {
        let m = model.as_dmat4();
        let [a, b, c] = [0, 1, 2].map(|k| {
            m.transform_point3(Vec3::from(mesh.vertices[t[k] as usize].position).as_dvec3())
        });
        let n = (b - a).cross(c - a);
        n.dot(eye.as_dvec3() - a) > 0.0
    }

    proptest! {
        #![proptest_config(ProptestConfig::with_cases(96))]

        /// A cluster dropped for its back faces has no triangle facing either eye, under any
        /// rotation, non-uniform scale and mirror, with eyes anywhere around it — close to its
        /// triangles' planes (grazing) included. Mutation: the cone's axis turned around fails.
        #[test]
        fn back_face_cones_are_conservative(
            axis in (-1.0f32..1.0, -1.0f32..1.0, 0.1f32..1.0),
            angle in 0.0f32..6.3,
            scale in (0.2f32..3.0, 0.2f32..3.0, 0.2f32..3.0),
            mirror in any::<bool>(),
            eyes in prop::array::uniform1((-3.0f32..3.0, -3.0f32..3.0, -3.0f32..3.0)),
            grazing in 0.0f32..1e-3,
        ) {
            let mesh = clustered(uv_sphere(24, 12));
            let scale = Vec3::new(scale.0, scale.1, if mirror { -scale.2 } else { scale.2 });
            let rotation = Quat::from_axis_angle(Vec3::new(axis.0, axis.1, axis.2).normalize(), angle);
            let model = Mat4::from_scale_rotation_translation(scale, rotation, Vec3::new(1.0, -2.0, 0.5));
            let placed = PlacedClusters::new(&Instance::new(model, Vec3::ONE));
            // One eye on a cluster's own plane, nudged by `grazing`, the other anywhere.
            let c0 = &mesh.clusters[0];
            let t0 = &mesh.indices[c0.first_index as usize..c0.first_index as usize + 3];
            let on_plane = {
                let m = model.as_dmat4();
                let [a, b, c] = [0, 1, 2].map(|k| m.transform_point3(Vec3::from(mesh.vertices[t0[k] as usize].position).as_dvec3()));
                let n = (b - a).cross(c - a).normalize();
                (a + (b - a) * 0.3 + (c - a) * 0.3 - n * grazing as f64 + (b - a).normalize() * 20.0).as_vec3()
            };
            let other = eyes[0];
            let eyes = [on_plane, Vec3::new(other.0, other.1, other.2) * 10.0];
            let local = placed.local_eyes(&eyes);
            for c in &mesh.clusters {
                if PlacedClusters::faces_away(c, &local) {
                    let run = &mesh.indices[c.first_index as usize..(c.first_index + c.index_count) as usize];
                    for t in run.chunks(3) {
                        for &eye in &eyes {
                            prop_assert!(!faces(model, &mesh, t, eye), "a dropped cluster faces {eye}");
                        }
                    }
                }
            }
            prop_assert!(!mirror || mesh.clusters.iter().all(|c| !PlacedClusters::faces_away(c, &local)));
        }
    }

    /// The cones do cull: from outside a sphere, some of its clusters face away. (Few: a
    /// sphere's clusters of 124 triangles span wide cones, and the sphere-bounded test is the
    /// looser of meshoptimizer's two.)
    #[test]
    fn cones_cull_the_far_side() {
        let mesh = clustered(uv_sphere(32, 16));
        let placed = PlacedClusters::new(&Instance::new(
            Mat4::from_scale(Vec3::splat(2.0)),
            Vec3::ONE,
        ));
        let local = placed.local_eyes(&[Vec3::new(0.0, 0.0, 20.0), Vec3::new(0.1, 0.0, 20.0)]);
        let away: Vec<&Cluster> = mesh
            .clusters
            .iter()
            .filter(|c| PlacedClusters::faces_away(c, &local))
            .collect();
        assert!(
            !away.is_empty(),
            "none of {} face away",
            mesh.clusters.len()
        );
        assert!(
            away.iter().all(|c| c.bounds.center.z < 0.0),
            "only the far side"
        );
    }
}
