//! The eye tracker's latency: a frame's fovea is placed where the tracker said the eye was
//! `latency` earlier, optionally predicted forward to the frame's time. Everything that places a
//! fovea from a gaze stream (the latency sweep, `view`'s mouse) goes through [`DelayedGaze`].

use std::collections::VecDeque;

use glam::Vec2;

use super::eye_movement::{amplitude_for_peak_velocity, GazeSpace, SaccadeEvent};
use super::{GazeFilter, GazeSample};

/// How the fovea's gaze is extrapolated from the tracker's latest samples to the frame.
#[derive(Clone, Copy, Debug, PartialEq, Eq, Hash)]
pub enum Prediction {
    /// The latest sample as reported.
    None,
    /// The latest two samples' velocity, extrapolated to the frame's time.
    Linear,
    /// Within a saccade, where it will land: before its velocity peaks, the amplitude whose
    /// main-sequence peak velocity is the velocity seen so far (a lower bound); after, twice the
    /// distance covered at the peak, a symmetric velocity profile's landing (Anliker 1976, the
    /// baseline of Arabadzhiyska et al. 2017). Outside saccades, the latest sample.
    SaccadeLanding,
}

impl Prediction {
    /// Every prediction, in the order the sweeps print them.
    pub const ALL: [Prediction; 3] = [
        Prediction::None,
        Prediction::Linear,
        Prediction::SaccadeLanding,
    ];

    /// Its name on the command line and in the printout.
    pub fn name(self) -> &'static str {
        match self {
            Prediction::None => "none",
            Prediction::Linear => "linear",
            Prediction::SaccadeLanding => "saccade-landing",
        }
    }
}

impl std::str::FromStr for Prediction {
    type Err = String;
    fn from_str(s: &str) -> Result<Self, String> {
        Prediction::ALL
            .into_iter()
            .find(|p| p.name() == s)
            .ok_or_else(|| format!("invalid gaze-predict = {s:?}: none, linear or saccade-landing"))
    }
}

/// The eye tracker's end-to-end latency and the prediction that counters it.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct GazeLatency {
    /// The tracker's latency in seconds.
    pub latency_s: f64,
    /// What predicts the gaze across it.
    pub prediction: Prediction,
}

/// The longest latency accepted (ms): ten times the worst measured headset tracker's.
pub const MAX_LATENCY_MS: f64 = 1000.0;

impl GazeLatency {
    /// No latency and no prediction: the fovea at the true gaze, as without a tracker model.
    pub const NONE: GazeLatency = GazeLatency {
        latency_s: 0.0,
        prediction: Prediction::None,
    };

    /// `latency_ms` (0 to [`MAX_LATENCY_MS`]) and `prediction`; an error names the value.
    pub fn new(latency_ms: f64, prediction: Prediction) -> Result<Self, String> {
        if !(latency_ms.is_finite() && (0.0..=MAX_LATENCY_MS).contains(&latency_ms)) {
            return Err(format!(
                "invalid gaze-latency = {latency_ms} ms: 0 to {MAX_LATENCY_MS} ms (headset trackers measure 45–81 ms)"
            ));
        }
        Ok(GazeLatency {
            latency_s: latency_ms / 1000.0,
            prediction,
        })
    }
}

/// Velocity above which the eye is in a saccade (°/s; the I-VT threshold of Salvucci &
/// Goldberg 2000). Pursuit stays below it.
pub const SACCADE_THRESHOLD_DEG_S: f64 = 30.0;

/// How much of the tracker's past a prediction looks at (s).
const HISTORY_S: f64 = 0.25;

/// A gaze stream seen through the tracker's latency: samples go in as the tracker makes them,
/// and each frame asks for the gaze to place its fovea at. Bad samples go through the
/// [`GazeFilter`]; predictions never leave the view (−1…1).
pub struct DelayedGaze {
    latency: GazeLatency,
    space: GazeSpace,
    pending: VecDeque<GazeSample>,
    filter: GazeFilter,
    /// Good samples the frame may use, oldest first; emptied by a bad one (a prediction does
    /// not reach across a blink).
    recent: VecDeque<(f64, Vec2)>,
    current: Vec2,
}

impl DelayedGaze {
    /// `space` is the view gaze moves in (velocities are in degrees).
    pub fn new(latency: GazeLatency, space: GazeSpace) -> Self {
        DelayedGaze {
            latency,
            space,
            pending: VecDeque::new(),
            filter: GazeFilter::new(0.5),
            recent: VecDeque::new(),
            current: Vec2::ZERO,
        }
    }

    /// A tracker sample, in time order.
    pub fn push(&mut self, sample: GazeSample) {
        self.pending.push_back(sample);
    }

    /// The gaze to render the frame displayed at `t` with: from the samples made by
    /// `t − latency`, predicted to `t`.
    pub fn gaze_at(&mut self, t: f64) -> Vec2 {
        let reported_by = t - self.latency.latency_s + 1e-9;
        while self.pending.front().is_some_and(|s| s.t <= reported_by) {
            let s = self.pending.pop_front().expect("checked");
            self.current = self.filter.update(&s)[0];
            if GazeFilter::is_good(&s) {
                self.recent.push_back((s.t, s.left));
                while self.recent.len() > 2 && s.t - self.recent[0].0 > HISTORY_S {
                    self.recent.pop_front();
                }
            } else {
                self.recent.clear();
            }
        }
        let predicted = match self.latency.prediction {
            Prediction::None => None,
            Prediction::Linear => self.linear(t),
            Prediction::SaccadeLanding => self.landing(),
        };
        predicted
            .filter(|g| g.is_finite())
            .map_or(self.current, |g| g.clamp(-Vec2::ONE, Vec2::ONE))
    }

    fn linear(&self, t: f64) -> Option<Vec2> {
        let n = self.recent.len();
        let ((t0, p0), (t1, p1)) = (*self.recent.get(n.checked_sub(2)?)?, self.recent[n - 1]);
        let velocity = (p1 - p0) / (t1 - t0).max(1e-6) as f32;
        Some(p1 + velocity * (t - t1) as f32)
    }

    fn landing(&self) -> Option<Vec2> {
        let samples: Vec<(f64, Vec2)> = self.recent.iter().copied().collect();
        let speeds = speeds(&samples, self.space);
        let last = speeds.len().checked_sub(1)?;
        if speeds[last] < SACCADE_THRESHOLD_DEG_S {
            return None;
        }
        // The saccade so far: its fast segments, the first starting at the onset sample.
        let first = (0..=last)
            .rev()
            .take_while(|&i| speeds[i] >= SACCADE_THRESHOLD_DEG_S)
            .last()
            .expect("the last segment is fast");
        let onset = samples[first].1;
        let newest = samples[last + 1].1;
        let peak = (first..=last)
            .max_by(|&a, &b| speeds[a].total_cmp(&speeds[b]))
            .expect("non-empty");
        let covered = self.space.angle_deg(onset, newest);
        let amplitude = if peak < last {
            let at_peak = (samples[peak].1 + samples[peak + 1].1) / 2.0;
            2.0 * self.space.angle_deg(onset, at_peak)
        } else {
            amplitude_for_peak_velocity(speeds[last]).unwrap_or(covered)
        };
        Some(
            self.space
                .rotate_towards(onset, newest, amplitude.max(covered)),
        )
    }
}

/// Angular speed (°/s) between consecutive samples.
fn speeds(samples: &[(f64, Vec2)], space: GazeSpace) -> Vec<f64> {
    samples
        .windows(2)
        .map(|w| space.angle_deg(w[0].1, w[1].1) / (w[1].0 - w[0].0).max(1e-6))
        .collect()
}

/// The saccades in a trace of at least `min_amplitude_deg` (microsaccades left out), found by
/// velocity threshold (I-VT): onset at the sample starting the first fast segment, landing at
/// the sample ending the last. Invalid samples end a run.
pub fn detect_saccades(
    trace: &[GazeSample],
    space: GazeSpace,
    min_amplitude_deg: f64,
) -> Vec<SaccadeEvent> {
    let mut found = Vec::new();
    let mut run: Option<usize> = None;
    for i in 1..=trace.len() {
        let fast = i < trace.len() && {
            let (a, b) = (&trace[i - 1], &trace[i]);
            let ok = GazeFilter::is_good(a) && GazeFilter::is_good(b);
            ok && space.angle_deg(a.left, b.left) / (b.t - a.t).max(1e-6) >= SACCADE_THRESHOLD_DEG_S
        };
        match (fast, run) {
            (true, None) => run = Some(i - 1),
            (false, Some(start)) => {
                let (a, b) = (&trace[start], &trace[i - 1]);
                let amplitude_deg = space.angle_deg(a.left, b.left);
                if amplitude_deg >= min_amplitude_deg {
                    found.push(SaccadeEvent {
                        onset_s: a.t,
                        landing_s: b.t,
                        amplitude_deg,
                    });
                }
                run = None;
            }
            _ => {}
        }
    }
    found
}

#[cfg(test)]
mod tests {
    use super::super::eye_movement::{saccade_duration_s, EyeMovementModel};
    use super::*;
    use crate::view::FovTangents;

    fn space() -> GazeSpace {
        GazeSpace {
            fov: FovTangents::from_angles_deg(52.0, 44.0, 48.0, 48.0),
        }
    }

    fn sample(t: f64, g: Vec2) -> GazeSample {
        GazeSample {
            t,
            left: g,
            right: g,
            valid: true,
        }
    }

    /// The gaze frames would get, one frame per display time, the stream fed as it goes.
    fn replay(trace: &[GazeSample], frames: &[f64], latency: GazeLatency) -> Vec<Vec2> {
        let mut delayed = DelayedGaze::new(latency, space());
        let mut next = trace.iter().peekable();
        frames
            .iter()
            .map(|&t| {
                while let Some(s) = next.next_if(|s| s.t <= t) {
                    delayed.push(*s);
                }
                delayed.gaze_at(t)
            })
            .collect()
    }

    /// Latency 0 without prediction is the gaze as sampled, bit for bit, so today's figures
    /// stand. Mutation: any smoothing or an off-by-one sample fails it.
    #[test]
    fn no_latency_is_the_sampled_gaze_exactly() {
        let trace = EyeMovementModel::default()
            .simulate(space(), 3.0, 4)
            .sampled(90.0);
        let times: Vec<f64> = trace.iter().map(|s| s.t).collect();
        let mut filter = GazeFilter::new(0.5);
        let expected: Vec<Vec2> = trace.iter().map(|s| filter.update(s)[0]).collect();
        assert_eq!(replay(&trace, &times, GazeLatency::NONE), expected);
    }

    /// A step in gaze reaches the fovea exactly `latency` later, frame for frame at 90 Hz.
    /// Mutation: the latency applied one frame short or long fails it.
    #[test]
    fn a_step_arrives_exactly_latency_later() {
        let hz = 90.0;
        let (from, to) = (Vec2::new(-0.2, 0.1), Vec2::new(0.5, -0.3));
        let trace: Vec<GazeSample> = (0..40)
            .map(|i| sample(i as f64 / hz, if i < 10 { from } else { to }))
            .collect();
        let times: Vec<f64> = trace.iter().map(|s| s.t).collect();
        for frames_late in [0usize, 1, 2, 4, 7] {
            let latency = GazeLatency::new(frames_late as f64 * 1000.0 / hz, Prediction::None);
            let shown = replay(&trace, &times, latency.unwrap());
            let arrives = shown.iter().position(|&g| g == to).unwrap();
            assert_eq!(arrives, 10 + frames_late, "{frames_late} frames late");
            assert!(shown[arrives..].iter().all(|&g| g == to));
        }
    }

    /// A skewed 20° saccade (peak velocity at 35 % of its duration, unlike the symmetric profile
    /// the predictor assumes) sampled at 120 Hz, displayed at 90 Hz with 50 ms of latency: the
    /// landing prediction's mean error to the true gaze is at least 0.5° below no prediction's, and no
    /// prediction leaves the view, even for a saccade landing at the edge. Mutation: predicting
    /// the onset, or dropping the clamp (linear overshoots past ±1), fails it.
    #[test]
    fn landing_prediction_beats_none_and_stays_in_view() {
        let s = space();
        for (from, to) in [
            (Vec2::new(-0.5, 0.0), Vec2::new(-0.5, 0.0)),
            (Vec2::new(0.4, 0.3), Vec2::new(0.98, 0.95)),
        ] {
            let end = s.rotate_towards(from, if to == from { Vec2::ZERO } else { to }, 20.0);
            let duration = saccade_duration_s(20.0);
            let onset = 0.3;
            // Velocity ∝ x^1.4 (1 − x)^2.6: it peaks at 35 % of the duration, and its peak
            // over its mean (2.0) is near the main sequence's 1.875.
            let steps = 1000;
            let velocity = |x: f64| x.powf(1.4) * (1.0 - x).powf(2.6);
            let mut cumulative = vec![0.0];
            for k in 0..steps {
                let x = (k as f64 + 0.5) / steps as f64;
                cumulative.push(cumulative[k] + velocity(x));
            }
            let total = cumulative[steps];
            let truth = |t: f64| {
                let x = ((t - onset) / duration).clamp(0.0, 1.0);
                let f = cumulative[(x * steps as f64).round() as usize] / total;
                s.rotate_towards(from, end, 20.0 * f)
            };
            let trace: Vec<GazeSample> = (0..120)
                .map(|k| sample(k as f64 / 120.0, truth(k as f64 / 120.0)))
                .collect();
            let frames: Vec<f64> = (0..90)
                .map(|i| i as f64 / 90.0)
                .filter(|&t| (onset..onset + duration + 0.1).contains(&t))
                .collect();
            let error = |p: Prediction| {
                let shown = replay(&trace, &frames, GazeLatency::new(50.0, p).unwrap());
                assert!(
                    shown.iter().all(|g| g.abs().max_element() <= 1.0),
                    "{p:?} left the view"
                );
                let sum: f64 = shown
                    .iter()
                    .zip(&frames)
                    .map(|(&g, &t)| s.angle_deg(g, truth(t)))
                    .sum();
                sum / frames.len() as f64
            };
            let (none, landing) = (error(Prediction::None), error(Prediction::SaccadeLanding));
            let _ = error(Prediction::Linear);
            assert!(landing < none - 0.5, "landing {landing}° vs none {none}°");
        }
    }

    /// Threshold detection finds the model's saccades (≥ 1°) where it made them. Mutation: a
    /// threshold above the saccades' speed, or onsets taken at the run's end, fails it.
    #[test]
    fn detection_finds_the_models_saccades() {
        let trace = EyeMovementModel {
            blinks_per_s: 0.0,
            ..Default::default()
        }
        .simulate(space(), 10.0, 2);
        let found = detect_saccades(&trace.truth, space(), 1.0);
        assert_eq!(found.len(), trace.saccades.len());
        for (f, e) in found.iter().zip(&trace.saccades) {
            assert!((f.onset_s - e.onset_s).abs() < 0.008, "{f:?} vs {e:?}");
            assert!((f.landing_s - e.landing_s).abs() < 0.008, "{f:?} vs {e:?}");
        }
    }

    #[test]
    fn bad_latencies_are_errors_naming_the_field() {
        for ms in [-1.0, f64::NAN, 5000.0] {
            let e = GazeLatency::new(ms, Prediction::None).unwrap_err();
            assert!(e.contains("gaze-latency"), "{e}");
        }
        assert!("sideways"
            .parse::<Prediction>()
            .unwrap_err()
            .contains("gaze-predict"));
        assert_eq!("saccade-landing".parse(), Ok(Prediction::SaccadeLanding));
    }
}
