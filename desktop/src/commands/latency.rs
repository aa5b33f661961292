//! `foveate compare --gaze-latency`: what the eye tracker's latency costs. The eye moves along a
//! trace (the eye-movement model, or a recorded CSV); each foveated configuration renders every
//! displayed frame with its fovea where the tracker reported the gaze `latency` earlier
//! (optionally predicted), and is judged in eccentricity-aware FLIP at the frame's *true* gaze.
//! Per latency and prediction: the worst frame after each saccade, how long the error stays above
//! the budget, and the smallest fovea ratio that stays within it — with what that ratio costs.

use std::collections::HashMap;
use std::path::PathBuf;

use anyhow::{Context, Result};
use clap::Args;
use foveate::foveation::{
    detect_saccades, parse_gaze_csv, DelayedGaze, EyeMovementModel, EyeTrace, GazeLatency,
    GazeSample, GazeSpace, Prediction, SaccadeEvent,
};
use foveate::gpu::Gpu;
use foveate::metrics::perceptual::{perceptual_error, Maps};
use foveate::metrics::Acuity;
use foveate::metrics::EyePixels;
use foveate::plan::{FramePlan, RenderConfig};
use foveate::render::{Renderer, StereoImage};
use foveate::scene::Scene;
use foveate::view::Eye;
use glam::Vec2;

use crate::commands::bench::plots::{latency_plot, LatencyCurve};
use crate::csv_out::{opt, CsvTable};
use crate::side_by_side::{measure_group, Group};

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
    let shown: Vec<Vec<Vec2>> = trackings
        .iter()
        .map(|k| {
            let latency =
                GazeLatency::new(k.latency_ms, k.prediction).map_err(anyhow::Error::msg)?;
            Ok(displayed(&tracker, &frames, latency, space))
        })
        .collect::<Result<_>>()?;
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
    let judged = judge_foveated(gpu, sweep, &plans, &shown, &frames, &judge)?;
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

/// The saccades within the judged span (`lead` seconds into the trace, `--trace-s` long) with
/// `--after-ms` after their landing, and the display frames judged around them.
fn judged_span(
    args: &LatencyArgs,
    trace: &EyeTrace,
    space: GazeSpace,
    lead: f64,
    display_hz: f64,
) -> Result<(Vec<SaccadeEvent>, Vec<Frame>)> {
    let start = trace.truth[0].t + lead;
    let end = start + args.trace_s;
    let saccades: Vec<SaccadeEvent> = detect_saccades(&trace.truth, space, 1.0)
        .into_iter()
        .filter(|s| s.onset_s >= start && s.landing_s + args.after_ms / 1000.0 <= end)
        .collect();
    let frames = judged_frames(trace, &saccades, start, end, display_hz, args.after_ms);
    anyhow::ensure!(
        !frames.is_empty(),
        "the gaze trace has no saccade of 1° or more with {} ms after it between {start:.2} s and {end:.2} s: a longer --trace-s or another --seed",
        args.after_ms
    );
    Ok((saccades, frames))
}

/// The figures `latency_sweep` checks before it renders; the tracker's rate.
fn checked_tracker_hz(args: &LatencyArgs, sweep: &Sweep) -> Result<f64> {
    anyhow::ensure!(
        args.trace_s.is_finite() && args.trace_s > 0.0 && args.trace_s <= 60.0,
        "invalid trace-s = {}: 0 < seconds ≤ 60",
        args.trace_s
    );
    for (name, value) in [
        ("after-ms", args.after_ms),
        ("suppression-ms", args.suppression_ms),
    ] {
        anyhow::ensure!(
            value.is_finite() && (0.0..=1000.0).contains(&value),
            "invalid {name} = {value}: 0 to 1000 ms"
        );
    }
    let tracker_hz = args
        .tracker_hz
        .or(sweep.hmd_tracker_hz.map(f64::from))
        .unwrap_or(120.0);
    anyhow::ensure!(
        tracker_hz.is_finite() && (1.0..=10_000.0).contains(&tracker_hz),
        "invalid tracker-hz = {tracker_hz}: 1 to 10000 Hz"
    );
    Ok(tracker_hz)
}

/// The true gaze over time, what the tracker sampled of it, and where both came from: a
/// recorded trace, or the eye-movement model's from `lead` seconds before the judged span.
fn gaze_source(
    args: &LatencyArgs,
    space: GazeSpace,
    lead: f64,
    tracker_hz: f64,
) -> Result<(EyeTrace, Vec<GazeSample>, String)> {
    Ok(match &args.gaze_trace {
        Some(path) => {
            let truth = parse_gaze_csv(path)?;
            anyhow::ensure!(
                truth.len() >= 2,
                "gaze trace {}: {} samples, at least 2",
                path.display(),
                truth.len()
            );
            let trace = EyeTrace {
                saccades: Vec::new(),
                truth: truth.clone(),
            };
            (trace, truth, format!("recorded trace {}", path.display()))
        }
        None => {
            let trace = EyeMovementModel::default().simulate(space, lead + args.trace_s, args.seed);
            let tracker = trace.sampled(tracker_hz);
            let source = format!(
                "eye-movement model (seed {}), tracker at {tracker_hz} Hz",
                args.seed
            );
            (trace, tracker, source)
        }
    })
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

/// Every foveated configuration's error per tracking and judged frame: each distinct gaze
/// the trackings displayed is rendered once and judged for every frame that showed it.
fn judge_foveated(
    gpu: &Gpu,
    sweep: &Sweep,
    plans: &[FramePlan],
    shown: &[Vec<Vec2>],
    frames: &[Frame],
    judge: &dyn Fn(&StereoImage, &FramePlan, Vec2, Vec2) -> Result<FrameError>,
) -> Result<Vec<Vec<Vec<FrameError>>>> {
    // Which (tracking, frame) showed each distinct gaze: every configuration renders each once.
    let mut by_gaze: HashMap<[u32; 2], Vec<(usize, usize)>> = HashMap::new();
    for (k, gazes) in shown.iter().enumerate() {
        for (i, g) in gazes.iter().enumerate() {
            by_gaze
                .entry(g.to_array().map(f32::to_bits))
                .or_default()
                .push((k, i));
        }
    }
    let mut gazes: Vec<[u32; 2]> = by_gaze.keys().copied().collect();
    gazes.sort();
    // Per configuration, per tracking, per judged frame.
    let mut judged: Vec<Vec<Vec<FrameError>>> = Vec::new();
    for (c, (name, _, _)) in sweep.foveated.iter().enumerate() {
        let plan = &plans[c + 2];
        let mut renderer = Renderer::new(gpu, plan, sweep.scene)?;
        let bar = crate::progress::bar(&format!("latency: {name}"), gazes.len() as u64);
        let mut rows = vec![vec![UNJUDGED; frames.len()]; shown.len()];
        for key in &gazes {
            if crate::interrupt::requested() {
                // Its tables compare every configuration at once: no partial table is a result.
                return Err(crate::interrupt::stopped(&format!(
                    "the latency sweep stopped in configuration {} of {}: nothing written",
                    c + 1,
                    sweep.foveated.len()
                )));
            }
            let g = Vec2::from_array(key.map(f32::from_bits));
            renderer.set_gaze([g; 2])?;
            renderer.render_frame(sweep.scene.head)?;
            let image = renderer.readback()?;
            for &(k, i) in &by_gaze[key] {
                rows[k][i] = judge(&image, plan, frames[i].truth, g)?;
            }
            bar.inc(1);
        }
        bar.finish_and_clear();
        judged.push(rows);
    }
    Ok(judged)
}

/// What a finished sweep writes: its table as CSV, its plots, its frames.
struct SweepOutputs<'a> {
    trackings: &'a [Tracking],
    sweep: &'a Sweep<'a>,
    frames: &'a [Frame],
    saccades: &'a [SaccadeEvent],
    shown: &'a [Vec<Vec2>],
    judged: &'a [Vec<Vec<FrameError>>],
    summaries: &'a [Vec<Summary>],
    times: &'a [f64],
    budget: f64,
}

impl SweepOutputs<'_> {
    /// One row per tracking and configuration (to `--csv`, or stdout).
    fn summary_csv(&self) -> Result<()> {
        let mut csv = CsvTable::new(&[
            "latency_ms",
            "prediction",
            "config",
            "ratio",
            "time_ratio",
            "eflip_p99_worst_after_landing",
            "eflip_p99_worst_in_saccade",
            "eflip_p99_mean",
            "ms_above_budget",
            "ms_above_budget_beyond_suppression",
            "budget",
        ])?;
        for (k, tracking) in self.trackings.iter().enumerate() {
            for (c, (name, ratio, _)) in self.sweep.foveated.iter().enumerate() {
                let s = self.summaries[c][k];
                csv.row(&[
                    &tracking.latency_ms,
                    &tracking.prediction.name(),
                    name,
                    ratio,
                    &format!("{:.4}", self.times[c + 2]),
                    &format!("{:.6}", s.worst_after),
                    &format!("{:.6}", s.worst_during),
                    &format!("{:.6}", s.mean_p99),
                    &format!("{:.1}", s.above_ms),
                    &format!("{:.1}", s.beyond_suppression_ms),
                    &format!("{:.6}", self.budget),
                ])?;
            }
        }
        csv.save(self.sweep.csv.as_deref())?;
        Ok(())
    }

    /// One plot per configuration: the error around each saccade, per tracking.
    fn plots(&self, stem: &std::path::Path) -> Result<()> {
        for (c, (name, ..)) in self.sweep.foveated.iter().enumerate() {
            let curves: Vec<LatencyCurve> = self
                .trackings
                .iter()
                .enumerate()
                .map(|(k, tracking)| LatencyCurve {
                    label: format!("{} ms, {}", tracking.latency_ms, tracking.prediction.name()),
                    saccades: (0..self.saccades.len())
                        .map(|s| {
                            let mine = self.frames.iter().zip(&self.judged[c][k]);
                            mine.filter(|(f, _)| f.saccade == s)
                                .map(|(f, e)| ((f.t - self.saccades[s].landing_s) * 1000.0, e.p99))
                                .collect()
                        })
                        .collect(),
                })
                .collect();
            let caption = format!("{name}: the error at the true gaze around each saccade, per tracker latency and prediction");
            let file = format!("{}-{}", stem.display(), crate::file_names::slug(name));
            latency_plot(&curves, self.budget, &caption, std::path::Path::new(&file))?;
        }
        println!(
            "wrote {} latency plots as {}-*.png/svg",
            self.sweep.foveated.len(),
            stem.display()
        );
        Ok(())
    }

    /// Every judged frame of every tracking and configuration.
    fn frames_csv(&self, path: &std::path::Path) -> Result<()> {
        let mut per_frame = CsvTable::new(&[
            "latency_ms",
            "prediction",
            "config",
            "t_s",
            "since_landing_ms",
            "true_x",
            "true_y",
            "fovea_x",
            "fovea_y",
            "eflip_p99",
            "eflip_mean",
            "eflip_p99_fovea",
            "eflip_p99_band",
            "eflip_p99_periphery",
        ])?;
        for (k, tracking) in self.trackings.iter().enumerate() {
            for (c, (name, _, _)) in self.sweep.foveated.iter().enumerate() {
                for (i, f) in self.frames.iter().enumerate() {
                    let e = self.judged[c][k][i];
                    let since = (f.t - self.saccades[f.saccade].landing_s) * 1000.0;
                    per_frame.row(&[
                        &tracking.latency_ms,
                        &tracking.prediction.name(),
                        name,
                        &format!("{:.4}", f.t),
                        &format!("{since:.1}"),
                        &f.truth.x,
                        &f.truth.y,
                        &self.shown[k][i].x,
                        &self.shown[k][i].y,
                        &format!("{:.6}", e.p99),
                        &format!("{:.6}", e.mean),
                        &opt(e.regions[0], 6),
                        &opt(e.regions[1], 6),
                        &opt(e.regions[2], 6),
                    ])?;
                }
            }
        }
        per_frame.save(Some(path))?;
        Ok(())
    }
}

/// Every latency without prediction (the baseline), and each latency above 0 with each other
/// prediction asked for.
fn trackings(args: &LatencyArgs) -> Result<Vec<Tracking>> {
    anyhow::ensure!(
        !args.gaze_latency.is_empty(),
        "invalid gaze-latency: give at least one"
    );
    let mut out = Vec::new();
    for &latency_ms in &args.gaze_latency {
        GazeLatency::new(latency_ms, Prediction::None).map_err(anyhow::Error::msg)?;
        let predicted = args
            .gaze_predict
            .iter()
            .filter(|&&p| p != Prediction::None && latency_ms > 0.0);
        for &prediction in std::iter::once(&Prediction::None).chain(predicted) {
            out.push(Tracking {
                latency_ms,
                prediction,
            });
        }
    }
    Ok(out)
}

/// The display frames from each saccade's onset to `after_ms` past its landing.
fn judged_frames(
    trace: &EyeTrace,
    saccades: &[SaccadeEvent],
    start: f64,
    end: f64,
    display_hz: f64,
    after_ms: f64,
) -> Vec<Frame> {
    let count = ((end - start) * display_hz).floor() as usize;
    (0..count)
        .map(|i| start + i as f64 / display_hz)
        .filter_map(|t| {
            let saccade = saccades
                .iter()
                .rposition(|s| s.onset_s <= t && t < s.landing_s + after_ms / 1000.0)?;
            Some(Frame {
                t,
                saccade,
                truth: trace.at(t),
            })
        })
        .collect()
}

/// The gaze each judged frame's fovea is placed at, the tracker's samples fed as time goes on.
fn displayed(
    tracker: &[GazeSample],
    frames: &[Frame],
    latency: GazeLatency,
    space: GazeSpace,
) -> Vec<Vec2> {
    let mut delayed = DelayedGaze::new(latency, space);
    let mut next = tracker.iter().peekable();
    frames
        .iter()
        .map(|f| {
            while let Some(s) = next.next_if(|s| s.t <= f.t) {
                delayed.push(*s);
            }
            delayed.gaze_at(f.t)
        })
        .collect()
}

/// The worst p99 of the frames at or after a saccade's landing.
fn worst_after_landing(j: &[FrameError], frames: &[Frame], saccades: &[SaccadeEvent]) -> f64 {
    frames
        .iter()
        .zip(j)
        .filter(|(f, _)| f.t >= saccades[f.saccade].landing_s)
        .map(|(_, e)| e.p99)
        .fold(0.0, f64::max)
}

/// The judged frames and what they are held to.
struct Windows<'a> {
    frames: &'a [Frame],
    saccades: &'a [SaccadeEvent],
    budget: f64,
    suppression_s: f64,
    frame_s: f64,
}

/// One configuration under one tracking, over the judged frames.
#[derive(Clone, Copy, Debug, PartialEq)]
struct Summary {
    worst_after: f64,
    worst_during: f64,
    mean_p99: f64,
    /// The longest any saccade's error stayed above budget after it landed (ms), and of that
    /// the part past the suppression window.
    above_ms: f64,
    beyond_suppression_ms: f64,
}

impl Windows<'_> {
    fn summary(&self, j: &[FrameError]) -> Summary {
        let mut above: Vec<f64> = vec![0.0; self.saccades.len()];
        let mut worst_during: f64 = 0.0;
        for (f, p) in self.frames.iter().zip(j.iter().map(|e| e.p99)) {
            let landing = self.saccades[f.saccade].landing_s;
            if f.t < landing {
                worst_during = worst_during.max(p);
            } else if p > self.budget {
                let until = f.t + self.frame_s - landing;
                above[f.saccade] = above[f.saccade].max(until);
            }
        }
        let above_s = above.iter().copied().fold(0.0, f64::max);
        Summary {
            worst_after: worst_after_landing(j, self.frames, self.saccades),
            worst_during,
            mean_p99: j.iter().map(|e| e.p99).sum::<f64>() / j.len().max(1) as f64,
            above_ms: above_s * 1000.0,
            beyond_suppression_ms: (above_s - self.suppression_s).max(0.0) * 1000.0,
        }
    }
}

/// The smallest fovea ratio whose worst frame after landing is within `budget`, the cheapest of
/// equal ratios; candidates are (ratio, time, worst).
fn smallest_within(candidates: &[(f32, f64, f64)], budget: f64) -> Option<usize> {
    (0..candidates.len())
        .filter(|&i| candidates[i].2 <= budget)
        .min_by(|&a, &b| {
            let (p, q) = (candidates[a], candidates[b]);
            p.0.total_cmp(&q.0).then(p.1.total_cmp(&q.1))
        })
}

fn print_table(
    trackings: &[Tracking],
    sweep: &Sweep,
    summaries: &[Vec<Summary>],
    windows: &Windows,
    times: &[f64],
    stereo: Summary,
) {
    let width = sweep
        .foveated
        .iter()
        .map(|(n, ..)| n.len())
        .max()
        .unwrap_or(0)
        .max(16);
    println!(
        "\n{:>7} {:<15} {:<width$} {:>7} {:>10} {:>10} {:>9} {:>9} {:>11}",
        "latency",
        "prediction",
        "configuration",
        "time",
        "worst p99",
        "in saccade",
        "mean p99",
        "ms above",
        "past suppr."
    );
    let line = |lat: &str, pred: &str, name: &str, time: f64, s: Summary| {
        println!(
            "{lat:>7} {pred:<15} {name:<width$} {time:>7.3} {:>10.4} {:>10.4} {:>9.4} {:>9.0} {:>11.0}",
            s.worst_after, s.worst_during, s.mean_p99, s.above_ms, s.beyond_suppression_ms
        )
    };
    line("-", "-", "stereo, MSAA 1", times[1], stereo);
    let mut picks = Vec::new();
    for (k, tracking) in trackings.iter().enumerate() {
        let mut candidates = Vec::new();
        for (c, (name, ratio, _)) in sweep.foveated.iter().enumerate() {
            let s = summaries[c][k];
            let latency = format!("{} ms", tracking.latency_ms);
            line(&latency, tracking.prediction.name(), name, times[c + 2], s);
            candidates.push((*ratio, times[c + 2], s.worst_after));
        }
        picks.push(smallest_within(&candidates, windows.budget));
    }
    println!(
        "(time: frame time to the reference (stereo, MSAA 4), this run; worst p99: the eccentricity-aware FLIP's 99th percentile at the frame's true gaze, the worst frame at or after a saccade's landing; in saccade: the worst frame from onset to landing; mean p99: over every judged frame; ms above: the longest a saccade's error stayed above the budget after landing, and past suppr.: the part of it beyond the {:.0} ms suppression window — saccadic suppression hides part of the first, none of the second; nothing is discounted)",
        windows.suppression_s * 1000.0
    );
    println!(
        "\nthe smallest fovea whose every frame after landing is within eFLIP p99 ≤ {:.4}:",
        windows.budget
    );
    for (tracking, pick) in trackings.iter().zip(picks) {
        let what = match pick {
            Some(c) => format!(
                "{} — {:.3}x the reference's time",
                sweep.foveated[c].0,
                times[c + 2]
            ),
            None => "none of the ratios measured".to_string(),
        };
        println!(
            "  latency {:>5} ms, {:<15} {what}",
            tracking.latency_ms,
            tracking.prediction.name()
        );
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    /// The selection on a table built here: the smallest ratio within the budget (inclusive),
    /// the cheaper of equal ratios. Mutation: picking the cheapest (not the smallest ratio) or
    /// an exclusive budget fails it.
    #[test]
    fn the_smallest_ratio_within_budget_is_picked() {
        let table = [
            (0.35, 0.55, 0.30),
            (0.5, 0.62, 0.12),
            (0.5, 0.60, 0.12),
            (0.7, 0.80, 0.05),
            (0.25, 0.50, 0.41),
        ];
        assert_eq!(smallest_within(&table, 0.30), Some(0), "inclusive");
        assert_eq!(smallest_within(&table, 0.2), Some(2), "the cheaper 0.5");
        assert_eq!(smallest_within(&table, 0.1), Some(3));
        assert_eq!(smallest_within(&table, 0.5), Some(4));
        assert_eq!(smallest_within(&table, 0.01), None);
    }

    /// Time above budget counts from landing to the end of the last frame above it, per
    /// saccade, and the suppression window is taken off only in its own column.
    #[test]
    fn time_above_budget_is_counted_from_landing() {
        let saccades = [SaccadeEvent {
            onset_s: 0.0,
            landing_s: 0.05,
            amplitude_deg: 10.0,
        }];
        let frames: Vec<Frame> = (0..12)
            .map(|i| Frame {
                t: i as f64 * 0.01,
                saccade: 0,
                truth: Vec2::ZERO,
            })
            .collect();
        // Above budget until t = 0.08 (frame 8), then within.
        let j: Vec<FrameError> = (0..12)
            .map(|i| FrameError {
                p99: if i <= 8 { 0.5 } else { 0.1 },
                ..UNJUDGED
            })
            .collect();
        let w = Windows {
            frames: &frames,
            saccades: &saccades,
            budget: 0.2,
            suppression_s: 0.02,
            frame_s: 0.01,
        };
        let s = w.summary(&j);
        assert!((s.above_ms - 40.0).abs() < 1e-6, "{s:?}");
        assert!((s.beyond_suppression_ms - 20.0).abs() < 1e-6, "{s:?}");
        assert_eq!((s.worst_after, s.worst_during), (0.5, 0.5));
    }
}
