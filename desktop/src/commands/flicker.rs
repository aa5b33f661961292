//! `foveate flicker`: temporal stability (`metrics::temporal`). Each approximation runs frame by
//! frame beside the full-quality reference (stereo, 4× MSAA) through two motions — the gaze
//! jumping along a simulated saccade trace with the head still, and the head walking with the
//! gaze straight ahead — and reports how much more its output changes between frames than the
//! reference's does.

use std::path::PathBuf;

use anyhow::Result;
use clap::Args;
use foveate::foveation::{simulated_trace, FoveationConfig};
use foveate::gpu::{Gpu, GpuOptions};
use foveate::metrics::temporal::{Flicker, FlickerSummary};
use foveate::metrics::{ErrorSummary, EyePixels};
use foveate::plan::RenderConfig;
use foveate::render::Renderer;
use foveate::scene::walking_pose;
use glam::{Mat4, Vec2};

use crate::csv_out::{opt, CsvTable};
use crate::frame_args::ComparedFrame;

#[derive(Args)]
pub struct FlickerArgs {
    /// Screen resolution per eye: N (square), WxH, or `native` (the headset's panel).
    #[arg(long, default_value = "512")]
    res: String,
    /// Scene: default, fill, city, thesis or atrium.
    #[arg(long, default_value = "atrium")]
    scene: String,
    #[command(flatten)]
    frame: ComparedFrame,
    /// Foveation ratios to measure (MSAA 4).
    #[arg(long, value_delimiter = ',', default_value = "0.35,0.5")]
    ratios: Vec<f32>,
    /// Also each ratio with the periphery sharpened at these strengths.
    #[arg(long, value_delimiter = ',')]
    sharpen: Vec<f32>,
    /// Frames of each motion, at 90 Hz.
    #[arg(long, default_value_t = 45)]
    frames: u32,
    /// Seed of the simulated saccade trace.
    #[arg(long, default_value_t = 3)]
    seed: u32,
    /// Also write the table as CSV to this file.
    #[arg(long)]
    csv: Option<PathBuf>,
}

/// Frame rate the motions are sampled at.
const RATE_HZ: f64 = 90.0;

/// One motion: per frame, the head pose and the gaze.
struct Motion {
    name: &'static str,
    frames: Vec<(Mat4, Vec2)>,
}

pub fn flicker(options: &GpuOptions, args: &FlickerArgs) -> Result<()> {
    anyhow::ensure!(
        args.frames >= 2,
        "invalid frames = {}: at least 2 (flicker is a change between frames)",
        args.frames
    );
    let scene = args.frame.scene(&args.scene)?;
    let screen = args.frame.screen(&args.res)?;
    let base = args.frame.base(&args.res)?;
    let mut configs = vec![(
        "stereo, MSAA 1".to_string(),
        RenderConfig {
            msaa: 1,
            ..base.clone()
        },
    )];
    for &ratio in &args.ratios {
        for sharpen in std::iter::once(0.0).chain(args.sharpen.iter().copied()) {
            let name = match sharpen {
                0.0 => format!("foveated {ratio}, MSAA 4"),
                s => format!("foveated {ratio}, sharpen {s}, MSAA 4"),
            };
            let foveation = FoveationConfig {
                ratio,
                blend_band_px: -1.0,
                periphery_sharpen: sharpen,
                ..Default::default()
            };
            foveation.geometry(screen)?;
            let config = RenderConfig {
                views: 4,
                foveation: Some(foveation),
                ..base.clone()
            };
            configs.push((name, config));
        }
    }
    let reference = RenderConfig {
        msaa: 4,
        ..base.clone()
    };
    let seconds = args.frames as f64 / RATE_HZ;
    let trace = simulated_trace(seconds, RATE_HZ, args.seed);
    let motions = [
        Motion {
            name: "saccades",
            frames: trace.iter().map(|s| (scene.head, s.left)).collect(),
        },
        Motion {
            name: "walking",
            frames: (0..args.frames)
                .map(|i| {
                    (
                        walking_pose(scene.head, i as f32 / RATE_HZ as f32),
                        Vec2::ZERO,
                    )
                })
                .collect(),
        },
    ];
    let gpu = Gpu::new(options)?;
    let plans = std::iter::once(&reference)
        .chain(configs.iter().map(|(_, c)| c))
        .map(|c| foveate::plan(&scene, c, gpu.caps()))
        .collect::<Result<Vec<_>, _>>()?;
    println!(
        "device: {}; scene {}, {}, output {}; {} frames at {RATE_HZ} Hz per motion: saccades (seed {}, head still), walking ({} m/s, turning {}°/s, gaze ahead)",
        gpu.info().name,
        args.scene,
        crate::frame_args::headset_line(&plans[0]),
        base.output,
        args.frames,
        args.seed,
        foveate::scene::WALK_SPEED_M_S,
        foveate::scene::TURN_DEG_S
    );
    let bar = crate::progress::bar("flicker", (motions.len() as u32 * args.frames) as u64);
    let mut results = Vec::new();
    for motion in &motions {
        bar.set_message(motion.name);
        let mut renderers = plans
            .iter()
            .map(|p| Renderer::new(&gpu, p, &scene))
            .collect::<Result<Vec<_>, _>>()?;
        let mut meters: Vec<Flicker> = configs.iter().map(|_| Flicker::default()).collect();
        // Each configuration's pixel map, made anew only when the gaze moves.
        let mut maps: Vec<Option<(Vec2, [EyePixels; 2])>> = configs.iter().map(|_| None).collect();
        for &(pose, gaze) in &motion.frames {
            // Frames of every configuration interleaved, the reference first.
            let mut images = Vec::new();
            for renderer in &mut renderers {
                renderer.set_gaze([gaze; 2]);
                renderer.render_frame(pose)?;
                images.push(renderer.readback()?);
            }
            for (i, (meter, map)) in meters.iter_mut().zip(&mut maps).enumerate() {
                let plan = &plans[i + 1];
                if map.as_ref().is_none_or(|(at, _)| *at != gaze) {
                    *map = Some((gaze, EyePixels::both(plan, gaze, plan.foveation.as_ref())));
                }
                let (_, pixels) = map.as_ref().expect("just made");
                meter.push(images[0].eyes(), images[i + 1].eyes(), pixels)?;
            }
            bar.inc(1);
        }
        for ((name, _), meter) in configs.iter().zip(&meters) {
            results.push((motion.name, name.clone(), meter.summary()));
        }
    }
    bar.finish_and_clear();
    print_table(&results);
    gpu.check_validation()?;
    let mut csv = CsvTable::new(&[
        "motion",
        "config",
        "changes",
        "flicker_mean",
        "flicker_p99",
        "flicker_mean_fovea",
        "flicker_mean_band",
        "flicker_mean_periphery",
    ])?;
    for (motion, name, s) in &results {
        let mean = |e: Option<ErrorSummary>| opt(e.map(|e| e.mean), 6);
        csv.row(&[
            motion,
            name,
            &s.changes,
            &mean(s.all),
            &opt(s.all.map(|e| e.p99), 6),
            &mean(s.regions[0]),
            &mean(s.regions[1]),
            &mean(s.regions[2]),
        ])?;
    }
    csv.save(args.csv.as_deref())
}

fn print_table(results: &[(&str, String, FlickerSummary)]) {
    println!(
        "\n{:<10} {:<34} {:>12} {:>10} {:>12} {:>12} {:>12}",
        "motion", "configuration", "mean", "p99", "fovea", "band", "periphery"
    );
    let mean = |e: Option<ErrorSummary>| e.map_or("-".to_string(), |e| format!("{:.5}", e.mean));
    for (motion, name, s) in results {
        println!(
            "{:<10} {:<34} {:>12} {:>10} {:>12} {:>12} {:>12}",
            motion,
            name,
            mean(s.all),
            s.all.map_or("-".to_string(), |e| format!("{:.4}", e.p99)),
            mean(s.regions[0]),
            mean(s.regions[1]),
            mean(s.regions[2]),
        );
    }
    println!(
        "(flicker: per pixel and frame, how much more the output's luma (0..1) changed from the previous frame than the reference's (stereo, MSAA 4) did — max(0, |ΔT| − |ΔR|) — over the pixels the lens shows, both eyes; mean and 99th percentile, then the mean per region at each frame's gaze; metrics::temporal)"
    );
}
