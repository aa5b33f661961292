//! Choosing a level of detail per draw set: the coarsest level whose error, projected into the
//! pixels of every view that draws it, stays within the plan's bound.
//!
//! A displacement `d` of a point at eye-space depth `z` with lateral tangent `t` (x/z, y/z) moves
//! its image by `f·|d_xy − t·d_z| / (z + d_z)` pixels (f the view's pixels per unit tangent).
//! `|d_xy − t·d_z| ≤ |d|·√(1 + |t|²)` (the map's largest singular value), `z + d_z ≥ z − |d|`, and
//! inside the frustum `√(1 + |t|²) ≤ |corner|/depth` of its farthest-off-axis corner. So an
//! error `e` on an instance within the sphere (c, r) moves no visible point by more than
//! `f · spread · e / (z_min − e)` pixels, `z_min` the sphere's nearest depth.

use glam::Vec3;

use crate::cull::{Frustum, Sphere};
use crate::vocab::Resolution;

/// One view that draws a set, as far as projected error is concerned.
#[derive(Clone, Copy, Debug)]
pub(super) struct LodView {
    origin: Vec3,
    forward: Vec3,
    /// The most pixels one unit of tangent spans, across or up.
    focal_px: f32,
    /// √(1 + |t|²) at the frustum's farthest-off-axis corner.
    spread: f32,
}

impl LodView {
    pub fn new(frustum: &Frustum, pixels: Resolution) -> Self {
        // The near plane's inward normal is the view's axis.
        let forward = frustum.planes[4].truncate();
        let near = &frustum.corners[..4];
        let depth = near[0].dot(forward);
        let span_x = near[1].distance(near[0]) / depth;
        let span_y = near[3].distance(near[0]) / depth;
        LodView {
            origin: frustum.origin,
            forward,
            focal_px: (pixels.width as f32 / span_x).max(pixels.height as f32 / span_y),
            spread: near
                .iter()
                .map(|c| c.length() / c.dot(forward))
                .fold(1.0, f32::max),
        }
    }

    /// The most pixels a displacement of `error` (world units) anywhere in `bounds` moves a
    /// visible point; infinite when the sphere reaches the view's plane.
    pub fn error_px(&self, bounds: &Sphere, error: f32) -> f32 {
        let z = (bounds.center - self.origin).dot(self.forward) - bounds.radius - error;
        if z <= 0.0 {
            f32::INFINITY
        } else {
            self.focal_px * self.spread * error / z
        }
    }
}

/// The level to draw (0: the full mesh, k: its k-th simplified level) for an instance within
/// `bounds`, scaled by at most `scale`, whose levels have the mesh-space `errors` (finer first):
/// the coarsest whose projected error stays within `max_error_px` in every view.
pub(super) fn lod_level(
    views: &[LodView],
    max_error_px: f32,
    bounds: &Sphere,
    scale: f32,
    errors: &[f32],
) -> usize {
    errors
        .iter()
        .rposition(|&e| {
            views
                .iter()
                .all(|v| v.error_px(bounds, e * scale) <= max_error_px)
        })
        .map_or(0, |k| k + 1)
}

#[cfg(test)]
mod tests {
    use glam::{DMat4, DVec3, Mat4, Quat};
    use proptest::prelude::*;

    use super::*;
    use crate::view::FovTangents;

    /// The pixel a world point lands on (f64 pinhole through the eye's pose and tangents), or
    /// `None` behind the eye.
    fn project(
        eye_from_world: &DMat4,
        fov: FovTangents,
        px: Resolution,
        p: DVec3,
    ) -> Option<DVec3> {
        let q = eye_from_world.transform_point3(p);
        let z = -q.z;
        (z > 1e-9).then(|| {
            let (tx, ty) = (q.x / z, q.y / z);
            let x = (tx + fov.left as f64) / (fov.left + fov.right) as f64 * px.width as f64;
            let y = (ty + fov.down as f64) / (fov.up + fov.down) as f64 * px.height as f64;
            DVec3::new(x, y, 0.0)
        })
    }

    /// Whether a point is inside the frustum's side planes (f64).
    fn inside(eye_from_world: &DMat4, fov: FovTangents, p: DVec3) -> bool {
        let q = eye_from_world.transform_point3(p);
        let z = -q.z;
        z > 0.0
            && q.x >= -(fov.left as f64) * z
            && q.x <= fov.right as f64 * z
            && q.y >= -(fov.down as f64) * z
            && q.y <= fov.up as f64 * z
    }

    fn unit(v: (f32, f32, f32)) -> DVec3 {
        DVec3::new(v.0 as f64, v.1 as f64, v.2 as f64).normalize_or(DVec3::X)
    }

    proptest! {
        #![proptest_config(ProptestConfig::with_cases(128))]

        /// The projected error bounds what an f64 pinhole measures: displacing sampled points of
        /// the sphere that lie in the frustum by the error, in sampled directions, never moves
        /// one further on the image than the bound — off-axis, close to the eye and with
        /// asymmetric tangents included. Mutation: the bound without its off-axis `spread`
        /// fails.
        #[test]
        fn projected_error_bounds_the_pinhole(
            yaw in -1.0f32..1.0,
            fov in (0.3f32..1.4, 0.3f32..1.4, 0.3f32..1.4, 0.3f32..1.4),
            size in (64u32..2048, 64u32..2048),
            along in 0.5f32..30.0,
            across in (-1.0f32..1.0, -1.0f32..1.0),
            radius in 0.01f32..3.0,
            error in 0.0001f32..0.3,
            seed in any::<u64>(),
        ) {
            let fov = FovTangents { left: fov.0, right: fov.1, up: fov.2, down: fov.3 };
            let pixels = Resolution { width: size.0, height: size.1 };
            let world_from_eye = Mat4::from_rotation_translation(Quat::from_rotation_y(yaw), Vec3::new(0.3, 1.6, -2.0));
            let frustum = Frustum::from_eye(world_from_eye, fov, 0.05, 100.0);
            let eye_from_world = world_from_eye.as_dmat4().inverse();
            // The sphere's centre somewhere in front, up to the frustum's edges.
            let local = Vec3::new(
                across.0 * if across.0 < 0.0 { fov.left } else { fov.right },
                across.1 * if across.1 < 0.0 { fov.down } else { fov.up },
                -1.0,
            ) * along;
            let bounds = Sphere::new(world_from_eye.transform_point3(local), radius);
            let bound = LodView::new(&frustum, pixels).error_px(&bounds, error);
            let mut rng = seed;
            let mut next = || {
                rng = rng.wrapping_mul(6364136223846793005).wrapping_add(1442695040888963407);
                ((rng >> 40) as f32 / (1u64 << 24) as f32) * 2.0 - 1.0
            };
            let c = bounds.center.as_dvec3();
            for _ in 0..400 {
                let p = c + unit((next(), next(), next())) * (radius as f64 * next().abs() as f64);
                if !inside(&eye_from_world, fov, p) {
                    continue;
                }
                let d = unit((next(), next(), next())) * error as f64;
                let (Some(a), Some(b)) = (
                    project(&eye_from_world, fov, pixels, p),
                    project(&eye_from_world, fov, pixels, p + d),
                ) else {
                    prop_assert!(bound.is_infinite(), "a displaced point behind the eye");
                    continue;
                };
                let moved = a.distance(b);
                prop_assert!(moved <= bound as f64 * (1.0 + 1e-4) + 1e-6, "moved {moved} px, bound {bound}");
            }
        }
    }

    /// The selection takes the coarsest level within the bound, and coarser levels for coarser
    /// pixels: the same instance at the same place gets a coarser level in a view of a third of
    /// the pixels. Mutation: `position` for `rposition` (the finest level within the bound).
    #[test]
    fn coarser_pixels_choose_coarser_levels() {
        let fov = FovTangents {
            left: 1.0,
            right: 1.0,
            up: 1.0,
            down: 1.0,
        };
        let frustum = Frustum::from_eye(Mat4::IDENTITY, fov, 0.05, 100.0);
        let fine = LodView::new(
            &frustum,
            Resolution {
                width: 1536,
                height: 1536,
            },
        );
        let coarse = LodView::new(
            &frustum,
            Resolution {
                width: 512,
                height: 512,
            },
        );
        let bounds = Sphere::new(Vec3::new(0.0, 0.0, -10.0), 1.0);
        let errors = [0.001, 0.004, 0.016, 0.064];
        let level = |views: &[LodView]| lod_level(views, 1.0, &bounds, 1.0, &errors);
        let (f, c) = (level(&[fine]), level(&[coarse]));
        assert!(c > f, "coarse pixels {c}, fine {f}");
        for (views, k) in [(vec![fine], f), (vec![coarse], c)] {
            assert!(k == 0 || views[0].error_px(&bounds, errors[k - 1]) <= 1.0);
            assert!(k == errors.len() || views[0].error_px(&bounds, errors[k]) > 1.0);
        }
        assert_eq!(level(&[fine, coarse]), f, "every view must resolve it");
        let at_eye = Sphere::new(Vec3::new(0.0, 0.0, -0.5), 1.0);
        assert_eq!(lod_level(&[coarse], 1.0, &at_eye, 1.0, &errors), 0);
    }
}
