//! The four views of a foveated frame and their stencil mask shapes, from the eyes, the gaze and
//! the resolved geometry. Views 0, 1: periphery left, right; views 2, 3: fovea left, right.

use glam::{Vec2, Vec4};

use super::{fovea_tangents, FoveationGeometry};
use crate::view::{Eye, EyeParams, FovTangents};

/// A gaze in normalised image coordinates (−1…1, x right, y up) as a tangent-space point.
pub fn gaze_tangent(fov: FovTangents, gaze: Vec2) -> Vec2 {
    let centre = Vec2::new((fov.right - fov.left) / 2.0, (fov.up - fov.down) / 2.0);
    let half = Vec2::new((fov.left + fov.right) / 2.0, (fov.up + fov.down) / 2.0);
    centre + gaze * half
}

/// Each eye's fovea view: the window of `ratio` around its gaze, kept inside the periphery.
pub fn fovea_views(eyes: &EyeParams, ratio: f32, gaze: [Vec2; 2]) -> [FovTangents; 2] {
    Eye::BOTH.map(|eye| {
        let fov = eyes.fov(eye);
        fovea_tangents(fov, ratio, gaze_tangent(fov, gaze[eye.index()]))
    })
}

/// Where a tangent-space point lands in a view's NDC (Vulkan: y down).
fn ndc(fov: FovTangents, t: Vec2) -> Vec2 {
    Vec2::new(
        (t.x + fov.left) / (fov.left + fov.right) * 2.0 - 1.0,
        1.0 - (t.y + fov.down) / (fov.up + fov.down) * 2.0,
    )
}

/// The stencil shapes (centre x, y, radius x, y in NDC) the mask shader draws: [0..4) what
/// each view keeps, [4..8) what it then drops. Periphery views keep everything (a radius of 2
/// covers the view) and drop the fovea's hole, centred on the fovea window; fovea views keep
/// their inset circle and drop nothing.
pub fn mask_shapes(g: &FoveationGeometry, eyes: &EyeParams, fovea: &[FovTangents; 2]) -> [Vec4; 8] {
    let (w, h) = (g.view.width as f32, g.view.height as f32);
    let mut shapes = [Vec4::ZERO; 8];
    for eye in Eye::BOTH {
        let i = eye.index();
        let f = fovea[i];
        let window_centre = Vec2::new((f.right - f.left) / 2.0, (f.up - f.down) / 2.0);
        let hole = ndc(eyes.fov(eye), window_centre);
        shapes[i] = Vec4::new(0.0, 0.0, 2.0, 2.0);
        shapes[2 + i] = Vec4::new(0.0, 0.0, g.fovea_circle_px / w, g.fovea_circle_px / h);
        shapes[4 + i] = Vec4::new(
            hole.x,
            hole.y,
            g.periphery_hole_px / w,
            g.periphery_hole_px / h,
        );
    }
    shapes
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::foveation::FoveationConfig;
    use crate::plan::Resolution;

    #[test]
    fn centred_gaze_puts_the_hole_in_the_middle_of_a_symmetric_eye() {
        let fov = FovTangents::symmetric_deg(90.0, 90.0);
        let eyes = EyeParams {
            left_fov: fov,
            right_fov: fov,
            ipd_m: 0.064,
            cant_rad: 0.0,
        };
        let g = FoveationConfig {
            ratio: 0.5,
            ..Default::default()
        }
        .geometry(Resolution::square(256))
        .unwrap();
        let fovea = fovea_views(&eyes, 0.5, [Vec2::ZERO; 2]);
        let s = mask_shapes(&g, &eyes, &fovea);
        assert!(
            s[4].truncate().truncate().length() < 1e-6,
            "hole at the centre: {:?}",
            s[4]
        );
        // The inset circle fills the fovea view; the hole is the fovea's size in periphery pixels.
        assert!(
            (s[2].z - 1.0).abs() < 1e-6 && (s[4].z - 0.5).abs() < 1e-6,
            "{s:?}"
        );
        assert_eq!(s[6], Vec4::ZERO, "fovea views drop nothing");
    }

    #[test]
    fn the_hole_follows_the_gaze_until_the_window_reaches_the_edge() {
        let fov = FovTangents::from_angles_deg(52.0, 45.0, 48.0, 50.0);
        let eyes = EyeParams {
            left_fov: fov,
            right_fov: fov.mirrored(),
            ipd_m: 0.064,
            cant_rad: 0.0,
        };
        let g = FoveationConfig {
            ratio: 0.35,
            ..Default::default()
        }
        .geometry(Resolution::square(512))
        .unwrap();
        let up_right = mask_shapes(
            &g,
            &eyes,
            &fovea_views(&eyes, 0.35, [Vec2::new(0.3, 0.3); 2]),
        );
        assert!(
            up_right[4].x > 0.29 && up_right[4].y < -0.29,
            "NDC y points down: {:?}",
            up_right[4]
        );
        let edge = mask_shapes(
            &g,
            &eyes,
            &fovea_views(&eyes, 0.35, [Vec2::new(1.0, -1.0); 2]),
        );
        // Clamped: the hole's centre stays a fovea-half inside the view.
        assert!(
            (edge[4].x - (1.0 - 0.35)).abs() < 1e-4 && (edge[4].y - (1.0 - 0.35)).abs() < 1e-4,
            "{:?}",
            edge[4]
        );
    }
}
