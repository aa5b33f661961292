//! What one frame's cull slots share — the head, both eyes' frusta, the fovea's frustum, the
//! views levels of detail are chosen for — and what each slot selects from the hierarchy: the
//! instances it keeps, its clusters' test, its levels' views, and for the one-pass fovea
//! layout's tagged set, which instances the fovea views see.

use glam::{Mat4, Vec3};

use super::cluster_cull::ClusterTest;
use super::lod_select::LodView;
use crate::cull::{
    CullHierarchy, CullResult, CullView, Frustum, StereoFrusta, Strategy, Superfrustum,
};
use crate::plan::{DrawSet, FramePlan};
use crate::view::{EyeParams, FovTangents, LensRegion};
use crate::vocab::Resolution;

/// One frame's culling, as every slot sees it.
pub(super) struct CullFrame<'a> {
    plan: &'a FramePlan,
    world_from_head: Mat4,
    frame: u64,
    /// The head's centre: distance culling's ball is around it.
    centre: Vec3,
    draw_distance: f32,
    /// With MFFR, how far the near field reaches.
    near_reach: Option<f32>,
    strategy: Strategy,
    /// The scene's clusters are culled per slot.
    clustered: bool,
    /// Level of detail's error bound in pixels, when on.
    pub lod: Option<f32>,
    /// Both eyes' frusta, when a slot culls per eye, clusters are culled or levels chosen.
    frusta: Option<StereoFrusta>,
    /// The fovea views' fields, in a foveated frame.
    fovea: Option<&'a [FovTangents; 2]>,
    /// The MFFR far view's frustum, with MFFR.
    far: Option<&'a Frustum>,
    lens_regions: [LensRegion; 2],
}

/// What one cull slot draws this frame.
pub(super) struct Selection {
    /// The instances it keeps (`None`: every instance).
    pub kept: Option<CullResult>,
    /// Its clusters' test (when the scene's clusters are culled).
    pub clusters: Option<ClusterTest>,
    /// The views its levels of detail are chosen for (none without level of detail).
    pub views: Vec<LodView>,
    /// The tagged set's: the test a cluster fails when the fovea views cannot see it.
    pub fovea_tags: Option<ClusterTest>,
    /// The tagged set's: the views an instance the fovea sees must also satisfy.
    pub tagged_views: Vec<LodView>,
}

/// The frame a [`CullFrame`] is for.
pub(super) struct FrameCull<'a> {
    pub plan: &'a FramePlan,
    pub world_from_head: Mat4,
    pub frame: u64,
    pub far: Option<&'a Frustum>,
    pub fovea: Option<&'a [FovTangents; 2]>,
}

impl<'a> CullFrame<'a> {
    pub fn new(
        at: FrameCull<'a>,
        lens_regions: [LensRegion; 2],
        draw_distance: f32,
        near_reach: Option<f32>,
    ) -> Self {
        let plan = at.plan;
        let clustered = plan.clusters.is_some_and(|c| c.culled());
        let lod = plan.lod.map(|l| l.max_error_px);
        let per_eye = plan
            .cull_slots
            .iter()
            .any(|s| matches!(s, DrawSet::VisibleToEye(_)));
        let frusta = (clustered || lod.is_some() || per_eye)
            .then(|| StereoFrusta::new(&plan.eyes, at.world_from_head, plan.near, draw_distance));
        CullFrame {
            plan,
            world_from_head: at.world_from_head,
            frame: at.frame,
            centre: at.world_from_head.transform_point3(Vec3::ZERO),
            draw_distance,
            near_reach,
            strategy: plan.culling.map_or(Strategy::PerEye, |c| c.strategy),
            clustered,
            lod,
            frusta,
            fovea: at.fovea,
            far: at.far,
            lens_regions,
        }
    }

    fn view(&self, distance: f32) -> CullView<'_> {
        CullView {
            eyes: &self.plan.eyes,
            world_from_head: self.world_from_head,
            near: self.plan.near,
            draw_distance: distance,
            frame: self.frame,
            lens_regions: &self.lens_regions,
        }
    }

    fn frusta(&self) -> &StereoFrusta {
        self.frusta
            .as_ref()
            .expect("computed with clusters, levels or per-eye slots")
    }

    fn eyes(&self) -> [Vec3; 2] {
        self.frusta().eyes.map(|f| f.origin)
    }

    fn superfrustum(&self, eyes: &EyeParams, distance: f32) -> Frustum {
        Superfrustum::new(eyes, self.world_from_head, self.plan.near, distance).frustum
    }

    /// The fovea views as eyes whose fields are the fovea windows.
    fn fovea_eyes(&self) -> EyeParams {
        let fovea = self.fovea.expect("fovea sets are planned with foveation");
        EyeParams {
            left_fov: fovea[0],
            right_fov: fovea[1],
            ..self.plan.eyes
        }
    }

    /// The superfrustum around both fovea frusta.
    fn fovea_frustum(&self) -> Frustum {
        self.superfrustum(&self.fovea_eyes(), self.draw_distance)
    }

    /// The views a set's level of detail must satisfy (none without level of detail).
    fn lod_views(&self, frusta: &[Frustum], pixels: Resolution) -> Vec<LodView> {
        match self.lod {
            Some(_) => frusta.iter().map(|f| LodView::new(f, pixels)).collect(),
            None => Vec::new(),
        }
    }

    /// The eyes at the scene passes' pixels (a foveated frame's periphery's).
    fn eye_views(&self) -> Vec<LodView> {
        let plan = self.plan;
        let pixels = plan
            .foveation
            .map_or(plan.eye_resolution, |g| g.periphery_view);
        self.frusta
            .as_ref()
            .map_or(Vec::new(), |f| self.lod_views(&f.eyes, pixels))
    }

    /// The fovea views at their pixels.
    fn fovea_views(&self) -> Vec<LodView> {
        match (self.lod, self.plan.foveation) {
            (Some(_), Some(g)) => {
                let eyes = self.fovea_eyes();
                let frusta = StereoFrusta::new(
                    &eyes,
                    self.world_from_head,
                    self.plan.near,
                    self.draw_distance,
                );
                self.lod_views(&frusta.eyes, g.fovea_view)
            }
            _ => Vec::new(),
        }
    }

    /// A slot's clusters' test, when the scene's clusters are culled (only then are the
    /// frustum and the projection centres worked out).
    fn test(
        &self,
        frustum: impl FnOnce() -> Frustum,
        eyes: impl FnOnce() -> [Vec3; 2],
        distance: f32,
    ) -> Option<ClusterTest> {
        self.clustered.then(|| ClusterTest {
            frustum: frustum(),
            eyes: eyes(),
            centre: self.centre,
            distance,
        })
    }

    /// Both eyes' clusters within the draw distance (the stereo sets and the periphery's).
    fn stereo_test(&self) -> Option<ClusterTest> {
        let distance = self.draw_distance;
        let frustum = || self.superfrustum(&self.plan.eyes, distance);
        self.test(frustum, || self.eyes(), distance)
    }

    /// What a slot drawing `draw_set` selects from `h`; `fovea_draws`: the fovea views draw
    /// it untagged, so its levels must satisfy them too. The tagged set marks in `in_fovea`
    /// (made one entry per instance of the scene's `instances`) those the fovea views see.
    pub fn select(
        &self,
        h: &CullHierarchy,
        draw_set: DrawSet,
        fovea_draws: bool,
        in_fovea: &mut Vec<bool>,
        instances: usize,
    ) -> Selection {
        let (centre, distance) = (self.centre, self.draw_distance);
        let stereo_views = || {
            let mut views = self.eye_views();
            if fovea_draws {
                views.extend(self.fovea_views());
            }
            views
        };
        let selection = |kept, clusters, views| Selection {
            kept,
            clusters,
            views,
            fovea_tags: None,
            tagged_views: Vec::new(),
        };
        match draw_set {
            DrawSet::All => selection(None, None, stereo_views()),
            DrawSet::Visible => selection(
                Some(self.strategy.cull(h, &self.view(distance))),
                self.stereo_test(),
                stereo_views(),
            ),
            DrawSet::VisibleToEye(e) => {
                let frustum = self.frusta().eyes[e.index()];
                let mut views = self.eye_views();
                if !views.is_empty() {
                    views = vec![views[e.index()]];
                }
                selection(
                    Some(h.cull(&frustum, centre, distance)),
                    self.test(|| frustum, || [frustum.origin; 2], distance),
                    views,
                )
            }
            DrawSet::NearField => {
                let reach = self.near_reach.expect("a near field is planned with MFFR");
                let frustum = || self.superfrustum(&self.plan.eyes, reach);
                selection(
                    Some(self.strategy.cull(h, &self.view(reach))),
                    self.test(frustum, || self.eyes(), reach),
                    self.eye_views(),
                )
            }
            DrawSet::FarField => {
                let far = self.far.expect("a far field is planned with MFFR");
                let pixels = self
                    .plan
                    .mffr
                    .map_or(self.plan.eye_resolution, |m| m.resolution);
                selection(
                    Some(h.cull(far, centre, distance)),
                    self.test(|| *far, || [far.origin; 2], distance),
                    self.lod_views(std::slice::from_ref(far), pixels),
                )
            }
            DrawSet::Fovea => {
                let frustum = self.fovea_frustum();
                selection(
                    Some(h.cull(&frustum, centre, distance)),
                    self.test(|| frustum, || self.eyes(), distance),
                    self.fovea_views(),
                )
            }
            DrawSet::FoveaTagged => {
                in_fovea.clear();
                in_fovea.resize(instances, false);
                self.tagged(h, in_fovea)
            }
        }
    }

    /// The one-pass fovea layout's set: the periphery's instances (every one without
    /// culling), each tagged where the fovea superfrustum keeps it.
    fn tagged(&self, h: &CullHierarchy, in_fovea: &mut [bool]) -> Selection {
        let (centre, distance) = (self.centre, self.draw_distance);
        let frustum = self.fovea_frustum();
        for i in h.cull(&frustum, centre, distance).visible.indices() {
            in_fovea[h.ids[i as usize] as usize] = true;
        }
        let views = self.eye_views();
        Selection {
            kept: self
                .plan
                .culling
                .map(|_| self.strategy.cull(h, &self.view(distance))),
            clusters: self.stereo_test(),
            tagged_views: [views.clone(), self.fovea_views()].concat(),
            views,
            fovea_tags: self.test(|| frustum, || self.eyes(), distance),
        }
    }
}
