//! What a viewer sees over time and in the periphery, on real frames: flicker (the temporal
//! measure) and periphery sharpening in the output pass.

use foveate::foveation::FoveationConfig;
use foveate::metrics::temporal::Flicker;
use foveate::metrics::{EyePixels, Region};
use foveate::plan::{FramePlan, RenderConfig, Resolution, StereoMode};
use foveate::render::{Renderer, StereoImage};
use foveate::scene::{default_scene, walking_pose, Scene};
use foveate_tests::{assert_validation_clean, gpu};
use glam::{Mat4, Vec2};

fn foveated(res: u32, sharpen: f32) -> RenderConfig {
    RenderConfig {
        stereo: StereoMode::Multiview,
        views: 4,
        msaa: 1,
        resolution: Some(Resolution::square(res)),
        foveation: Some(FoveationConfig {
            ratio: 0.5,
            blend_band_px: 4.0,
            periphery_sharpen: sharpen,
            ..Default::default()
        }),
        ..RenderConfig::default()
    }
}

/// Renders `frames` (head pose, gaze) with one renderer, reading each frame back.
fn frames(
    gpu: &foveate::gpu::Gpu,
    scene: &Scene,
    plan: &FramePlan,
    motion: &[(Mat4, Vec2)],
) -> Vec<StereoImage> {
    let mut renderer = Renderer::new(gpu, plan, scene).unwrap();
    let images = motion
        .iter()
        .map(|&(pose, gaze)| {
            renderer.set_gaze([gaze; 2]);
            renderer.render_frame(pose).unwrap();
            renderer.readback().unwrap()
        })
        .collect();
    drop(renderer);
    assert_validation_clean(gpu);
    images
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
            views: 2,
            foveation: None,
            ..config.clone()
        },
        gpu.caps(),
    )
    .unwrap();
    let flicker = |motion: &[(Mat4, Vec2)]| {
        let (r, t) = (
            frames(&gpu, &scene, &reference, motion),
            frames(&gpu, &scene, &plan, motion),
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
        let image = frames(&gpu, &scene, &plan, &[(scene.head, Vec2::ZERO)]).remove(0);
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
