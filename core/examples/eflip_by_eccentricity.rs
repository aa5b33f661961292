//! Where in the field a foveated frame's error lies: the eccentricity-aware FLIP's 99th
//! percentile in rings of eccentricity around the gaze (both eyes, the pixels the lens shows),
//! for aliased stereo and a foveated frame at each periphery density asked for, each against the
//! full-quality reference (stereo at 4× MSAA), judged on the GPU. The judge's own regions are
//! the fovea, its blend band and the periphery; a periphery whose density falls with
//! eccentricity needs to know how the error is spread across it.
//!
//! ```text
//! cargo run --release -p foveate --example eflip_by_eccentricity -- [--scene NAME] \
//!     [--hmd NAME] [--res N] [--ratio R] [--gaze X,Y] [--prefilter] [--ring R] [--supersampled] \
//!     [DENSITY[:accumulated] ...]
//! ```
//!
//! By default the lit atrium at the Quest Pro's panel, the fovea at 0.35 with 4× MSAA, the gaze
//! ahead, and the periphery at 0.35 and 0.85 in one frame and at 0.6 accumulated.
//!
//! `--prefilter` measures every one-frame row beside its twin with the periphery's highlights
//! prefiltered (`FoveationConfig::periphery_prefilter`), `--ring R` beside its twin with a
//! parafoveal ring R of the field wide (`FoveationConfig::ring_ratio`). The usual reference shades each pixel
//! once, so `--supersampled` judges every row, the usual reference among them, against a truth
//! shaded 4 times as densely instead: the reference rendered at twice the
//! resolution per axis, its 2×2 pixels averaged in linear light; every row then undistorted
//! (the lens's resampling of an image twice the size is not the same resampling).

use foveate::foveation::{FoveationConfig, TemporalConfig};
use foveate::glam::Vec2;
use foveate::gpu::{Gpu, GpuOptions};
use foveate::judge::FlipJudge;
use foveate::metrics::{Acuity, ErrorSummary, EyePixels, RgbaImage};
use foveate::plan::{OutputStage, RenderConfig, Resolution};
use foveate::render::{FrameInput, Renderer, StereoImage};
use foveate::scene::{named_scene, Scene};
use foveate::view::Eye;

type Error = Box<dyn std::error::Error>;

/// The rings, degrees from the gaze.
const RINGS: [(f64, f64); 6] = [
    (0.0, 5.0),
    (5.0, 10.0),
    (10.0, 15.0),
    (15.0, 20.0),
    (20.0, 30.0),
    (30.0, f64::INFINITY),
];

struct Options {
    scene: String,
    hmd: String,
    resolution: Option<Resolution>,
    ratio: f32,
    gaze: Vec2,
    rows: Vec<(f32, bool)>,
    prefilter: bool,
    ring: Option<f32>,
    supersampled: bool,
}

fn number<T: std::str::FromStr>(flag: &str, value: Option<String>) -> Result<T, Error> {
    let value = value.ok_or_else(|| format!("{flag} needs a value"))?;
    value
        .parse()
        .map_err(|_| format!("{flag}: `{value}` is not a number").into())
}

fn options() -> Result<Options, Error> {
    let mut o = Options {
        scene: "atrium".into(),
        hmd: "quest-pro".into(),
        resolution: None,
        ratio: 0.35,
        gaze: Vec2::ZERO,
        rows: Vec::new(),
        prefilter: false,
        ring: None,
        supersampled: false,
    };
    let mut args = std::env::args().skip(1);
    while let Some(arg) = args.next() {
        match arg.as_str() {
            "--scene" => o.scene = args.next().ok_or("--scene needs a name")?,
            "--hmd" => o.hmd = args.next().ok_or("--hmd needs a name")?,
            "--res" => o.resolution = Some(Resolution::square(number("--res", args.next())?)),
            "--ratio" => o.ratio = number("--ratio", args.next())?,
            "--prefilter" => o.prefilter = true,
            "--ring" => o.ring = Some(number("--ring", args.next())?),
            "--supersampled" => o.supersampled = true,
            "--gaze" => {
                let value = args.next().ok_or("--gaze needs X,Y")?;
                let (x, y) = value
                    .split_once(',')
                    .ok_or_else(|| format!("--gaze: `{value}` is not X,Y"))?;
                o.gaze = Vec2::new(
                    number("--gaze", Some(x.into()))?,
                    number("--gaze", Some(y.into()))?,
                );
            }
            row => {
                let (density, accumulated) = match row.split_once(':') {
                    Some((d, "accumulated")) => (d, true),
                    Some(_) => {
                        return Err(
                            format!("`{row}`: a row is DENSITY or DENSITY:accumulated").into()
                        )
                    }
                    None => (row, false),
                };
                o.rows
                    .push((number("density", Some(density.into()))?, accumulated));
            }
        }
    }
    if o.rows.is_empty() {
        o.rows = vec![(0.35, false), (0.85, false), (0.6, true)];
    }
    Ok(o)
}

/// One still frame of `config` (an accumulated periphery settled over two jitter cycles first).
fn frame(
    gpu: &Gpu,
    scene: &Scene,
    config: &RenderConfig,
    gaze: Vec2,
) -> Result<StereoImage, Error> {
    let plan = foveate::plan(scene, config, gpu.caps())?;
    let mut renderer = Renderer::new(gpu, &plan, scene)?;
    let temporal = config.foveation.as_ref().and_then(|f| f.periphery_temporal);
    let frames = 1 + temporal.map_or(0, |t| 2 * t.jitter_cycle);
    for _ in 0..frames {
        renderer.render(&FrameInput::new(scene.head).with_gaze([gaze; 2]))?;
    }
    Ok(renderer.readback()?)
}

/// `image` at half its size per axis, each pixel the mean of its 2×2 in linear light (sRGB
/// bytes in and out).
fn half_size(image: &RgbaImage) -> RgbaImage {
    let linear = |c: u8| {
        let c = c as f64 / 255.0;
        if c <= 0.04045 {
            c / 12.92
        } else {
            ((c + 0.055) / 1.055).powf(2.4)
        }
    };
    let srgb = |l: f64| {
        let c = if l <= 0.0031308 {
            l * 12.92
        } else {
            1.055 * l.powf(1.0 / 2.4) - 0.055
        };
        (c.clamp(0.0, 1.0) * 255.0).round() as u8
    };
    let mut half = RgbaImage::new(image.width / 2, image.height / 2);
    for y in 0..half.height {
        for x in 0..half.width {
            for c in 0..4 {
                let at = |dx, dy| {
                    let i = ((2 * y + dy) * image.width + 2 * x + dx) as usize * 4 + c;
                    image.data[i]
                };
                let texels = [at(0, 0), at(1, 0), at(0, 1), at(1, 1)];
                let out = (y * half.width + x) as usize * 4 + c;
                half.data[out] = match c {
                    3 => (texels.iter().map(|&a| a as u32).sum::<u32>() / 4) as u8,
                    _ => srgb(texels.iter().map(|&t| linear(t)).sum::<f64>() / 4.0),
                };
            }
        }
    }
    half
}

/// The truth rows are judged against: the reference itself, or (`supersampled`) the reference
/// at twice the resolution per axis, averaged down.
fn truth(
    gpu: &Gpu,
    scene: &Scene,
    reference: &RenderConfig,
    o: &Options,
) -> Result<StereoImage, Error> {
    if !o.supersampled {
        return frame(gpu, scene, reference, o.gaze);
    }
    let eye = foveate::plan(scene, reference, gpu.caps())?.eye_resolution;
    let dense = RenderConfig {
        resolution: Some(Resolution {
            width: 2 * eye.width,
            height: 2 * eye.height,
        }),
        ..reference.clone()
    };
    let image = frame(gpu, scene, &dense, o.gaze)?;
    Ok(StereoImage {
        left: half_size(&image.left),
        right: half_size(&image.right),
    })
}

/// `rows`, each one-frame row followed by its prefiltered twin (`--prefilter`) and its twin
/// with a parafoveal ring (`--ring`).
fn twins(rows: Vec<(String, RenderConfig)>, o: &Options) -> Vec<(String, RenderConfig)> {
    let mut twinned = Vec::new();
    for (name, config) in rows {
        let single = config.foveation.filter(|f| f.periphery_temporal.is_none());
        let twin = |suffix: String, foveation| {
            let config = RenderConfig {
                foveation: Some(foveation),
                ..config.clone()
            };
            (format!("{name}, {suffix}"), config)
        };
        let prefiltered = single.filter(|_| o.prefilter).map(|f| {
            let foveation = FoveationConfig {
                periphery_prefilter: true,
                ..f
            };
            twin("prefiltered".into(), foveation)
        });
        let ringed = single.zip(o.ring).map(|(f, ring)| {
            let foveation = FoveationConfig {
                ring_ratio: Some(ring),
                ..f
            };
            twin(format!("ring {ring}"), foveation)
        });
        twinned.push((name.clone(), config.clone()));
        twinned.extend(prefiltered.into_iter().chain(ringed));
    }
    twinned
}

fn main() -> Result<(), Error> {
    let o = options()?;
    let gpu = Gpu::new(&GpuOptions::default())?;
    let scene = named_scene(&o.scene)?;
    let reference = RenderConfig {
        hmd: o.hmd.clone(),
        resolution: o.resolution,
        msaa: 4,
        // The lens resamples the rendered image; averaging a resampled image of twice the size
        // is not the same resampling, so a supersampled truth is judged undistorted.
        output: match o.supersampled {
            true => OutputStage::Undistorted,
            false => OutputStage::Lens,
        },
        ..RenderConfig::default()
    };
    let foveated = |density: f32, accumulated: bool| RenderConfig {
        foveation: Some(FoveationConfig {
            ratio: o.ratio,
            periphery_density: Some(density),
            periphery_temporal: accumulated.then(TemporalConfig::default),
            ..FoveationConfig::single_frame()
        }),
        ..reference.clone()
    };
    let mut rows = vec![(
        "stereo, MSAA 1 (aliased)".to_string(),
        RenderConfig {
            msaa: 1,
            ..reference.clone()
        },
    )];
    if o.supersampled {
        rows.push(("stereo, MSAA 4 (the reference)".into(), reference.clone()));
    }
    for &(density, accumulated) in &o.rows {
        let how = if accumulated {
            "accumulated"
        } else {
            "one frame"
        };
        let name = format!("periphery {density}, {how}");
        rows.push((name, foveated(density, accumulated)));
    }
    let rows = twins(rows, &o);
    let want = truth(&gpu, &scene, &reference, &o)?;
    // Every row's rings are where the last row (foveated) puts the fovea (as `foveate compare`
    // places aliased stereo's regions): the same pixels in every row.
    let last = &rows.last().expect("a foveated row").1;
    let plan = foveate::plan(&scene, last, gpu.caps())?;
    let eyes = EyePixels::both(&plan, o.gaze, plan.foveation.as_ref());
    let mut judge = FlipJudge::new(&gpu, plan.eye_resolution.width, plan.eye_resolution.height)?;
    let truth = match o.supersampled {
        true => "shaded 4x as densely (every row undistorted)",
        false => "stereo, MSAA 4",
    };
    println!("against {truth}:");
    print!("{:<46}", "eFLIP p99 by eccentricity");
    for (a, b) in RINGS {
        print!(
            " {:>9}",
            if b.is_finite() {
                format!("{a}–{b}°")
            } else {
                format!("{a}°+")
            }
        );
    }
    println!(" {:>9}", "all");
    for (name, config) in &rows {
        let got = frame(&gpu, &scene, config, o.gaze)?;
        let mut rings = vec![Vec::new(); RINGS.len()];
        let mut all = Vec::new();
        for eye in Eye::BOTH {
            let pixels = &eyes[eye.index()];
            let eccentricity = |x, y| pixels.at(x, y).map(|p| p.eccentricity_deg);
            let maps = judge.flip_maps(
                want.eye(eye),
                got.eye(eye),
                pixels.ppd,
                Acuity::default(),
                &eccentricity,
            )?;
            for (ring, (a, b)) in rings.iter_mut().zip(RINGS) {
                ring.extend(
                    pixels.select(&maps.eccentric, |p| (a..b).contains(&p.eccentricity_deg)),
                );
            }
            all.extend(pixels.select(&maps.eccentric, |_| true));
        }
        print!("{name:<46}");
        for ring in rings.iter().chain([&all]) {
            match ErrorSummary::of(ring) {
                Some(s) => print!(" {:>9.4}", s.p99),
                None => print!(" {:>9}", "–"),
            }
        }
        println!();
    }
    gpu.check_validation()?;
    Ok(())
}
