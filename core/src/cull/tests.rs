//! Conservativeness of every fast test against the `f64` oracles, by property tests over the
//! hard cases (the named catalogue of those cases is `hard_cases_tests.rs`).

use std::f32::consts::FRAC_PI_2;

use glam::{DVec3, Mat4, Quat, Vec2, Vec3};
use proptest::prelude::*;

use super::oracle;
use super::{
    Aabb, Cone, DualCone, EllipticalCone, Frustum, Sphere, StereoCull, StereoFrusta, Superfrustum,
    Triangle,
};
use crate::view::{Eye, EyeParams, FovTangents, LensRegion};

/// Spheres checked per property case.
const PER_CASE: usize = 16;

/// A uniform f32 in [lo, hi), drawn through integers: proptest 1.12's own f32 range sampler
/// trips an internal assertion (`self.low - result < initial.step`) on some seeds.
fn fr(lo: f32, hi: f32) -> impl Strategy<Value = f32> {
    const STEPS: u32 = 1 << 24;
    (0u32..STEPS).prop_map(move |k| lo + (hi - lo) * (k as f32 / STEPS as f32))
}

fn log_uniform(lo: f32, hi: f32) -> impl Strategy<Value = f32> {
    fr(lo.ln(), hi.ln()).prop_map(f32::exp)
}

/// A coordinate: 0, or ± a magnitude from 1e-2 to 1e6.
fn coordinate() -> impl Strategy<Value = f32> {
    prop_oneof![
        Just(0.0f32),
        (any::<bool>(), log_uniform(1e-2, 1e6)).prop_map(|(neg, m)| if neg { -m } else { m })
    ]
}

fn position() -> impl Strategy<Value = Vec3> {
    (coordinate(), coordinate(), coordinate()).prop_map(|(x, y, z)| Vec3::new(x, y, z))
}

fn rotation() -> impl Strategy<Value = Quat> {
    (fr(-3.2, 3.2), fr(-1.6, 1.6), fr(-3.2, 3.2))
        .prop_map(|(y, p, r)| Quat::from_euler(glam::EulerRot::YXZ, y, p, r))
}

/// FOV tangents from 1° to 80° half-angles, independently per side.
fn fov() -> impl Strategy<Value = FovTangents> {
    let t = || log_uniform(0.0175, 5.67);
    (t(), t(), t(), t()).prop_map(|(left, right, up, down)| FovTangents {
        left,
        right,
        up,
        down,
    })
}

fn unit_vector() -> impl Strategy<Value = Vec3> {
    (fr(-1.0, 1.0), fr(0.0, std::f32::consts::TAU)).prop_map(|(z, phi)| {
        let s = (1.0 - z * z).sqrt();
        Vec3::new(s * phi.cos(), s * phi.sin(), z)
    })
}

/// A frustum anywhere, any orientation, near from 1e-4 to 1, far up to 1e4.
fn frustum() -> impl Strategy<Value = Frustum> {
    (
        position(),
        rotation(),
        fov(),
        log_uniform(1e-4, 1.0),
        log_uniform(2.0, 1e4),
    )
        .prop_map(|(p, q, fov, near, k)| {
            let far = (near * k).min(1e4).max(near * 2.0);
            Frustum::from_eye(Mat4::from_rotation_translation(q, p), fov, near, far)
        })
}

/// Spheres around a surface point: `(surface point index data, direction, radius, offset factor)`.
fn sphere_params() -> impl Strategy<Value = Vec<(usize, f32, f32, Vec3, f32, f32)>> {
    prop::collection::vec(
        (
            0usize..6,
            fr(0.0, 1.0),
            fr(0.0, 1.0),
            unit_vector(),
            log_uniform(1e-6, 1e4),
            fr(0.0, 2.0),
        ),
        PER_CASE,
    )
}

/// A point on face `face` of the frustum at bilinear (s, t), in f64 world space.
fn on_face(f: &Frustum, face: usize, s: f32, t: f32) -> DVec3 {
    let c = Frustum::FACES[face].map(|i| f.origin.as_dvec3() + f.corners[i].as_dvec3());
    let (s, t) = (s as f64, t as f64);
    let a = c[0] + (c[1] - c[0]) * s;
    let b = c[3] + (c[2] - c[3]) * s;
    a + (b - a) * t
}

fn check_frustum_sphere(f: &Frustum, center: Vec3, r: f32) -> Result<(), TestCaseError> {
    let s = Sphere::new(center, r);
    if oracle::sphere_frustum(f, &s) {
        prop_assert!(
            f.sphere(&s).visible(),
            "false negative: {s:?} against {f:?}"
        );
    }
    Ok(())
}

proptest! {
    #![proptest_config(ProptestConfig::with_cases(65_536))]

    /// 65 536 frusta × 16 spheres near their surfaces: no false negatives.
    #[test]
    fn sphere_frustum_is_conservative(f in frustum(), spheres in sphere_params()) {
        for (face, s, t, dir, r, k) in spheres {
            let p = on_face(&f, face, s, t) + dir.as_dvec3() * (r * k) as f64;
            check_frustum_sphere(&f, p.as_vec3(), r)?;
        }
    }

    /// 65 536 cones × 16 spheres at the surface, at the apex, behind and straddling the plane.
    #[test]
    fn sphere_cone_is_conservative(
        apex in position(),
        axis in unit_vector(),
        half in prop_oneof![log_uniform(1e-4, 1e-2), fr(0.01, 1.55), (fr(1e-5, 1e-2)).prop_map(|e| FRAC_PI_2 - e)],
        spheres in prop::collection::vec((unit_vector(), log_uniform(1e-6, 1e6), log_uniform(1e-6, 1e4), fr(-2.0, 2.0)), PER_CASE),
    ) {
        let cone = Cone::new(apex, axis, half);
        for (dir, t, r, k) in spheres {
            // A point on the cone's surface ray nearest `dir`, then offset by k·r.
            let perp = (dir - axis * dir.dot(axis)).try_normalize().unwrap_or(axis.any_orthonormal_vector());
            let surface = (axis * half.cos() + perp * half.sin()) * t;
            let center = apex.as_dvec3() + surface.as_dvec3() + dir.as_dvec3() * (r * k) as f64;
            let s = Sphere::new(center.as_vec3(), r);
            if oracle::sphere_cone(&cone, &s) {
                prop_assert!(cone.intersects_sphere(&s), "false negative: {s:?} against {cone:?}");
            }
        }
    }

    /// Boxes whose sampled points touch the cone are accepted.
    #[test]
    fn aabb_cone_is_conservative(
        apex in (fr(-50.0, 50.0), fr(-50.0, 50.0), fr(-50.0, 50.0)),
        axis in unit_vector(),
        half in fr(0.01, 1.55),
        boxes in prop::collection::vec(((fr(-60.0, 60.0), fr(-60.0, 60.0), fr(-60.0, 60.0)), (fr(0.01, 20.0), fr(0.01, 20.0), fr(0.01, 20.0))), 4),
    ) {
        let cone = Cone::new(Vec3::from(apex), axis, half);
        for (c, e) in boxes {
            let b = Aabb::new(Vec3::from(c) - Vec3::from(e), Vec3::from(c) + Vec3::from(e));
            let touches = box_samples(&b).any(|p| oracle::cone_distance(&cone, p) == 0.0);
            if touches {
                prop_assert!(cone.intersects_aabb(&b), "false negative: {b:?} against {cone:?}");
            }
        }
    }

    /// Triangles whose sampled points touch the cone (or frustum) are accepted.
    #[test]
    fn triangle_tests_are_conservative(
        f in frustum(),
        apex in (fr(-20.0, 20.0), fr(-20.0, 20.0), fr(-20.0, 20.0)),
        axis in unit_vector(),
        half in fr(0.01, 1.55),
        tris in prop::collection::vec(((fr(-40.0, 40.0), fr(-40.0, 40.0), fr(-40.0, 40.0)), unit_vector(), unit_vector(), fr(0.1, 30.0)), 4),
    ) {
        let cone = Cone::new(Vec3::from(apex), axis, half);
        for (c, u, v, size) in tris {
            let a = Vec3::from(c);
            let tri = Triangle::new(a, a + u * size, a + v * size);
            let samples: Vec<DVec3> = triangle_samples(&tri).collect();
            if samples.iter().any(|&p| oracle::cone_distance(&cone, p) == 0.0) {
                prop_assert!(tri.intersects_cone(&cone), "cone false negative: {tri:?} {cone:?}");
            }
            let shifted = Triangle::new(tri.a + f.origin, tri.b + f.origin, tri.c + f.origin);
            if triangle_samples(&shifted).any(|p| oracle::frustum_distance(&f, p) == 0.0) {
                prop_assert!(shifted.intersects_frustum(&f), "frustum false negative: {shifted:?}");
            }
        }
    }

    /// Elliptical cones against the exact (minimised) distance.
    #[test]
    fn sphere_elliptical_cone_is_conservative(
        apex in (fr(-10.0, 10.0), fr(-10.0, 10.0), fr(-10.0, 10.0)),
        q in rotation(),
        tx in log_uniform(0.05, 4.0),
        ty in log_uniform(0.05, 4.0),
        spheres in prop::collection::vec(((fr(-30.0, 30.0), fr(-30.0, 30.0), fr(-30.0, 30.0)), log_uniform(1e-3, 5.0)), 8),
    ) {
        let cone = EllipticalCone::new(Vec3::from(apex), glam::Mat3::from_quat(q), tx, ty);
        for (c, r) in spheres {
            let s = Sphere::new(Vec3::from(c) + cone.origin, r);
            if oracle::elliptical_cone_distance(&cone, s.center) <= r as f64 * (1.0 - 1e-6) {
                prop_assert!(cone.intersects_sphere(&s), "false negative: {s:?} against {cone:?}");
            }
        }
    }
}

/// An upper bound of the distance to an elliptical cone: the nearest of 4096 sampled boundary
/// rays (the distance to part of the surface can only be larger). A cross-check for the exact
/// oracle, not an oracle.
fn sampled_elliptical_cone_distance(cone: &EllipticalCone, p: Vec3) -> f64 {
    let q = cone.cone_from_world.as_dmat3() * (p.as_dvec3() - cone.origin.as_dvec3());
    let (tx, ty) = (cone.tan_x as f64, cone.tan_y as f64);
    if q.z > 0.0 && (q.x / tx).powi(2) + (q.y / ty).powi(2) <= q.z * q.z {
        return 0.0; // inside the solid cone
    }
    (0..4096)
        .map(|i| {
            let phi = i as f64 / 4096.0 * std::f64::consts::TAU;
            let dir = DVec3::new(tx * phi.cos(), ty * phi.sin(), 1.0).normalize();
            (q - dir * q.dot(dir).max(0.0)).length()
        })
        .fold(f64::INFINITY, f64::min)
}

proptest! {
    #![proptest_config(ProptestConfig::with_cases(1024))]

    /// The exact elliptical-cone distance (a bisected KKT projection) never exceeds the
    /// distance to 4096 sampled boundary rays and falls short of it by no more than that
    /// sampling's resolution; inside points are at 0. Mutation: a wrong branch for points
    /// behind the apex (q_z < 0), or a root bracketed on the wrong side, fails it.
    #[test]
    fn exact_elliptical_cone_distance_agrees_with_dense_sampling(
        q in rotation(),
        tx in log_uniform(0.05, 4.0),
        ty in log_uniform(0.05, 4.0),
        points in prop::collection::vec((fr(-30.0, 30.0), fr(-30.0, 30.0), fr(-30.0, 30.0)), 8),
    ) {
        let cone = EllipticalCone::new(Vec3::ZERO, glam::Mat3::from_quat(q), tx, ty);
        for c in points {
            let p = Vec3::from(c);
            let exact = oracle::elliptical_cone_distance(&cone, p);
            let sampled = sampled_elliptical_cone_distance(&cone, p);
            let scale = 1.0 + p.length() as f64;
            prop_assert!(exact <= sampled + 1e-9 * scale, "{p}: exact {exact} > sampled {sampled}");
            // 4096 rays: the arc between two covers at most ~0.0016 rad of the ellipse's
            // parameter, times the tangent's stretch.
            let resolution = 2e-3 * (tx.max(ty) / tx.min(ty)) as f64 * scale;
            prop_assert!(sampled - exact <= resolution, "{p}: exact {exact}, sampled {sampled}");
            if cone.contains_point(p) {
                prop_assert!(exact <= 1e-6 * scale);
            }
        }
    }
}

/// A grazing contact with a convex volume, built exactly in f64: a point `p` on its surface and
/// the outward normal `n` of a supporting plane there. Anything on the outer side of that plane
/// that contains `p` touches the volume at `p` and nowhere else: its exact distance is 0.
struct Contact {
    p: DVec3,
    n: DVec3,
}

impl Contact {
    /// On the cone's surface at distance `t` from the apex, towards the side `side` leans to.
    fn on_cone(cone: &Cone, half: f64, side: Vec3, t: f64) -> Option<Contact> {
        let axis = cone.axis.as_dvec3().normalize();
        let w = side.as_dvec3() - axis * side.as_dvec3().dot(axis);
        (w.length() > 1e-3).then(|| {
            let w = w.normalize();
            let along = axis * half.cos() + w * half.sin();
            Contact {
                p: cone.origin.as_dvec3() + along * t,
                n: w * half.cos() - axis * half.sin(),
            }
        })
    }

    /// Inside face `face` of the frustum at bilinear (s, t), with that face's outward normal.
    fn on_frustum(f: &Frustum, face: usize, s: f32, t: f32) -> Contact {
        let c = Frustum::FACES[face].map(|i| f.origin.as_dvec3() + f.corners[i].as_dvec3());
        let centre = f
            .corners
            .iter()
            .map(|c| f.origin.as_dvec3() + c.as_dvec3())
            .sum::<DVec3>()
            / 8.0;
        let n = (c[1] - c[0]).cross(c[2] - c[0]).normalize();
        let n = if (centre - c[0]).dot(n) > 0.0 { -n } else { n };
        Contact {
            p: on_face(f, face, s, t),
            n,
        }
    }

    /// The contact point as an f32 input: moved inward by a few ulps of its magnitude first,
    /// so that rounding to f32 cannot carry it outside (the caller's f32 coordinates are the
    /// input; a point one ulp outside genuinely does not touch).
    fn vertex(&self) -> Vec3 {
        (self.p - self.n * (8.0 * f32::EPSILON as f64 * (1.0 + self.p.abs().max_element())))
            .as_vec3()
    }

    /// The box with a corner at the contact, reaching `extents` away on the outer side.
    fn aabb(&self, extents: Vec3) -> Aabb {
        let corner = self.vertex();
        let far = corner + (self.n.signum() * extents.as_dvec3()).as_vec3();
        Aabb::new(corner.min(far), corner.max(far))
    }

    /// A triangle with a vertex at `p`, its edges pushed onto the outer side of the plane (an
    /// edge that pointed inward lies in the plane: a contact along a whole edge).
    fn triangle(&self, u: Vec3, v: Vec3) -> Triangle {
        let out = |d: Vec3| {
            let d = d.as_dvec3();
            d + self.n * (-d.dot(self.n)).max(0.0)
        };
        let a = self.vertex();
        Triangle::new(
            a,
            (a.as_dvec3() + out(u)).as_vec3(),
            (a.as_dvec3() + out(v)).as_vec3(),
        )
    }
}

proptest! {
    #![proptest_config(ProptestConfig::with_cases(2048))]

    /// Boxes and triangles that graze the cone — touching it at one point or along an edge,
    /// from outside, the exact distance 0 by construction — are accepted. The sampled-point
    /// properties above never produce such contacts. Mutation: dropping the rounding slack, or
    /// a strict `<` where `<=` belongs, fails here.
    #[test]
    fn grazing_boxes_and_triangles_touch_the_cone(
        apex in (fr(-50.0, 50.0), fr(-50.0, 50.0), fr(-50.0, 50.0)),
        axis in unit_vector(),
        half in fr(0.01, 1.55),
        contacts in prop::collection::vec((unit_vector(), fr(0.01, 60.0), (fr(0.01, 20.0), fr(0.01, 20.0), fr(0.01, 20.0)), unit_vector(), unit_vector(), fr(0.01, 30.0)), 8),
    ) {
        let cone = Cone::new(Vec3::from(apex), axis, half);
        for (side, t, e, u, v, size) in contacts {
            let Some(c) = Contact::on_cone(&cone, half as f64, side, t as f64) else { continue };
            // The exact f64 distance of the f32 contact vertex: 0, or the case proves nothing.
            if oracle::cone_distance(&cone, c.vertex()) > 0.0 {
                continue;
            }
            let b = c.aabb(Vec3::from(e));
            prop_assert!(cone.intersects_aabb(&b), "grazing box rejected: {b:?} against {cone:?}");
            let tri = c.triangle(u * size, v * size);
            prop_assert!(tri.intersects_cone(&cone), "grazing triangle rejected: {tri:?} against {cone:?}");
        }
    }

    /// Triangles grazing a frustum face from outside (at a vertex, or along an edge lying in
    /// the face's plane) are accepted, for frusta anywhere up to 1e6 with near planes to 1e-4.
    #[test]
    fn grazing_triangles_touch_the_frustum(
        f in frustum(),
        contacts in prop::collection::vec((0usize..6, fr(0.01, 0.99), fr(0.01, 0.99), unit_vector(), unit_vector(), log_uniform(1e-3, 1e3)), 8),
    ) {
        for (face, s, t, u, v, size) in contacts {
            let c = Contact::on_frustum(&f, face, s, t);
            if oracle::frustum_distance(&f, c.vertex()) > 0.0 {
                continue;
            }
            let tri = c.triangle(u * size, v * size);
            prop_assert!(tri.intersects_frustum(&f), "grazing triangle rejected: {tri:?} on face {face}");
        }
    }
}

/// Signed distances of `p` to the frustum's planes, in f64 (positive inside).
fn plane_distances_f64(f: &Frustum, p: DVec3) -> [f64; 6] {
    f.planes
        .map(|pl| pl.truncate().as_dvec3().dot(p - f.origin.as_dvec3()) + pl.w as f64)
}

/// Points in the box, in `f64` like the triangle's samples below.
fn box_samples(b: &Aabb) -> impl Iterator<Item = DVec3> + '_ {
    let n = 6;
    let (min, max) = (DVec3::from(b.min), DVec3::from(b.max));
    (0..n * n * n).map(move |i| {
        let f = |k: usize| (k % n) as f64 / (n - 1) as f64;
        min + (max - min) * DVec3::new(f(i), f(i / n), f(i / (n * n)))
    })
}

/// Points on the triangle, in `f64`: an `f32` sample far from the origin rounds off the
/// triangle (by up to half an ulp, 1/64 at x = 262 144) and can touch a frustum the exact
/// triangle misses, which a correct test then rightly rejects (CI found one, 2026-11-24).
fn triangle_samples(t: &Triangle) -> impl Iterator<Item = DVec3> + '_ {
    let n = 12;
    let [a, b, c] = [t.a, t.b, t.c].map(DVec3::from);
    (0..=n).flat_map(move |i| {
        (0..=n - i).map(move |j| {
            let (u, v) = (i as f64 / n as f64, j as f64 / n as f64);
            a + (b - a) * u + (c - a) * v
        })
    })
}

/// An eye pair: IPD up to 8 cm, cant ±12°, independent asymmetric tangents per eye.
fn eye_params() -> impl Strategy<Value = EyeParams> {
    let t = || log_uniform(0.2, 3.0);
    (
        (t(), t(), t(), t()),
        (t(), t(), t(), t()),
        fr(0.0, 0.08),
        fr(-12.0, 12.0),
    )
        .prop_map(|(l, r, ipd, cant)| EyeParams {
            left_fov: FovTangents {
                left: l.0,
                right: l.1,
                up: l.2,
                down: l.3,
            },
            right_fov: FovTangents {
                left: r.0,
                right: r.1,
                up: r.2,
                down: r.3,
            },
            ipd_m: ipd,
            cant_rad: cant.to_radians(),
        })
}

fn head() -> impl Strategy<Value = Mat4> {
    (position(), rotation()).prop_map(|(p, q)| Mat4::from_rotation_translation(q, p))
}

proptest! {
    #![proptest_config(ProptestConfig::with_cases(4096))]

    /// The superfrustum contains both eye frusta: every eye corner is inside it, and every
    /// sphere touching an eye frustum is accepted by it.
    #[test]
    fn superfrustum_contains_both_eye_frusta(
        eyes in eye_params(),
        head in head(),
        near in log_uniform(1e-4, 0.5),
        far in log_uniform(1.0, 1e4),
        spheres in sphere_params(),
    ) {
        let frusta = StereoFrusta::new(&eyes, head, near, far);
        let sf = Superfrustum::new(&eyes, head, near, far);
        for f in &frusta.eyes {
            for c in f.corners {
                let p = f.origin.as_dvec3() + c.as_dvec3();
                let worst = plane_distances_f64(&sf.frustum, p).into_iter().fold(f64::MAX, f64::min);
                // f32 rounding of the planes and corners: a few ulps of the magnitudes involved
                // (the corner relative to the superfrustum's apex), not a fraction of `far`.
                let magnitude = (p - sf.frustum.origin.as_dvec3()).abs().max_element();
                let tolerance = 16.0 * f32::EPSILON as f64 * magnitude;
                prop_assert!(worst >= -tolerance, "eye corner {p} outside the superfrustum {:?} by {worst} (tolerance {tolerance})", sf.fov);
            }
            for &(face, s, t, dir, r, k) in &spheres {
                let p = on_face(f, face, s, t) + dir.as_dvec3() * (r * k) as f64;
                let sphere = Sphere::new(p.as_vec3(), r);
                if oracle::sphere_frustum(f, &sphere) {
                    prop_assert!(sf.sphere(&sphere), "superfrustum misses {sphere:?}");
                }
            }
        }
    }

    /// Dual cones cover each eye's lens-visible region: a sphere around any point seen through a
    /// lens is accepted (circular and elliptical).
    #[test]
    fn dual_cones_cover_the_lens_visible_region(
        eyes in eye_params(),
        head in head(),
        hidden in fr(0.0, 0.25),
        points in prop::collection::vec((fr(0.0, 1.0), fr(0.0, 1.0), log_uniform(0.01, 1e3), any::<bool>(), unit_vector(), log_uniform(1e-5, 2.0), fr(0.0, 1.0)), PER_CASE),
    ) {
        let regions = Eye::BOTH.map(|e| LensRegion::with_hidden_fraction(eyes.fov(e), hidden));
        let circular = DualCone::new(&eyes, head, &regions, false);
        let elliptical = DualCone::new(&eyes, head, &regions, true);
        for (s, t, depth, right, dir, r, k) in points {
            let eye = if right { Eye::Right } else { Eye::Left };
            let fov = eyes.fov(eye);
            let tangent = Vec2::new(-fov.left + (fov.left + fov.right) * s, -fov.down + (fov.up + fov.down) * t);
            if !regions[eye.index()].contains(tangent) {
                continue;
            }
            // The seen point exactly (f64, through the eye pose as represented); the sphere must
            // contain it even where f32 cannot place its centre that precisely.
            let world_from_eye = (head * eyes.head_from_eye(eye)).as_dmat4();
            let p = world_from_eye.transform_point3(DVec3::new(tangent.x as f64, tangent.y as f64, -1.0) * depth as f64);
            let centre = (p + dir.as_dvec3() * (r * k) as f64).as_vec3();
            let radius = r.max((centre.as_dvec3().distance(p) * (1.0 + 1e-6)) as f32);
            let sphere = Sphere::new(centre, radius);
            prop_assert!(circular.sphere(&sphere), "dual cone misses {sphere:?}");
            prop_assert!(elliptical.sphere(&sphere), "dual elliptical cone misses {sphere:?}");
        }
    }
}
