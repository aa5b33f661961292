//! Slow `f64` ground truths the fast `f32` tests are checked against (tests and statistics).

use glam::DVec3;

use super::{Cone, EllipticalCone, Frustum, Sphere};

fn d(v: glam::Vec3) -> DVec3 {
    v.as_dvec3()
}

/// Distance from `p` to a convex polygon (vertices in order) in 3D.
fn point_polygon_distance(p: DVec3, poly: &[DVec3]) -> f64 {
    let n = (poly[1] - poly[0]).cross(poly[2] - poly[0]).normalize();
    let plane = (p - poly[0]).dot(n);
    let proj = p - n * plane;
    let centroid = poly.iter().copied().sum::<DVec3>() / poly.len() as f64;
    let inside = (0..poly.len()).all(|i| {
        let (a, b) = (poly[i], poly[(i + 1) % poly.len()]);
        let edge_normal = (b - a).cross(n);
        // Orient each edge's normal away from the centroid.
        let outward = if (centroid - a).dot(edge_normal) > 0.0 {
            -edge_normal
        } else {
            edge_normal
        };
        (proj - a).dot(outward) <= 0.0
    });
    if inside {
        return plane.abs();
    }
    (0..poly.len())
        .map(|i| {
            let (a, b) = (poly[i], poly[(i + 1) % poly.len()]);
            let t = ((p - a).dot(b - a) / (b - a).length_squared()).clamp(0.0, 1.0);
            (p - (a + (b - a) * t)).length()
        })
        .fold(f64::INFINITY, f64::min)
}

/// Exact Euclidean distance from `p` to the (solid) frustum given by its eight corners, 0
/// inside.
pub fn frustum_distance(f: &Frustum, p: impl Into<DVec3>) -> f64 {
    let c: Vec<DVec3> = f.corners.iter().map(|&v| d(f.origin) + d(v)).collect();
    let faces = Frustum::FACES;
    let centre = c.iter().copied().sum::<DVec3>() / 8.0;
    let p = p.into();
    let inside = faces.iter().all(|face| {
        let n = (c[face[1]] - c[face[0]]).cross(c[face[2]] - c[face[0]]);
        let toward_centre = (centre - c[face[0]]).dot(n).signum();
        (p - c[face[0]]).dot(n) * toward_centre >= 0.0
    });
    if inside {
        return 0.0;
    }
    faces
        .iter()
        .map(|face| point_polygon_distance(p, &face.map(|i| c[i])))
        .fold(f64::INFINITY, f64::min)
}

/// Does the sphere touch the frustum? Exact, in `f64`.
pub fn sphere_frustum(f: &Frustum, s: &Sphere) -> bool {
    frustum_distance(f, s.center) <= s.radius as f64
}

/// Hale's ground truth (his Listing 3.1, with `acos`), corrected for points whose nearest cone
/// point is the apex: the distance from `p` to the solid single cone.
pub fn cone_distance(cone: &Cone, p: impl Into<DVec3>) -> f64 {
    let c = p.into() - d(cone.origin);
    let len = c.length();
    if len == 0.0 {
        return 0.0;
    }
    let half = (cone.tan as f64).atan();
    let angle = (c.dot(d(cone.axis).normalize()) / len)
        .clamp(-1.0, 1.0)
        .acos();
    if angle <= half {
        0.0
    } else if angle - half >= std::f64::consts::FRAC_PI_2 {
        len
    } else {
        len * (angle - half).sin()
    }
}

pub fn sphere_cone(cone: &Cone, s: &Sphere) -> bool {
    cone_distance(cone, s.center) <= s.radius as f64
}

/// Exact distance to an elliptical cone (one nappe, apex at `origin`): the projection onto the
/// convex set C = {(x/a)² + (y/b)² ≤ z², z ≥ 0} in the cone's frame. Outside C the nearest
/// point is the apex or satisfies the KKT conditions with a multiplier μ ≥ 0:
/// x = qₓa²/(a²+μ), y = q_y b²/(b²+μ), z = q_z/(1−μ), on the surface, i.e. F(μ) = 0 with
/// F(μ) = qₓ²a²/(a²+μ)² + q_y²b²/(b²+μ)² − q_z²/(1−μ)².
/// - q_z > 0: F(0) > 0 (q is outside), F decreases to −∞ as μ → 1⁻: one root in (0, 1).
/// - q_z < 0: z ≥ 0 needs μ > 1; F rises from −∞ and ends with the sign of
///   qₓ²a² + q_y²b² − q_z² (q outside the polar cone): then it crosses zero exactly once (two
///   crossings would be two projections onto a convex set), else the apex is nearest.
/// - q_z = 0: μ = 1, z taken from the surface.
///
/// Each root is bracketed and bisected to f64 resolution: no sampling.
pub fn elliptical_cone_distance(cone: &EllipticalCone, p: glam::Vec3) -> f64 {
    let q = cone.cone_from_world.as_dmat3() * (d(p) - d(cone.origin));
    let (a, b) = (cone.tan_x as f64, cone.tan_y as f64);
    let (a2, b2) = (a * a, b * b);
    if q.z >= 0.0 && (q.x / a).powi(2) + (q.y / b).powi(2) <= q.z * q.z {
        return 0.0;
    }
    let point = |mu: f64, z: f64| DVec3::new(q.x * a2 / (a2 + mu), q.y * b2 / (b2 + mu), z);
    // (x/a)² + (y/b)² at the KKT point for μ.
    let xy = |mu: f64| (q.x * a / (a2 + mu)).powi(2) + (q.y * b / (b2 + mu)).powi(2);
    let f = |mu: f64| xy(mu) - (q.z / (1.0 - mu)).powi(2);
    // Bisection on [lo, hi] where f(lo) > 0 > f(hi) (or the reverse, given by `rising`).
    let bisect = |mut lo: f64, mut hi: f64, rising: bool| {
        for _ in 0..200 {
            let mid = 0.5 * (lo + hi);
            if mid <= lo || mid >= hi {
                break;
            }
            if (f(mid) > 0.0) != rising {
                lo = mid;
            } else {
                hi = mid;
            }
        }
        0.5 * (lo + hi)
    };
    let nearest = if q.z > 0.0 {
        let mu = bisect(0.0, 1.0, false);
        Some(point(mu, q.z / (1.0 - mu)))
    } else if q.z < 0.0 {
        if q.x * q.x * a2 + q.y * q.y * b2 <= q.z * q.z {
            None // in the polar cone: the apex is nearest
        } else {
            // F > 0 somewhere past 1: double until it is, then bisect the crossing.
            let mut hi = 2.0;
            while f(hi) <= 0.0 && hi < 1e300 {
                hi *= 2.0;
            }
            let mu = bisect(1.0, hi, true);
            Some(point(mu, q.z / (1.0 - mu)))
        }
    } else {
        let s = point(1.0, 0.0);
        Some(DVec3::new(
            s.x,
            s.y,
            ((s.x / a).powi(2) + (s.y / b).powi(2)).sqrt(),
        ))
    };
    let apex = q.length();
    nearest.map_or(apex, |n| (q - n).length().min(apex))
}
