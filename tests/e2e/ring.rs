//! The parafoveal ring (`FoveationConfig::ring_ratio`): a third level between the fovea and the
//! periphery, rendered in the fovea's pass and composed between them.

use foveate::foveation::{fovea_centre_px, fovea_views, ring_views, FoveationConfig};
use foveate::plan::{OutputStage, RenderConfig, Resolution};
use foveate::render::StereoImage;
use foveate::scene::atrium_scene;
use foveate::view::Eye;
use foveate_tests::{gpu, render_at};
use glam::Vec2;

const SCREEN: u32 = 192;

fn single_frame(ring: Option<f32>) -> RenderConfig {
    RenderConfig {
        resolution: Some(Resolution::square(SCREEN)),
        output: OutputStage::Undistorted,
        foveation: Some(FoveationConfig {
            periphery_density: Some(0.25),
            ring_ratio: ring,
            ..FoveationConfig::single_frame()
        }),
        ..RenderConfig::default()
    }
}

/// Pixels where two frames differ, and all pixels, in three zones of each eye: inside the
/// fovea's band (fovea only), between it and the ring's outer edge, beyond that edge.
fn differing_by_zone(
    a: &StereoImage,
    b: &StereoImage,
    centres: [[Vec2; 2]; 2],
    radii: (f32, f32),
) -> [(usize, usize); 3] {
    let mut zones = [(0, 0); 3];
    for eye in Eye::BOTH {
        let [fovea, ring] = centres[eye.index()];
        let (a, b) = (a.eye(eye), b.eye(eye));
        for y in 0..a.height {
            for x in 0..a.width {
                let p = Vec2::new(x as f32 + 0.5, y as f32 + 0.5);
                let zone = if p.distance(fovea) < radii.0 - 1.0 {
                    0
                } else if p.distance(ring) <= radii.1 + 1.5 {
                    1
                } else {
                    2
                };
                zones[zone].1 += 1;
                zones[zone].0 += (a.pixel(x, y) != b.pixel(x, y)) as usize;
            }
        }
    }
    zones
}

/// On the lit atrium with the periphery at a quarter of the screen's density and a ring 0.7
/// of the field wide (at half the density), gaze off to the side: the ring changes most pixels
/// between the fovea's band and its own outer edge, and not one inside the fovea's band or
/// beyond the ring. Mutations: the output's `RING` constant ignored (nothing changes), the
/// ring's weight 1 everywhere (pixels beyond it change), the fovea composed under the ring
/// (the fovea changes), or the ring views given the fovea's window (between, they agree with
/// the fovea and the periphery nearly everywhere), fail it.
#[test]
fn the_ring_shows_between_the_fovea_and_its_edge_only() {
    let gpu = gpu();
    let scene = atrium_scene();
    let gaze = Vec2::new(0.3, -0.2);
    let two = render_at(&gpu, &scene, &single_frame(None), gaze);
    let three = render_at(&gpu, &scene, &single_frame(Some(0.7)), gaze);

    let plan = foveate::plan(&scene, &single_frame(Some(0.7)), gpu.caps()).unwrap();
    let g = plan.foveation.unwrap();
    let ring = g.ring.expect("a ring");
    let screen = (SCREEN, SCREEN);
    let fovea = fovea_views(&plan.eyes, g.ratio, [gaze; 2], screen);
    let rings = ring_views(&plan.eyes, ring.ratio, &fovea, screen);
    let centres = Eye::BOTH.map(|e| {
        let fov = plan.eyes.fov(e);
        let i = e.index();
        [
            fovea_centre_px(fov, fovea[i], screen),
            fovea_centre_px(fov, rings[i], screen),
        ]
    });
    let radii = (
        g.fovea_screen_px / 2.0 - g.blend_band_px,
        ring.screen_px / 2.0,
    );
    let [inside, between, beyond] = differing_by_zone(&two, &three, centres, radii);
    assert!(
        inside.1 > 0 && inside.0 == 0,
        "inside the fovea: {inside:?}"
    );
    assert!(beyond.1 > 0 && beyond.0 == 0, "beyond the ring: {beyond:?}");
    assert!(
        between.0 * 2 > between.1,
        "between: only {} of {} pixels changed",
        between.0,
        between.1
    );
}
