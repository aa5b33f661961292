//! No panic reachable from a library caller's input, on the GPU: any configuration the planner
//! accepts renders frames for any gaze and head it is handed, and bad per-frame input (a NaN gaze,
//! a gaze past the view's edge, a non-finite head, eyes outside the plan) is an error that leaves
//! the renderer working. The pure half of the fuzzing (thousands of hostile configurations
//! through the planner) is `plan::robustness_tests` in the library.

use std::sync::OnceLock;

use foveate::foveation::{FoveationConfig, TemporalConfig};
use foveate::gpu::Gpu;
use foveate::mffr::MffrConfig;
use foveate::plan::{OutputStage, RadialDensity, RenderConfig, Resolution, StereoMode};
use foveate::render::Renderer;
use foveate::scene::{default_scene, Scene};
use foveate::view::HMD_PROFILES;
use foveate_tests::{assert_validation_clean, gpu};
use glam::{Mat4, Vec2, Vec3};
use proptest::prelude::*;

/// The fuzz cases' device and scene, made once (this test's alone: `Gpu` queues are not shared
/// between threads, and tests run on several).
fn fuzz_gpu() -> &'static (Gpu, Scene) {
    static SHARED: OnceLock<(Gpu, Scene)> = OnceLock::new();
    SHARED.get_or_init(|| (gpu(), default_scene()))
}

fn foveated(hmd: &str, res: Resolution, ratio: f32) -> RenderConfig {
    RenderConfig {
        hmd: hmd.into(),
        resolution: Some(res),
        msaa: 1,
        foveation: Some(FoveationConfig {
            ratio,
            ..FoveationConfig::single_frame()
        }),
        ..RenderConfig::default()
    }
}

proptest! {
    // Each case compiles and renders on lavapipe: a bounded budget, not a soak.
    #![proptest_config(ProptestConfig { cases: 64, failure_persistence: None, ..ProptestConfig::default() })]

    /// The fuzz harness on the GPU: headset × stereo mode × tiny and odd resolutions ×
    /// foveation (ratio up to 1, periphery density and samples) × MSAA × the effects × gaze and
    /// head; a plan error is fine, a planned frame must render (two frames: the second reuses a
    /// history) validation-clean.
    #[test]
    fn every_planned_configuration_renders_any_gaze_and_head(
        (profile, stereo) in (0..HMD_PROFILES.len(), prop_oneof![4 => Just(0usize), 1 => 1..StereoMode::ALL.len()]),
        (width, height) in (1u32..80, 1u32..80),
        foveation in prop::option::weighted(0.8, (prop_oneof![0.05f32..=1.0, Just(1.0)], prop::option::of(0.25f32..=1.0), prop::option::of(prop_oneof![Just(1u32), Just(4)]))),
        (msaa, hmd_mask, lens, temporal, mffr, radial) in (prop_oneof![Just(1u32), Just(4)], any::<bool>(), any::<bool>(), any::<bool>(), any::<bool>(), prop::bool::weighted(0.2)),
        gaze in (-1.0f32..=1.0, -1.0f32..=1.0),
        (yaw, step) in (-3.2f32..3.2, -100.0f32..100.0),
    ) {
        let (gpu, scene) = fuzz_gpu();
        let (ratio, density, periphery_msaa) = foveation.unwrap_or((0.5, None, None));
        let mut config = foveated(HMD_PROFILES[profile].name, Resolution { width, height }, ratio);
        config.stereo = StereoMode::ALL[stereo];
        config.msaa = msaa;
        config.hmd_mask = hmd_mask;
        config.output = if lens { OutputStage::Lens } else { OutputStage::Undistorted };
        if let Some(f) = &mut config.foveation {
            f.periphery_density = density;
            f.periphery_msaa = periphery_msaa;
            f.periphery_temporal = temporal.then(TemporalConfig::default);
        }
        if foveation.is_none() {
            config.foveation = None;
        }
        config.mffr = mffr.then(MffrConfig::default);
        config.radial_density = radial.then(RadialDensity::default);
        let Ok(plan) = foveate::plan(scene, &config, gpu.caps()) else {
            return Ok(());
        };
        let mut renderer = Renderer::new(gpu, &plan, scene).expect("a planned frame's renderer");
        renderer.set_gaze([Vec2::from(gaze); 2]).expect("a gaze in -1..1");
        let head = scene.head * Mat4::from_rotation_y(yaw) * Mat4::from_translation(Vec3::X * step);
        for _ in 0..2 {
            renderer.render_frame(head).expect("a planned frame renders");
        }
        drop(renderer);
        assert_validation_clean(gpu);
    }
}

/// Bad per-frame input from a library caller is an error naming the field and the limit, the
/// renderer keeps its last good state and renders on. Negative control: `set_gaze` without its
/// check accepts the NaN gaze, and the next frame panics in the fovea window's snapping.
#[test]
fn bad_per_frame_input_is_an_error_and_the_renderer_renders_on() {
    let (gpu, scene) = (&gpu(), &default_scene());
    let plan = foveate::plan(
        scene,
        &foveated("quest-pro", Resolution::square(64), 0.5),
        gpu.caps(),
    )
    .unwrap();
    let mut renderer = Renderer::new(gpu, &plan, scene).unwrap();
    let good = [Vec2::new(0.3, -0.2); 2];
    renderer.set_gaze(good).unwrap();
    for (gaze, expected) in [
        (
            [Vec2::new(f32::NAN, 0.0); 2],
            "invalid left gaze = NaN,0: finite numbers in -1..1",
        ),
        (
            [Vec2::ZERO, Vec2::new(5.0, -3.0)],
            "invalid right gaze = 5,-3: X and Y in -1..1",
        ),
        (
            [Vec2::new(1e30, 0.0); 2],
            "invalid left gaze = 1000000000000000000000000000000,0",
        ),
    ] {
        let e = renderer.set_gaze(gaze).unwrap_err().to_string();
        assert!(e.starts_with(expected), "{e}");
        assert_eq!(
            renderer.gaze(),
            good,
            "a refused gaze leaves the last good one"
        );
    }
    let mut head = scene.head;
    head.w_axis.x = f32::NAN;
    let e = renderer.render_frame(head).unwrap_err().to_string();
    assert!(
        e.starts_with("invalid world_from_head") && e.contains("a finite matrix"),
        "{e}"
    );
    let mut eyes = plan.eyes;
    eyes.cant_rad = f32::NAN;
    let e = renderer.set_eyes(eyes).unwrap_err().to_string();
    assert!(e.starts_with("invalid cant = NaN"), "{e}");
    renderer
        .render_frame(scene.head)
        .expect("the renderer renders on");
    drop(renderer);
    assert_validation_clean(gpu);
}

/// One `Gpu` shared by two threads, each rendering its own frames: the queue is locked around
/// every submission, so validation (whose thread checker reports a queue used by two threads at
/// once) stays silent. Negative control: `Gpu::with_queue` without its lock reports
/// `UNASSIGNED-Threading-MultipleThreads` on vkQueueSubmit.
#[test]
fn two_threads_render_on_one_gpu() {
    let (gpu, scene) = (&gpu(), &default_scene());
    let config = RenderConfig {
        resolution: Some(Resolution::square(48)),
        msaa: 1,
        ..RenderConfig::default()
    };
    let plan = foveate::plan(scene, &config, gpu.caps()).unwrap();
    std::thread::scope(|s| {
        for _ in 0..2 {
            s.spawn(|| {
                let mut renderer = Renderer::new(gpu, &plan, scene).unwrap();
                for _ in 0..40 {
                    renderer.render_frame(scene.head).unwrap();
                }
            });
        }
    });
    assert_validation_clean(gpu);
}
