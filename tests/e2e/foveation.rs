//! Foveated rendering on the GPU: four views in one multiview pass, in-pass stencil masks, and
//! pixel counts measured by the coverage probe against the analytic budget.

use foveate::foveation::{FoveationConfig, PixelBudget};
use foveate::plan::{CountedStep, RenderConfig, Resolution, StereoMode};
use foveate::scene::{default_scene, Scene};
use foveate_tests::{gpu, render_plan};
use glam::Vec2;

fn foveated(screen: u32, foveation: FoveationConfig, msaa: u32) -> RenderConfig {
    RenderConfig {
        stereo: StereoMode::Multiview,
        views: 4,
        msaa,
        resolution: Some(Resolution::square(screen)),
        foveation: Some(foveation),
        coverage_probe: true,
        count_fragments: true,
        ..RenderConfig::default()
    }
}

/// Measured per-view pixels (coverage probe) agree with the analytic budget within 0.2 %, with
/// masks off and on, for a fovea the size of its window and for a fixed fovea.
#[test]
fn measured_pixels_match_the_analytic_budget() {
    let gpu = gpu();
    let scene = Scene::empty();
    let cases = [
        FoveationConfig {
            ratio: 0.5,
            stencil: false,
            ..Default::default()
        },
        FoveationConfig {
            ratio: 0.5,
            stencil: true,
            ..Default::default()
        },
        FoveationConfig {
            ratio: 0.35,
            stencil: true,
            view_resolution: Some(100),
            ..Default::default()
        },
        FoveationConfig {
            ratio: 0.7,
            stencil: true,
            // Large enough that counting pixel centres stays within 0.2 % of the circle (a
            // 64 px circle misses by ~0.25 %: the Gauss circle problem).
            fovea_size: Some(128),
            ..Default::default()
        },
    ];
    for f in cases {
        let plan =
            foveate::plan(&scene, &foveated(256, f, 1), gpu.caps()).expect("valid foveation");
        let g = plan.foveation.expect("foveation planned");
        let (_, stats) = render_plan(&gpu, &scene, &plan, 1);
        let probe = stats.per_view(CountedStep::Probe);
        let measured_periphery = (probe[0] + probe[1]) as f64;
        let measured_fovea = (probe[2] + probe[3]) as f64;
        let analytic = PixelBudget::of(&g);
        for (what, m, a) in [
            ("fovea", measured_fovea, analytic.fovea),
            ("periphery", measured_periphery, analytic.periphery),
        ] {
            assert!(
                (m - a).abs() / a < 0.002,
                "{f:?}: {what} measured {m}, analytic {a:.1}"
            );
        }
    }
}

/// With masks, the fovea views render only their inset circle and the periphery skips the
/// hole: fewer pixels than without, in both.
#[test]
fn stencil_masks_cut_pixels_in_every_view() {
    let gpu = gpu();
    let scene = Scene::empty();
    let count = |stencil| {
        let f = FoveationConfig {
            ratio: 0.5,
            stencil,
            ..Default::default()
        };
        let plan = foveate::plan(&scene, &foveated(192, f, 1), gpu.caps()).unwrap();
        render_plan(&gpu, &scene, &plan, 1)
            .1
            .per_view(CountedStep::Probe)[..4]
            .to_vec()
    };
    let (without, with) = (count(false), count(true));
    let view = 96u64 * 96;
    assert_eq!(
        without,
        vec![view; 4],
        "no masks: every pixel of every view"
    );
    assert!(
        with.iter().zip(&without).all(|(a, b)| a < b),
        "{with:?} vs {without:?}"
    );
}

/// The default scene renders through the 4-view pass at 4× MSAA with masks and a moving gaze,
/// validation clean, and the fovea views see less of the scene than the periphery views.
#[test]
fn default_scene_renders_foveated_with_a_moving_gaze() {
    let gpu = gpu();
    let scene = default_scene();
    let config = RenderConfig {
        coverage_probe: false,
        ..foveated(128, FoveationConfig::default(), 4)
    };
    let plan = foveate::plan(&scene, &config, gpu.caps()).unwrap();
    let mut renderer = foveate::render::Renderer::new(&gpu, &plan, &scene).unwrap();
    // Centre, off-centre, and clamped at the bottom-right edge (ground there, not sky).
    for gaze in [Vec2::ZERO, Vec2::new(0.6, -0.3), Vec2::new(1.0, -1.0)] {
        renderer.set_gaze([gaze, gaze]);
        let stats = renderer.render_frame(scene.head).unwrap();
        assert_eq!(stats.fragments.len(), 4);
        assert!(
            stats.fragments.iter().all(|&n| n > 0),
            "{gaze}: {:?}",
            stats.fragments
        );
    }
    let image = renderer.readback().unwrap();
    assert_eq!(image.left.width, 128, "composed at full resolution");
    drop(renderer);
    foveate_tests::assert_validation_clean(&gpu);
}

/// Composition: inside the fovea the composed image is the full-resolution reference (the fovea
/// view maps 1:1 to the screen); the periphery is an upscaled approximation; and crossing the
/// blend band introduces no step that neither side has.
#[test]
fn composition_keeps_the_fovea_exact_and_the_band_seamless() {
    let gpu = gpu();
    let scene = default_scene();
    let screen = 128u32;
    let reference_config = RenderConfig {
        resolution: Some(Resolution::square(screen)),
        msaa: 4,
        ..RenderConfig::default()
    };
    let (reference, _) = foveate_tests::render(&gpu, &scene, &reference_config);
    let band = 8.0;
    let f = FoveationConfig {
        ratio: 0.5,
        blend_band_px: band,
        ..Default::default()
    };
    let (foveated_image, _) = foveate_tests::render(
        &gpu,
        &scene,
        &RenderConfig {
            coverage_probe: false,
            ..foveated(screen, f, 4)
        },
    );
    let geometry = f.geometry(Resolution::square(screen)).unwrap();
    let (cx, cy) = (screen as f32 / 2.0, screen as f32 / 2.0);
    let radius = geometry.fovea_screen_px / 2.0;
    let dist =
        |x: u32, y: u32| ((x as f32 + 0.5 - cx).powi(2) + (y as f32 + 0.5 - cy).powi(2)).sqrt();
    for eye in foveate::view::Eye::BOTH {
        let (a, b) = (reference.eye(eye), foveated_image.eye(eye));
        let fovea = a
            .psnr_where(b, |x, y| dist(x, y) < radius - band - 1.0)
            .unwrap()
            .unwrap();
        let periphery = a
            .psnr_where(b, |x, y| dist(x, y) > radius + 1.0)
            .unwrap()
            .unwrap();
        assert!(
            fovea > 40.0,
            "{eye:?}: fovea PSNR {fovea:.1} dB against the full-resolution reference"
        );
        assert!(
            periphery < fovea,
            "{eye:?}: periphery {periphery:.1} dB should be the approximation"
        );
        // Seam: along the row through the gaze, neighbouring pixels in the band differ no more
        // than the larger neighbour step the reference or the fovea/periphery sides show.
        let row = cy as u32;
        let step = |img: &foveate::metrics::RgbaImage, x: u32| {
            let (p, q) = (img.pixel(x, row), img.pixel(x + 1, row));
            (0..3).map(|c| p[c].abs_diff(q[c])).max().unwrap()
        };
        let in_band = |x: u32| (dist(x, row) - (radius - band / 2.0)).abs() <= band / 2.0;
        let worst_band = (0..screen - 1)
            .filter(|&x| in_band(x))
            .map(|x| step(b, x))
            .max()
            .unwrap();
        let worst_elsewhere = (0..screen - 1)
            .filter(|&x| !in_band(x))
            .map(|x| step(b, x).max(step(a, x)))
            .max()
            .unwrap();
        assert!(
            worst_band <= worst_elsewhere + 8,
            "{eye:?}: step {worst_band} in the band vs {worst_elsewhere} elsewhere"
        );
    }
}
