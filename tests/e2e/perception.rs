//! What a viewer sees over time and in the periphery, on real frames: flicker (the temporal
//! measure) and periphery sharpening in the output pass.

use foveate::foveation::FoveationConfig;
use foveate::metrics::temporal::Flicker;
use foveate::metrics::{EyePixels, Region};
use foveate::plan::{RenderConfig, Resolution, StereoMode};
use foveate::scene::{default_scene, walking_pose};
use foveate_tests::{gpu, render_motion};
use glam::{Mat4, Vec2};

fn foveated(res: u32, sharpen: f32) -> RenderConfig {
    RenderConfig {
        stereo: StereoMode::Multiview,
        msaa: 1,
        resolution: Some(Resolution::square(res)),
        foveation: Some(FoveationConfig {
            ratio: 0.5,
            blend_band_px: 4.0,
            periphery_sharpen: sharpen,
            ..FoveationConfig::single_frame()
        }),
        ..RenderConfig::default()
    }
}

/// The flicker of a foveated output against a stereo reference is 0 when neither the gaze nor
/// the head moves; the same frames with the gaze moving (negative control) or the head walking
/// flicker.
#[test]
fn flicker_is_zero_when_nothing_moves() {
    let gpu = gpu();
    let scene = default_scene();
    let config = foveated(64, 0.0);
    let plan = foveate::plan(&scene, &config, gpu.caps()).unwrap();
    let reference = foveate::plan(
        &scene,
        &RenderConfig {
            foveation: None,
            ..config.clone()
        },
        gpu.caps(),
    )
    .unwrap();
    let flicker = |motion: &[(Mat4, Vec2)]| {
        let (r, t) = (
            render_motion(&gpu, &scene, &reference, motion, |_| true),
            render_motion(&gpu, &scene, &plan, motion, |_| true),
        );
        let mut f = Flicker::default();
        for (i, &(_, gaze)) in motion.iter().enumerate() {
            let pixels = EyePixels::both(&plan, gaze, plan.foveation.as_ref());
            f.push(r[i].eyes(), t[i].eyes(), &pixels).unwrap();
        }
        f.summary().all.unwrap()
    };
    let head = scene.head;
    let still = flicker(&[(head, Vec2::new(0.2, 0.1)); 3]);
    assert_eq!((still.mean, still.p99), (0.0, 0.0), "{still:?}");
    let gaze = [(0.2, 0.1), (-0.4, 0.3), (0.5, -0.5)].map(|(x, y)| (head, Vec2::new(x, y)));
    let moving = flicker(&gaze);
    assert!(moving.mean > 1e-4, "a moving gaze flickers: {moving:?}");
    let walk = [0.0, 0.05, 0.1].map(|t| (walking_pose(head, t), Vec2::ZERO));
    let walking = flicker(&walk);
    assert!(walking.mean > 0.0, "{walking:?}");
}

/// Sharpening the periphery changes periphery pixels and leaves the fovea (band excluded)
/// alone. Mutations: sharpening ignored (no periphery change) or applied to the fovea too.
#[test]
fn sharpening_touches_the_periphery_only() {
    let gpu = gpu();
    let scene = default_scene();
    let render = |sharpen| {
        let plan = foveate::plan(&scene, &foveated(96, sharpen), gpu.caps()).unwrap();
        let image =
            render_motion(&gpu, &scene, &plan, &[(scene.head, Vec2::ZERO)], |_| true).remove(0);
        (plan, image)
    };
    let (plan, plain) = render(0.0);
    let (_, sharp) = render(1.0);
    let pixels = EyePixels::both(&plan, Vec2::ZERO, plan.foveation.as_ref());
    let mut changed = [0usize; 3];
    for (eye, p) in pixels.iter().enumerate() {
        for y in 0..p.height {
            for x in 0..p.width {
                let Some(d) = p.at(x, y) else { continue };
                if plain.eyes()[eye].pixel(x, y) != sharp.eyes()[eye].pixel(x, y) {
                    changed[Region::ALL.iter().position(|&r| r == d.region).unwrap()] += 1;
                }
            }
        }
    }
    assert_eq!(changed[0], 0, "fovea pixels changed: {changed:?}");
    assert!(changed[2] > 100, "periphery pixels changed: {changed:?}");
}
