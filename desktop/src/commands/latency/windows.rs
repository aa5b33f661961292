//! The judged frames held to the budget: each configuration's summary per tracking, and the
//! table that picks the smallest fovea within it.

use foveate::foveation::SaccadeEvent;

use super::{Frame, FrameError, Sweep, Tracking};

/// The worst p99 of the frames at or after a saccade's landing.
pub(super) fn worst_after_landing(
    j: &[FrameError],
    frames: &[Frame],
    saccades: &[SaccadeEvent],
) -> f64 {
    frames
        .iter()
        .zip(j)
        .filter(|(f, _)| f.t >= saccades[f.saccade].landing_s)
        .map(|(_, e)| e.p99)
        .fold(0.0, f64::max)
}

/// The judged frames and what they are held to.
pub(super) struct Windows<'a> {
    pub(super) frames: &'a [Frame],
    pub(super) saccades: &'a [SaccadeEvent],
    pub(super) budget: f64,
    pub(super) suppression_s: f64,
    pub(super) frame_s: f64,
}

/// One configuration under one tracking, over the judged frames.
#[derive(Clone, Copy, Debug, PartialEq)]
pub(super) struct Summary {
    pub(super) worst_after: f64,
    pub(super) worst_during: f64,
    pub(super) mean_p99: f64,
    /// The longest any saccade's error stayed above budget after it landed (ms), and of that
    /// the part past the suppression window.
    pub(super) above_ms: f64,
    pub(super) beyond_suppression_ms: f64,
}

impl Windows<'_> {
    pub(super) fn summary(&self, j: &[FrameError]) -> Summary {
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

pub(super) fn print_table(
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
    use crate::commands::latency::UNJUDGED;
    use glam::Vec2;

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
