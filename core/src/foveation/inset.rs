use glam::Vec2;

use crate::view::FovTangents;

/// The fovea views' full field of view for a periphery of `fov_ext_deg` and a resolution
/// ratio: FOV_ins = 2·atan(tan(FOV_ext / 2) · ratio) (Di Donato 2017 §3.3).
pub fn inset_fov_deg(fov_ext_deg: f64, ratio: f64) -> f64 {
    2.0 * ((fov_ext_deg.to_radians() / 2.0).tan() * ratio)
        .atan()
        .to_degrees()
}

/// The fovea view's tangents, generalised to asymmetric eyes: a window `ratio` times the
/// periphery's tangent extent on each axis, centred on the gaze point `gaze` (tangent space,
/// x right, y up). The window is kept inside the periphery image — its centre is clamped so
/// the window's edges stay within the periphery's — so a gaze at the edge moves the fovea to the
/// edge, not beyond it, and every fovea pixel still has periphery behind it to blend with.
pub fn fovea_tangents(periphery: FovTangents, ratio: f32, gaze: Vec2) -> FovTangents {
    let p = periphery;
    let half = Vec2::new(p.left + p.right, p.up + p.down) * (ratio * 0.5);
    let lo = Vec2::new(-p.left, -p.down) + half;
    let hi = Vec2::new(p.right, p.up) - half;
    let c = Vec2::new(
        clamp_inside(gaze.x, lo.x, hi.x),
        clamp_inside(gaze.y, lo.y, hi.y),
    );
    FovTangents {
        left: half.x - c.x,
        right: half.x + c.x,
        up: half.y + c.y,
        down: half.y - c.y,
    }
}

/// `v` clamped to `lo..=hi`; when rounding has put `lo` past `hi` (a window as wide as what
/// holds it: ratio 1, or a fovea view that rounds to the periphery's size), the one place left,
/// their midpoint (`f32::clamp` panics there, and on a NaN bound, which passes through here).
pub(crate) fn clamp_inside(v: f32, lo: f32, hi: f32) -> f32 {
    if lo > hi || lo.is_nan() || hi.is_nan() {
        (lo + hi) * 0.5
    } else {
        v.clamp(lo, hi)
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn arms_example_90_degrees_at_0_35_is_38_58() {
        assert!(
            (inset_fov_deg(90.0, 0.35) - 38.58).abs() < 0.005,
            "{}",
            inset_fov_deg(90.0, 0.35)
        );
        assert_eq!(inset_fov_deg(90.0, 1.0), 90.0);
    }

    #[test]
    fn centred_symmetric_fovea_matches_the_formula() {
        let p = FovTangents::symmetric_deg(90.0, 90.0);
        let f = fovea_tangents(p, 0.35, Vec2::ZERO);
        let fov = 2.0 * f.left.atan().to_degrees();
        assert!(
            (fov as f64 - inset_fov_deg(90.0, 0.35)).abs() < 1e-3,
            "{fov}"
        );
        assert_eq!(f.left, f.right);
    }

    #[test]
    fn gaze_moves_the_window_and_edges_clamp_it_inside() {
        let p = FovTangents::from_angles_deg(52.0, 45.0, 48.0, 50.0);
        let ratio = 0.35;
        let f = fovea_tangents(p, ratio, Vec2::new(0.3, -0.2));
        // Window centre at the gaze: (right − left)/2 = gaze.x, (up − down)/2 = gaze.y.
        assert!(
            ((f.right - f.left) / 2.0 - 0.3).abs() < 1e-6
                && ((f.up - f.down) / 2.0 + 0.2).abs() < 1e-6
        );
        for gaze in [
            Vec2::new(10.0, 10.0),
            Vec2::new(-10.0, -10.0),
            Vec2::new(p.right, 0.0),
            Vec2::new(0.0, -p.down),
        ] {
            let f = fovea_tangents(p, ratio, gaze);
            assert!(
                f.left <= p.left + 1e-6 && f.right <= p.right + 1e-6,
                "{gaze}: {f:?}"
            );
            assert!(
                f.up <= p.up + 1e-6 && f.down <= p.down + 1e-6,
                "{gaze}: {f:?}"
            );
            // Same size wherever it goes.
            assert!(((f.left + f.right) - ratio * (p.left + p.right)).abs() < 1e-5);
        }
    }
}
