//! Culling a draw set's clusters: after instance culling has kept an instance of a clustered
//! mesh, each of its clusters is tested against the set's own frustum, its reach, and the
//! back-face cones seen from the set's projection centres.

use glam::Vec3;

use crate::cull::Frustum;
use crate::scene::{Cluster, PlacedClusters};

/// What one draw set's clusters are tested against.
pub(super) struct ClusterTest {
    pub frustum: Frustum,
    /// The projection centres of the set's views (the same one twice for a single view): a
    /// cluster is dropped for its back faces only when it faces away from both (the pipeline
    /// culls back faces in every scene pass).
    pub eyes: [Vec3; 2],
    /// Distance culling, as the instance culling of the same set: the ball of radius
    /// `distance` around `centre`.
    pub centre: Vec3,
    pub distance: f32,
}

impl ClusterTest {
    /// The instance's clusters the set may see (conservative), by index.
    pub fn kept<'a>(
        &'a self,
        placed: &'a PlacedClusters,
        clusters: &'a [Cluster],
    ) -> impl Iterator<Item = usize> + 'a {
        let eyes = placed.local_eyes(&self.eyes);
        clusters.iter().enumerate().filter_map(move |(j, c)| {
            let bounds = placed.bounds(c);
            let reach = self.distance + bounds.radius;
            let seen = (bounds.center - self.centre).length_squared() <= reach * reach
                && self.frustum.intersects_sphere(&bounds)
                && !PlacedClusters::faces_away(c, &eyes);
            seen.then_some(j)
        })
    }
}
