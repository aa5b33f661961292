//! `foveate flicker`: temporal stability (`metrics::temporal`). Each approximation runs frame by
//! frame beside the full-quality reference (stereo, 4× MSAA) through the motions asked for —
//! head and gaze still, the gaze jumping along saccade traces with the head still, the head
//! walking with the gaze at rest (ahead, or `--gaze`) — and reports how much more its output
//! changes between frames than the reference's does.

mod measure;
mod motion;
mod rows;

use std::path::PathBuf;

use anyhow::Result;
use clap::Args;
use foveate::foveation::{FoveationConfig, GazeSpace};
use foveate::gpu::{Gpu, GpuOptions};
use foveate::plan::RenderConfig;
use foveate::scene::Walker;

use crate::commands::motion_frontier::{self, plot_stem, MotionPoint};
use crate::compared_frame::ComparedFrame;
use crate::variants::{with_temporal, with_view_sets, Accumulation};
use measure::{MotionRun, Spent};
use motion::{motions, Motion, MotionKind, RATE_HZ};
use rows::{print_table, write_csv, Row};

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
    /// Foveation ratios to measure (the fovea at `--fovea-msaa`).
    #[arg(long, value_delimiter = ',', default_value = "0.35,0.5")]
    ratios: Vec<f32>,
    /// Each foveated row once per sample count of its fovea views (the frame's MSAA), 1 or 4.
    /// An accumulated periphery stays at its own (1×), a single-frame one follows the fovea's.
    #[arg(long, value_delimiter = ',', default_value = "4")]
    fovea_msaa: Vec<u32>,
    /// Also each ratio with the periphery sharpened at these strengths.
    #[arg(long, value_delimiter = ',')]
    sharpen: Vec<f32>,
    /// Also each foveated row with the periphery at these densities (fractions of the screen's
    /// pixels per side, independent of the fovea's ratio), one row each.
    #[arg(long, value_delimiter = ',')]
    densities: Vec<f32>,
    /// Also each plain foveated row (every density) with its periphery accumulated over frames
    /// (1x, jittered; the fovea at `--fovea-msaa`). Its history first settles on the motion's
    /// first frame (two jitter cycles, not measured).
    #[arg(long)]
    temporal: bool,
    #[command(flatten)]
    accumulation: Accumulation,
    /// Also judge frames against the reference's frame in eccentricity-aware FLIP at that
    /// frame's gaze: every frame, or with a number N every Nth (FLIP is slow at a headset's
    /// native resolution). Per motion: the mean over the judged frames of the mean and of the
    /// 99th percentile, and the worst frame's.
    #[arg(long, num_args = 0..=1, default_missing_value = "1", value_name = "EVERY")]
    flip: Option<u32>,
    /// Frames of each motion, at 90 Hz.
    #[arg(long, default_value_t = 45)]
    frames: u32,
    /// Seed of the simulated saccade traces.
    #[arg(long, default_value_t = 3)]
    seed: u32,
    /// Gaze of both eyes where it rests (`still`, `walking`), normalised X,Y in -1..1. The
    /// saccade traces start at the centre and move on their own.
    #[arg(
        long,
        value_delimiter = ',',
        allow_hyphen_values = true,
        default_value = "0,0"
    )]
    gaze: Vec<f32>,
    /// The motions, in order: `still` (head and gaze still: the jitter's shimmer alone),
    /// `saccades` (a simulated trace, head still), `large-saccades` (15–30° each, head still),
    /// `walking` (gaze at rest, `--gaze`).
    #[arg(
        long,
        value_delimiter = ',',
        default_value = "still,saccades,large-saccades,walking"
    )]
    motions: Vec<MotionKind>,
    /// A walker crosses the view in every motion (a person-sized box 4 m ahead, 1.4 m/s), so
    /// accumulation meets a surface moving on its own: ghosting and what it uncovers.
    #[arg(long)]
    walker: bool,
    /// Also count, every frame, what became of each accumulated pixel's history (kept,
    /// clipped, taken from the fovea, or dropped: reset, off-screen, disoccluded, empty), per
    /// region: the accumulated rows run as counting frames. With a file, every frame's counts
    /// are written to it as CSV.
    #[arg(long, num_args = 0..=1, value_name = "CSV")]
    history_outcomes: Option<Option<PathBuf>>,
    /// Also plot each motion's eFLIP p99 against frame time (× the reference's), stereo and
    /// foveated points marked and the Pareto frontier joined, to `<STEM>-<motion>.png` and
    /// `.svg`, and print the points. Needs `--flip`. A configuration's time is the median of
    /// its frames along the motion (every configuration's frames interleaved, as `compare`
    /// times them); rows counting `--history-outcomes` are not timed.
    #[arg(long, value_name = "STEM")]
    pareto: Option<PathBuf>,
    /// Also write the table as CSV to this file.
    #[arg(long)]
    csv: Option<PathBuf>,
}

pub fn flicker(options: &GpuOptions, args: &FlickerArgs) -> Result<()> {
    crate::interrupt::install();
    let history_csv = check_args(args)?;
    let gaze = crate::gaze_arg::gaze_from(&args.gaze)?;
    let mut scene = args.frame.scene(&args.scene)?;
    let walker = args.walker.then(|| Walker::add(&mut scene, 4.0));
    let screen = args.frame.screen(&args.res)?;
    let base = args.frame.base(&args.res)?;
    let base = RenderConfig {
        moving_instances: args.walker,
        ..base
    };
    let configs = flicker_configs(args, &base, screen)?;
    let reference = RenderConfig {
        msaa: 4,
        ..base.clone()
    };
    let gpu = Gpu::new(options)?;
    // With --history-outcomes the accumulated rows count (their frames show the same image).
    let accumulates =
        |c: &RenderConfig| (c.foveation.as_ref()).is_some_and(|f| f.periphery_temporal.is_some());
    let plans = std::iter::once(&reference)
        .chain(configs.iter().map(|(_, c)| c))
        .map(
            |c| match args.history_outcomes.is_some() && accumulates(c) {
                true => foveate::plan(&scene, &c.counting(), gpu.caps()),
                false => foveate::plan(&scene, c, gpu.caps()),
            },
        )
        .collect::<Result<Vec<_>, _>>()?;
    let space = GazeSpace {
        fov: plans[0].eyes.fov(foveate::view::Eye::Left),
    };
    let motions = motions(args, gaze, &scene, space);
    println!(
        "device: {}; scene {}{}, {}, output {}; {} frames at {RATE_HZ} Hz per motion: {}",
        gpu.info().name,
        args.scene,
        if args.walker {
            " with a walker crossing 4 m ahead"
        } else {
            ""
        },
        crate::frame_args::headset_line(&plans[0]),
        base.output,
        args.frames,
        motions
            .iter()
            .map(|m| m.describe(args))
            .collect::<Vec<_>>()
            .join(", ")
    );
    let bar = crate::progress::bar("flicker", (motions.len() as u32 * args.frames) as u64);
    let spent = Spent::default();
    let mut results = Vec::new();
    // Ctrl-C or SIGTERM, or a motion that fails (a lost device): the motions finished so far
    // are printed and written, then the run ends saying why.
    let mut interrupted = false;
    let mut failed = None;
    for motion in &motions {
        let measured = MotionRun {
            gpu: &gpu,
            scene: &scene,
            plans: &plans,
            configs: &configs,
            walker,
            flip: args.flip,
            bar: &bar,
            spent: &spent,
        }
        .measure(motion);
        match measured {
            Ok(Some(rows)) => results.extend(rows),
            Ok(None) => {
                interrupted = true;
                break;
            }
            Err(e) => {
                failed = Some(e.context(format!("flicker's {} motion failed", motion.name())));
                break;
            }
        }
    }
    bar.finish_and_clear();
    print_table(&results);
    if let Some(stem) = &args.pareto {
        report_frontiers(stem, &motions, &results, &plans[0])?;
    }
    let outcomes: Vec<_> = results
        .iter_mut()
        .filter_map(|r| r.history.take())
        .collect();
    crate::history_table::print(&outcomes);
    println!("{}", spent.describe());
    if failed.is_none() {
        gpu.check_validation()?;
    }
    write_csv(&results, args.csv.as_deref())?;
    if let Some(path) = &history_csv {
        crate::history_table::write_csv(&outcomes, path)?;
    }
    let finished = format!(
        "the {} motions finished before it are in the table above{}",
        results.len() / configs.len().max(1),
        if args.csv.is_some() {
            " and the CSV"
        } else {
            ""
        }
    );
    if let Some(e) = failed {
        return Err(e.context(format!("flicker stopped: {finished}")));
    }
    if interrupted {
        return Err(crate::interrupt::stopped(&format!(
            "flicker stopped during a motion; {finished}"
        )));
    }
    Ok(())
}

/// The arguments checked, and every output path writable, before any work: the history
/// outcomes' CSV path, if asked for.
fn check_args(args: &FlickerArgs) -> Result<Option<PathBuf>> {
    let history_csv = args.history_outcomes.clone().flatten();
    crate::outputs::files(&[args.csv.as_deref(), history_csv.as_deref()])?;
    anyhow::ensure!(
        args.frames >= 2,
        "invalid frames = {}: at least 2 (flicker is a change between frames)",
        args.frames
    );
    if let Some(m) = args.fovea_msaa.iter().find(|m| !matches!(m, 1 | 4)) {
        anyhow::bail!("invalid fovea-msaa = {m}: each sample count 1 or 4");
    }
    anyhow::ensure!(
        args.flip != Some(0),
        "invalid flip = 0: judge every Nth frame, N ≥ 1 (leave it out for none)"
    );
    anyhow::ensure!(
        args.pareto.is_none() || args.flip.is_some(),
        "invalid pareto without flip: the frontier is eFLIP p99 against time, so --pareto needs --flip [N]"
    );
    if let Some(stem) = &args.pareto {
        for motion in &args.motions {
            crate::outputs::plot(&plot_stem(stem, motion.name()))?;
        }
    }
    Ok(history_csv)
}

/// Each motion's frontier (`--pareto`): its judged rows against their times, printed and
/// plotted to `stem`'s file for the motion.
fn report_frontiers(
    stem: &std::path::Path,
    motions: &[Motion],
    results: &[Row],
    plan: &foveate::plan::FramePlan,
) -> Result<()> {
    let headset = format!("{}, {}/eye", plan.hmd.display_name, plan.eye_resolution);
    for motion in motions {
        let points: Vec<MotionPoint> = (results.iter())
            .filter(|r| r.motion == motion.name())
            .filter_map(|r| r.point())
            .collect();
        // A motion an interruption cut short has no points: no empty plot.
        if points.is_empty() {
            continue;
        }
        motion_frontier::report(motion.name(), &points, &headset, stem)?;
    }
    Ok(())
}

/// The rows compared: aliased stereo, then every foveated variant the arguments ask for (each
/// checked against the screen), at 4× MSAA.
fn flicker_configs(
    args: &FlickerArgs,
    base: &RenderConfig,
    screen: foveate::plan::Resolution,
) -> Result<Vec<(String, RenderConfig)>> {
    let mut variants = Vec::new();
    for &ratio in &args.ratios {
        for sharpen in std::iter::once(0.0).chain(args.sharpen.iter().copied()) {
            let name = match sharpen {
                0.0 => format!("foveated {ratio}"),
                s => format!("foveated {ratio}, sharpen {s}"),
            };
            let foveation = FoveationConfig {
                ratio,
                periphery_sharpen: sharpen,
                ..FoveationConfig::single_frame()
            };
            variants.push((name, foveation));
        }
    }
    variants = with_view_sets(variants, &args.densities, &[]);
    if args.temporal {
        variants = with_temporal(variants, &args.accumulation)?;
    }
    let mut configs = vec![(
        "stereo, MSAA 1".to_string(),
        RenderConfig {
            msaa: 1,
            ..base.clone()
        },
    )];
    for (name, foveation) in variants {
        foveation.geometry(screen)?;
        for &msaa in &args.fovea_msaa {
            let config = RenderConfig {
                msaa,
                foveation: Some(foveation),
                ..base.clone()
            };
            configs.push((format!("{name}, MSAA {msaa}"), config));
        }
    }
    let rows = configs.into_iter().map(|(n, c)| (n, (), c)).collect();
    let twinned = crate::variants::with_twins(rows, args.frame.prefilter, &args.frame.rings);
    Ok(twinned.into_iter().map(|(n, (), c)| (n, c)).collect())
}
