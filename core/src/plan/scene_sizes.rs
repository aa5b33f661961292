//! What a plan sizes from its scene: the instance buffers (each frame slot's copy when
//! instances move, room for spare ones, the culled id lists), the clusters as culled or drawn
//! whole, and the levels of detail.

use super::model::*;
use super::steps::Step;
use super::{DeviceCaps, RenderConfig};
use crate::scene::Scene;

/// What the instances need: each frame slot's copy when they move; for culled draw sets, the
/// scene's clusters as culled (or drawn whole, and why) and the id buffer sized for them.
pub(super) fn plan_instance_buffers(
    plan: &mut FramePlan,
    scene: &Scene,
    caps: &DeviceCaps,
    config: &RenderConfig,
) {
    // The scene's instances and the spare ones (each spare of a clustered mesh culls as
    // its clusters).
    let spare = config.spare_instances as usize;
    if config.moving_instances {
        let bytes = std::mem::size_of::<crate::scene::Instance>() * plan.scene_instances.max(1);
        plan.buffers.push(BufferPlan {
            name: MOVING_INSTANCES,
            bytes: bytes as u64,
        });
    }
    if plan.cull_slots.is_empty() {
        return;
    }
    plan.clusters = cluster_plan(scene).map(|c| ClusterPlan {
        drawn_whole: clusters_drawn_whole(plan, caps),
        ..c
    });
    let entries = if plan.clusters.is_some_and(|c| c.culled()) {
        let per_mesh = scene.meshes.iter().map(|m| m.clusters.len().max(1));
        scene.cull_entries() + spare * per_mesh.sum::<usize>()
    } else {
        plan.scene_instances
    };
    // Near and far sets of one frame, each at most every instance (every cluster of a
    // clustered one).
    plan.buffers.push(BufferPlan {
        name: INSTANCE_IDS,
        bytes: 2 * 4 * (entries.max(1) as u64),
    });
}

/// Spare instances planned for `scene`: `spare` of each of its meshes
/// ([`RenderConfig::spare_instances`]).
pub(super) fn spare_total(scene: &Scene, spare: u32) -> usize {
    spare as usize * scene.meshes.len()
}

/// Level of detail, when asked for and the scene has levels.
pub(crate) fn lod_plan(config: &RenderConfig, scene: &Scene) -> Option<LodPlan> {
    let (levels, meshes) = scene.lod_counts();
    config.lod.filter(|_| levels > 0).map(|l| LodPlan {
        max_error_px: l.max_error_px,
        levels,
        meshes,
    })
}

/// The scene's clusters, when it has any.
pub(crate) fn cluster_plan(scene: &Scene) -> Option<ClusterPlan> {
    let (clusters, meshes) = scene.cluster_counts();
    let max_triangles = scene
        .meshes
        .iter()
        .flat_map(|m| &m.clusters)
        .map(|c| c.index_count / 3)
        .max()?;
    Some(ClusterPlan {
        clusters,
        meshes,
        max_triangles,
        drawn_whole: None,
    })
}

/// Why a plan's clusters must be drawn whole: lavapipe 22.3's multiview clipping bug
/// (`DriverQuirks::multiview_clipping_drops_views`) draws a mesh split into several draws
/// differently from the mesh in one (measured on the atrium: up to 1.5k pixels of a 128² eye
/// change, whether or not any cluster is culled; identical on 25.0), so a multiview pass that
/// culls keeps whole meshes there.
fn clusters_drawn_whole(plan: &FramePlan, caps: &DeviceCaps) -> Option<&'static str> {
    let multiview_culls = plan
        .passes
        .iter()
        .filter(|p| p.view_mask.count_ones() > 1)
        .flat_map(|p| &p.steps)
        .any(|s| {
            matches!(
                s,
                Step::Scene {
                    cull_slot: Some(_),
                    ..
                }
            )
        });
    (caps.quirks.multiview_clipping_drops_views && multiview_culls)
        .then_some("this driver's multiview clipping bug draws a mesh split into draws differently")
}
