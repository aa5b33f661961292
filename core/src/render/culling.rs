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
        let h = &self.hierarchy;
        let centre = world_from_head.transform_point3(Vec3::ZERO);
        let strategy = plan.culling.map_or(Strategy::PerEye, |c| c.strategy);
        let draw_distance = self.draw_distance;
        let view = |distance| CullView {
            eyes: &plan.eyes,
            world_from_head,
            near: plan.near,
            draw_distance: distance,
            frame,
            lens_regions: &self.lens_regions,
        };
        // Both eyes' frusta once a frame, when a slot culls per eye.
        let frusta = plan
            .cull_slots
            .iter()
            .any(|s| matches!(s, DrawSet::VisibleToEye(_)))
            .then(|| StereoFrusta::new(&plan.eyes, world_from_head, plan.near, draw_distance));
        let eye = |e: Eye| {
            let frusta = frusta.as_ref().expect("computed for per-eye slots");
            h.cull(&frusta.eyes[e.index()], centre, draw_distance)
        };
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
        let as_ids = |r: crate::cull::CullResult| -> Vec<u32> {
            r.visible.indices().map(|i| h.ids[i as usize]).collect()
        };
        let mut results: Vec<Vec<u32>> = Vec::with_capacity(plan.cull_slots.len());
        for set in &plan.cull_slots {
            let ids = match set {
                DrawSet::Visible | DrawSet::All => as_ids(strategy.cull(h, &view(draw_distance))),
                DrawSet::VisibleToEye(e) => as_ids(eye(*e)),
                DrawSet::NearField => as_ids(strategy.cull(
                    h,
                    &view(self.near_reach.expect("a near field is planned with MFFR")),
                )),
                DrawSet::FarField => as_ids(h.cull(
                    far.expect("a far field is planned with MFFR"),
                    centre,
                    draw_distance,
                )),
                DrawSet::Fovea => as_ids(fovea_cull()),
                DrawSet::FoveaTagged => {
                    self.in_fovea.clear();
                    self.in_fovea.resize(self.draw_of.len(), false);
                    for id in as_ids(fovea_cull()) {
                        self.in_fovea[id as usize] = true;
                    }
                    let periphery = match plan.culling {
                        Some(_) => as_ids(strategy.cull(h, &view(draw_distance))),
                        None => (0..self.draw_of.len() as u32).collect(),
                    };
                    periphery
                        .into_iter()
                        .map(|id| {
                            if self.in_fovea[id as usize] {
                                id | FOVEA_TAG
                            } else {
                                id
                            }
                        })
                        .collect()
                }
            };
            results.push(ids);
        }
        self.ids.clear();
        for (set, result) in self.sets.iter_mut().zip(&results) {
            set.clear();
            self.buckets.iter_mut().for_each(Vec::clear);
            for &id in result {
                let instance = (id & !FOVEA_TAG) as usize;
                self.buckets[self.draw_of[instance] as usize].push(id);
            }
            for (bucket, draw) in self.buckets.iter().zip(draws) {
                if bucket.is_empty() {
                    continue;
                }
                set.push(Draw {
                    mesh: draw.mesh,
                    first_instance: self.ids.len() as u32,
                    instance_count: bucket.len() as u32,
                });
                self.ids.extend_from_slice(bucket);
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
