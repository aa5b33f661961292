//! Where in the field a foveated frame's error lies: the eccentricity-aware FLIP's 99th
//! percentile in rings of eccentricity around the gaze (both eyes, the pixels the lens shows),
//! for aliased stereo and a foveated frame at each periphery density asked for, each against the
//! full-quality reference (stereo at 4× MSAA), judged on the GPU. The judge's own regions are
//! the fovea, its blend band and the periphery; a periphery whose density falls with
//! eccentricity needs to know how the error is spread across it.
//!
//! ```text
//! cargo run --release -p foveate --example eflip_by_eccentricity -- [--scene NAME] \
//!     [--hmd NAME] [--res N] [--ratio R] [--gaze X,Y] [DENSITY[:accumulated] ...]
//! ```
//!
//! By default the lit atrium at the Quest Pro's panel, the fovea at 0.35 with 4× MSAA, the gaze
//! ahead, and the periphery at 0.35 and 0.85 in one frame and at 0.6 accumulated.

use foveate::foveation::{FoveationConfig, TemporalConfig};
use foveate::glam::Vec2;
use foveate::gpu::{Gpu, GpuOptions};
use foveate::judge::FlipJudge;
use foveate::metrics::{Acuity, ErrorSummary, EyePixels};
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
    };
    let mut args = std::env::args().skip(1);
    while let Some(arg) = args.next() {
        match arg.as_str() {
            "--scene" => o.scene = args.next().ok_or("--scene needs a name")?,
            "--hmd" => o.hmd = args.next().ok_or("--hmd needs a name")?,
            "--res" => o.resolution = Some(Resolution::square(number("--res", args.next())?)),
            "--ratio" => o.ratio = number("--ratio", args.next())?,
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

fn main() -> Result<(), Error> {
    let o = options()?;
    let gpu = Gpu::new(&GpuOptions::default())?;
    let scene = named_scene(&o.scene)?;
    let reference = RenderConfig {
        hmd: o.hmd.clone(),
        resolution: o.resolution,
        msaa: 4,
        output: OutputStage::Lens,
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
    for &(density, accumulated) in &o.rows {
        let how = if accumulated {
            "accumulated"
        } else {
            "one frame"
        };
        let name = format!("periphery {density}, {how}");
        rows.push((name, foveated(density, accumulated)));
    }
    let want = frame(&gpu, &scene, &reference, o.gaze)?;
    // Every row's rings are where the first foveated row puts the fovea (as `foveate compare`
    // places aliased stereo's regions): the same pixels in every row.
    let plan = foveate::plan(&scene, &rows[1].1, gpu.caps())?;
    let eyes = EyePixels::both(&plan, o.gaze, plan.foveation.as_ref());
    let mut judge = FlipJudge::new(&gpu, plan.eye_resolution.width, plan.eye_resolution.height)?;
    print!("{:<34}", "eFLIP p99 by eccentricity");
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
        print!("{name:<34}");
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
