//! The views of a foveated frame and their stencil mask shapes, from the eyes, the gaze and
//! the resolved geometry. Views 0, 1: periphery left, right; views 2, 3: fovea left, right;
//! with a parafoveal ring, views 4, 5: the ring left, right.

use glam::{Vec2, Vec4};

use super::inset::clamp_inside;
use super::{fovea_tangents, FoveationGeometry};
use crate::view::{Eye, EyeParams, FovTangents};

/// A gaze in normalised image coordinates (−1…1, x right, y up) as a tangent-space point.
pub fn gaze_tangent(fov: FovTangents, gaze: Vec2) -> Vec2 {
    let centre = Vec2::new((fov.right - fov.left) / 2.0, (fov.up - fov.down) / 2.0);
    let half = Vec2::new((fov.left + fov.right) / 2.0, (fov.up + fov.down) / 2.0);
    centre + gaze * half
}

/// Each eye's fovea view: the window of `ratio` around its gaze, kept inside the periphery, with
/// its edges on whole pixels of a `screen`-sized image. With a window a whole number of pixels
/// wide, fovea texels then land exactly on screen pixels and composition copies them 1:1.
pub fn fovea_views(
    eyes: &EyeParams,
    ratio: f32,
    gaze: [Vec2; 2],
    screen: (u32, u32),
) -> [FovTangents; 2] {
    Eye::BOTH.map(|eye| {
        let fov = eyes.fov(eye);
        let window = fovea_tangents(fov, ratio, gaze_tangent(fov, gaze[eye.index()]));
        snap_to_pixels(fov, window, screen)
    })
}

/// Moves a window (by under half a pixel) so its left and top edges fall on pixel edges of the
/// periphery's `screen` image, still inside it.
fn snap_to_pixels(p: FovTangents, f: FovTangents, screen: (u32, u32)) -> FovTangents {
    let (w, h) = (screen.0 as f32, screen.1 as f32);
    let (sx, sy) = (w / (p.left + p.right), h / (p.up + p.down));
    let (width, height) = (f.left + f.right, f.up + f.down);
    let left_px = clamp_inside(((p.left - f.left) * sx).round(), 0.0, w - width * sx);
    let top_px = clamp_inside(((p.up - f.up) * sy).round(), 0.0, h - height * sy);
    let x0 = -p.left + left_px / sx;
    let top = p.up - top_px / sy;
    FovTangents {
        left: -x0,
        right: x0 + width,
        up: top,
        down: height - top,
    }
}

/// The fovea window's centre in screen pixels (x right, y down) for an eye whose periphery is
/// `periphery` and whose fovea view is `fovea`, at `screen` pixels.
pub fn fovea_centre_px(periphery: FovTangents, fovea: FovTangents, screen: (u32, u32)) -> Vec2 {
    let ndc = FovTangents::ndc(
        periphery,
        Vec2::new(
            (fovea.right - fovea.left) / 2.0,
            (fovea.up - fovea.down) / 2.0,
        ),
    );
    Vec2::new(
        (ndc.x + 1.0) * 0.5 * screen.0 as f32,
        (ndc.y + 1.0) * 0.5 * screen.1 as f32,
    )
}

/// The stencil shapes a frame's views can have: what each of its six views keeps, then drops.
pub const MASK_SHAPES: usize = 12;

/// Each eye's parafoveal ring window: `ratio` of the periphery around the fovea window's centre
/// (the gaze, unless the fovea was kept inside the field), kept inside the periphery and
/// snapped to whole pixels of a `screen`-sized image like the fovea's.
pub fn ring_views(
    eyes: &EyeParams,
    ratio: f32,
    fovea: &[FovTangents; 2],
    screen: (u32, u32),
) -> [FovTangents; 2] {
    Eye::BOTH.map(|eye| {
        let fov = eyes.fov(eye);
        let window = fovea_tangents(fov, ratio, window_centre(fovea[eye.index()]));
        snap_to_pixels(fov, window, screen)
    })
}

/// A window's centre as a tangent-space point.
fn window_centre(f: FovTangents) -> Vec2 {
    Vec2::new((f.right - f.left) / 2.0, (f.up - f.down) / 2.0)
}

/// The stencil shapes (centre x, y, radius x, y in NDC) the mask shader draws: [0..6) what
/// each view keeps, [6..12) what it then drops. Periphery views keep everything (a radius of 2
/// covers the view) and drop the hole of what covers them (the ring's with a ring, else the
/// fovea's); fovea views keep their inset circle and drop nothing; ring views (`ring`) keep
/// their circle and drop the fovea's hole.
pub fn mask_shapes(
    g: &FoveationGeometry,
    eyes: &EyeParams,
    fovea: &[FovTangents; 2],
    ring: Option<&[FovTangents; 2]>,
) -> [Vec4; MASK_SHAPES] {
    // A circle `px` pixels across around `centre` (NDC) of a view of `view`'s pixels.
    let circle = |centre: Vec2, px: f32, view: crate::vocab::Resolution| {
        Vec4::new(
            centre.x,
            centre.y,
            px / view.width as f32,
            px / view.height as f32,
        )
    };
    let (periphery, fovea_view) = (g.periphery_view, g.fovea_view);
    let mut shapes = [Vec4::ZERO; MASK_SHAPES];
    for eye in Eye::BOTH {
        let i = eye.index();
        let covering = ring.map_or(fovea[i], |r| r[i]);
        let hole = eyes.fov(eye).ndc(window_centre(covering));
        shapes[i] = Vec4::new(0.0, 0.0, 2.0, 2.0);
        shapes[2 + i] = circle(Vec2::ZERO, g.fovea_circle_px, fovea_view);
        shapes[6 + i] = circle(hole, g.periphery_hole_px, periphery);
        if let (Some(r), Some(ring)) = (g.ring, ring) {
            // The ring views have the fovea's pixels over the ring's window.
            let fovea_in_ring = ring[i].ndc(window_centre(fovea[i]));
            shapes[4 + i] = circle(Vec2::ZERO, r.circle_px, fovea_view);
            shapes[10 + i] = circle(fovea_in_ring, r.hole_px, fovea_view);
        }
    }
    shapes
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::foveation::{FoveationConfig, FOVEA_REACH_TEXELS, PERIPHERY_REACH_TEXELS};
    use crate::vocab::Resolution;

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
            blend_band_px: 0.0,
            ..FoveationConfig::single_frame()
        }
        .geometry(Resolution::square(256))
        .unwrap();
        let fovea = fovea_views(&eyes, 0.5, [Vec2::ZERO; 2], (256, 256));
        let s = mask_shapes(&g, &eyes, &fovea, None);
        assert!(
            s[6].truncate().truncate().length() < 1e-6,
            "hole at the centre: {:?}",
            s[6]
        );
        // The inset circle fills the fovea view and the hole is the fovea's size in periphery
        // pixels, each with the filters' margin.
        let circle = (128.0 + 2.0 * FOVEA_REACH_TEXELS) / 128.0;
        let hole = (64.0 - 2.0 * PERIPHERY_REACH_TEXELS) / 128.0;
        assert!(
            (s[2].z - circle).abs() < 1e-6 && (s[6].z - hole).abs() < 1e-6,
            "{s:?}"
        );
        assert_eq!(s[8], Vec4::ZERO, "fovea views drop nothing");
    }

    #[test]
    fn windows_snap_to_whole_pixels_inside_the_image() {
        let fov = FovTangents::from_angles_deg(52.0, 45.0, 48.0, 50.0);
        let eyes = EyeParams {
            left_fov: fov,
            right_fov: fov.mirrored(),
            ipd_m: 0.064,
            cant_rad: 0.0,
        };
        for gaze in [
            Vec2::ZERO,
            Vec2::new(0.37, -0.21),
            Vec2::new(1.0, 1.0),
            Vec2::new(-1.0, -1.0),
        ] {
            let f = fovea_views(&eyes, 90.0 / 256.0, [gaze; 2], (256, 256))[0];
            let left_px = (fov.left - f.left) * 256.0 / (fov.left + fov.right);
            let top_px = (fov.up - f.up) * 256.0 / (fov.up + fov.down);
            assert!(
                (left_px - left_px.round()).abs() < 1e-3 && (top_px - top_px.round()).abs() < 1e-3,
                "{gaze}: {left_px}, {top_px}"
            );
            assert!(
                left_px >= -1e-3 && left_px + 90.0 <= 256.0 + 1e-3,
                "{gaze}: inside"
            );
        }
    }

    #[test]
    fn fovea_centre_in_screen_pixels() {
        let fov = FovTangents::symmetric_deg(90.0, 90.0);
        let eyes = EyeParams {
            left_fov: fov,
            right_fov: fov,
            ipd_m: 0.0,
            cant_rad: 0.0,
        };
        let centred = fovea_views(&eyes, 0.5, [Vec2::ZERO; 2], (128, 64));
        assert_eq!(
            fovea_centre_px(fov, centred[0], (128, 64)),
            Vec2::new(64.0, 32.0)
        );
        let right_down = fovea_views(&eyes, 0.5, [Vec2::new(0.5, -0.5); 2], (128, 128));
        assert_eq!(
            fovea_centre_px(fov, right_down[0], (128, 128)),
            Vec2::new(96.0, 96.0)
        );
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
            ..FoveationConfig::single_frame()
        }
        .geometry(Resolution::square(512))
        .unwrap();
        let up_right = mask_shapes(
            &g,
            &eyes,
            &fovea_views(&eyes, 0.35, [Vec2::new(0.3, 0.3); 2], (512, 512)),
            None,
        );
        assert!(
            up_right[6].x > 0.29 && up_right[6].y < -0.29,
            "NDC y points down: {:?}",
            up_right[6]
        );
        let edge = mask_shapes(
            &g,
            &eyes,
            &fovea_views(&eyes, 0.35, [Vec2::new(1.0, -1.0); 2], (512, 512)),
            None,
        );
        // Clamped: the hole's centre stays a fovea-half inside the view.
        assert!(
            (edge[6].x - (1.0 - 0.35)).abs() < 1e-4 && (edge[6].y - (1.0 - 0.35)).abs() < 1e-4,
            "{:?}",
            edge[6]
        );
    }
}
