//! The periphery's specular prefilter (`FoveationConfig::periphery_prefilter`): a periphery
//! rendered coarser than the screen widens its highlights by the spread of the normals its
//! pixels average beyond the screen's; at the screen's density it changes nothing.

use foveate::foveation::FoveationConfig;
use foveate::metrics::{EyePixels, Region};
use foveate::plan::{OutputStage, RenderConfig, Resolution};
use foveate::render::StereoImage;
use foveate::scene::atrium_scene;
use foveate::view::Eye;
use foveate_tests::{gpu, render_at};
use glam::Vec2;

const SCREEN: u32 = 192;

fn single_frame(density: f32, prefilter: bool) -> RenderConfig {
    RenderConfig {
        resolution: Some(Resolution::square(SCREEN)),
        output: OutputStage::Undistorted,
        foveation: Some(FoveationConfig {
            periphery_density: Some(density),
            periphery_prefilter: prefilter,
            ..FoveationConfig::single_frame()
        }),
        ..RenderConfig::default()
    }
}

/// Pixels of each region (fovea, band, periphery: `Region::ALL`'s order) where two frames
/// differ in any channel, and the region's pixels.
fn differing(a: &StereoImage, b: &StereoImage, eyes: &[EyePixels; 2]) -> [(usize, usize); 3] {
    let mut counts = [(0, 0); 3];
    for eye in Eye::BOTH {
        let (a, b) = (a.eye(eye), b.eye(eye));
        for y in 0..a.height {
            for x in 0..a.width {
                let Some(p) = eyes[eye.index()].at(x, y) else {
                    continue;
                };
                let i = Region::ALL.iter().position(|&r| r == p.region).unwrap();
                counts[i].1 += 1;
                counts[i].0 += (a.pixel(x, y) != b.pixel(x, y)) as usize;
            }
        }
    }
    counts
}

/// On the lit atrium with the periphery at half the screen's density, the prefilter changes
/// the periphery (over 1 % of its pixels) and leaves every fovea pixel as it was, to the bit.
/// With the periphery at the screen's density it changes no pixel at all: the widening is the
/// spread beyond the screen's footprint, not the screen's own. Mutations: the constant ignored
/// (nothing changes), the highlights widened by the whole footprint's spread rather than the
/// part beyond the screen's (the dense frame changes), or the fovea views given the periphery's
/// footprint (the fovea changes), fail it.
#[test]
fn the_prefilter_changes_only_a_periphery_coarser_than_the_screen() {
    let gpu = gpu();
    let scene = atrium_scene();
    let gaze = Vec2::new(0.3, -0.2);
    let frame =
        |density, prefilter| render_at(&gpu, &scene, &single_frame(density, prefilter), gaze);
    let plan = foveate::plan(&scene, &single_frame(0.5, false), gpu.caps()).unwrap();
    let eyes = EyePixels::both(&plan, gaze, plan.foveation.as_ref());

    let [fovea, _, periphery] = differing(&frame(0.5, false), &frame(0.5, true), &eyes);
    assert!(fovea.1 > 0 && fovea.0 == 0, "fovea: {fovea:?}");
    assert!(
        periphery.0 * 100 > periphery.1,
        "periphery: only {} of {} pixels changed",
        periphery.0,
        periphery.1
    );

    let dense = differing(&frame(1.0, false), &frame(1.0, true), &eyes);
    assert!(
        dense.iter().all(|&(changed, _)| changed == 0),
        "at the screen's density: {dense:?}"
    );
}
