//! The gaze a sweep follows: the trace (recorded or the model's), the trackings swept, the
//! frames judged around each saccade and where each tracking put the fovea for them.

use anyhow::Result;
use foveate::foveation::{
    detect_saccades, parse_gaze_csv, DelayedGaze, EyeMovementModel, EyeTrace, GazeLatency,
    GazeSample, GazeSpace, Prediction, SaccadeEvent,
};
use glam::Vec2;

use super::{Frame, LatencyArgs, Sweep, Tracking};

/// The saccades within the judged span (`lead` seconds into the trace, `--trace-s` long) with
/// `--after-ms` after their landing, and the display frames judged around them.
pub(super) fn judged_span(
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
pub(super) fn checked_tracker_hz(args: &LatencyArgs, sweep: &Sweep) -> Result<f64> {
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
pub(super) fn gaze_source(
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

/// Every latency without prediction (the baseline), and each latency above 0 with each other
/// prediction asked for.
pub(super) fn trackings(args: &LatencyArgs) -> Result<Vec<Tracking>> {
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
pub(super) fn judged_frames(
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
pub(super) fn displayed(
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
