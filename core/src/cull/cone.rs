//! Circular and elliptical cones (Hale 2018 §3.2) and their intersection tests.
//!
//! Hale's sphere test (his Listing 3.2) rejects spheres behind `z = −r·cos θ` without checking
//! whether they contain the apex — a false negative for a sphere around the apex. The test here
//! splits at `a = −r·sin θ` as his §3.2.2 text derives: behind it only the apex can be within
//! `r`, in front of it the apex-offset cone decides; both parts are conservative.

use glam::{Mat3, Vec3};

use super::{rounding_slack, Aabb, Relation, Sphere};

/// A single acute cone: apex `origin`, unit `axis`, half-angle θ ∈ (0°, 90°).
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct Cone {
    /// Its apex.
    pub origin: Vec3,
    /// Its unit axis.
    pub axis: Vec3,
    /// tan θ.
    pub tan: f32,
    /// sin θ.
    pub sin: f32,
    /// cos θ.
    pub cos: f32,
    /// 1 / cos θ.
    pub sec: f32,
    /// tan²θ + 1 (Hale's σ).
    pub sigma: f32,
    /// cos²θ (Hale's ρ).
    pub rho: f32,
}

impl Cone {
    /// A cone from apex, direction (normalised here) and half-angle in radians, clamped to
    /// (1e-6, π/2 − 1e-6) so the precomputed factors stay finite.
    pub fn new(origin: Vec3, axis: Vec3, half_angle: f32) -> Self {
        let t = half_angle.clamp(1e-6, std::f32::consts::FRAC_PI_2 - 1e-6);
        let (sin, cos) = t.sin_cos();
        Cone {
            origin,
            axis: axis.normalize(),
            tan: sin / cos,
            sin,
            cos,
            sec: 1.0 / cos,
            sigma: 1.0 / (cos * cos),
            rho: cos * cos,
        }
    }

    /// Its half-angle θ in radians.
    pub fn half_angle(&self) -> f32 {
        self.tan.atan()
    }

    /// Point test through tangents (Hale eq. 3.3): a > 0 ∧ |c|² ≤ σ a².
    #[inline]
    pub fn contains_point_tan(&self, p: Vec3) -> bool {
        let c = p - self.origin;
        let a = c.dot(self.axis);
        a > 0.0 && c.length_squared() <= self.sigma * a * a
    }

    /// Point test through cosines (Hale eq. 3.4): a > 0 ∧ ρ|c|² ≤ a².
    #[inline]
    pub fn contains_point_cos(&self, p: Vec3) -> bool {
        let c = p - self.origin;
        let a = c.dot(self.axis);
        a > 0.0 && self.rho * c.length_squared() <= a * a
    }

    /// Conservative sphere test (see the module docs), without roots or trigonometry.
    #[inline]
    pub fn intersects_sphere(&self, s: &Sphere) -> bool {
        let c = s.center - self.origin;
        let r = s.radius + rounding_slack(c.abs().element_sum() + s.radius);
        let a = c.dot(self.axis);
        // The distance from the axis comes from the perpendicular vector itself: |c|² − a²
        // would cancel catastrophically for narrow cones.
        sphere_in_axis_frame(
            a,
            (c - self.axis * a).length_squared(),
            c.length_squared(),
            r,
            self,
        )
    }

    /// The cone's frame, for Hale's fastest sphere variant: transform the centre so the cone is
    /// z-aligned with its apex at the origin, then test there (his Listing 3.2, with the apex
    /// case fixed).
    pub fn view(&self) -> ConeView {
        ConeView {
            cone: *self,
            cone_from_world: self.view_rotation(),
        }
    }

    /// Conservative box test: the box's bounding sphere first, then exact-or-conservative
    /// refinements (apex in box, a corner in the cone, an edge crossing the cone, the axis
    /// crossing a face — Hale 2018 §3.2.2 and Eberly).
    pub fn intersects_aabb(&self, b: &Aabb) -> bool {
        let bound = Sphere::new(b.center(), b.extents().length());
        if !self.intersects_sphere(&bound) {
            return false;
        }
        let grown = Aabb::new(
            b.min - Vec3::splat(bound_slack(b)),
            b.max + Vec3::splat(bound_slack(b)),
        );
        if grown.distance_squared(self.origin) == 0.0 {
            return true;
        }
        let corners = grown.corners();
        if corners.iter().any(|&p| self.contains_point_tan(p)) {
            return true;
        }
        const EDGES: [(usize, usize); 12] = [
            (0, 1),
            (2, 3),
            (4, 5),
            (6, 7),
            (0, 2),
            (1, 3),
            (4, 6),
            (5, 7),
            (0, 4),
            (1, 5),
            (2, 6),
            (3, 7),
        ];
        if EDGES
            .iter()
            .any(|&(i, j)| self.intersects_segment(corners[i], corners[j]))
        {
            return true;
        }
        self.axis_hits_box(&grown)
    }

    /// Box relation for hierarchies: Inside when all corners are inside (the cone is convex).
    pub fn aabb(&self, b: &Aabb) -> Relation {
        if !self.intersects_aabb(b) {
            Relation::Outside
        } else if b.corners().iter().all(|&p| self.contains_point_tan(p)) {
            Relation::Inside
        } else {
            Relation::Intersecting
        }
    }

    /// Whether the segment p0–p1 has a point inside the cone (both ends outside assumed or not).
    pub(crate) fn intersects_segment(&self, p0: Vec3, p1: Vec3) -> bool {
        if self.contains_point_tan(p0) || self.contains_point_tan(p1) {
            return true;
        }
        // f(t) = (n·c(t))² − ρ|c(t)|², positive inside the double cone; restrict to the single
        // cone by n·c(t) > 0. f is quadratic: f(t) = A t² + 2B t + C.
        let c = p0 - self.origin;
        let d = p1 - p0;
        let (nc, nd) = (self.axis.dot(c), self.axis.dot(d));
        let a2 = nd * nd - self.rho * d.length_squared();
        let b = nd * nc - self.rho * d.dot(c);
        let c0 = nc * nc - self.rho * c.length_squared();
        // The front part of the segment: n·c(t) > 0 for t in (lo, hi).
        let (mut lo, mut hi) = (0.0f32, 1.0f32);
        if nd.abs() < f32::MIN_POSITIVE {
            if nc <= 0.0 {
                return false;
            }
        } else {
            let t_plane = -nc / nd;
            if nd > 0.0 {
                lo = lo.max(t_plane);
            } else {
                hi = hi.min(t_plane);
            }
        }
        if lo >= hi {
            return false;
        }
        // Max of f on [lo, hi]: at an end or at the vertex of a concave parabola.
        let f = |t: f32| (a2 * t + 2.0 * b) * t + c0;
        let mut best = f(lo).max(f(hi));
        if a2 < 0.0 {
            let tv = -b / a2;
            if tv > lo && tv < hi {
                best = best.max(f(tv));
            }
        }
        // Slack relative to the quadratic's magnitude keeps the test conservative.
        let scale =
            (nc.abs() + nd.abs()).powi(2) + self.rho * (c.length_squared() + d.length_squared());
        best >= -rounding_slack(scale)
    }

    /// Whether the axis ray from the apex passes through the box (then the box meets the cone).
    fn axis_hits_box(&self, b: &Aabb) -> bool {
        let inv = self.axis.recip();
        let t0 = (b.min - self.origin) * inv;
        let t1 = (b.max - self.origin) * inv;
        let tmin = t0.min(t1).max_element();
        let tmax = t0.max(t1).min_element();
        tmax >= tmin.max(0.0)
    }

    /// The rotation taking the cone's axis to +Z (for the view-space variants).
    pub fn view_rotation(&self) -> Mat3 {
        let forward = self.axis;
        let helper = if forward.y.abs() < 0.99 {
            Vec3::Y
        } else {
            Vec3::X
        };
        let right = helper.cross(forward).normalize();
        let up = forward.cross(right);
        Mat3::from_cols(right, up, forward).transpose()
    }
}

/// The sphere test in the cone's axis frame: axial coordinate `a`, squared distance from the
/// axis `perp_sq`, squared distance from the apex `cc`, radius `r` (slack included). Behind
/// `a = −r·sin θ` only the apex can be within r; in front, the cone with its apex moved back by
/// r / sin θ decides — its radius at `a` is a·tan θ + r / cos θ, stable as θ → 0.
#[inline(always)]
fn sphere_in_axis_frame(a: f32, perp_sq: f32, cc: f32, r: f32, cone: &Cone) -> bool {
    if a <= -r * cone.sin {
        return cc <= r * r;
    }
    let reach = a * cone.tan + r * cone.sec;
    perp_sq <= reach * reach
}

/// A cone with its view rotation precomputed (see [`Cone::view`]).
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct ConeView {
    /// The cone.
    pub cone: Cone,
    /// World to cone frame: the axis becomes +Z.
    pub cone_from_world: Mat3,
}

impl ConeView {
    #[inline]
    /// Conservative: false only if no point of the sphere lies in the cone.
    pub fn intersects_sphere(&self, s: &Sphere) -> bool {
        let q = self.cone_from_world * (s.center - self.cone.origin);
        let r = s.radius + rounding_slack(q.abs().max_element() + s.radius);
        sphere_in_axis_frame(
            q.z,
            q.x * q.x + q.y * q.y,
            q.length_squared(),
            r,
            &self.cone,
        )
    }

    /// Point test in the cone frame (Hale eq. 3.1): z > 0 ∧ x² + y² ≤ tan²θ z².
    #[inline]
    pub fn contains_point(&self, p: Vec3) -> bool {
        let q = self.cone_from_world * (p - self.cone.origin);
        let t = self.cone.tan * q.z;
        q.z > 0.0 && q.x * q.x + q.y * q.y <= t * t
    }
}

fn bound_slack(b: &Aabb) -> f32 {
    rounding_slack(b.min.abs().max(b.max.abs()).max_element())
}

/// A cone with an elliptical cross-section: in its own frame (x right, y up, z along the axis)
/// x²/tx² + y²/ty² ≤ z², z > 0 — Hale's proposed fit for asymmetric fields of view.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct EllipticalCone {
    /// Its apex.
    pub origin: Vec3,
    /// World to cone frame.
    pub cone_from_world: Mat3,
    /// The half-width of its cross-section at unit depth.
    pub tan_x: f32,
    /// The half-height of its cross-section at unit depth.
    pub tan_y: f32,
    /// x scale making it circular, and that circular cone (apex at the origin, axis +Z).
    scale_x: f32,
    circular: Cone,
}

impl EllipticalCone {
    /// The cone with apex `origin`, frame `cone_from_world` and cross-section `tan_x` × `tan_y` at unit depth.
    pub fn new(origin: Vec3, cone_from_world: Mat3, tan_x: f32, tan_y: f32) -> Self {
        let circular = Cone::new(Vec3::ZERO, Vec3::Z, tan_y.atan());
        EllipticalCone {
            origin,
            cone_from_world,
            tan_x,
            tan_y,
            scale_x: tan_y / tan_x,
            circular,
        }
    }

    /// Whether `p` lies in it.
    pub fn contains_point(&self, p: Vec3) -> bool {
        let q = self.cone_from_world * (p - self.origin);
        q.z > 0.0 && (q.x / self.tan_x).powi(2) + (q.y / self.tan_y).powi(2) <= q.z * q.z
    }

    /// Conservative sphere test: scaling x by `tan_y / tan_x` makes the cone circular and the
    /// sphere an ellipsoid, bounded by a sphere of radius r·max(1, scale).
    #[inline]
    pub fn intersects_sphere(&self, s: &Sphere) -> bool {
        let q = self.cone_from_world * (s.center - self.origin);
        let k = self.scale_x;
        let scaled = Sphere::new(Vec3::new(q.x * k, q.y, q.z), s.radius * k.max(1.0));
        self.circular.intersects_sphere(&scaled)
    }

    /// Conservative box relation: the box's bounding sphere; Inside when all corners are.
    pub fn aabb(&self, b: &Aabb) -> Relation {
        if !self.intersects_sphere(&Sphere::new(b.center(), b.extents().length())) {
            Relation::Outside
        } else if b.corners().iter().all(|&p| self.contains_point(p)) {
            Relation::Inside
        } else {
            Relation::Intersecting
        }
    }
}
