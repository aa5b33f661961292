//! The part of an eye's image visible through the lens, as foveate models it when a profile has
//! no hidden-area mesh: an ellipse centred on the image, scaled so that the area it hides in
//! the corners matches the headset's published hidden-area fraction, clipped to the image.

use glam::{DVec2, Vec2};

use super::{polygon, FovTangents};

/// The lens-visible region of one eye in tangent space (x = tan right, y = tan up).
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct LensRegion {
    /// The field the region lies in.
    pub fov: FovTangents,
    /// Ellipse scale relative to the inscribed ellipse (1 = touches the image edges).
    pub scale: f32,
}

impl LensRegion {
    /// The region hiding `hidden_fraction` of the image (0 ⇒ the whole image is visible).
    pub fn with_hidden_fraction(fov: FovTangents, hidden_fraction: f32) -> Self {
        let visible = (1.0 - hidden_fraction.clamp(0.0, 0.99)) as f64;
        let (mut lo, mut hi) = (0.0, std::f64::consts::SQRT_2);
        for _ in 0..60 {
            let mid = 0.5 * (lo + hi);
            let region = LensRegion {
                fov,
                scale: mid as f32,
            };
            if 1.0 - region.hidden_fraction() < visible {
                lo = mid;
            } else {
                hi = mid;
            }
        }
        LensRegion {
            fov,
            scale: hi as f32,
        }
    }

    /// Centre and semi-axes of the ellipse in tangent space.
    pub fn ellipse(&self) -> (Vec2, Vec2) {
        let f = self.fov;
        let centre = Vec2::new((f.right - f.left) / 2.0, (f.up - f.down) / 2.0);
        let half = Vec2::new((f.left + f.right) / 2.0, (f.up + f.down) / 2.0);
        (centre, half * self.scale)
    }

    /// The ellipse in the view's NDC: (centre x, centre y, radius x, radius y), as the stencil
    /// mask shader draws it (the scissor clips it to the image).
    pub fn ndc_ellipse(&self) -> glam::Vec4 {
        let (centre, axes) = self.ellipse();
        let f = self.fov;
        let c = f.ndc(centre);
        glam::Vec4::new(
            c.x,
            c.y,
            2.0 * axes.x / (f.left + f.right),
            2.0 * axes.y / (f.up + f.down),
        )
    }

    /// The fraction of the image the region hides, by area (exact for the ellipse clipped to
    /// the image, integrated numerically).
    pub fn hidden_fraction(&self) -> f64 {
        // The ellipse maps to a disc of radius `scale` over the square [-1,1]² (the image
        // stretched to it), so the visible fraction is the disc's share of the square.
        let k = self.scale as f64;
        let pi = std::f64::consts::PI;
        let visible = if k <= 1.0 {
            pi * k * k / 4.0
        } else if k >= std::f64::consts::SQRT_2 {
            1.0
        } else {
            (pi * k * k - 4.0 * (k * k * (1.0 / k).acos() - (k * k - 1.0).sqrt())) / 4.0
        };
        1.0 - visible
    }

    /// A convex polygon that contains the region: the ellipse's circumscribed `n`-gon clipped
    /// to the image rectangle.
    pub fn bounding_polygon(&self, n: usize) -> Vec<Vec2> {
        let (centre, axes) = self.ellipse();
        let grow = 1.0 / (std::f32::consts::PI / n as f32).cos();
        let poly = (0..n)
            .map(|i| {
                let a = std::f32::consts::TAU * i as f32 / n as f32;
                (centre + axes * grow * Vec2::new(a.cos(), a.sin())).as_dvec2()
            })
            .collect();
        let f = self.fov;
        let (min, max) = (
            DVec2::new(-f.left as f64, -f.down as f64),
            DVec2::new(f.right as f64, f.up as f64),
        );
        polygon::clip_to_rect(poly, min, max)
            .into_iter()
            .map(|p| p.as_vec2())
            .collect()
    }

    /// Whether pixel (x, y) of a `width` × `height` image of the region's view lies wholly
    /// inside the region (all four corners), y down.
    pub fn contains_pixel(&self, x: u32, y: u32, width: u32, height: u32) -> bool {
        let f = self.fov;
        [(0, 0), (1, 0), (0, 1), (1, 1)].iter().all(|&(dx, dy)| {
            self.contains(Vec2::new(
                -f.left + (x + dx) as f32 / width as f32 * (f.left + f.right),
                f.up - (y + dy) as f32 / height as f32 * (f.up + f.down),
            ))
        })
    }

    /// Whether a tangent-space point is inside the region.
    pub fn contains(&self, p: Vec2) -> bool {
        let f = self.fov;
        let (centre, axes) = self.ellipse();
        let q = (p - centre) / axes;
        p.x >= -f.left
            && p.x <= f.right
            && p.y >= -f.down
            && p.y <= f.up
            && q.length_squared() <= 1.0
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn hidden_fraction_is_matched_by_measured_area() {
        let fov = FovTangents::from_angles_deg(50.0, 40.0, 45.0, 48.0);
        for hidden in [0.0913f32, 0.1407, 0.1910, 0.2146] {
            let region = LensRegion::with_hidden_fraction(fov, hidden);
            // Count samples on a fine grid of the image.
            let n = 400;
            let mut inside = 0;
            for i in 0..n {
                for j in 0..n {
                    let x = -fov.left + (fov.left + fov.right) * (i as f32 + 0.5) / n as f32;
                    let y = -fov.down + (fov.up + fov.down) * (j as f32 + 0.5) / n as f32;
                    inside += region.contains(Vec2::new(x, y)) as u32;
                }
            }
            let measured_hidden = 1.0 - inside as f32 / (n * n) as f32;
            assert!(
                (measured_hidden - hidden).abs() < 0.003,
                "{hidden}: {measured_hidden}"
            );
        }
    }

    #[test]
    fn bounding_polygon_contains_the_region() {
        let fov = FovTangents::from_angles_deg(44.0, 35.6, 41.7, 48.0);
        let region = LensRegion::with_hidden_fraction(fov, 0.1407);
        let poly = region.bounding_polygon(48);
        let inside_poly = |p: Vec2| {
            (0..poly.len()).all(|i| {
                let (a, b) = (poly[i], poly[(i + 1) % poly.len()]);
                (b - a).perp_dot(p - a) >= -1e-6
            })
        };
        for i in 0..200 {
            for j in 0..200 {
                let p = Vec2::new(-1.2 + 2.4 * i as f32 / 199.0, -1.2 + 2.4 * j as f32 / 199.0);
                if region.contains(p) {
                    assert!(inside_poly(p), "{p} in the region but not in its polygon");
                }
            }
        }
    }
}
