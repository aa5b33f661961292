//! Per-frame culling in the renderer (Preißner 2020 §3): the scene's instances in the chunk-and-octree
//! hierarchy, culled into the plan's cull slots — both eyes' set, each eye's own set (per-eye
//! culling of a two-pass frame), MFFR's near and far fields, or a foveated frame's fovea set
//! (alone, or as tags on the periphery's) — and written as the instance ids the indirect scene
//! shader reads. With level of detail each set also chooses, per instance, the level its views'
//! pixels cannot tell from the full mesh.

use glam::{Mat4, Vec3};

use super::cull_slots::{CullFrame, FrameCull, Selection};
use super::lod_select::lod_level;
use super::scene_buffers::SceneBuffers;
use crate::cull::{CullHierarchy, Frustum, HierarchyParams, Sphere, StereoFrusta};
use crate::plan::{DrawSet, FramePlan, Step};
use crate::scene::{Cluster, Draw, PlacedClusters, Scene};
use crate::view::{Eye, EyeParams, FovTangents, LensRegion};

/// The top bit of a culled id in the one-pass fovea layout: the fovea superfrustum keeps the
/// instance (`FOVEA_TAG` in `shaders/scene.vert`).
pub(crate) const FOVEA_TAG: u32 = 1 << 31;

pub(crate) struct FrameCulling {
    hierarchy: CullHierarchy,
    /// Which of the scene's draws (meshes) each instance belongs to.
    draw_of: Vec<u32>,
    /// Whether each instance is in the scene (empty: all are); absent ones are never kept.
    present: Vec<bool>,
    /// Each instance of a clustered mesh placed (`None`: its mesh is drawn whole).
    placed: Vec<Option<PlacedClusters>>,
    /// Each instance of a mesh with levels: its bounding sphere and its longest axis's scale
    /// (empty without level of detail).
    lod_bounds: Vec<Option<(Sphere, f32)>>,
    /// Each draw's buckets: the whole mesh first, then one per cluster of its mesh.
    draw_buckets: Vec<DrawBuckets>,
    /// Each cull slot: whether fovea views draw it untagged (a foveated frame's unculled set,
    /// drawn by all four views of the one-pass layout or by both passes of the two-pass one),
    /// so its levels must satisfy their pixels too.
    fovea_draws: Vec<bool>,
    lens_regions: [LensRegion; 2],
    /// Distance culling radius: the configured draw distance, or without one the eyes'
    /// frusta's far corners, so nothing in them is dropped.
    draw_distance: f32,
    /// With MFFR, how far from the head the near field reaches: everything in front of the
    /// split, whose far corners lie farther from the head than the split itself.
    near_reach: Option<f32>,
    /// Culled ids by bucket ([`FrameCulling::draw_buckets`]), each bucket one draw.
    buckets: Vec<Vec<u32>>,
    /// This frame's fovea set, by instance (one-pass fovea layout).
    in_fovea: Vec<bool>,
    /// Which clusters of one instance the fovea views see (one-pass fovea layout).
    seen_by_fovea: Vec<bool>,
    /// This frame's ids: slot 0's, then slot 1's.
    pub ids: Vec<u32>,
    /// This frame's draws of each of the plan's cull slots, each indexing its part of `ids`.
    pub sets: Vec<Vec<Draw>>,
}

/// Where one draw's ids go: bucket `first` draws the whole mesh (range `mesh`), buckets
/// `first + 1 + j` its cluster j (range `first_cluster + j`), then one per simplified level
/// (ranges from `first_lod`).
struct DrawBuckets {
    first: usize,
    mesh: usize,
    first_cluster: usize,
    clusters: Vec<Cluster>,
    first_lod: usize,
    /// Its mesh's levels' errors, finer first.
    lod_errors: Vec<f32>,
}

impl DrawBuckets {
    /// The bucket of simplified level `level` (1: the first).
    fn lod_bucket(&self, level: usize) -> usize {
        self.first + self.clusters.len() + level
    }

    /// The mesh ranges its buckets draw, in bucket order.
    fn ranges(&self) -> impl Iterator<Item = usize> + '_ {
        std::iter::once(self.mesh)
            .chain((0..self.clusters.len()).map(|j| self.first_cluster + j))
            .chain((0..self.lod_errors.len()).map(|k| self.first_lod + k))
    }
}

impl FrameCulling {
    pub fn new(scene: &Scene, buffers: &SceneBuffers, plan: &FramePlan) -> Self {
        let draws = &buffers.draws;
        let mut draw_of = vec![0; scene.instance_count()];
        for (k, d) in draws.iter().enumerate() {
            let range = d.first_instance as usize..(d.first_instance + d.instance_count) as usize;
            draw_of[range].fill(k as u32);
        }
        let mut first = 0;
        let draw_buckets: Vec<DrawBuckets> = draws
            .iter()
            .map(|d| {
                let mesh = &scene.meshes[d.mesh];
                let b = DrawBuckets {
                    first,
                    mesh: d.mesh,
                    first_cluster: buffers.first_cluster[d.mesh],
                    clusters: mesh.clusters.clone(),
                    first_lod: buffers.first_lod[d.mesh],
                    lod_errors: if plan.lod.is_some() {
                        mesh.lods.iter().map(|l| l.error).collect()
                    } else {
                        Vec::new()
                    },
                };
                first += b.ranges().count();
                b
            })
            .collect();
        let culled = plan.clusters.is_some_and(|c| c.culled());
        let instances = scene.flat_instances();
        let spheres = scene.instance_spheres();
        let placed = instances
            .iter()
            .zip(&draw_of)
            .map(|(i, &k)| {
                let clustered = culled && !draw_buckets[k as usize].clusters.is_empty();
                clustered.then(|| PlacedClusters::new(i))
            })
            .collect();
        let lod_bounds = instances
            .iter()
            .zip(&draw_of)
            .zip(&spheres)
            .map(|((i, &k), &s)| {
                let levels = !draw_buckets[k as usize].lod_errors.is_empty();
                levels.then(|| (s, i.max_scale()))
            })
            .collect();
        let draw_distance = plan.culling.map_or_else(
            || reach(&plan.eyes, plan.near, plan.far),
            |c| c.draw_distance,
        );
        FrameCulling {
            fovea_draws: (0..plan.cull_slots.len())
                .map(|slot| fovea_draws(plan, slot))
                .collect(),
            hierarchy: CullHierarchy::build(&spheres, HierarchyParams::default()),
            draw_of,
            present: Vec::new(),
            placed,
            lod_bounds,
            draw_buckets,
            lens_regions: Eye::BOTH.map(|e| plan.hmd.lens_region(plan.eyes.fov(e))),
            draw_distance,
            near_reach: plan
                .mffr
                .map(|m| reach(&plan.eyes, plan.near, m.split_m).min(draw_distance)),
            buckets: vec![Vec::new(); first],
            in_fovea: Vec::new(),
            seen_by_fovea: Vec::new(),
            ids: Vec::new(),
            sets: vec![Vec::new(); plan.cull_slots.len()],
        }
    }

    /// The same culling for a scene of which only the instances `present` says are in it.
    pub fn with_present(self, present: &[bool]) -> Self {
        FrameCulling {
            present: present.to_vec(),
            ..self
        }
    }

    /// Culls one frame into [`FrameCulling::sets`], one set per cull slot of the plan. `far` is
    /// the MFFR far view's frustum, when MFFR is planned; `fovea` the fovea views' tangents,
    /// when foveation is. Instances of clustered meshes are then culled cluster by cluster
    /// against the slot's own frustum.
    pub fn cull(
        &mut self,
        plan: &FramePlan,
        world_from_head: Mat4,
        frame: u64,
        far: Option<&Frustum>,
        fovea: Option<&[FovTangents; 2]>,
    ) {
        let at = FrameCull {
            plan,
            world_from_head,
            frame,
            far,
            fovea,
        };
        let frame = CullFrame::new(at, self.lens_regions, self.draw_distance, self.near_reach);
        self.ids.clear();
        for (slot, &draw_set) in plan.cull_slots.iter().enumerate() {
            let selection = frame.select(
                &self.hierarchy,
                draw_set,
                self.fovea_draws[slot],
                &mut self.in_fovea,
                self.draw_of.len(),
            );
            let tagged = draw_set == DrawSet::FoveaTagged;
            self.fill_buckets(&selection, tagged, frame.lod);
            self.emit_set(slot);
        }
    }

    /// Sorts the instances `selection` keeps into the draw buckets: each present instance's
    /// level of detail, or its clusters the set may see, or the whole mesh; `tagged`: ids of
    /// what the fovea views see carry [`FOVEA_TAG`].
    fn fill_buckets(&mut self, selection: &Selection, tagged: bool, lod: Option<f32>) {
        let FrameCulling {
            hierarchy: h,
            draw_of,
            present,
            placed,
            lod_bounds,
            draw_buckets,
            buckets,
            in_fovea,
            seen_by_fovea,
            ..
        } = self;
        buckets.iter_mut().for_each(Vec::clear);
        let mut keep = |id: u32| {
            let i = id as usize;
            if present.get(i) == Some(&false) {
                return;
            }
            let tag = |seen: bool| if tagged && seen { FOVEA_TAG } else { 0 };
            let draw = &draw_buckets[draw_of[i] as usize];
            let instance_in_fovea = in_fovea.get(i) == Some(&true);
            let level = match (lod, lod_bounds.get(i).and_then(Option::as_ref)) {
                (Some(px), Some((bounds, scale))) => {
                    let views = if tagged && instance_in_fovea {
                        &selection.tagged_views
                    } else {
                        &selection.views
                    };
                    lod_level(views, px, bounds, *scale, &draw.lod_errors)
                }
                _ => 0,
            };
            if level > 0 {
                buckets[draw.lod_bucket(level)].push(id | tag(instance_in_fovea));
                return;
            }
            match (placed[i].as_ref(), selection.clusters.as_ref()) {
                (Some(p), Some(test)) => {
                    seen_by_fovea.clear();
                    seen_by_fovea.resize(draw.clusters.len(), false);
                    let fovea_tags = selection.fovea_tags.as_ref();
                    if let Some(f) = fovea_tags.filter(|_| instance_in_fovea) {
                        f.kept(p, &draw.clusters)
                            .for_each(|j| seen_by_fovea[j] = true);
                    }
                    for j in test.kept(p, &draw.clusters) {
                        buckets[draw.first + 1 + j].push(id | tag(seen_by_fovea[j]));
                    }
                }
                _ => buckets[draw.first].push(id | tag(instance_in_fovea)),
            }
        };
        match &selection.kept {
            Some(r) => r.visible.indices().for_each(|i| keep(h.ids[i as usize])),
            None => (0..draw_of.len() as u32).for_each(keep),
        }
    }

    /// Slot `slot`'s draws from the filled buckets: one draw per non-empty bucket, its ids
    /// appended to the frame's.
    fn emit_set(&mut self, slot: usize) {
        let set = &mut self.sets[slot];
        set.clear();
        for draw in &self.draw_buckets {
            for (b, range) in draw.ranges().enumerate() {
                let bucket = &self.buckets[draw.first + b];
                if bucket.is_empty() {
                    continue;
                }
                set.push(Draw {
                    mesh: range,
                    first_instance: self.ids.len() as u32,
                    instance_count: bucket.len() as u32,
                });
                self.ids.extend_from_slice(bucket);
            }
        }
    }
}

/// Whether a foveated frame's fovea views draw cull slot `slot` without tags: a scene step of
/// the slot in a pass that renders a fovea view (frame views 2 and 3).
fn fovea_draws(plan: &FramePlan, slot: usize) -> bool {
    plan.foveation.is_some()
        && plan.cull_slots[slot] != DrawSet::FoveaTagged
        && plan.passes.iter().any(|p| {
            let views = p.view_mask.max(1) << p.first_view;
            views >> 2 != 0
                && p.steps
                    .iter()
                    .any(|s| matches!(s, Step::Scene { cull_slot: Some(k), .. } if *k == slot))
        })
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

// Levels of detail are built by the `clusters` feature (meshoptimizer).
#[cfg(all(test, feature = "clusters"))]
mod tests {
    use super::*;
    use crate::foveation::FoveationConfig;
    use crate::plan::{DeviceCaps, FoveaLayout, RenderConfig};
    use crate::scene::{default_scene, LodSettings};

    /// With level of detail, a set's levels must satisfy the fovea views wherever they draw it
    /// untagged: the one-pass layout's unculled set (all four views), and the two-pass layout's
    /// when the fovea pass draws the periphery's set too (fovea culling off), and the fovea's
    /// own culled set; not the two-pass layout's periphery set beside it. Mutation: deciding by the
    /// pass's view mask alone (without its first view) misses the two-pass fovea pass.
    #[test]
    fn fovea_views_choose_the_levels_of_the_sets_they_draw() {
        let scene = default_scene().with_lod().unwrap();
        let plan = |layout, cull_fovea| {
            let config = RenderConfig {
                foveation: Some(FoveationConfig {
                    ratio: 0.35,
                    cull_fovea,
                    ..FoveationConfig::single_frame()
                }),
                fovea_layout: layout,
                lod: Some(LodSettings::default()),
                ..RenderConfig::default()
            };
            crate::plan(&scene, &config, &DeviceCaps::generic()).unwrap()
        };
        let slots = |plan: &FramePlan| {
            (0..plan.cull_slots.len())
                .map(|k| (plan.cull_slots[k], fovea_draws(plan, k)))
                .collect::<Vec<_>>()
        };
        assert_eq!(
            slots(&plan(FoveaLayout::OnePass, false)),
            [(DrawSet::All, true)]
        );
        assert_eq!(
            slots(&plan(FoveaLayout::TwoPass, false)),
            [(DrawSet::All, true)]
        );
        assert_eq!(
            slots(&plan(FoveaLayout::TwoPass, true)),
            [(DrawSet::All, false), (DrawSet::Fovea, true)]
        );
    }
}
