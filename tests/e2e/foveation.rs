//! Foveated rendering on the GPU: four views in one multiview pass, in-pass stencil masks, and
//! pixel counts measured by the coverage probe against the analytic budget.

use foveate::foveation::{fovea_centre_px, fovea_views};
use foveate::foveation::{FoveationConfig, PeripheryFilter, PixelBudget};
use foveate::metrics::RgbaImage;
use foveate::plan::{
    CountedStep, FoveaLayout, FramePlan, OutputStage, RenderConfig, Resolution, StereoMode,
};
use foveate::render::{Renderer, StereoImage};
use foveate::scene::{atrium_scene, default_scene, Scene};
use foveate::view::{Eye, FovTangents};
use foveate_tests::{gpu, linear, render_at, render_plan};
use glam::Vec2;

fn foveated(screen: u32, foveation: FoveationConfig, msaa: u32) -> RenderConfig {
    RenderConfig {
        stereo: StereoMode::Multiview,
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
            ..FoveationConfig::single_frame()
        },
        FoveationConfig {
            ratio: 0.5,
            stencil: true,
            ..FoveationConfig::single_frame()
        },
        FoveationConfig {
            ratio: 0.35,
            stencil: true,
            view_resolution: Some(100),
            ..FoveationConfig::single_frame()
        },
        FoveationConfig {
            ratio: 0.7,
            stencil: true,
            // Large enough that counting pixel centres stays within 0.2 % of the circle (a
            // 64 px circle misses by ~0.25 %: the Gauss circle problem).
            fovea_size: Some(128),
            ..FoveationConfig::single_frame()
        },
        // The periphery at its own density: views of two sizes, two passes.
        FoveationConfig {
            ratio: 0.5,
            periphery_density: Some(0.7),
            stencil: true,
            ..FoveationConfig::single_frame()
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
            ..FoveationConfig::single_frame()
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
        ..foveated(128, FoveationConfig::single_frame(), 4)
    };
    let plan = foveate::plan(&scene, &config, gpu.caps()).unwrap();
    let mut renderer = foveate::render::Renderer::new(&gpu, &plan, &scene).unwrap();
    // Centre, off-centre, and clamped at the bottom-right edge (ground there, not sky).
    for gaze in [Vec2::ZERO, Vec2::new(0.6, -0.3), Vec2::new(1.0, -1.0)] {
        renderer.set_gaze([gaze, gaze]).unwrap();
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
/// pixels, the fovea's radius and the band's width; through the lens, where each display pixel
/// looks.
pub(crate) struct Blend {
    centres: [Vec2; 2],
    radius: f32,
    band: f32,
    lens: Option<LensOracle>,
}

/// The lens model evaluated independently of the shader, in f64: where the eye sees a display
/// pixel, in pixels of the undistorted eye image.
#[derive(Clone)]
struct LensOracle {
    display: [FovTangents; 2],
    fov: [FovTangents; 2],
    k1: f64,
    k2: f64,
    screen: (u32, u32),
}

impl LensOracle {
    fn of(plan: &FramePlan) -> Option<LensOracle> {
        plan.lens.map(|l| LensOracle {
            display: l.display,
            fov: Eye::BOTH.map(|e| plan.eyes.fov(e)),
            k1: l.distortion.k1 as f64,
            k2: l.distortion.k2 as f64,
            screen: (plan.eye_resolution.width, plan.eye_resolution.height),
        })
    }

    /// Display pixel (x, y)'s centre seen through the lens, in undistorted image pixels; `None`
    /// beyond the rendered field.
    fn render_px(&self, eye: Eye, x: f64, y: f64) -> Option<(f64, f64)> {
        let (w, h) = (self.screen.0 as f64, self.screen.1 as f64);
        let (px, py) = self.image_point(eye, x, y);
        ((0.0..=w).contains(&px) && (0.0..=h).contains(&py)).then_some((px, py))
    }

    /// Display pixel (x, y)'s centre in display tangents (x right, y up).
    fn display_point(&self, eye: Eye, x: f64, y: f64) -> (f64, f64) {
        let (w, h) = (self.screen.0 as f64, self.screen.1 as f64);
        let d = self.display[eye.index()];
        let (dl, dr, du, dd) = (d.left as f64, d.right as f64, d.up as f64, d.down as f64);
        let (u, v) = ((x + 0.5) / w, (y + 0.5) / h);
        (-dl + u * (dl + dr), du - v * (du + dd))
    }

    /// Display pixel (x, y)'s centre seen through the lens, in undistorted image pixels.
    fn image_point(&self, eye: Eye, x: f64, y: f64) -> (f64, f64) {
        let (w, h) = (self.screen.0 as f64, self.screen.1 as f64);
        let p = self.fov[eye.index()];
        let (pl, pr, pu, pd) = (p.left as f64, p.right as f64, p.up as f64, p.down as f64);
        let (dx, dy) = self.display_point(eye, x, y);
        let r2 = dx * dx + dy * dy;
        let k = 1.0 + r2 * (self.k1 + self.k2 * r2);
        let (tx, ty) = (dx * k, dy * k);
        ((tx + pl) / (pl + pr) * w, (pu - ty) / (pu + pd) * h)
    }
}

impl Blend {
    pub(crate) fn of(gpu: &foveate::gpu::Gpu, config: &RenderConfig, gaze: Vec2) -> Blend {
        let plan = foveate::plan(&Scene::empty(), config, gpu.caps()).unwrap();
        let g = plan.foveation.unwrap();
        let screen = (plan.eye_resolution.width, plan.eye_resolution.height);
        let fovea = fovea_views(&plan.eyes, g.ratio, [gaze; 2], screen);
        Blend {
            centres: Eye::BOTH.map(|e| fovea_centre_px(plan.eyes.fov(e), fovea[e.index()], screen)),
            radius: g.fovea_screen_px / 2.0,
            band: g.blend_band_px,
            lens: LensOracle::of(&plan),
        }
    }

    /// How far from the fovea's centre the image point a display pixel shows lies (infinitely
    /// far beyond the rendered field).
    fn distance(&self, eye: Eye, x: u32, y: u32) -> f32 {
        let p = match &self.lens {
            Some(lens) => match lens.render_px(eye, x as f64, y as f64) {
                Some((px, py)) => Vec2::new(px as f32, py as f32),
                None => return f32::INFINITY,
            },
            None => Vec2::new(x as f32 + 0.5, y as f32 + 0.5),
        };
        p.distance(self.centres[eye.index()])
    }

    /// How far from the lens's axis display pixel (x, y) lies, in display tangents (through
    /// the lens).
    pub(crate) fn display_radius(&self, eye: Eye, x: u32, y: u32) -> Option<f64> {
        let lens = self.lens.as_ref()?;
        let (dx, dy) = lens.display_point(eye, x as f64, y as f64);
        Some(dx.hypot(dy))
    }

    /// Whether display pixel (x, y) shows the periphery alone, two pixels clear of the fovea,
    /// within the rendered field.
    pub(crate) fn periphery_only(&self, eye: Eye, x: u32, y: u32) -> bool {
        let d = self.distance(eye, x, y);
        d.is_finite() && d > self.radius + 2.0
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
                ..FoveationConfig::single_frame()
            },
            4,
        )
    }
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
/// centre, off-centre and clamped at a corner; and through the output stage's lens (against the
/// reference through the same lens, on the display pixels whose image point the f64 lens oracle
/// puts inside the fovea) in both fovea layouts, on the default scene and the lit atrium's
/// textures; and with the periphery at its own density and sample count (periphery 0.5 at 1x,
/// fovea 4x: the view pairs in images of their own). Negative control: the same frame compared
/// one pixel off — what a fovea window one pixel off would compose — fails.
#[test]
fn the_fovea_is_the_full_resolution_reference() {
    let gpu = gpu();
    let screen = 256;
    let (default, atrium) = (default_scene(), atrium_scene());
    let undistorted = OutputStage::Undistorted;
    let lens = OutputStage::Lens;
    // Centre, off-centre, and clamped at the bottom-left corner (content there, so a shift
    // shows: the bottom-right corner is uniform ground).
    let off_centre = Vec2::new(0.3, -0.25);
    let (coupled, split) = (false, true);
    let cases = [
        (
            undistorted,
            &default,
            FoveaLayout::Auto,
            Vec2::ZERO,
            coupled,
        ),
        (
            undistorted,
            &default,
            FoveaLayout::Auto,
            off_centre,
            coupled,
        ),
        (
            undistorted,
            &default,
            FoveaLayout::Auto,
            Vec2::new(-1.0, -1.0),
            coupled,
        ),
        (lens, &default, FoveaLayout::OnePass, off_centre, coupled),
        (lens, &default, FoveaLayout::TwoPass, off_centre, coupled),
        (lens, &atrium, FoveaLayout::TwoPass, off_centre, coupled),
        (lens, &atrium, FoveaLayout::Auto, off_centre, split),
    ];
    for (output, scene, fovea_layout, gaze, split) in cases {
        let reference_config = RenderConfig {
            resolution: Some(Resolution::square(screen)),
            msaa: 4,
            output,
            ..RenderConfig::default()
        };
        let (reference, _) = foveate_tests::render(&gpu, scene, &reference_config);
        let mut config = RenderConfig {
            fovea_layout,
            output,
            ..foveated_frame(screen, 0.35, 8.0)
        };
        if split {
            let f = config.foveation.as_mut().unwrap();
            (f.periphery_density, f.periphery_msaa) = (Some(0.5), Some(1));
        }
        let image = render_at(&gpu, scene, &config, gaze);
        let blend = Blend::of(&gpu, &config, gaze);
        assert_eq!(blend.lens.is_some(), output == lens);
        let case = format!("{output}, {fovea_layout}, gaze {gaze}, split {split}");
        let (psnr, off) = fovea_identity(&reference, &image, &blend);
        assert!(
            psnr >= 55.0 && off <= 0.001,
            "{case}: fovea PSNR {psnr:.1} dB, {:.3} % of pixels > 2 levels off",
            100.0 * off
        );
        let (psnr, off) = fovea_identity(&shifted_one_pixel(&reference), &image, &blend);
        assert!(
            psnr < 55.0 && off > 0.001,
            "{case}: negative control, a window one pixel off, passes ({psnr:.1} dB, {:.3} %)",
            100.0 * off
        );
    }
}

/// Linear light as an sRGB level (0–255, unrounded).
fn encode(l: f64) -> f64 {
    let c = if l <= 0.0031308 {
        12.92 * l
    } else {
        1.055 * l.powf(1.0 / 2.4) - 0.055
    };
    c * 255.0
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
    let in_band = |eye, x, y| {
        let d = blend.distance(eye, x, y);
        d >= blend.radius - blend.band - 1.0 && d <= blend.radius + 1.0
    };
    let model = |eye: Eye, x, y| {
        let w = blend.weight(blend.distance(eye, x, y)) as f64;
        let (rp, pp) = (
            reference.eye(eye).pixel(x, y),
            periphery.eye(eye).pixel(x, y),
        );
        std::array::from_fn(|k| encode(w * linear(rp[k]) + (1.0 - w) * linear(pp[k])))
    };
    fraction_off(composed, 3.0, in_band, model)
}

/// Fraction of the pixels `select` picks, both eyes, whose colour in `image` is more than
/// `levels` from what `expected` says there (in any channel).
fn fraction_off(
    image: &StereoImage,
    levels: f64,
    select: impl Fn(Eye, u32, u32) -> bool,
    expected: impl Fn(Eye, u32, u32) -> [f64; 3],
) -> f64 {
    let (mut off, mut n) = (0u64, 0u64);
    for eye in Eye::BOTH {
        let img = image.eye(eye);
        for y in 0..img.height {
            for x in (0..img.width).filter(|&x| select(eye, x, y)) {
                let (got, want) = (img.pixel(x, y), expected(eye, x, y));
                n += 1;
                off += (0..3).any(|k| (got[k] as f64 - want[k]).abs() > levels) as u64;
            }
        }
    }
    off as f64 / n as f64
}

/// The band blends fovea into periphery as the smoothstep model says on every row crossing it,
/// both eyes, undistorted and through the lens (at each display pixel's image point): at most
/// 0.5 % of band pixels more than three levels off the model. Negative controls on the same
/// content: a hard cut (band 0) and a misplaced band (the fovea 8 px smaller, its band 4 px
/// inward) both fail.
#[test]
fn the_band_blends_as_the_model_says() {
    let gpu = gpu();
    let scene = default_scene();
    let screen = 256;
    for output in [OutputStage::Undistorted, OutputStage::Lens] {
        let with_output = |c: RenderConfig| RenderConfig { output, ..c };
        let (reference, _) = foveate_tests::render(
            &gpu,
            &scene,
            &with_output(RenderConfig {
                resolution: Some(Resolution::square(screen)),
                msaa: 4,
                ..RenderConfig::default()
            }),
        );
        let gaze = Vec2::new(0.3, -0.25);
        let config = with_output(foveated_frame(screen, 0.35, 12.0));
        let blend = Blend::of(&gpu, &config, gaze);
        assert_eq!(blend.lens.is_some(), output == OutputStage::Lens);
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
            "{output}: {:.2} % of band pixels off the model",
            100.0 * mismatch
        );

        let hard_cut = with_output(foveated_frame(screen, 0.35, 0.0));
        let cut = band_mismatch(
            &render_at(&gpu, &scene, &hard_cut, gaze),
            &reference,
            &periphery,
            &blend,
        );
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
            "{output}: negative controls pass: hard cut {:.2} %, misplaced band {:.2} %",
            100.0 * cut,
            100.0 * moved
        );
    }
}

/// Fraction of display pixels (both eyes) more than three levels from the undistorted image
/// sampled bilinearly (in linear light) where `oracle` says the eye sees them, or not black
/// beyond the rendered field.
fn lens_mismatch(lens: &StereoImage, undistorted: &StereoImage, oracle: &LensOracle) -> f64 {
    let (mut off, mut n) = (0u64, 0u64);
    for eye in Eye::BOTH {
        let (out, src) = (lens.eye(eye), undistorted.eye(eye));
        let texel = |x: i64, y: i64, c: usize| {
            let x = x.clamp(0, src.width as i64 - 1) as u32;
            let y = y.clamp(0, src.height as i64 - 1) as u32;
            linear(src.pixel(x, y)[c])
        };
        for y in 0..out.height {
            for x in 0..out.width {
                let p = out.pixel(x, y);
                n += 1;
                let expected: [f64; 3] = match oracle.render_px(eye, x as f64, y as f64) {
                    None => [0.0; 3],
                    Some((px, py)) => {
                        let (sx, sy) = (px - 0.5, py - 0.5);
                        let (x0, y0) = (sx.floor(), sy.floor());
                        let (fx, fy) = (sx - x0, sy - y0);
                        let (x0, y0) = (x0 as i64, y0 as i64);
                        std::array::from_fn(|c| {
                            let top = texel(x0, y0, c) * (1.0 - fx) + texel(x0 + 1, y0, c) * fx;
                            let bottom =
                                texel(x0, y0 + 1, c) * (1.0 - fx) + texel(x0 + 1, y0 + 1, c) * fx;
                            encode(top * (1.0 - fy) + bottom * fy)
                        })
                    }
                };
                off += (0..3).any(|c| (p[c] as f64 - expected[c]).abs() > 3.0) as u64;
            }
        }
    }
    off as f64 / n as f64
}

/// The output stage distorts as the lens model says: every display pixel of the lens output is
/// the undistorted frame sampled where an independent f64 evaluation of the radial polynomial
/// puts it (black beyond the field), to three levels on 99 % of pixels. Negative controls: the
/// oracle with k1 10 % larger, or without distortion, fails.
#[test]
fn the_lens_distorts_as_the_model_says() {
    let gpu = gpu();
    let scene = default_scene();
    let base = RenderConfig {
        resolution: Some(Resolution::square(128)),
        msaa: 4,
        ..RenderConfig::default()
    };
    let (undistorted, _) = foveate_tests::render(&gpu, &scene, &base);
    let lens_config = RenderConfig {
        output: OutputStage::Lens,
        ..base.clone()
    };
    let (lens, _) = foveate_tests::render(&gpu, &scene, &lens_config);
    let plan = foveate::plan(&scene, &lens_config, gpu.caps()).unwrap();
    let oracle = LensOracle::of(&plan).expect("planned for the lens");
    // On the lens axis's row the display's edges show the rendered field's edges, by the
    // oracle's own polynomial (a check of the solved display field).
    for eye in Eye::BOTH {
        let (w, h) = (
            plan.eye_resolution.width as f64,
            plan.eye_resolution.height as f64,
        );
        let d = oracle.display[eye.index()];
        let axis_row = d.up as f64 / (d.up + d.down) as f64 * h - 0.5;
        let (left, _) = oracle.image_point(eye, -0.5, axis_row);
        let (right, _) = oracle.image_point(eye, w - 0.5, axis_row);
        assert!(
            left.abs() < 1e-3 && (right - w).abs() < 1e-3,
            "{left}, {right}"
        );
    }
    let mismatch = lens_mismatch(&lens, &undistorted, &oracle);
    assert!(
        mismatch <= 0.01,
        "{:.2} % of display pixels off the model",
        100.0 * mismatch
    );
    for (what, k1, k2) in [
        ("k1 10 % larger", oracle.k1 * 1.1, oracle.k2),
        ("no distortion", 0.0, 0.0),
    ] {
        let wrong = LensOracle {
            k1,
            k2,
            ..oracle.clone()
        };
        let m = lens_mismatch(&lens, &undistorted, &wrong);
        assert!(
            m > 0.05,
            "negative control ({what}) passes: {:.2} %",
            100.0 * m
        );
    }
}

/// The fovea views draw only what their superfrustum keeps, and no pixel changes: in each
/// layout the fovea-culled frame equals the unculled one, and the two layouts give the same
/// image. The culled frames draw fewer instances (two-pass); in one pass, the tags turn
/// primitives outside the fovea views into degenerate ones, which the clipper rejects as it
/// would have rejected them anyway — unless a guard band (lavapipe 22.3's workaround) keeps them
/// inside the clip volume until the scissor: then the tagged frame rasterises fewer, elsewhere
/// the same. Mutation: the superfrustum built from one eye's fovea only drops the other
/// fovea's instances and fails; tags ignored by the shader fail the primitive count on a
/// driver with the guard band.
#[test]
fn fovea_culling_changes_no_pixel_in_either_layout() {
    let gpu = gpu();
    let scene = default_scene();
    let gaze = Vec2::new(0.35, -0.2);
    let frame = |fovea_layout, cull_fovea| {
        let config = RenderConfig {
            fovea_layout,
            foveation: Some(FoveationConfig {
                ratio: 0.35,
                cull_fovea,
                ..FoveationConfig::single_frame()
            }),
            ..foveated_frame(128, 0.35, 4.0)
        };
        let plan = foveate::plan(&scene, &config, gpu.caps()).unwrap();
        let mut renderer = Renderer::new(&gpu, &plan, &scene).unwrap();
        renderer.set_gaze([gaze; 2]).unwrap();
        let stats = renderer.render_frame(scene.head).unwrap();
        let image = renderer.readback().unwrap();
        drop(renderer);
        // Primitives the scene pass rasterised, from a counting frame of the same gaze, and
        // whether that pass has a guard band.
        let counts =
            foveate::render::counting_frame(&gpu, &scene, &config, [gaze; 2], scene.head).unwrap();
        let rasterised = counts
            .pass_statistics
            .first()
            .map(|p| (p.rasterised, plan.passes[0].guard_band > 1));
        foveate_tests::assert_validation_clean(&gpu);
        (image, stats, rasterised)
    };
    let (two_pass, culled_stats, _) = frame(FoveaLayout::TwoPass, true);
    let (two_pass_all, all_stats, _) = frame(FoveaLayout::TwoPass, false);
    assert_eq!(
        culled_stats.instances_drawn.len(),
        2,
        "periphery and fovea passes"
    );
    assert!(
        culled_stats.instances_drawn[1] < all_stats.instances_drawn[1],
        "the fovea pass draws fewer instances: {:?} vs {:?}",
        culled_stats.instances_drawn,
        all_stats.instances_drawn
    );
    assert!(
        two_pass == two_pass_all,
        "two-pass: fovea culling changed pixels"
    );
    let (one_pass, _, tagged) = frame(FoveaLayout::OnePass, true);
    let (one_pass_all, _, untagged) = frame(FoveaLayout::OnePass, false);
    assert!(
        one_pass == one_pass_all,
        "one-pass: fovea culling changed pixels"
    );
    // One pass draws the same instances either way; where the device has pipeline
    // statistics, the tags drop primitives the guard band would have kept, and add none.
    if let (Some((tagged, guarded)), Some((untagged, _))) = (tagged, untagged) {
        if guarded {
            assert!(
                tagged < untagged,
                "one-pass: fovea tags drop no primitive ({tagged} vs {untagged})"
            );
        } else {
            assert_eq!(
                tagged, untagged,
                "one-pass: the tags change what is rasterised"
            );
        }
    }
    let diff = one_pass.left.psnr(&two_pass.left).unwrap();
    assert!(
        one_pass == two_pass,
        "the layouts differ (left eye PSNR {diff:.1} dB)"
    );
}

/// The periphery of `image` upscaled to the output at output pixel (`x`, `y`) of a `screen`-wide
/// eye, in linear light as the output pass filters it, then encoded: bilinear, or the
/// Catmull-Rom spline (a = -0.5) over the 4×4 texels around it, edges repeated, clamped.
fn upscaled(image: &RgbaImage, screen: u32, x: u32, y: u32, catmull_rom: bool) -> [f64; 3] {
    let (w, h) = (image.width as i64, image.height as i64);
    let to_texels = |p: u32, n: i64| (p as f64 + 0.5) / screen as f64 * n as f64 - 0.5;
    let (px, py) = (to_texels(x, w), to_texels(y, h));
    let (bx, by) = (px.floor(), py.floor());
    let (tx, ty) = (px - bx, py - by);
    let weights = |t: f64| {
        if catmull_rom {
            [
                ((-0.5 * t + 1.0) * t - 0.5) * t,
                (1.5 * t - 2.5) * t * t + 1.0,
                ((-1.5 * t + 2.0) * t + 0.5) * t,
                (0.5 * t - 0.5) * t * t,
            ]
        } else {
            [0.0, 1.0 - t, t, 0.0]
        }
    };
    let (wx, wy) = (weights(tx), weights(ty));
    let mut sum = [0.0; 3];
    for (j, wj) in wy.iter().enumerate() {
        for (i, wi) in wx.iter().enumerate() {
            let tx = (bx as i64 + i as i64 - 1).clamp(0, w - 1) as u32;
            let ty = (by as i64 + j as i64 - 1).clamp(0, h - 1) as u32;
            let p = image.pixel(tx, ty);
            for (c, s) in sum.iter_mut().enumerate() {
                *s += wi * wj * linear(p[c]);
            }
        }
    }
    sum.map(|l| encode(l.clamp(0.0, 1.0)))
}

/// Fraction of periphery pixels (both eyes, beyond the band) more than two levels from
/// `periphery` upscaled as `catmull_rom` says.
fn upscale_mismatch(
    composed: &StereoImage,
    periphery: &StereoImage,
    blend: &Blend,
    catmull_rom: bool,
) -> f64 {
    let beyond_band = |eye, x, y| blend.distance(eye, x, y) > blend.radius + 1.0;
    let width = composed.left.width;
    let filtered = |eye, x, y| upscaled(periphery.eye(eye), width, x, y, catmull_rom);
    fraction_off(composed, 2.0, beyond_band, filtered)
}

/// The periphery upscaled with Catmull-Rom is the spline the CPU evaluates on the periphery
/// views — rendered alone as a stereo frame at their resolution — and bilinear upscaling is the
/// CPU's bilinear on the same views (which checks the views and the sampling positions): at most
/// 1 % of periphery pixels more than two levels off. Negative control: the bilinear frame against
/// the spline fails. The fovea is the same pixels with either filter (only the periphery's
/// upscaling changes).
#[test]
fn catmull_rom_upscales_the_periphery_as_the_spline_says() {
    let gpu = gpu();
    let scene = default_scene();
    let (screen, ratio) = (128, 0.5);
    let gaze = Vec2::new(0.3, -0.25);
    // No masks, so the periphery has no hole for the filter to reach into.
    let with_filter = |periphery_filter| {
        let frame = foveated_frame(screen, ratio, 8.0);
        RenderConfig {
            output: OutputStage::Undistorted,
            foveation: frame.foveation.map(|f| FoveationConfig {
                stencil: false,
                periphery_filter,
                ..f
            }),
            ..frame
        }
    };
    let bilinear_config = with_filter(PeripheryFilter::Bilinear);
    let blend = Blend::of(&gpu, &bilinear_config, gaze);
    let views = RenderConfig {
        resolution: Some(Resolution::square((screen as f32 * ratio) as u32)),
        msaa: 4,
        output: OutputStage::Undistorted,
        ..RenderConfig::default()
    };
    let periphery = render_at(&gpu, &scene, &views, gaze);
    let bilinear = render_at(&gpu, &scene, &bilinear_config, gaze);
    let spline = render_at(
        &gpu,
        &scene,
        &with_filter(PeripheryFilter::CatmullRom),
        gaze,
    );
    let (as_bilinear, as_spline, wrong) = (
        upscale_mismatch(&bilinear, &periphery, &blend, false),
        upscale_mismatch(&spline, &periphery, &blend, true),
        upscale_mismatch(&bilinear, &periphery, &blend, true),
    );
    println!(
        "periphery pixels off the CPU's filter: bilinear {:.2} %, Catmull-Rom {:.2} %; bilinear against the spline {:.2} %",
        100.0 * as_bilinear,
        100.0 * as_spline,
        100.0 * wrong
    );
    assert!(as_bilinear <= 0.01, "bilinear {:.2} %", 100.0 * as_bilinear);
    assert!(as_spline <= 0.01, "Catmull-Rom {:.2} %", 100.0 * as_spline);
    assert!(
        wrong > 0.01,
        "negative control passes: {:.2} %",
        100.0 * wrong
    );
    for eye in Eye::BOTH {
        let (a, b) = (bilinear.eye(eye), spline.eye(eye));
        for y in 0..a.height {
            for x in (0..a.width).filter(|&x| blend.distance(eye, x, y) < blend.radius - 9.0) {
                assert_eq!(a.pixel(x, y), b.pixel(x, y), "fovea pixel ({x}, {y})");
            }
        }
    }
}

/// Channels of two frames that differ.
fn channels_differing(a: &StereoImage, b: &StereoImage) -> usize {
    let channels = |i: &StereoImage| {
        i.left
            .data
            .iter()
            .chain(&i.right.data)
            .copied()
            .collect::<Vec<u8>>()
    };
    channels(a)
        .iter()
        .zip(&channels(b))
        .filter(|(x, y)| x != y)
        .count()
}

/// A foveated frame of `foveation` at `gaze`, 160² per eye, after three frames (so an
/// accumulated periphery has a history).
fn masked_frame(
    gpu: &foveate::gpu::Gpu,
    scene: &Scene,
    foveation: FoveationConfig,
    msaa: u32,
    output: OutputStage,
    gaze: Vec2,
) -> StereoImage {
    let config = RenderConfig {
        output,
        coverage_probe: false,
        count_fragments: false,
        ..foveated(160, foveation, msaa)
    };
    let plan = foveate::plan(scene, &config, gpu.caps()).unwrap();
    let mut renderer = Renderer::new(gpu, &plan, scene).unwrap();
    renderer.set_gaze([gaze; 2]).unwrap();
    for _ in 0..3 {
        renderer.render_frame(scene.head).unwrap();
    }
    renderer.readback().unwrap()
}

/// The stencil masks only save work: with them on, not one pixel of the output differs from
/// the same frame with them off — with no band (a hard edge), at the default band (an eighth
/// of the fovea), with the Catmull-Rom filter and sharpening, a half-density periphery
/// accumulated over frames, a parafoveal ring, MSAA and the lens, the gaze centred and off to
/// the side. A hole cut up to where the periphery is still read shows as a ring of the clear
/// colour around the fovea: the negative control, masks cut at the edges as in Arm's tables
/// (the ring a band of 0, once the library's default, drew), differs.
#[test]
fn stencil_masks_change_no_pixel_of_the_output() {
    let gpu = gpu();
    let scene = default_scene();
    let hard_edge = FoveationConfig {
        blend_band_px: 0.0,
        ..FoveationConfig::single_frame()
    };
    let configs = [
        (hard_edge, 1, OutputStage::Undistorted),
        (FoveationConfig::single_frame(), 4, OutputStage::Lens),
        (
            FoveationConfig {
                periphery_filter: PeripheryFilter::CatmullRom,
                periphery_sharpen: 0.5,
                ..FoveationConfig::single_frame()
            },
            4,
            OutputStage::Undistorted,
        ),
        (
            FoveationConfig {
                periphery_density: Some(0.5),
                periphery_temporal: Some(Default::default()),
                ..FoveationConfig::single_frame()
            },
            1,
            OutputStage::Undistorted,
        ),
        // A parafoveal ring: the periphery's hole under it, its own under the fovea.
        (
            FoveationConfig {
                ring_ratio: Some(0.6),
                ..hard_edge
            },
            1,
            OutputStage::Undistorted,
        ),
        (
            FoveationConfig {
                ring_ratio: Some(0.7),
                periphery_density: Some(0.25),
                ..FoveationConfig::single_frame()
            },
            4,
            OutputStage::Lens,
        ),
    ];
    for (foveation, msaa, output) in configs {
        for gaze in [Vec2::ZERO, Vec2::new(0.3, -0.2)] {
            let frame = |stencil| {
                let foveation = FoveationConfig {
                    stencil,
                    ..foveation
                };
                masked_frame(&gpu, &scene, foveation, msaa, output, gaze)
            };
            assert_eq!(
                channels_differing(&frame(true), &frame(false)),
                0,
                "{foveation:?}, MSAA {msaa}, {output:?}, gaze {gaze}: channels differing"
            );
        }
    }
    let frame = |foveation| {
        masked_frame(
            &gpu,
            &scene,
            foveation,
            1,
            OutputStage::Undistorted,
            Vec2::ZERO,
        )
    };
    let arms = FoveationConfig {
        mask_margins: false,
        ..hard_edge
    };
    let whole = FoveationConfig {
        stencil: false,
        ..hard_edge
    };
    assert!(
        channels_differing(&frame(arms), &frame(whole)) > 100,
        "masks without margins show the hole"
    );
    foveate_tests::assert_validation_clean(&gpu);
}
