//! Flicker measured on the GPU (`judge::GpuFlicker`) against the CPU measure it replaces
//! (`metrics::temporal::Flicker`, the oracle), over the same rendered frames.

use foveate::foveation::FoveationConfig;
use foveate::judge::GpuFlicker;
use foveate::metrics::temporal::{Flicker, FlickerSummary};
use foveate::metrics::{ErrorSummary, EyePixels};
use foveate::plan::{FramePlan, OutputFormat, RenderConfig, Resolution};
use foveate::render::Renderer;
use foveate::scene::{default_scene, walking_pose, Scene};
use foveate_tests::{assert_validation_clean, gpu};
use glam::Vec2;

/// Half a histogram bin, and room for `f32`'s rounding of the bins' edges.
const TOLERANCE: f64 = 0.5 / 16384.0 + 1e-6;

/// Whether two summaries agree: the same pixels, mean and percentiles within [`TOLERANCE`].
fn agree(a: Option<ErrorSummary>, b: Option<ErrorSummary>) -> bool {
    match (a, b) {
        (Some(a), Some(b)) => {
            a.pixels == b.pixels
                && [(a.mean, b.mean), (a.p95, b.p95), (a.p99, b.p99)]
                    .iter()
                    .all(|(x, y)| (x - y).abs() <= TOLERANCE)
        }
        (a, b) => a.is_none() && b.is_none(),
    }
}

fn summaries_agree(a: &FlickerSummary, b: &FlickerSummary) -> bool {
    a.changes == b.changes
        && agree(a.all, b.all)
        && a.regions.iter().zip(&b.regions).all(|(x, y)| agree(*x, *y))
}

/// Frame `i` of the motion: walking, the gaze jumping every second frame.
fn frame(scene: &Scene, i: usize) -> (glam::Mat4, Vec2) {
    let gaze = [Vec2::ZERO, Vec2::new(0.3, -0.2)][i / 2 % 2];
    (walking_pose(scene.head, i as f32 / 90.0), gaze)
}

/// Both measures (and the GPU's again with each frame's pixel map taken at a gaze 10 % off, a
/// negative control) over `frames` frames of `approximation` against `reference`.
fn measure(
    scene: &Scene,
    reference: &FramePlan,
    approximation: &FramePlan,
    frames: usize,
) -> [FlickerSummary; 3] {
    let gpu = gpu();
    let mut renderers = [reference, approximation].map(|p| Renderer::new(&gpu, p, scene).unwrap());
    let (mut on_gpu, mut off_gaze) = (
        GpuFlicker::new(&gpu).unwrap(),
        GpuFlicker::new(&gpu).unwrap(),
    );
    let mut on_cpu = Flicker::default();
    let fovea = approximation.foveation.as_ref();
    for i in 0..frames {
        let (pose, gaze) = frame(scene, i);
        for r in &mut renderers {
            r.set_gaze([gaze; 2]).unwrap();
            r.render_frame(pose).unwrap();
        }
        let pixels = EyePixels::both(approximation, gaze, fovea);
        let [r, a] = &renderers;
        on_gpu.push(r, a, &pixels).unwrap();
        let off = EyePixels::both(approximation, gaze * 1.1 + Vec2::new(0.03, 0.0), fovea);
        off_gaze.push(r, a, &off).unwrap();
        let [r, a] = renderers.each_mut().map(|r| r.readback().unwrap());
        on_cpu.push(r.eyes(), a.eyes(), &pixels).unwrap();
    }
    drop(renderers);
    assert_validation_clean(&gpu);
    [on_gpu.summary(), on_cpu.summary(), off_gaze.summary()]
}

/// Over a walk with the gaze jumping, foveated frames (sRGB output, and linear half floats)
/// and aliased stereo (linear 8-bit output) against 4× stereo: the GPU's flicker is the CPU's,
/// whole and per region, within half a histogram bin, every pixel counted alike; the same
/// frames measured with the regions taken at a gaze 10 % off do not agree (the test can fail).
/// Mutations: the shader's previous luma not kept (every change measured from zero), its
/// regions' labels off by one, or a linear output taken as sRGB, each fail.
#[test]
fn gpu_flicker_matches_the_cpu_measure() {
    let scene = default_scene();
    let caps = gpu().caps().clone();
    let reference = RenderConfig {
        resolution: Some(Resolution::square(96)),
        msaa: 4,
        ..RenderConfig::default()
    };
    let foveated = |format| RenderConfig {
        foveation: Some(FoveationConfig::single_frame()),
        output_format: format,
        ..reference.clone()
    };
    let approximations = [
        ("foveated, sRGB", foveated(OutputFormat::Srgb8)),
        ("foveated, half floats", foveated(OutputFormat::Float16)),
        (
            "stereo 1x, linear 8-bit",
            RenderConfig {
                msaa: 1,
                output_format: OutputFormat::Unorm8,
                ..reference.clone()
            },
        ),
    ];
    let reference = foveate::plan(&scene, &reference, &caps).unwrap();
    for (name, config) in approximations {
        let plan = foveate::plan(&scene, &config, &caps).unwrap();
        let [gpu, cpu, off] = measure(&scene, &reference, &plan, 5);
        assert_eq!(cpu.changes, 4);
        assert!(cpu.all.unwrap().mean > 0.0, "{name}: it flickers: {cpu:?}");
        assert!(summaries_agree(&gpu, &cpu), "{name}:\n{gpu:?}\n{cpu:?}");
        if plan.foveation.is_some() {
            assert!(
                !summaries_agree(&off, &cpu),
                "{name}: regions 10 % off agree"
            );
        }
    }
}
