use glam::{Mat4, Vec3, Vec4};

use super::{rounding_slack, Aabb, Relation, Sphere};
use crate::view::FovTangents;

/// A six-plane frustum. Planes are stored relative to `origin` (the eye), so tests subtract the
/// eye position first and keep `f32` precision near the viewer even at large world coordinates.
/// Each plane is (inward unit normal, offset): a point p is inside when n·(p − origin) + d ≥ 0.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct Frustum {
    /// The eye: the planes are relative to it.
    pub origin: Vec3,
    /// Left, right, bottom, top, near, far: (inward unit normal, offset).
    pub planes: [Vec4; 6],
    /// The eight corners relative to `origin` (so they keep `f32` precision far from the world
    /// origin): near (l-d, r-d, r-u, l-u), then far in the same order.
    pub corners: [Vec3; 8],
}

impl Frustum {
    /// The six faces as corner indices (near, far, left, right, bottom, top).
    pub const FACES: [[usize; 4]; 6] = [
        [0, 1, 2, 3],
        [4, 5, 6, 7],
        [0, 3, 7, 4],
        [1, 5, 6, 2],
        [0, 4, 5, 1],
        [3, 2, 6, 7],
    ];

    /// The frustum of an eye at `world_from_eye` (looking down its −Z) with FOV tangents and
    /// near/far distances.
    pub fn from_eye(world_from_eye: Mat4, fov: FovTangents, near: f32, far: f32) -> Self {
        let FovTangents {
            left,
            right,
            up,
            down,
        } = fov;
        let local = [
            (Vec3::new(1.0, 0.0, -left), 0.0),
            (Vec3::new(-1.0, 0.0, -right), 0.0),
            (Vec3::new(0.0, -1.0, -up), 0.0),
            (Vec3::new(0.0, 1.0, -down), 0.0),
            (Vec3::new(0.0, 0.0, -1.0), -near),
            (Vec3::new(0.0, 0.0, 1.0), far),
        ];
        let (_, rotation, origin) = world_from_eye.to_scale_rotation_translation();
        let planes = local.map(|(n, d)| {
            let len = n.length();
            (rotation * (n / len)).extend(d / len)
        });
        let corner = |t: f32, x: f32, y: f32| rotation * Vec3::new(x * t, y * t, -t);
        let corners = [
            corner(near, -left, -down),
            corner(near, right, -down),
            corner(near, right, up),
            corner(near, -left, up),
            corner(far, -left, -down),
            corner(far, right, -down),
            corner(far, right, up),
            corner(far, -left, up),
        ];
        Frustum {
            origin,
            planes,
            corners,
        }
    }

    /// The corners in world space.
    pub fn world_corners(&self) -> [Vec3; 8] {
        self.corners.map(|c| self.origin + c)
    }

    /// Signed distance of `p` to plane `i` (positive inside).
    #[inline(always)]
    pub fn plane_distance(&self, i: usize, p: Vec3) -> f32 {
        let pl = self.planes[i];
        pl.truncate().dot(p - self.origin) + pl.w
    }

    #[inline]
    fn relation_with_reach(&self, center: Vec3, reach: impl Fn(Vec3) -> f32) -> Relation {
        let rel = center - self.origin;
        let slack = rounding_slack(rel.abs().element_sum() + self.planes[5].w);
        let mut inside = true;
        for pl in &self.planes {
            let n = pl.truncate();
            let d = n.dot(rel) + pl.w;
            let r = reach(n);
            if d < -(r + slack) {
                return Relation::Outside;
            }
            inside &= d >= r + slack;
        }
        if inside {
            Relation::Inside
        } else {
            Relation::Intersecting
        }
    }

    /// Conservative sphere relation: Outside only if the sphere is entirely outside one plane.
    #[inline]
    pub fn sphere(&self, s: &Sphere) -> Relation {
        self.relation_with_reach(s.center, |_| s.radius)
    }

    /// Whether the sphere may touch the frustum (conservative).
    #[inline]
    pub fn intersects_sphere(&self, s: &Sphere) -> bool {
        self.sphere(s) != Relation::Outside
    }

    /// Conservative box relation (the box's reach along each plane normal).
    #[inline]
    pub fn aabb(&self, b: &Aabb) -> Relation {
        let e = b.extents();
        self.relation_with_reach(b.center(), |n| n.abs().dot(e))
    }

    /// Whether a point is inside (conservatively, within rounding slack).
    #[inline]
    pub fn contains_point(&self, p: Vec3) -> bool {
        let rel = p - self.origin;
        let slack = rounding_slack(rel.abs().element_sum() + self.planes[5].w);
        self.planes
            .iter()
            .all(|pl| pl.truncate().dot(rel) + pl.w >= -slack)
    }
}
