//! Lens distortion: where the eye sees each display pixel through the headset's lens, which is
//! what the output stage needs to pre-distort the rendered image (Di Donato 2017 §2: the lens's
//! pincushion distortion, countered by the compositor's barrel distortion).

use glam::Vec2;

use super::FovTangents;

/// A radial polynomial lens model in tangent units (the Cardboard SDK's convention): a display
/// point at tangent offset `d` from the lens axis is seen by the eye in the direction
/// `d · (1 + k1·r² + k2·r⁴)`, `r = |d|`. With `k1, k2 ≥ 0` this is a pincushion lens: the
/// further out, the more magnified.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct RadialDistortion {
    /// The r² coefficient.
    pub k1: f32,
    /// The r⁴ coefficient.
    pub k2: f32,
}

impl RadialDistortion {
    /// No lens: every display point is seen where it is.
    pub const NONE: RadialDistortion = RadialDistortion { k1: 0.0, k2: 0.0 };

    /// The magnification at squared display radius `r2`.
    pub fn factor(self, r2: f32) -> f32 {
        1.0 + r2 * (self.k1 + self.k2 * r2)
    }

    /// The eye's direction (tangents, x right, y up) of the display point `d`.
    pub fn eye_from_display(self, d: Vec2) -> Vec2 {
        d * self.factor(d.length_squared())
    }

    /// The display radius the eye sees at radius `r_eye`: the polynomial's inverse, by bisection
    /// in f64 (it increases monotonically for non-negative coefficients).
    pub fn display_radius(self, r_eye: f64) -> f64 {
        let (k1, k2) = (self.k1 as f64, self.k2 as f64);
        let eye = |r: f64| r * (1.0 + r * r * (k1 + k2 * r * r));
        let (mut lo, mut hi) = (0.0, r_eye.max(0.0));
        for _ in 0..100 {
            let mid = 0.5 * (lo + hi);
            if eye(mid) < r_eye {
                lo = mid;
            } else {
                hi = mid;
            }
        }
        0.5 * (lo + hi)
    }

    /// The display's field: along each axis, the display tangent at which the eye sees `fov`'s
    /// edge, so the display's edges show exactly the rendered field and its corners, magnified
    /// further, reach past it (they stay black, as on a headset).
    pub fn display_fov(self, fov: FovTangents) -> FovTangents {
        let d = |t: f32| self.display_radius(t as f64) as f32;
        FovTangents {
            left: d(fov.left),
            right: d(fov.right),
            up: d(fov.up),
            down: d(fov.down),
        }
    }

    /// Whether the coefficients describe a lens the output stage can invert (finite, not
    /// negative: a monotonic polynomial).
    pub fn is_valid(self) -> bool {
        [self.k1, self.k2]
            .iter()
            .all(|k| k.is_finite() && *k >= 0.0)
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn display_fov_maps_back_onto_the_rendered_field() {
        let lens = RadialDistortion { k1: 0.34, k2: 0.55 };
        let fov = FovTangents {
            left: 1.28,
            right: 1.0,
            up: 1.11,
            down: 1.19,
        };
        let d = lens.display_fov(fov);
        for (display, eye) in d.as_array().into_iter().zip(fov.as_array()) {
            assert!(display < eye, "a pincushion lens magnifies");
            let seen = lens.eye_from_display(Vec2::new(display, 0.0)).x;
            assert!((seen - eye).abs() < 1e-5, "{seen} vs {eye}");
        }
        let none = RadialDistortion::NONE.display_fov(fov).as_array();
        assert!(none
            .iter()
            .zip(fov.as_array())
            .all(|(a, b)| (a - b).abs() < 1e-6));
    }

    /// Newton's method on the polynomial in f32 from display radius `start`, as the
    /// accumulating output stage runs it (`accumulate.glsl`'s `distorted`).
    fn newton(lens: RadialDistortion, target: f32, start: f32, steps: usize) -> f32 {
        let (k1, k2) = (lens.k1, lens.k2);
        let mut r = start;
        for _ in 0..steps {
            let r2 = r * r;
            let f = r * (1.0 + r2 * (k1 + k2 * r2)) - target;
            let slope = 1.0 + r2 * (3.0 * k1 + 5.0 * k2 * r2);
            r -= f / slope;
        }
        r
    }

    /// The worst miss, in panel pixels, over `hmd`'s rendered field, of Newton's method finding
    /// the display radius at which the frame before showed each pixel's direction, the head
    /// having turned `deg_per_frame` about either axis since; `start` picks where it begins from
    /// this pixel's display point and the direction's radius.
    fn worst_miss_px(
        hmd: &crate::view::HmdProfile,
        deg_per_frame: f32,
        steps: usize,
        start: impl Fn(Vec2, f32) -> f32,
    ) -> f64 {
        let lens = hmd.distortion;
        let fov = hmd.left_fov;
        let display = lens.display_fov(fov);
        let px_per_tangent = hmd.panel_per_eye.0 as f64 / (display.left + display.right) as f64;
        let a = deg_per_frame.to_radians();
        let turns = [
            glam::Quat::from_rotation_y(a),
            glam::Quat::from_rotation_y(-a),
            glam::Quat::from_rotation_x(a),
            glam::Quat::from_rotation_x(-a),
        ];
        let n = 48;
        let mut worst: f64 = 0.0;
        for i in 0..=n {
            for j in 0..=n {
                let (u, v) = (i as f32 / n as f32, j as f32 / n as f32);
                let here = Vec2::new(
                    -display.left + u * (display.left + display.right),
                    -display.down + v * (display.down + display.up),
                );
                let t = lens.eye_from_display(here);
                if t.x < -fov.left || t.x > fov.right || t.y < -fov.down || t.y > fov.up {
                    continue; // black on the display: nothing is accumulated there
                }
                for turn in turns {
                    let seen = turn * t.extend(-1.0);
                    if seen.z >= 0.0 {
                        continue;
                    }
                    let target = (seen.truncate() / -seen.z).length();
                    let found = newton(lens, target, start(here, target), steps) as f64;
                    let miss = (found - lens.display_radius(target as f64)).abs();
                    worst = worst.max(miss * px_per_tangent);
                }
            }
        }
        worst
    }

    /// Where the frame before's display showed a point, as the accumulating output stage finds
    /// it: Newton's method from the display radius of the pixel being drawn, whose own direction
    /// lies a frame's head motion away. The scheme in f32 (the shader itself is run by the e2e
    /// test `a_turning_history_is_found_through_the_lens`) against the f64 bisection, over every
    /// headset's rendered field, the head turning 300°/s at its refresh rate: two steps land
    /// within a tenth of a panel pixel (at most 0.06, the Varjo XR-4's), and with the head still
    /// within a thousandth. Negative control: started from the direction's own radius, as it was
    /// before, four steps miss by more than a pixel with the head still at some headset's field
    /// corners (21.6 px at the Varjo XR-4's, 0.8 at the Quest Pro's): a still head's history
    /// drifted there every frame. Mutation run: one step instead of two misses by 1.15 px
    /// (the Index's), and fails.
    #[test]
    fn two_newton_steps_from_the_pixel_find_the_frame_before() {
        let mut cold_worst: f64 = 0.0;
        for hmd in crate::view::HMD_PROFILES {
            let per_frame = 300.0 / hmd.refresh_hz;
            let warm = worst_miss_px(hmd, per_frame, 2, |here, _| here.length());
            assert!(warm < 0.1, "{}: {warm} px", hmd.name);
            let still = worst_miss_px(hmd, 0.0, 2, |here, _| here.length());
            assert!(still < 0.001, "{} still: {still} px", hmd.name);
            let cold = worst_miss_px(hmd, 0.0, 4, |_, target| target);
            cold_worst = cold_worst.max(cold);
        }
        assert!(
            cold_worst > 1.0,
            "negative control: from the direction's radius the worst miss is {cold_worst} px"
        );
    }

    #[test]
    fn negative_or_nan_coefficients_are_invalid() {
        assert!(RadialDistortion { k1: 0.34, k2: 0.55 }.is_valid());
        assert!(!RadialDistortion { k1: -0.1, k2: 0.0 }.is_valid());
        assert!(!RadialDistortion {
            k1: f32::NAN,
            k2: 0.0
        }
        .is_valid());
    }
}
