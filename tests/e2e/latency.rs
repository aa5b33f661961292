//! The eye tracker's latency on real frames: the fovea arrives exactly `latency` after a step in
//! gaze, latency 0 is today's frame bit for bit, and a late fovea is judged at the true gaze.

use foveate::foveation::{
    DelayedGaze, FoveationConfig, GazeLatency, GazeSample, GazeSpace, Prediction,
};
use foveate::metrics::perceptual::{perceptual_error, Maps};
use foveate::metrics::Acuity;
use foveate::metrics::EyePixels;
use foveate::plan::{RenderConfig, Resolution, StereoMode};
use foveate::render::StereoImage;
use foveate::scene::default_scene;
use foveate::view::Eye;
use foveate_tests::{gpu, render_motion};
use glam::Vec2;

const HZ: f64 = 90.0;
const RES: u32 = 128;

/// Both eyes' pixels.
fn pixels(image: &StereoImage) -> [&[u8]; 2] {
    image.eyes().map(|e| e.data.as_slice())
}

fn foveated() -> RenderConfig {
    RenderConfig {
        stereo: StereoMode::Multiview,
        msaa: 1,
        resolution: Some(Resolution::square(RES)),
        foveation: Some(FoveationConfig {
            ratio: 0.5,
            blend_band_px: 4.0,
            ..FoveationConfig::single_frame()
        }),
        ..RenderConfig::default()
    }
}

/// A gaze step at frame 3, seen through `frames_late` display frames of latency: the gaze each
/// frame's fovea is placed at.
fn shown(space: GazeSpace, from: Vec2, to: Vec2, frames_late: u32) -> Vec<Vec2> {
    let latency = GazeLatency::new(frames_late as f64 * 1000.0 / HZ, Prediction::None).unwrap();
    let mut delayed = DelayedGaze::new(latency, space);
    // The tracker has been reporting `from` for a while before the first frame.
    (-8..9)
        .map(|i| {
            let t = i as f64 / HZ;
            let g = if i < 3 { from } else { to };
            delayed.push(GazeSample {
                t,
                left: g,
                right: g,
                valid: true,
            });
            delayed.gaze_at(t)
        })
        .skip(8)
        .collect()
}

/// Rendered frame by frame at 90 Hz, the fovea of a step in gaze arrives exactly 2 frames late
/// with 22.2 ms of latency and on the step's own frame with none: each frame is bit for bit the
/// frame rendered at the old or the new gaze. Mutation: a latency one frame short or long, or
/// any smoothing of the gaze, fails it.
#[test]
fn the_fovea_arrives_exactly_latency_late() {
    let gpu = gpu();
    let scene = default_scene();
    let plan = foveate::plan(&scene, &foveated(), gpu.caps()).unwrap();
    let space = GazeSpace {
        fov: plan.eyes.fov(Eye::Left),
    };
    let (from, to) = (Vec2::new(-0.4, 0.0), Vec2::new(0.4, 0.1));
    let still = |g: Vec2| render_motion(&gpu, &scene, &plan, &[(scene.head, g)], |_| true);
    let (old, new) = (still(from).remove(0), still(to).remove(0));
    assert!(pixels(&old) != pixels(&new), "the step moves the fovea");
    for (frames_late, arrives) in [(0, 3), (2, 5)] {
        let gazes = shown(space, from, to, frames_late);
        let motion: Vec<_> = gazes.iter().map(|&g| (scene.head, g)).collect();
        let frames = render_motion(&gpu, &scene, &plan, &motion, |_| true);
        for (i, frame) in frames.iter().enumerate() {
            let expected = if i < arrives { &old } else { &new };
            assert!(
                pixels(frame) == pixels(expected),
                "latency {frames_late} frames: frame {i} is not the frame at the gaze it should show"
            );
        }
    }
}

/// A fovea left behind by latency is judged where the eye really looks: its eccentricity-aware
/// FLIP at the true gaze is worse than the frame's with the fovea on time, and its pixel map
/// takes eccentricities from the true gaze and regions from the fovea's. Mutation:
/// eccentricities taken from the fovea's gaze fails it.
#[test]
fn a_late_fovea_is_judged_at_the_true_gaze() {
    let gpu = gpu();
    let scene = default_scene();
    let plan = foveate::plan(&scene, &foveated(), gpu.caps()).unwrap();
    let reference_config = RenderConfig {
        msaa: 4,
        foveation: None,
        ..foveated()
    };
    let reference_plan = foveate::plan(&scene, &reference_config, gpu.caps()).unwrap();
    let (truth, late) = (Vec2::new(0.45, 0.0), Vec2::new(-0.45, 0.0));
    let reference = render_motion(
        &gpu,
        &scene,
        &reference_plan,
        &[(scene.head, truth)],
        |_| true,
    );
    let motion = [(scene.head, truth), (scene.head, late)];
    let frames = render_motion(&gpu, &scene, &plan, &motion, |_| true);
    let flip = std::cell::RefCell::new(foveate::judge::GpuFlip::new(&gpu));
    let judge = |image: usize, fovea: Vec2| {
        let pixels = Eye::BOTH
            .map(|e| EyePixels::seen(&reference_plan, e, truth, fovea, plan.foveation.as_ref()));
        let e = perceptual_error(
            reference[0].eyes(),
            frames[image].eyes(),
            &pixels,
            Acuity::default(),
            &mut *flip.borrow_mut(),
            Maps::Drop,
        )
        .unwrap();
        e.eccentric.unwrap().mean
    };
    let on_time = judge(0, truth);
    let behind = judge(1, late);
    assert!(
        behind > on_time * 1.05,
        "late {behind} vs on time {on_time}"
    );
    // The map of a late frame: eccentricities from the true gaze, regions from the fovea's.
    let f = plan.foveation.as_ref();
    let at_truth = EyePixels::new(&reference_plan, Eye::Left, truth, f);
    let at_late = EyePixels::new(&reference_plan, Eye::Left, late, f);
    let late_map = EyePixels::seen(&reference_plan, Eye::Left, truth, late, f);
    let pixels = late_map
        .pixels
        .iter()
        .zip(&at_truth.pixels)
        .zip(&at_late.pixels);
    for ((p, t), l) in pixels {
        assert_eq!(p.map(|p| p.eccentricity_deg), t.map(|t| t.eccentricity_deg));
        assert_eq!(p.map(|p| p.region), l.map(|l| l.region));
    }
    let same =
        Eye::BOTH.map(|e| EyePixels::new(&reference_plan, e, truth, plan.foveation.as_ref()));
    let seen = Eye::BOTH
        .map(|e| EyePixels::seen(&reference_plan, e, truth, truth, plan.foveation.as_ref()));
    assert_eq!(same, seen, "no latency: the map as before");
}
