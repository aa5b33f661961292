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
