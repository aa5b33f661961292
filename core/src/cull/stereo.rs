//! Stereo culling strategies behind one trait.

use glam::{DVec3, Mat3, Mat4, Vec3};

use super::{Aabb, Cone, EllipticalCone, Frustum, Relation, Sphere, SphereSoa};
use crate::view::{Eye, EyeParams, FovTangents, LensRegion};

/// A culling volume for a stereo pair: does an object need drawing for either eye?
pub trait StereoCull: Sync {
    /// The strategy's name, as [`Strategy::name`] spells it.
    fn name(&self) -> &'static str;
    /// Conservative: false only if the sphere cannot be seen by the eyes this strategy covers.
    fn sphere(&self, s: &Sphere) -> bool;
    /// Conservative box relation, for hierarchy nodes.
    fn aabb(&self, b: &Aabb) -> Relation;
    /// Batch test over `soa[range]`, appending the indices that pass. The default calls
    /// [`StereoCull::sphere`]; strategies with a vectorised kernel override it.
    fn spheres(&self, soa: &SphereSoa, range: std::ops::Range<usize>, out: &mut Vec<u32>) {
        out.extend(
            range
                .filter(|&i| self.sphere(&soa.get(i)))
                .map(|i| i as u32),
        );
    }
}

/// One frustum alone: one eye's own pass (per-eye culling in two-pass stereo), or the MFFR far
/// view.
impl StereoCull for Frustum {
    fn name(&self) -> &'static str {
        "frustum"
    }

    fn sphere(&self, s: &Sphere) -> bool {
        self.intersects_sphere(s)
    }

    fn aabb(&self, b: &Aabb) -> Relation {
        Frustum::aabb(self, b)
    }

    fn spheres(&self, soa: &SphereSoa, range: std::ops::Range<usize>, out: &mut Vec<u32>) {
        soa.frustum_union_unchecked(std::slice::from_ref(self), range, out);
    }
}

/// Both eyes' frusta for a head pose, near plane and draw distance.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct StereoFrusta {
    /// Left, then right.
    pub eyes: [Frustum; 2],
}

impl StereoFrusta {
    /// Both eyes' frusta for the head at `world_from_head`, from `near` to `far` metres.
    pub fn new(eyes: &EyeParams, world_from_head: Mat4, near: f32, far: f32) -> Self {
        let frustum = |eye| {
            Frustum::from_eye(
                world_from_head * eyes.head_from_eye(eye),
                eyes.fov(eye),
                near,
                far,
            )
        };
        StereoFrusta {
            eyes: [frustum(Eye::Left), frustum(Eye::Right)],
        }
    }
}

/// Two frusta, their union, with early accept on the first.
#[derive(Clone, Copy, Debug)]
pub struct PerEye {
    /// The two eyes' frusta.
    pub frusta: StereoFrusta,
}

impl StereoCull for PerEye {
    fn name(&self) -> &'static str {
        "per-eye"
    }

    fn sphere(&self, s: &Sphere) -> bool {
        self.frusta.eyes[0].intersects_sphere(s) || self.frusta.eyes[1].intersects_sphere(s)
    }

    fn aabb(&self, b: &Aabb) -> Relation {
        let left = self.frusta.eyes[0].aabb(b);
        if left == Relation::Inside {
            return left;
        }
        left.union(self.frusta.eyes[1].aabb(b))
    }

    fn spheres(&self, soa: &SphereSoa, range: std::ops::Range<usize>, out: &mut Vec<u32>) {
        soa.frustum_union_unchecked(&self.frusta.eyes, range, out);
    }
}

/// One frustum containing both eye frusta (Everitt's superfrustum with Oddou's recession,
/// generalised): its apex is where the left eye's left plane and the right eye's right plane
/// meet behind the eyes, and its four tangents and near/far distances are the extremes over the
/// sixteen corners of the eye frusta. A frustum is convex, so containing the corners means
/// containing both frusta — for asymmetric and canted eyes too, without symmetrising.
#[derive(Clone, Copy, Debug)]
pub struct Superfrustum {
    /// The frustum containing both eyes'.
    pub frustum: Frustum,
    /// Distance of the apex behind the eyes' baseline (Oddou's recession for parallel eyes).
    pub recession: f32,
    /// Its field, as tangents from its apex.
    pub fov: FovTangents,
}

impl Superfrustum {
    /// The superfrustum of both eyes for the head at `world_from_head`, from `near` to `far` metres.
    pub fn new(eyes: &EyeParams, world_from_head: Mat4, near: f32, far: f32) -> Self {
        let in_head = StereoFrusta::new(eyes, Mat4::IDENTITY, near, far);
        let mut apex = outer_planes_meet(eyes).unwrap_or(Vec3::ZERO);
        let min_depth = in_head
            .eyes
            .iter()
            .flat_map(|f| f.world_corners())
            .map(|p| apex.z - p.z)
            .fold(f32::MAX, f32::min);
        if min_depth <= near * 0.5 {
            // The outer planes meet in front of a near corner (eyes canted inwards): fall back
            // to an apex behind every corner.
            apex.z += near - min_depth;
        }
        // Fit against the eye frusta as they are represented in world space (f64, relative to
        // the apex as rounded), so containment survives rounding at large coordinates. Far from
        // the world origin the rounded apex can land in front of a (rounded) eye: walk it back.
        let world = StereoFrusta::new(eyes, world_from_head, near, far);
        let represented = |apex: Vec3| {
            let world_from_apex = world_from_head * Mat4::from_translation(apex);
            let (_, rotation, origin) = world_from_apex.to_scale_rotation_translation();
            let apex_from_world = rotation.as_dquat().inverse();
            let points: Vec<DVec3> = world
                .eyes
                .iter()
                .flat_map(|f| {
                    f.corners.map(|c| {
                        apex_from_world * (f.origin.as_dvec3() + c.as_dvec3() - origin.as_dvec3())
                    })
                })
                .collect();
            (world_from_apex, points)
        };
        let (mut world_from_apex, mut points) = represented(apex);
        for _ in 0..64 {
            let min_depth = points.iter().map(|p| -p.z).fold(f64::MAX, f64::min);
            if min_depth >= near as f64 * 0.5 {
                break;
            }
            let ulp = world_from_apex.w_axis.truncate().abs().max_element() * f32::EPSILON;
            apex.z += (near as f64 - min_depth) as f32 + 2.0 * ulp;
            (world_from_apex, points) = represented(apex);
        }
        let (mut l, mut r, mut u, mut d) = (f64::MIN, f64::MIN, f64::MIN, f64::MIN);
        let (mut n, mut f) = (f64::MAX, f64::MIN);
        for p in &points {
            let depth = -p.z;
            l = l.max(-p.x / depth);
            r = r.max(p.x / depth);
            u = u.max(p.y / depth);
            d = d.max(-p.y / depth);
            n = n.min(depth);
            f = f.max(depth);
        }
        // Round outwards: tangents and far up, near down.
        let grow = |t: f64| (t + 1e-5 * t.abs().max(1e-3)) as f32;
        let fov = FovTangents {
            left: grow(l),
            right: grow(r),
            up: grow(u),
            down: grow(d),
        };
        let frustum = Frustum::from_eye(
            world_from_apex,
            fov,
            (n * (1.0 - 1e-5)) as f32,
            (f * (1.0 + 1e-5)) as f32,
        );
        Superfrustum {
            frustum,
            recession: apex.z,
            fov,
        }
    }
}

/// Where, in head space, the left eye's left frustum plane and the right eye's right plane
/// cross in the horizontal plane — behind the eyes for parallel or outward-canted eyes.
fn outer_planes_meet(eyes: &EyeParams) -> Option<Vec3> {
    let edge = |eye, tangent_x: f32| {
        let m = eyes.head_from_eye(eye);
        (
            m.transform_point3(Vec3::ZERO),
            m.transform_vector3(Vec3::new(tangent_x, 0.0, -1.0)),
        )
    };
    let (p, u) = edge(Eye::Left, -eyes.left_fov.left);
    let (q, v) = edge(Eye::Right, eyes.right_fov.right);
    // Solve p + s·u = q + t·v in x and z.
    let det = u.x * -v.z + v.x * u.z;
    if det.abs() < 1e-12 {
        return None;
    }
    let (bx, bz) = (q.x - p.x, q.z - p.z);
    let s = (bx * -v.z + v.x * bz) / det;
    let meet = p + u * s;
    (s <= 0.0 && meet.is_finite()).then_some(Vec3::new(meet.x, 0.0, meet.z))
}

/// Strategies that cull with one frustum (`self.frustum`).
macro_rules! single_frustum_culler {
    ($ty:ty, $name:literal) => {
        impl StereoCull for $ty {
            fn name(&self) -> &'static str {
                $name
            }

            fn sphere(&self, s: &Sphere) -> bool {
                self.frustum.intersects_sphere(s)
            }

            fn aabb(&self, b: &Aabb) -> Relation {
                self.frustum.aabb(b)
            }

            fn spheres(&self, soa: &SphereSoa, range: std::ops::Range<usize>, out: &mut Vec<u32>) {
                soa.frustum_union_unchecked(std::slice::from_ref(&self.frustum), range, out);
            }
        }
    };
}

single_frustum_culler!(Superfrustum, "superfrustum");

/// The cones of one eye fitted around its lens-visible region: axis through the region's
/// centre, wide enough that every ray of the region's bounding polygon is inside — and since a
/// cone is convex, the whole region is.
fn fit_cones(
    eyes: &EyeParams,
    world_from_head: Mat4,
    regions: &[LensRegion; 2],
) -> [(Cone, EllipticalCone); 2] {
    Eye::BOTH.map(|eye| {
        let world_from_eye = world_from_head * eyes.head_from_eye(eye);
        let region = regions[eye.index()];
        let rays: Vec<Vec3> = region
            .bounding_polygon(64)
            .iter()
            .map(|p| Vec3::new(p.x, p.y, -1.0).normalize())
            .collect();
        let axis_eye = enclosing_axis(&rays);
        let cos_min = rays.iter().map(|r| r.dot(axis_eye)).fold(1.0f32, f32::min);
        let half_angle = cos_min.clamp(-1.0, 1.0).acos() * (1.0 + 1e-5) + 1e-6;
        let origin = world_from_eye.transform_point3(Vec3::ZERO);
        let axis = world_from_eye.transform_vector3(axis_eye);
        let circular = Cone::new(origin, axis, half_angle);

        // Elliptical: cone frame with z along the axis, x along the eye's right, y up (a mirrored
        // frame; the test is symmetric in x and y).
        let right_eye = Vec3::Y.cross(-axis_eye).normalize();
        let up_eye = (-axis_eye).cross(right_eye);
        let cone_from_eye = Mat3::from_cols(right_eye, up_eye, axis_eye).transpose();
        let uv: Vec<(f32, f32)> = rays
            .iter()
            .map(|r| {
                let q = cone_from_eye * *r;
                (q.x / q.z, q.y / q.z)
            })
            .collect();
        let max_u = uv.iter().map(|p| p.0.abs()).fold(0.0f32, f32::max);
        let max_v = uv.iter().map(|p| p.1.abs()).fold(0.0f32, f32::max);
        let aspect = max_u / max_v;
        let tan_y = uv
            .iter()
            .map(|&(u, v)| ((u / aspect).powi(2) + v * v).sqrt())
            .fold(0.0f32, f32::max)
            * (1.0 + 1e-5);
        let rotation = Mat3::from_mat4(world_from_eye);
        let elliptical = EllipticalCone::new(
            origin,
            cone_from_eye * rotation.transpose(),
            tan_y * aspect,
            tan_y,
        );
        (circular, elliptical)
    })
}

/// The axis of (nearly) the narrowest cone around unit vectors `rays` (Bădoiu–Clarkson steps
/// towards the farthest ray). The region's centre is a poor axis for lopsided eyes: a 124°-wide
/// asymmetric eye needs over 90° around its centre but ~62° around this axis. The half-angle is
/// measured afterwards over all rays, so a not-quite-optimal axis costs tightness, not safety.
fn enclosing_axis(rays: &[Vec3]) -> Vec3 {
    let mut axis = rays.iter().copied().sum::<Vec3>().normalize();
    for i in 1..=400 {
        let farthest = rays
            .iter()
            .copied()
            .min_by(|a, b| a.dot(axis).total_cmp(&b.dot(axis)))
            .unwrap_or(axis);
        axis = (axis + (farthest - axis) / (i as f32 + 1.0)).normalize();
    }
    axis
}

/// One cone per eye around its lens-visible region; circular (Hale) or elliptical (his
/// proposed fix for asymmetric headsets). Conservative for the visible region, not for the
/// frustum corners the lens hides.
#[derive(Clone, Copy, Debug)]
pub struct DualCone {
    /// The circular cones, left then right.
    pub cones: [Cone; 2],
    /// The elliptical cones, left then right.
    pub elliptical_cones: [EllipticalCone; 2],
    /// Whether the elliptical cones are the ones tested.
    pub elliptical: bool,
}

impl DualCone {
    /// One cone per eye around its lens-visible `regions`, circular or `elliptical`.
    pub fn new(
        eyes: &EyeParams,
        world_from_head: Mat4,
        regions: &[LensRegion; 2],
        elliptical: bool,
    ) -> Self {
        let fitted = fit_cones(eyes, world_from_head, regions);
        DualCone {
            cones: fitted.map(|f| f.0),
            elliptical_cones: fitted.map(|f| f.1),
            elliptical,
        }
    }
}

impl StereoCull for DualCone {
    fn name(&self) -> &'static str {
        if self.elliptical {
            "dual elliptical cone"
        } else {
            "dual cone"
        }
    }

    fn sphere(&self, s: &Sphere) -> bool {
        if self.elliptical {
            self.elliptical_cones.iter().any(|c| c.intersects_sphere(s))
        } else {
            self.cones.iter().any(|c| c.intersects_sphere(s))
        }
    }

    fn aabb(&self, b: &Aabb) -> Relation {
        if self.elliptical {
            self.elliptical_cones[0]
                .aabb(b)
                .union(self.elliptical_cones[1].aabb(b))
        } else {
            self.cones[0].aabb(b).union(self.cones[1].aabb(b))
        }
    }

    fn spheres(&self, soa: &SphereSoa, range: std::ops::Range<usize>, out: &mut Vec<u32>) {
        if self.elliptical {
            out.extend(
                range
                    .filter(|&i| self.sphere(&soa.get(i)))
                    .map(|i| i as u32),
            );
        } else {
            soa.cone_union_unchecked(&self.cones, range, out);
        }
    }
}

/// One eye's frustum per frame, alternating (Preißner 2020 §3.4). Objects only the other eye sees
/// are missed for a frame — expected, and measured by [`super::CullStats`].
#[derive(Clone, Copy, Debug)]
pub struct RoundRobin {
    /// This frame's eye's frustum.
    pub frustum: Frustum,
    /// This frame's eye.
    pub eye: Eye,
}

impl RoundRobin {
    /// The eye of `frame`: left on even frames, right on odd ones.
    pub fn new(frusta: &StereoFrusta, frame: u64) -> Self {
        let eye = if frame.is_multiple_of(2) {
            Eye::Left
        } else {
            Eye::Right
        };
        RoundRobin {
            frustum: frusta.eyes[eye.index()],
            eye,
        }
    }
}

single_frustum_culler!(RoundRobin, "round robin");

/// The strategies by name, for benchmarks and the CLI.
#[derive(Clone, Copy, Debug, PartialEq, Eq, Hash)]
pub enum Strategy {
    /// [`PerEye`].
    PerEye,
    /// [`Superfrustum`].
    Superfrustum,
    /// [`DualCone`], circular.
    DualCone,
    /// [`DualCone`], elliptical.
    DualEllipticalCone,
    /// [`RoundRobin`].
    RoundRobin,
}

impl Strategy {
    /// Every strategy, in the order the benchmarks print them.
    pub const ALL: [Strategy; 5] = [
        Strategy::PerEye,
        Strategy::Superfrustum,
        Strategy::DualCone,
        Strategy::DualEllipticalCone,
        Strategy::RoundRobin,
    ];

    /// Whether the strategy culls to the lens-visible region (the cones), dropping objects
    /// the lens hides but the frustum shows: correct only where the HMD mask hides them too.
    pub fn culls_to_lens(self) -> bool {
        matches!(self, Strategy::DualCone | Strategy::DualEllipticalCone)
    }

    /// The strategy named `name` (as [`Strategy::name`] spells it).
    pub fn by_name(name: &str) -> Option<Strategy> {
        Strategy::ALL.into_iter().find(|s| s.name() == name)
    }

    /// Its name on the command line and in the printout.
    pub fn name(self) -> &'static str {
        match self {
            Strategy::PerEye => "per-eye",
            Strategy::Superfrustum => "superfrustum",
            Strategy::DualCone => "dual-cone",
            Strategy::DualEllipticalCone => "dual-elliptical-cone",
            Strategy::RoundRobin => "round-robin",
        }
    }
}

/// Everything a strategy needs to build its volume for one frame.
#[derive(Clone, Copy, Debug)]
pub struct CullView<'a> {
    /// The eyes.
    pub eyes: &'a EyeParams,
    /// The head's pose this frame.
    pub world_from_head: Mat4,
    /// Near plane, metres.
    pub near: f32,
    /// How far objects are drawn, metres.
    pub draw_distance: f32,
    /// The frame's number (round robin alternates on it).
    pub frame: u64,
    /// Each eye's lens-visible region (the cones fit it).
    pub lens_regions: &'a [LensRegion; 2],
}

impl Strategy {
    /// Builds this strategy's volume for `view` and culls `hierarchy` with it (the volume's
    /// construction counts as culling work).
    pub fn cull(self, hierarchy: &super::CullHierarchy, view: &CullView<'_>) -> super::CullResult {
        let centre = view.world_from_head.transform_point3(Vec3::ZERO);
        let frusta = || {
            StereoFrusta::new(
                view.eyes,
                view.world_from_head,
                view.near,
                view.draw_distance,
            )
        };
        let distance = view.draw_distance;
        match self {
            Strategy::PerEye => hierarchy.cull(&PerEye { frusta: frusta() }, centre, distance),
            Strategy::Superfrustum => hierarchy.cull(
                &Superfrustum::new(view.eyes, view.world_from_head, view.near, distance),
                centre,
                distance,
            ),
            Strategy::DualCone | Strategy::DualEllipticalCone => hierarchy.cull(
                &DualCone::new(
                    view.eyes,
                    view.world_from_head,
                    view.lens_regions,
                    self == Strategy::DualEllipticalCone,
                ),
                centre,
                distance,
            ),
            Strategy::RoundRobin => {
                hierarchy.cull(&RoundRobin::new(&frusta(), view.frame), centre, distance)
            }
        }
    }
}
