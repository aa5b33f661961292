//! An accumulated periphery at 4×: its depth, resolved to one sample in its own pass, steers
//! the reprojection as a single-sample periphery's depth does.

use foveate::foveation::{FoveationConfig, HistoryClip, TemporalConfig};
use foveate::plan::RenderConfig;
use foveate::scene::atrium_scene;
use foveate_tests::gpu;
use glam::{Mat4, Vec2, Vec3};

use super::temporal::{config, periphery_error, periphery_only, render_sequence, supersampled};

const SCREEN: u32 = 128;

/// The accumulated periphery at `samples`, its history neither clipped nor depth-tested
/// (`HistoryClip::Off`): only the reprojection, steered by the depth, keeps it in place.
fn accumulated(samples: u32) -> RenderConfig {
    let base = config(
        SCREEN,
        Some(TemporalConfig {
            clip: HistoryClip::Off,
            ..Default::default()
        }),
    );
    RenderConfig {
        foveation: base.foveation.map(|f| FoveationConfig {
            periphery_msaa: Some(samples),
            ..f
        }),
        ..base
    }
}

/// With the head stepping sideways (every point moves by its own parallax, so the
/// reprojection needs each pixel's depth) the 4× periphery's history stays as close to the
/// supersampled reference as the 1× periphery's. Mutation: the render pass without its depth
/// resolve (the resolved image then holds nothing the pass wrote) fails it.
#[test]
fn a_multisampled_periphery_reprojects_by_its_resolved_depth() {
    let gpu = gpu();
    if !gpu.caps().depth_resolve {
        eprintln!(
            "skipped: {} cannot resolve depth in a pass",
            gpu.caps().device_name
        );
        return;
    }
    let scene = atrium_scene();
    let frames = 24;
    // 3 m/s to the right: a near surface's parallax outruns the accumulation's memory.
    let step = |f: usize| {
        let x = 3.0 / 90.0 * f as f32;
        (
            scene.head * Mat4::from_translation(Vec3::new(x, 0.0, 0.0)),
            Vec2::ZERO,
        )
    };
    let motion: Vec<(Mat4, Vec2)> = (0..frames).map(step).collect();
    let reference = supersampled(&gpu, &scene, step(frames - 1));
    let error = |samples| {
        let (plan, images) = render_sequence(&gpu, &scene, &accumulated(samples), &motion, |f| {
            f == frames - 1
        });
        periphery_error(&images[0], &reference, &periphery_only(&plan, Vec2::ZERO))
    };
    let (single, multi) = (error(1), error(4));
    eprintln!("periphery error after stepping sideways: 1x {single:.5}, 4x {multi:.5}");
    assert!(
        multi < 1.1 * single,
        "the 4x history strays from the scene: {multi:.5} against {single:.5} at 1x"
    );
}
