//! The GPU judge (`judge::FlipJudge`) against its oracles on the CPU: NVIDIA's reference FLIP
//! (`metrics::flip::flip_map`) and the eccentricity-aware FLIP built on it
//! (`metrics::flip::eccentric_flip_map`), over rendered frames and synthetic images.

use foveate::foveation::FoveationConfig;
use foveate::judge::{reference_config, FlipJudge, GpuFlip, LiveJudge};
use foveate::metrics::flip::eccentric_flip_map;
use foveate::metrics::perceptual::{perceptual_error, Maps};
use foveate::metrics::{
    Acuity, ErrorHistogram, ErrorSummary, EyePixels, FlipMaps, Region, RgbaImage,
};
use foveate::plan::{OutputStage, RenderConfig, Resolution};
use foveate::render::{FrameInput, Renderer};
use foveate::scene::default_scene;
use foveate::view::Eye;
use foveate_tests::{assert_validation_clean, gpu, render_at};
use glam::{Mat4, Vec2, Vec3};

/// How two maps of the same pixels agree: the fraction of pixels within 0.02, and how far
/// their means and 99th percentiles lie apart.
#[derive(Debug)]
struct Agreement {
    within: f64,
    mean: f64,
    p99: f64,
}

impl Agreement {
    /// Over the pixels either map judged: one judged by only one of them counts as apart.
    fn of(gpu: &[f32], cpu: &[f32]) -> Agreement {
        assert_eq!(gpu.len(), cpu.len());
        let judged: Vec<(f32, f32)> = gpu
            .iter()
            .zip(cpu)
            .filter(|(g, c)| !(g.is_nan() && c.is_nan()))
            .map(|(&g, &c)| (g, c))
            .collect();
        let close = judged.iter().filter(|(g, c)| (g - c).abs() <= 0.02).count();
        let both: Vec<(f32, f32)> = judged
            .iter()
            .copied()
            .filter(|(g, c)| !g.is_nan() && !c.is_nan())
            .collect();
        let summary = |v: Vec<f32>| ErrorSummary::of(&v).unwrap();
        let (g, c) = (
            summary(both.iter().map(|p| p.0).collect()),
            summary(both.iter().map(|p| p.1).collect()),
        );
        Agreement {
            within: close as f64 / judged.len() as f64,
            mean: (g.mean - c.mean).abs(),
            p99: (g.p99 - c.p99).abs(),
        }
    }

    /// The bounds the GPU judge is held to.
    fn holds(&self) -> bool {
        self.within >= 0.999 && self.mean <= 0.001 && self.p99 <= 0.005
    }
}

/// A synthetic viewing model: the eye looks at `gaze` (pixels) on a display of `ppd` pixels per
/// degree, and sees a disc of `radius` pixels around the image's centre.
fn eccentricity(
    width: u32,
    height: u32,
    gaze: Vec2,
    degrees_per_pixel: f64,
) -> impl Fn(u32, u32) -> Option<f64> + Sync {
    let centre = Vec2::new(width as f32, height as f32) / 2.0;
    let radius = centre.min_element() * 0.95;
    move |x, y| {
        let p = Vec2::new(x as f32 + 0.5, y as f32 + 0.5);
        (p.distance(centre) <= radius).then(|| p.distance(gaze) as f64 * degrees_per_pixel)
    }
}

/// The default scene foveated at `res`² and its 4× MSAA reference, left eye.
fn frames(res: u32, gaze: Vec2) -> (RgbaImage, RgbaImage) {
    let gpu = gpu();
    let scene = default_scene();
    let reference = RenderConfig {
        resolution: Some(Resolution::square(res)),
        msaa: 4,
        ..RenderConfig::default()
    };
    let foveated = RenderConfig {
        foveation: Some(FoveationConfig::single_frame()),
        msaa: 1,
        ..reference.clone()
    };
    let want = render_at(&gpu, &scene, &reference, gaze).left;
    let got = render_at(&gpu, &scene, &foveated, gaze).left;
    (want, got)
}

fn judge_both(
    reference: &RgbaImage,
    test: &RgbaImage,
    ppd: f64,
    ecc: &(dyn Fn(u32, u32) -> Option<f64> + Sync),
) -> (FlipMaps, FlipMaps) {
    let gpu = gpu();
    let mut judge = FlipJudge::new(&gpu, reference.width, reference.height).unwrap();
    let on_gpu = judge
        .flip_maps(reference, test, ppd, Acuity::default(), ecc)
        .unwrap();
    assert_validation_clean(&gpu);
    let on_cpu = eccentric_flip_map(reference, test, ppd, Acuity::default(), ecc).unwrap();
    (on_gpu, on_cpu)
}

/// A synthetic image of edges and points: a bright disc, thin lines at several angles, single
/// bright pixels, a soft gradient; and the same shifted by a pixel and blurred, so every one of
/// FLIP's features differs somewhere.
fn edges_and_points(size: u32, shift: f32, blur: bool) -> RgbaImage {
    let mut img = RgbaImage::new(size, size);
    let c = size as f32 / 2.0;
    for y in 0..size {
        for x in 0..size {
            let (fx, fy) = (x as f32 + shift, y as f32);
            let mut v = 0.25 + 0.25 * fx / size as f32;
            if (fx - c * 0.6).hypot(fy - c * 0.7) < size as f32 * 0.12 {
                v = 0.9;
            }
            if ((fx + 2.0 * fy) as i32).rem_euclid(29) == 0
                || (fx as i32 - fy as i32).rem_euclid(37) == 0
            {
                v = 0.05;
            }
            if (x * 7 + y * 13) % 97 == 0 {
                v = 1.0;
            }
            let colour = [v, v * 0.8, (1.0 - v) * 0.6].map(|c| (c * 255.0) as u8);
            img.set_pixel(x, y, [colour[0], colour[1], colour[2], 255]);
        }
    }
    if blur {
        let copy = img.clone();
        for y in 1..size - 1 {
            for x in 1..size - 1 {
                let mut sum = [0u32; 3];
                for (dx, dy) in [(0, 0), (1, 0), (0, 1), (1, 1)] {
                    let p = copy.pixel(x + dx - 1, y + dy - 1);
                    (0..3).for_each(|k| sum[k] += p[k] as u32);
                }
                img.set_pixel(
                    x,
                    y,
                    [
                        (sum[0] / 4) as u8,
                        (sum[1] / 4) as u8,
                        (sum[2] / 4) as u8,
                        255,
                    ],
                );
            }
        }
    }
    img
}

/// Uniform noise from a seed.
fn noise(size: u32, seed: u32) -> RgbaImage {
    let mut state = seed.wrapping_mul(2_654_435_761).max(1);
    let mut img = RgbaImage::new(size, size);
    for byte in img.data.iter_mut() {
        state ^= state << 13;
        state ^= state >> 17;
        state ^= state << 5;
        *byte = (state >> 24) as u8;
    }
    img.data.chunks_exact_mut(4).for_each(|p| p[3] = 255);
    img
}

/// The pairs the GPU judge is held to its oracles on: the default scene foveated against its
/// reference at two resolutions and two gazes, edges and points, noise.
fn pairs() -> Vec<(String, RgbaImage, RgbaImage)> {
    let mut pairs = Vec::new();
    for res in [160, 256] {
        for gaze in [Vec2::ZERO, Vec2::new(0.3, -0.2)] {
            let (want, got) = frames(res, gaze);
            pairs.push((format!("scene {res}² gaze {gaze}"), want, got));
        }
    }
    pairs.push((
        "edges and points".into(),
        edges_and_points(192, 0.0, false),
        edges_and_points(192, 1.0, true),
    ));
    pairs.push(("noise".into(), noise(256, 1), noise(256, 2)));
    pairs
}

/// Plain FLIP on the GPU against NVIDIA's reference C++: per pixel within 0.02 on 99.9 % of
/// pixels, means within 0.001, 99th percentiles within 0.005. Mutation runs: the blue–yellow
/// filter's halves normalised apart, the feature exponent 0.7 instead of 0.5, the Hunt
/// adjustment left out: each fails.
#[test]
fn gpu_flip_matches_nvidias_reference() {
    let everywhere = |_: u32, _: u32| Some(0.0);
    for (name, reference, test) in pairs() {
        for ppd in [8.0, 40.0] {
            let (gpu, cpu) = judge_both(&reference, &test, ppd, &everywhere);
            let a = Agreement::of(&gpu.plain, &cpu.plain);
            assert!(a.holds(), "{name} at {ppd} ppd: {a:?}");
        }
    }
}

/// The eccentricity-aware FLIP on the GPU (its coarse levels filtered on a pyramid) against
/// the CPU's, which filters every level at full resolution, with the gaze off centre and
/// eccentricities reaching every level: the same bounds.
#[test]
fn gpu_eccentric_flip_matches_the_cpus() {
    for (name, reference, test) in pairs() {
        let (w, h) = (reference.width, reference.height);
        let gaze = Vec2::new(w as f32 * 0.65, h as f32 * 0.6);
        for (ppd, degrees_per_pixel) in [(12.0, 0.3), (40.0, 0.15)] {
            let ecc = eccentricity(w, h, gaze, degrees_per_pixel);
            let (gpu, cpu) = judge_both(&reference, &test, ppd, &ecc);
            let a = Agreement::of(&gpu.eccentric, &cpu.eccentric);
            assert!(a.holds(), "{name} at {ppd} ppd: {a:?}");
        }
    }
}

/// The bounds catch a judge that is slightly wrong: the ppd off by 10 %, the gaze off by 10 %
/// of the image, the pixels' eccentricities read one pixel over.
#[test]
fn the_bounds_catch_a_slightly_wrong_judge() {
    let (reference, test) = frames(256, Vec2::new(0.3, -0.2));
    let (w, h) = (reference.width, reference.height);
    let gaze = Vec2::new(w as f32 * 0.65, h as f32 * 0.6);
    let (ppd, dpp) = (20.0, 0.3);
    let ecc = eccentricity(w, h, gaze, dpp);
    let cpu = eccentric_flip_map(&reference, &test, ppd, Acuity::default(), &ecc).unwrap();
    let gpu_device = gpu();
    let mut judge = FlipJudge::new(&gpu_device, w, h).unwrap();
    let mut on_gpu = |ppd: f64, ecc: &(dyn Fn(u32, u32) -> Option<f64> + Sync)| {
        judge
            .flip_maps(&reference, &test, ppd, Acuity::default(), ecc)
            .unwrap()
    };
    let right = Agreement::of(&on_gpu(ppd, &ecc).eccentric, &cpu.eccentric);
    assert!(right.holds(), "{right:?}");
    let wrong_ppd = Agreement::of(&on_gpu(ppd * 1.1, &ecc).eccentric, &cpu.eccentric);
    let moved = eccentricity(w, h, gaze + Vec2::new(w as f32 * 0.1, 0.0), dpp);
    let wrong_gaze = Agreement::of(&on_gpu(ppd, &moved).eccentric, &cpu.eccentric);
    let shifted = |x: u32, y: u32| ecc((x + 1).min(w - 1), y);
    let wrong_map = Agreement::of(&on_gpu(ppd, &shifted).eccentric, &cpu.eccentric);
    for (what, a) in [("ppd", wrong_ppd), ("gaze", wrong_gaze), ("map", wrong_map)] {
        eprintln!("{what}: {a:?}");
        assert!(!a.holds(), "a wrong {what} passes: {a:?}");
    }
    assert_validation_clean(&gpu_device);
}

/// A judgement of no pixel (the lens hides them all) is all `NaN`, not whatever the maps held:
/// judged once with every pixel, then with none, on the same judge.
#[test]
fn nothing_judged_is_nan() {
    let image = noise(64, 3);
    let other = noise(64, 4);
    let gpu = gpu();
    let mut judge = FlipJudge::new(&gpu, 64, 64).unwrap();
    let all = judge
        .flip_maps(&image, &other, 20.0, Acuity::default(), &|_, _| Some(1.0))
        .unwrap();
    assert!(all.plain.iter().all(|v| v.is_finite()));
    let none = judge
        .flip_maps(&image, &other, 20.0, Acuity::default(), &|_, _| None)
        .unwrap();
    assert!(none.plain.iter().chain(&none.eccentric).all(|v| v.is_nan()));
    assert_validation_clean(&gpu);
}

/// The live judge judges a renderer's last frame against the reference of its head pose and
/// gaze: a frame of the reference's own configuration, from a head moved off the scene's,
/// judges as no error at all (a reference rendered from the scene's head instead would not), a
/// foveated one as some. It judges the first frame and then every Nth; an interval of 0 is
/// refused by name.
#[test]
fn the_live_judge_judges_the_renderers_last_frame() {
    let gpu = gpu();
    let scene = default_scene();
    let foveated = RenderConfig {
        resolution: Some(Resolution::square(128)),
        foveation: Some(FoveationConfig::single_frame()),
        output: OutputStage::Lens,
        msaa: 1,
        ..RenderConfig::default()
    };
    let head = scene.head * Mat4::from_translation(Vec3::new(0.3, 0.0, -0.5));
    let input = FrameInput::new(head).with_gaze([Vec2::new(0.3, -0.2); 2]);
    let judged = |config: &RenderConfig| {
        let plan = foveate::plan(&scene, config, gpu.caps()).unwrap();
        let mut renderer = Renderer::new(&gpu, &plan, &scene).unwrap();
        renderer.render(&input).unwrap();
        let mut judge = LiveJudge::new(&gpu, &scene, config, 1).unwrap();
        let judgement = judge.judge(&renderer, &input, Maps::Drop).unwrap();
        assert!(judgement.reference_ms > 0.0 && judgement.judge_ms > 0.0);
        assert!(
            judgement.error.maps.is_none(),
            "maps come back only if asked"
        );
        judgement.error.eccentric.unwrap()
    };
    let same = judged(&reference_config(&foveated));
    assert_eq!((same.mean, same.p99), (0.0, 0.0), "{same:?}");
    let foveated_error = judged(&foveated);
    assert!(foveated_error.mean > 0.0, "{foveated_error:?}");
    let mut judge = LiveJudge::new(&gpu, &scene, &foveated, 3).unwrap();
    let due: Vec<bool> = (0..7).map(|_| judge.due()).collect();
    assert_eq!(due, [true, false, false, true, false, false, true]);
    let refused = LiveJudge::new(&gpu, &scene, &foveated, 0).err().unwrap();
    assert!(refused.to_string().contains("judge every"), "{refused}");
    assert_validation_clean(&gpu);
}

/// The histograms the GPU reduces its maps to are those maps counted on the host, bin for bin:
/// the plain FLIP over every visible pixel, the eccentricity-aware FLIP per region (each
/// region non-empty here); the map comes back only when asked for. Mutations: a region's label
/// taken for another's, or the shader's bins shifted by one, each fail.
#[test]
fn the_gpus_histograms_count_the_maps_they_reduce() {
    let gpu = gpu();
    let gaze = Vec2::new(0.3, -0.2);
    let (want, got) = frames(96, gaze);
    let config = RenderConfig {
        resolution: Some(Resolution::square(96)),
        foveation: Some(FoveationConfig::single_frame()),
        ..RenderConfig::default()
    };
    let plan = foveate::plan(&default_scene(), &config, gpu.caps()).unwrap();
    let pixels = EyePixels::new(&plan, Eye::Left, gaze, plan.foveation.as_ref());
    let mut judge = FlipJudge::new(&gpu, 96, 96).unwrap();
    let acuity = Acuity::default();
    let kept = judge
        .flip_errors(&want, &got, &pixels, acuity, true)
        .unwrap();
    let eccentric = kept.map.as_ref().expect("the map was asked for");
    let eccentricity = |x: u32, y: u32| pixels.at(x, y).map(|d| d.eccentricity_deg);
    let maps = judge
        .flip_maps(&want, &got, pixels.ppd, acuity, &eccentricity)
        .unwrap();
    // Bit for bit (the hidden pixels' NaNs too): the same judgement twice.
    let bits = |m: &[f32]| m.iter().map(|v| v.to_bits()).collect::<Vec<_>>();
    assert!(
        bits(&maps.eccentric) == bits(eccentric),
        "the same judgement twice"
    );
    let counted = ErrorHistogram::of(pixels.select(&maps.plain, |_| true));
    assert_eq!(kept.plain, counted, "plain FLIP");
    for (histogram, region) in kept.regions.iter().zip(Region::ALL) {
        let counted = ErrorHistogram::of(pixels.select(eccentric, |d| d.region == region));
        assert!(counted.pixels() > 0, "{}", region.name());
        assert_eq!(*histogram, counted, "{}", region.name());
    }
    let dropped = judge
        .flip_errors(&want, &got, &pixels, acuity, false)
        .unwrap();
    assert!(
        dropped.map.is_none(),
        "the map comes back only when asked for"
    );
    assert_eq!(dropped.regions, kept.regions);
    assert_validation_clean(&gpu);
}

/// Judging two renderers' last frames where they lie on the device (`GpuFlip::frame_errors`:
/// copied and gathered there, never read back) gives the figures of judging their read-back
/// eyes: bin for bin with an sRGB output, within a hair with a half-float one (its sRGB
/// encoding done by the GPU instead of the host). The eyes swapped (each eye's pixels judged
/// against the other's map) do not agree: the comparison can fail. Mutations: the gather not
/// taking hidden pixels from the reference, or reading the left eye for both, each fail.
#[test]
fn judging_outputs_where_they_lie_equals_judging_read_back_frames() {
    let gpu = gpu();
    let scene = default_scene();
    let gaze = Vec2::new(0.3, -0.2);
    let base = RenderConfig {
        resolution: Some(Resolution::square(96)),
        foveation: Some(FoveationConfig::single_frame()),
        ..RenderConfig::default()
    };
    let half_floats = RenderConfig {
        output_format: foveate::plan::OutputFormat::Float16,
        ..base.clone()
    };
    let acuity = Acuity::default();
    for (name, config, exact) in [("sRGB", base, true), ("half floats", half_floats, false)] {
        let render = |config: &RenderConfig| {
            let plan = foveate::plan(&scene, config, gpu.caps()).unwrap();
            let mut renderer = Renderer::new(&gpu, &plan, &scene).unwrap();
            renderer.set_gaze([gaze; 2]).unwrap();
            renderer.render_frame(scene.head).unwrap();
            renderer
        };
        let (mut reference, mut test) = (render(&reference_config(&config)), render(&config));
        let plan = test.plan().clone();
        let pixels = EyePixels::both(&plan, gaze, plan.foveation.as_ref());
        let mut flip = GpuFlip::new(&gpu);
        let in_place = flip
            .frame_errors(&reference, &test, &pixels, acuity, Maps::Drop)
            .unwrap();
        let swapped = [pixels[1].clone(), pixels[0].clone()];
        let off = flip
            .frame_errors(&reference, &test, &swapped, acuity, Maps::Drop)
            .unwrap();
        let (want, got) = (reference.readback().unwrap(), test.readback().unwrap());
        let read_back = perceptual_error(
            want.eyes(),
            got.eyes(),
            &pixels,
            acuity,
            &mut flip,
            Maps::Drop,
        )
        .unwrap();
        let close = |a: Option<ErrorSummary>, b: Option<ErrorSummary>, tolerance: f64| {
            let (a, b) = (a.unwrap(), b.unwrap());
            a.pixels == b.pixels
                && (a.mean - b.mean).abs() <= tolerance
                && (a.p99 - b.p99).abs() <= tolerance
        };
        let tolerance = if exact { 0.0 } else { 1e-3 };
        assert!(
            close(in_place.flip, read_back.flip, tolerance),
            "{name}: {in_place:?}\n{read_back:?}"
        );
        for (a, b) in in_place.regions.iter().zip(&read_back.regions) {
            assert!(
                close(*a, *b, tolerance),
                "{name}: {in_place:?}\n{read_back:?}"
            );
        }
        assert!(
            !close(off.eccentric, read_back.eccentric, 1e-3),
            "{name}: the eyes swapped agree"
        );
    }
    assert_validation_clean(&gpu);
}
