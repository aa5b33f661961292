use glam::Vec3;

use super::{Cone, Frustum};

/// A triangle, for GPU-style primitive culling (Hale §3.2.2, Table 4.4).
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct Triangle {
    /// First corner.
    pub a: Vec3,
    /// Second corner.
    pub b: Vec3,
    /// Third corner.
    pub c: Vec3,
}

impl Triangle {
    /// The triangle `a`, `b`, `c`.
    pub fn new(a: Vec3, b: Vec3, c: Vec3) -> Self {
        Self { a, b, c }
    }

    /// Conservative frustum test: rejected only when all three vertices are outside one plane.
    #[inline]
    pub fn intersects_frustum(&self, f: &Frustum) -> bool {
        let slack = super::rounding_slack(
            (self.a - f.origin)
                .abs()
                .max((self.b - f.origin).abs())
                .max((self.c - f.origin).abs())
                .max_element()
                + f.planes[5].w,
        );
        (0..6).all(|i| {
            f.plane_distance(i, self.a) >= -slack
                || f.plane_distance(i, self.b) >= -slack
                || f.plane_distance(i, self.c) >= -slack
        })
    }

    /// Eberly's order: a vertex inside, else an edge crossing, else the axis through the face.
    pub fn intersects_cone(&self, cone: &Cone) -> bool {
        let [a, b, c] = [self.a, self.b, self.c];
        if cone.contains_point_tan(a) || cone.contains_point_tan(b) || cone.contains_point_tan(c) {
            return true;
        }
        if cone.intersects_segment(a, b)
            || cone.intersects_segment(b, c)
            || cone.intersects_segment(c, a)
        {
            return true;
        }
        self.hit_by_ray(cone.origin, cone.axis)
    }

    /// Möller–Trumbore without the hit point: does the ray from `o` along `d` cross the triangle?
    fn hit_by_ray(&self, o: Vec3, d: Vec3) -> bool {
        let e1 = self.b - self.a;
        let e2 = self.c - self.a;
        let p = d.cross(e2);
        let det = e1.dot(p);
        if det.abs() < f32::MIN_POSITIVE {
            return false;
        }
        let inv = 1.0 / det;
        let s = o - self.a;
        let u = s.dot(p) * inv;
        let q = s.cross(e1);
        let v = d.dot(q) * inv;
        let t = e2.dot(q) * inv;
        let eps = 1e-5;
        u >= -eps && v >= -eps && u + v <= 1.0 + eps && t >= -eps
    }
}
