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
pub fn frustum_distance(f: &Frustum, p: glam::Vec3) -> f64 {
    let c: Vec<DVec3> = f.corners.iter().map(|&v| d(f.origin) + d(v)).collect();
    let faces = Frustum::FACES;
    let centre = c.iter().copied().sum::<DVec3>() / 8.0;
    let p = d(p);
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
pub fn cone_distance(cone: &Cone, p: glam::Vec3) -> f64 {
    let c = d(p) - d(cone.origin);
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

/// Distance to an elliptical cone, by minimising over its boundary rays (the cone is convex, so
/// outside points are nearest to some boundary ray). Sampled densely, then refined.
pub fn elliptical_cone_distance(cone: &EllipticalCone, p: glam::Vec3) -> f64 {
    let q = cone.cone_from_world.as_dmat3() * (d(p) - d(cone.origin));
    let (tx, ty) = (cone.tan_x as f64, cone.tan_y as f64);
    if q.z > 0.0 && (q.x / tx).powi(2) + (q.y / ty).powi(2) <= q.z * q.z {
        return 0.0;
    }
    let ray_distance = |phi: f64| {
        let dir = DVec3::new(tx * phi.cos(), ty * phi.sin(), 1.0).normalize();
        let t = q.dot(dir).max(0.0);
        (q - dir * t).length()
    };
    let steps = 720;
    let mut best = (f64::INFINITY, 0.0);
    for i in 0..steps {
        let phi = i as f64 / steps as f64 * std::f64::consts::TAU;
        let dist = ray_distance(phi);
        if dist < best.0 {
            best = (dist, phi);
        }
    }
    // Golden-section refinement around the best sample.
    let step = std::f64::consts::TAU / steps as f64;
    let (mut lo, mut hi) = (best.1 - step, best.1 + step);
    for _ in 0..60 {
        let m1 = hi - (hi - lo) * 0.618_033_988_75;
        let m2 = lo + (hi - lo) * 0.618_033_988_75;
        if ray_distance(m1) < ray_distance(m2) {
            hi = m2;
        } else {
            lo = m1;
        }
    }
    best.0.min(ray_distance((lo + hi) / 2.0))
}
