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
    let start = span_start(trace, lead);
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

/// Where the judged span starts: `lead` seconds into the trace.
fn span_start(trace: &EyeTrace, lead: f64) -> f64 {
    trace.truth[0].t + lead
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

/// Per tracking, the gaze it displayed at each of `frames`.
pub(super) fn shown_per_tracking(
    tracker: &[GazeSample],
    trackings: &[Tracking],
    frames: &[Frame],
    space: GazeSpace,
) -> Result<Vec<Vec<Vec2>>> {
    trackings
        .iter()
        .map(|k| {
            let latency =
                GazeLatency::new(k.latency_ms, k.prediction).map_err(anyhow::Error::msg)?;
            Ok(displayed(tracker, frames, latency, space))
        })
        .collect()
}

/// Display frames rendered before the first judged one when the frames are rendered in order
/// (a history's): what a headset that had been running would have accumulated, about 0.18 s.
pub(super) const WARM_UP_FRAMES: usize = 16;

/// Every display frame from `WARM_UP_FRAMES` before the first judged one to the last judged,
/// in order: per tracking, the gaze it displayed at each; `judged_at[j]`, where judged frame
/// `j` lies among them.
pub(super) struct Sequences {
    pub gazes: Vec<Vec<Vec2>>,
    pub judged_at: Vec<usize>,
}

/// The display frames a sweep renders in order (`Sequences`) for `frames`, judged from the
/// trace's start plus `lead` at `display_hz`.
pub(super) fn sequences(
    trace: &EyeTrace,
    tracker: &[GazeSample],
    trackings: &[Tracking],
    frames: &[Frame],
    lead: f64,
    display_hz: f64,
    space: GazeSpace,
) -> Result<Sequences> {
    let start = span_start(trace, lead);
    // The judged frames lie on the display's clock from `start` (judged_frames).
    let index = |t: f64| ((t - start) * display_hz).round() as i64;
    let first = index(frames[0].t) - WARM_UP_FRAMES as i64;
    let last = index(frames[frames.len() - 1].t);
    let all: Vec<Frame> = (first..=last)
        .map(|i| {
            let t = start + i as f64 / display_hz;
            Frame {
                t,
                saccade: 0,
                truth: trace.at(t),
            }
        })
        .collect();
    let gazes = shown_per_tracking(tracker, trackings, &all, space)?;
    let judged_at = frames
        .iter()
        .map(|f| (index(f.t) - first) as usize)
        .collect();
    Ok(Sequences { gazes, judged_at })
}

#[cfg(test)]
mod tests {
    use super::*;
    use foveate::view::FovTangents;

    /// The frames rendered in order show, at each judged frame, the gaze the judged frame
    /// itself shows, for every tracking, with the warm-up before the first. Mutation: a
    /// sequence one frame off (or judged frames indexed from the span's start rather than the
    /// sequence's) fails it.
    #[test]
    fn a_sequence_shows_each_judged_frame_its_own_gaze() {
        let space = GazeSpace {
            fov: FovTangents::symmetric_deg(100.0, 100.0),
        };
        let (lead, hz) = (0.3, 90.0);
        let trace = EyeMovementModel::default().simulate(space, lead + 3.0, 2);
        let tracker = trace.sampled(120.0);
        let saccades = detect_saccades(&trace.truth, space, 1.0);
        let start = trace.truth[0].t + lead;
        let frames = judged_frames(&trace, &saccades, start, start + 3.0, hz, 150.0);
        assert!(frames.len() > 10, "{} judged frames", frames.len());
        let trackings = [
            Tracking {
                latency_ms: 0.0,
                prediction: Prediction::None,
            },
            Tracking {
                latency_ms: 50.0,
                prediction: Prediction::Linear,
            },
        ];
        let s = sequences(&trace, &tracker, &trackings, &frames, lead, hz, space).unwrap();
        assert_eq!(s.judged_at[0], WARM_UP_FRAMES);
        for (k, tracking) in trackings.iter().enumerate() {
            let latency = GazeLatency::new(tracking.latency_ms, tracking.prediction).unwrap();
            let judged = displayed(&tracker, &frames, latency, space);
            for (j, &at) in s.judged_at.iter().enumerate() {
                assert_eq!(s.gazes[k][at], judged[j], "tracking {k}, judged frame {j}");
            }
        }
        // Gaps between saccades are rendered too: more frames than are judged.
        assert!(s.gazes[0].len() > frames.len() + WARM_UP_FRAMES);
    }
}
