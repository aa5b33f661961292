//! Per-frame culling in the renderer (seed 000 §3): the scene's instances in the chunk-and-octree
//! hierarchy, culled into the plan's cull slots — both eyes' set, each eye's own set (per-eye
//! culling of a two-pass frame), MFFR's near and far fields, or a foveated frame's fovea set
//! (alone, or as tags on the periphery's) — and written as the instance ids the indirect scene
//! shader reads.

use glam::{Mat4, Vec3};

use crate::cull::{
    CullHierarchy, CullView, Frustum, HierarchyParams, StereoFrusta, Strategy, Superfrustum,
};
use crate::plan::{DrawSet, FramePlan};
use crate::scene::{Draw, Scene};
use crate::view::{Eye, EyeParams, FovTangents, LensRegion};

/// The top bit of a culled id in the one-pass fovea layout: the fovea superfrustum keeps the
/// instance (`FOVEA_TAG` in `shaders/scene.vert`).
pub(crate) const FOVEA_TAG: u32 = 1 << 31;

pub(crate) struct FrameCulling {
    hierarchy: CullHierarchy,
    /// Which of the scene's draws (meshes) each instance belongs to.
    draw_of: Vec<u32>,
    lens_regions: [LensRegion; 2],
    /// Distance culling radius: the configured draw distance, or without one the eyes'
    /// frusta's far corners, so nothing in them is dropped.
    draw_distance: f32,
    /// With MFFR, how far from the head the near field reaches: everything in front of the
    /// split, whose far corners lie farther from the head than the split itself.
    near_reach: Option<f32>,
    buckets: Vec<Vec<u32>>,
    /// This frame's fovea set, by instance (one-pass fovea layout).
    in_fovea: Vec<bool>,
    /// This frame's ids: slot 0's, then slot 1's.
    pub ids: Vec<u32>,
    /// This frame's draws of each of the plan's cull slots, each indexing its part of `ids`.
    pub sets: Vec<Vec<Draw>>,
}

impl FrameCulling {
    pub fn new(scene: &Scene, draws: &[Draw], plan: &FramePlan) -> Self {
        let mut draw_of = vec![0; scene.instance_count()];
        for (k, d) in draws.iter().enumerate() {
            let range = d.first_instance as usize..(d.first_instance + d.instance_count) as usize;
            draw_of[range].fill(k as u32);
        }
        let draw_distance = plan.culling.map_or_else(
            || reach(&plan.eyes, plan.near, plan.far),
            |c| c.draw_distance,
        );
        FrameCulling {
            hierarchy: CullHierarchy::build(&scene.instance_spheres(), HierarchyParams::default()),
            draw_of,
            lens_regions: Eye::BOTH.map(|e| plan.hmd.lens_region(plan.eyes.fov(e))),
            draw_distance,
            near_reach: plan
                .mffr
                .map(|m| reach(&plan.eyes, plan.near, m.split_m).min(draw_distance)),
            buckets: vec![Vec::new(); draws.len()],
            in_fovea: Vec::new(),
            ids: Vec::new(),
            sets: vec![Vec::new(); plan.cull_slots.len()],
        }
    }

    /// Culls one frame into [`FrameCulling::sets`], one set per cull slot of the plan. `far` is
    /// the MFFR far view's frustum, when MFFR is planned; `fovea` the fovea views' tangents,
    /// when foveation is.
    pub fn cull(
        &mut self,
        plan: &FramePlan,
        world_from_head: Mat4,
        frame: u64,
        far: Option<&Frustum>,
        fovea: Option<&[FovTangents; 2]>,
        draws: &[Draw],
    ) {
        let FrameCulling {
            hierarchy: h,
            draw_of,
            lens_regions,
            draw_distance,
            near_reach,
            buckets,
            in_fovea,
            ids,
            sets,
        } = self;
        let draw_distance = *draw_distance;
        let centre = world_from_head.transform_point3(Vec3::ZERO);
        let strategy = plan.culling.map_or(Strategy::PerEye, |c| c.strategy);
        let view = |distance| CullView {
            eyes: &plan.eyes,
            world_from_head,
            near: plan.near,
            draw_distance: distance,
            frame,
            lens_regions,
        };
        // Both eyes' frusta once a frame, when a slot culls per eye.
        let frusta = plan
            .cull_slots
            .iter()
            .any(|s| matches!(s, DrawSet::VisibleToEye(_)))
            .then(|| StereoFrusta::new(&plan.eyes, world_from_head, plan.near, draw_distance));
        // The superfrustum around both fovea frusta (the fovea windows as the eyes' fields).
        let fovea_cull = || {
            let fovea = fovea.expect("fovea sets are planned with foveation");
            let eyes = EyeParams {
                left_fov: fovea[0],
                right_fov: fovea[1],
                ..plan.eyes
            };
            let sf = Superfrustum::new(&eyes, world_from_head, plan.near, draw_distance);
            h.cull(&sf.frustum, centre, draw_distance)
        };
        ids.clear();
        for (set, draw_set) in sets.iter_mut().zip(&plan.cull_slots) {
            // What the slot draws (`None`: every instance), and whether ids carry fovea tags.
            let (kept, tagged) = match draw_set {
                DrawSet::Visible | DrawSet::All => {
                    (Some(strategy.cull(h, &view(draw_distance))), false)
                }
                DrawSet::VisibleToEye(e) => {
                    let frusta = frusta.as_ref().expect("computed for per-eye slots");
                    (
                        Some(h.cull(&frusta.eyes[e.index()], centre, draw_distance)),
                        false,
                    )
                }
                DrawSet::NearField => {
                    let reach = near_reach.expect("a near field is planned with MFFR");
                    (Some(strategy.cull(h, &view(reach))), false)
                }
                DrawSet::FarField => {
                    let far = far.expect("a far field is planned with MFFR");
                    (Some(h.cull(far, centre, draw_distance)), false)
                }
                DrawSet::Fovea => (Some(fovea_cull()), false),
                DrawSet::FoveaTagged => {
                    in_fovea.clear();
                    in_fovea.resize(draw_of.len(), false);
                    for i in fovea_cull().visible.indices() {
                        in_fovea[h.ids[i as usize] as usize] = true;
                    }
                    let periphery = plan.culling.map(|_| strategy.cull(h, &view(draw_distance)));
                    (periphery, true)
                }
            };
            buckets.iter_mut().for_each(Vec::clear);
            let mut keep = |id: u32| {
                let tag = if tagged && in_fovea[id as usize] {
                    FOVEA_TAG
                } else {
                    0
                };
                buckets[draw_of[id as usize] as usize].push(id | tag);
            };
            match &kept {
                Some(r) => r.visible.indices().for_each(|i| keep(h.ids[i as usize])),
                None => (0..draw_of.len() as u32).for_each(keep),
            }
            set.clear();
            for (bucket, draw) in buckets.iter().zip(draws) {
                if bucket.is_empty() {
                    continue;
                }
                set.push(Draw {
                    mesh: draw.mesh,
                    first_instance: ids.len() as u32,
                    instance_count: bucket.len() as u32,
                });
                ids.extend_from_slice(bucket);
            }
        }
    }
}

/// The farthest any point of the eyes' frusta up to depth `depth` lies from the head.
fn reach(eyes: &EyeParams, near: f32, depth: f32) -> f32 {
    StereoFrusta::new(eyes, Mat4::IDENTITY, near, depth)
        .eyes
        .iter()
        .flat_map(Frustum::world_corners)
        .map(Vec3::length)
        .fold(depth, f32::max)
}
