//! Foveated rendering on the GPU: four views in one multiview pass, in-pass stencil masks, and
//! pixel counts measured by the coverage probe against the analytic budget.

use foveate::foveation::{fovea_centre_px, fovea_views};
use foveate::foveation::{FoveationConfig, PixelBudget};
use foveate::metrics::RgbaImage;
use foveate::plan::{CountedStep, RenderConfig, Resolution, StereoMode};
use foveate::render::{Renderer, StereoImage};
use foveate::scene::{default_scene, Scene};
use foveate::view::Eye;
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

/// Where the composite blends, for one foveated frame: each eye's fovea centre in screen
/// pixels, the fovea's radius and the band's width.
struct Blend {
    centres: [Vec2; 2],
    radius: f32,
    band: f32,
}

impl Blend {
    fn of(gpu: &foveate::gpu::Gpu, config: &RenderConfig, gaze: Vec2) -> Blend {
        let plan = foveate::plan(&Scene::empty(), config, gpu.caps()).unwrap();
        let g = plan.foveation.unwrap();
        let screen = (plan.eye_resolution.width, plan.eye_resolution.height);
        let fovea = fovea_views(&plan.eyes, g.ratio, [gaze; 2], screen);
        Blend {
            centres: Eye::BOTH.map(|e| fovea_centre_px(plan.eyes.fov(e), fovea[e.index()], screen)),
            radius: g.fovea_screen_px / 2.0,
            band: g.blend_band_px,
        }
    }

    fn distance(&self, eye: Eye, x: u32, y: u32) -> f32 {
        Vec2::new(x as f32 + 0.5, y as f32 + 0.5).distance(self.centres[eye.index()])
    }

    /// The fovea's weight at distance `d`, as the composite computes it.
    fn weight(&self, d: f32) -> f32 {
        if self.band <= 0.0 {
            return (d < self.radius) as u32 as f32;
        }
        let t = ((d - (self.radius - self.band)) / self.band).clamp(0.0, 1.0);
        1.0 - t * t * (3.0 - 2.0 * t)
    }
}

fn foveated_frame(screen: u32, ratio: f32, band: f32) -> RenderConfig {
    RenderConfig {
        coverage_probe: false,
        count_fragments: false,
        ..foveated(
            screen,
            FoveationConfig {
                ratio,
                blend_band_px: band,
                ..Default::default()
            },
            4,
        )
    }
}

fn render_at(
    gpu: &foveate::gpu::Gpu,
    scene: &Scene,
    config: &RenderConfig,
    gaze: Vec2,
) -> StereoImage {
    let plan = foveate::plan(scene, config, gpu.caps()).unwrap();
    let mut renderer = Renderer::new(gpu, &plan, scene).unwrap();
    renderer.set_gaze([gaze; 2]);
    renderer.render_frame(scene.head).unwrap();
    let image = renderer.readback().unwrap();
    drop(renderer);
    foveate_tests::assert_validation_clean(gpu);
    image
}

/// The fovea (band excluded) against the reference, both eyes: the lower PSNR and the larger
/// fraction of pixels more than two 8-bit levels off in any channel.
fn fovea_identity(reference: &StereoImage, image: &StereoImage, blend: &Blend) -> (f64, f64) {
    let mut worst = (f64::INFINITY, 0.0f64);
    for eye in Eye::BOTH {
        let (a, b) = (reference.eye(eye), image.eye(eye));
        let inside = |x, y| blend.distance(eye, x, y) < blend.radius - blend.band - 0.5;
        let psnr = a.psnr_where(b, inside).unwrap().unwrap();
        let (mut off, mut n) = (0u64, 0u64);
        for y in 0..a.height {
            for x in (0..a.width).filter(|&x| inside(x, y)) {
                let (p, q) = (a.pixel(x, y), b.pixel(x, y));
                n += 1;
                off += (0..3).any(|c| p[c].abs_diff(q[c]) > 2) as u64;
            }
        }
        worst = (worst.0.min(psnr), worst.1.max(off as f64 / n as f64));
    }
    worst
}

/// `image` moved right by one pixel (the first column repeated).
fn shifted_one_pixel(image: &StereoImage) -> StereoImage {
    let shift = |img: &RgbaImage| {
        let mut out = img.clone();
        for y in 0..img.height {
            for x in 1..img.width {
                out.set_pixel(x, y, img.pixel(x - 1, y));
            }
        }
        out
    };
    StereoImage {
        left: shift(&image.left),
        right: shift(&image.right),
    }
}

/// Inside the fovea the composed image is the full-resolution reference: after snapping to
/// whole pixels the fovea view is a 1:1 copy. PSNR ≥ 55 dB and at most 0.1 % of its pixels more
/// than two levels off (a silhouette at the view border may flip a coverage sample), at the
/// centre, off-centre and clamped at a corner. Negative control: the same frame compared one
/// pixel off — what a fovea window one pixel off would compose — fails.
#[test]
fn the_fovea_is_the_full_resolution_reference() {
    let gpu = gpu();
    let scene = default_scene();
    let screen = 256;
    let reference_config = RenderConfig {
        resolution: Some(Resolution::square(screen)),
        msaa: 4,
        ..RenderConfig::default()
    };
    let (reference, _) = foveate_tests::render(&gpu, &scene, &reference_config);
    let config = foveated_frame(screen, 0.35, 8.0);
    // Centre, off-centre, and clamped at the bottom-left corner (content there, so a shift
    // shows: the bottom-right corner is uniform ground).
    for gaze in [Vec2::ZERO, Vec2::new(0.3, -0.25), Vec2::new(-1.0, -1.0)] {
        let image = render_at(&gpu, &scene, &config, gaze);
        let blend = Blend::of(&gpu, &config, gaze);
        let (psnr, off) = fovea_identity(&reference, &image, &blend);
        assert!(
            psnr >= 55.0 && off <= 0.001,
            "gaze {gaze}: fovea PSNR {psnr:.1} dB, {:.3} % of pixels > 2 levels off",
            100.0 * off
        );
        let (psnr, off) = fovea_identity(&shifted_one_pixel(&reference), &image, &blend);
        assert!(
            psnr < 55.0 && off > 0.001,
            "negative control: a window one pixel off passes ({psnr:.1} dB, {:.3} %)",
            100.0 * off
        );
    }
}

/// Fraction of band pixels (both eyes, every row crossing the band) whose composed colour is
/// more than three levels from the blend the model predicts: the fovea (the reference) over
/// the periphery with the smoothstep weight at that pixel's distance, mixed in linear light.
fn band_mismatch(
    composed: &StereoImage,
    reference: &StereoImage,
    periphery: &StereoImage,
    blend: &Blend,
) -> f64 {
    let linear = |v: u8| {
        let c = v as f64 / 255.0;
        if c <= 0.04045 {
            c / 12.92
        } else {
            ((c + 0.055) / 1.055).powf(2.4)
        }
    };
    let encode = |l: f64| {
        let c = if l <= 0.0031308 {
            12.92 * l
        } else {
            1.055 * l.powf(1.0 / 2.4) - 0.055
        };
        c * 255.0
    };
    let (mut off, mut n) = (0u64, 0u64);
    for eye in Eye::BOTH {
        let (c, r, p) = (composed.eye(eye), reference.eye(eye), periphery.eye(eye));
        for y in 0..c.height {
            for x in 0..c.width {
                let d = blend.distance(eye, x, y);
                if d < blend.radius - blend.band - 1.0 || d > blend.radius + 1.0 {
                    continue;
                }
                let w = blend.weight(d) as f64;
                let (cp, rp, pp) = (c.pixel(x, y), r.pixel(x, y), p.pixel(x, y));
                n += 1;
                off += (0..3).any(|k| {
                    let expected = encode(w * linear(rp[k]) + (1.0 - w) * linear(pp[k]));
                    (cp[k] as f64 - expected).abs() > 3.0
                }) as u64;
            }
        }
    }
    off as f64 / n as f64
}

/// The band blends fovea into periphery as the smoothstep model says on every row crossing it,
/// both eyes: at most 0.5 % of band pixels more than three levels off the model. Negative
/// controls on the same content: a hard cut (band 0) and a misplaced band (the fovea 8 px
/// smaller, its band 4 px inward) both fail.
#[test]
fn the_band_blends_as_the_model_says() {
    let gpu = gpu();
    let scene = default_scene();
    let screen = 256;
    let (reference, _) = foveate_tests::render(
        &gpu,
        &scene,
        &RenderConfig {
            resolution: Some(Resolution::square(screen)),
            msaa: 4,
            ..RenderConfig::default()
        },
    );
    let gaze = Vec2::new(0.3, -0.25);
    let config = foveated_frame(screen, 0.35, 12.0);
    let blend = Blend::of(&gpu, &config, gaze);
    // The periphery alone where the band lies: the fovea moved to the far corner, no masks.
    let periphery_only = RenderConfig {
        foveation: config.foveation.map(|f| FoveationConfig {
            stencil: false,
            ..f
        }),
        ..config.clone()
    };
    let periphery = render_at(&gpu, &scene, &periphery_only, Vec2::new(-1.0, 1.0));
    let composed = render_at(&gpu, &scene, &config, gaze);
    let mismatch = band_mismatch(&composed, &reference, &periphery, &blend);
    assert!(
        mismatch <= 0.005,
        "{:.2} % of band pixels off the model",
        100.0 * mismatch
    );

    let hard_cut = render_at(&gpu, &scene, &foveated_frame(screen, 0.35, 0.0), gaze);
    let cut = band_mismatch(&hard_cut, &reference, &periphery, &blend);
    let misplaced_config = RenderConfig {
        foveation: config.foveation.map(|f| FoveationConfig {
            fovea_size: Some((2.0 * blend.radius) as u32 - 8),
            ..f
        }),
        ..config.clone()
    };
    let misplaced = render_at(&gpu, &scene, &misplaced_config, gaze);
    let moved = band_mismatch(&misplaced, &reference, &periphery, &blend);
    assert!(
        cut > 0.005 && moved > 0.005,
        "negative controls pass: hard cut {:.2} %, misplaced band {:.2} %",
        100.0 * cut,
        100.0 * moved
    );
}
