//! `foveate compare --gaze-latency`: what the eye tracker's latency costs. The eye moves along a
//! trace (the eye-movement model, or a recorded CSV); each foveated configuration renders every
//! displayed frame with its fovea where the tracker reported the gaze `latency` earlier
//! (optionally predicted), and is judged in eccentricity-aware FLIP at the frame's *true* gaze.
//! Per latency and prediction: the worst frame after each saccade, how long the error stays above
//! the budget, and the smallest fovea ratio that stays within it — with what that ratio costs.

mod judge;
mod outputs;
mod trace;
mod windows;

use std::path::PathBuf;

use anyhow::{Context, Result};
use clap::Args;
use foveate::foveation::{GazeSpace, Prediction};
use foveate::gpu::Gpu;
use foveate::metrics::perceptual::{perceptual_error, Maps};
use foveate::metrics::Acuity;
use foveate::metrics::EyePixels;
use foveate::plan::{FramePlan, RenderConfig};
use foveate::render::StereoImage;
use foveate::scene::Scene;
use foveate::view::Eye;
use glam::Vec2;

use crate::side_by_side::{measure_group, Group};
use judge::judge_foveated;
use outputs::SweepOutputs;
use trace::{
    checked_tracker_hz, gaze_source, judged_span, sequences, shown_per_tracking, trackings,
};
use windows::{print_table, worst_after_landing, Summary, Windows};

/// The latency sweep's own settings (the rest are `compare`'s).
#[derive(Args, Clone)]
pub struct LatencyArgs {
    /// Eye-tracker latencies to sweep (ms, each 0 to 1000): the fovea placed at the gaze the
    /// tracker reported this long before the frame is displayed. Makes `compare` a latency
    /// sweep along a gaze trace; `--recommend` is then the eFLIP budget every frame after a
    /// saccade must meet.
    #[arg(
        long,
        value_delimiter = ',',
        value_name = "MS",
        allow_hyphen_values = true
    )]
    pub gaze_latency: Vec<f64>,
    /// Predictions to sweep at each latency above 0 beside none (always measured): linear,
    /// saccade-landing.
    #[arg(long, value_delimiter = ',', default_value = "none")]
    pub gaze_predict: Vec<Prediction>,
    /// A recorded gaze trace (CSV: time,left_x,left_y,right_x,right_y,valid) in place of the
    /// eye-movement model's.
    #[arg(long)]
    pub gaze_trace: Option<PathBuf>,
    /// Each ratio as single frames (the periphery at the fovea's ratio, nothing kept between
    /// frames) rather than the library's default foveation (the periphery accumulated over
    /// frames, which the sweep renders in order, every display frame).
    #[arg(long)]
    pub single_frame: bool,
    /// Seed of the eye-movement model's trace.
    #[arg(long, default_value_t = 1)]
    pub seed: u32,
    /// Seconds of the trace displayed (at the headset's refresh rate).
    #[arg(long, default_value_t = 1.5)]
    pub trace_s: f64,
    /// The tracker's sample rate (Hz; default the headset's, else 120).
    #[arg(long)]
    pub tracker_hz: Option<f64>,
    /// How long after each saccade lands its frames are judged (ms).
    #[arg(long, default_value_t = 150.0)]
    pub after_ms: f64,
    /// Saccadic suppression's window after landing (ms), reported apart, never discounted.
    #[arg(long, default_value_t = 50.0)]
    pub suppression_ms: f64,
    /// Also write every judged frame (time, true and displayed gaze, eFLIP p99, mean and p99 per
    /// region) as CSV here.
    #[arg(long)]
    pub frames_csv: Option<PathBuf>,
    /// Also plot each configuration's eFLIP p99 against time since landing, every tracking a
    /// colour, as PATH-<configuration>.png and .svg.
    #[arg(long, value_name = "PATH")]
    pub latency_plot: Option<PathBuf>,
}

/// What the sweep needs from `compare`'s arguments.
pub struct Sweep<'a> {
    pub scene: &'a Scene,
    pub scene_name: &'a str,
    pub base: &'a RenderConfig,
    /// Foveated configurations: name, fovea ratio, config.
    pub foveated: Vec<(String, f32, RenderConfig)>,
    pub budget: Option<f64>,
    pub acuity: Acuity,
    pub timing_rounds: u32,
    pub csv: Option<PathBuf>,
    pub hmd_refresh_hz: f32,
    pub hmd_tracker_hz: Option<f32>,
}

/// One latency and prediction.
#[derive(Clone, Copy)]
struct Tracking {
    latency_ms: f64,
    prediction: Prediction,
}

/// A display frame judged: its time, the saccade it follows and the eye's true gaze.
struct Frame {
    t: f64,
    saccade: usize,
    truth: Vec2,
}

/// One judged frame's eFLIP at the true gaze: the 99th percentile, the mean, and the p99 per
/// region (where the fovea was placed).
#[derive(Clone, Copy)]
struct FrameError {
    p99: f64,
    mean: f64,
    regions: [Option<f64>; 3],
}

const UNJUDGED: FrameError = FrameError {
    p99: f64::NAN,
    mean: f64::NAN,
    regions: [None; 3],
};

pub fn latency_sweep(gpu: &Gpu, args: &LatencyArgs, sweep: &Sweep) -> Result<()> {
    let trackings = trackings(args)?;
    let tracker_hz = checked_tracker_hz(args, sweep)?;
    let display_hz = sweep.hmd_refresh_hz as f64;
    let (configs, plans) = sweep_configs(gpu, sweep)?;
    let space = GazeSpace {
        fov: plans[0].eyes.fov(Eye::Left),
    };
    // Display frames start once the longest latency has a history behind it.
    let lead = 0.2 + trackings.iter().map(|k| k.latency_ms).fold(0.0, f64::max) / 1000.0;
    let (trace, tracker, source) = gaze_source(args, space, lead, tracker_hz)?;
    let (saccades, frames) = judged_span(args, &trace, space, lead, display_hz)?;
    // Each tracking's displayed gaze per judged frame.
    let shown = shown_per_tracking(&tracker, &trackings, &frames, space)?;
    let amplitudes: Vec<String> = saccades
        .iter()
        .map(|s| format!("{:.1}°", s.amplitude_deg))
        .collect();
    println!(
        "device: {}; scene {}, {}; {source}; display at {display_hz} Hz; {} saccades ({}), {} frames judged from each onset to {} ms after landing; eFLIP at each frame's true gaze",
        gpu.info().name,
        sweep.scene_name,
        crate::frame_args::headset_line(&plans[0]),
        saccades.len(),
        amplitudes.join(", "),
        frames.len(),
        args.after_ms
    );
    let group = Group {
        scene: sweep.scene,
        configs: &configs,
        gaze: Vec2::ZERO,
        rounds: sweep.timing_rounds,
        label: "latency: timing",
    };
    let measured = measure_group(gpu, &group)?;
    let times: Vec<f64> = measured
        .iter()
        .map(|m| m.frame_ms / measured[0].frame_ms)
        .collect();
    let reference = measured[0].image.clone();
    let flip = std::cell::RefCell::new(crate::metric::flip_mapper(gpu));
    let judge = |image: &StereoImage, plan: &FramePlan, truth: Vec2, fovea: Vec2| {
        let pixels =
            Eye::BOTH.map(|e| EyePixels::seen(&plans[0], e, truth, fovea, plan.foveation.as_ref()));
        let mut flip = flip.borrow_mut();
        frame_error(perceptual_error(
            reference.eyes(),
            image.eyes(),
            &pixels,
            sweep.acuity,
            &mut **flip,
            Maps::Drop,
        )?)
    };
    // Aliased stereo at every frame's true gaze: the row foveation is held to.
    let bar = crate::progress::bar("latency: FLIP", frames.len() as u64);
    let mut stereo = Vec::new();
    for f in &frames {
        stereo.push(judge(&measured[1].image, &plans[1], f.truth, f.truth)?);
        bar.inc(1);
    }
    bar.finish_and_clear();
    let budget = sweep
        .budget
        .unwrap_or(worst_after_landing(&stereo, &frames, &saccades));
    // A history needs its frames in order: every display frame a tracking showed, from a
    // warm-up before the first judged one to the last.
    let sequences = sequences(
        &trace, &tracker, &trackings, &frames, lead, display_hz, space,
    )?;
    let judged = judge_foveated(gpu, sweep, &plans, &shown, &frames, &sequences, &judge)?;
    gpu.check_validation()?;
    let windows = Windows {
        frames: &frames,
        saccades: &saccades,
        budget,
        suppression_s: args.suppression_ms / 1000.0,
        frame_s: 1.0 / display_hz,
    };
    let stereo_row = windows.summary(&stereo);
    // Per configuration, per tracking.
    let summaries: Vec<Vec<Summary>> = judged
        .iter()
        .map(|rows| rows.iter().map(|j| windows.summary(j)).collect())
        .collect();
    println!(
        "reference: stereo, MSAA 4, {:.2} ms; budget: eFLIP p99 ≤ {budget:.4} on every frame after landing ({})",
        measured[0].frame_ms,
        match sweep.budget {
            Some(_) => "--recommend".to_string(),
            None => format!(
                "stereo MSAA 1's worst, {:.3}x the reference's time",
                times[1]
            ),
        }
    );
    print_table(&trackings, sweep, &summaries, &windows, &times, stereo_row);
    let outputs = SweepOutputs {
        trackings: &trackings,
        sweep,
        frames: &frames,
        saccades: &saccades,
        shown: &shown,
        judged: &judged,
        summaries: &summaries,
        times: &times,
        budget,
    };
    outputs.summary_csv()?;
    if let Some(stem) = &args.latency_plot {
        outputs.plots(stem)?;
    }
    if let Some(path) = &args.frames_csv {
        outputs.frames_csv(path)?;
    }
    Ok(())
}

/// The configurations a sweep times — the reference (stereo, 4×), aliased stereo, then the
/// foveated ones — and their plans.
fn sweep_configs(gpu: &Gpu, sweep: &Sweep) -> Result<(Vec<RenderConfig>, Vec<FramePlan>)> {
    let stereo = |msaa| RenderConfig {
        msaa,
        ..sweep.base.clone()
    };
    let mut configs = vec![stereo(4), stereo(1)];
    configs.extend(sweep.foveated.iter().map(|(_, _, c)| c.clone()));
    let plans = configs
        .iter()
        .map(|c| foveate::plan(sweep.scene, c, gpu.caps()))
        .collect::<Result<Vec<_>, _>>()?;
    Ok((configs, plans))
}

/// The figures a latency row keeps of a judged frame: eFLIP's mean and p99, and its p99 per
/// region.
fn frame_error(error: foveate::metrics::perceptual::PerceptualError) -> Result<FrameError> {
    let e = error.eccentric.context("no visible pixel to judge")?;
    Ok(FrameError {
        p99: e.p99,
        mean: e.mean,
        regions: error.regions.map(|r| r.map(|r| r.p99)),
    })
}
