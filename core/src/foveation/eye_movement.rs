//! A simulated eye for gaze traces: fixations that drift and make microsaccades, saccades on the
//! main sequence, smooth pursuit of a moving target, and blinks, sampled at an eye tracker's
//! rate. The eye moves in true angles (directions), so amplitudes and velocities are degrees of
//! visual angle whatever the view's field.
//!
//! Constants and where they come from:
//! - saccade duration, the main sequence's linear part: D = 2.2 ms/° · A + 21 ms (Carpenter,
//!   *Movements of the Eyes*, 1988);
//! - the velocity profile: minimum jerk (Flash & Hogan 1985), so peak velocity is
//!   1.875 · A / D — 436 °/s at 10°, 577 °/s at 20°, 643 °/s at 30°, within the spread of
//!   measured main sequences (Bahill, Clark & Stark 1975). It is symmetric; real large saccades
//!   decelerate longer than they accelerate (Van Opstal & Van Gisbergen 1987), which is why the
//!   landing predictor's test uses a skewed saccade;
//! - saccade amplitudes: most natural saccades are 15° or less (Bahill, Adler & Stark 1975):
//!   85 % are drawn from 2–15°, the rest from 15–30°;
//! - fixations of 200–400 ms (scene viewing's mean fixation is 260–330 ms; Rayner 2009);
//! - fixational eye movements (Martinez-Conde, Macknik & Hubel 2004): drift as a random walk of
//!   0.13 °/√s per axis (a few arcmin per 100 ms) and microsaccades of 0.1–0.5° about 1.5 times a
//!   second, on the same main sequence;
//! - pursuit: a target moving at 5–20 °/s for 300–600 ms, followed at a gain of 0.9 (pursuit
//!   gain is near 0.9 below 30 °/s; Lisberger, Morris & Tychsen 1987); 15 % of gaze shifts;
//! - blinks: 150 ms of invalid samples, about 17 a minute (Bentivoglio et al. 1997).

use glam::{DVec3, Vec2};

use super::{gaze_tangent, GazeSample};
use crate::view::FovTangents;

/// Saccade duration in seconds for an amplitude in degrees (Carpenter 1988).
pub fn saccade_duration_s(amplitude_deg: f64) -> f64 {
    0.0022 * amplitude_deg + 0.021
}

/// Peak velocity in °/s of a minimum-jerk saccade on the main sequence.
pub fn saccade_peak_velocity(amplitude_deg: f64) -> f64 {
    MIN_JERK_PEAK * amplitude_deg / saccade_duration_s(amplitude_deg)
}

/// The amplitude whose main-sequence peak velocity is `velocity` °/s (the inverse of
/// [`saccade_peak_velocity`]); `None` beyond the sequence's asymptote (≈ 852 °/s).
pub fn amplitude_for_peak_velocity(velocity: f64) -> Option<f64> {
    let denominator = MIN_JERK_PEAK - 0.0022 * velocity;
    (velocity >= 0.0 && denominator > 0.0).then(|| 0.021 * velocity / denominator)
}

/// Peak velocity of a minimum-jerk move over its mean velocity.
const MIN_JERK_PEAK: f64 = 1.875;

/// Fraction of the way along a minimum-jerk move at fraction `s` of its duration.
fn min_jerk(s: f64) -> f64 {
    let s = s.clamp(0.0, 1.0);
    s * s * s * (10.0 - 15.0 * s + 6.0 * s * s)
}

/// An eye's view as the space gaze moves in: normalised gaze (as `Renderer::set_gaze` takes it)
/// to a direction and back.
///
/// Each eye's gaze at a point in the world (where an eye tracker says the eyes converge, or a
/// target of the engine's): the point in each eye's space, then its normalised gaze there. The
/// eyes converge, so each looks a little towards the nose.
///
/// ```
/// use foveate::foveation::GazeSpace;
/// use foveate::glam::{Mat4, Vec3};
/// use foveate::view::{Eye, EyeParams, FovTangents};
///
/// let eyes = EyeParams {
///     left_fov: FovTangents::symmetric_deg(90.0, 90.0),
///     right_fov: FovTangents::symmetric_deg(90.0, 90.0),
///     ipd_m: 0.064,
///     cant_rad: 0.0,
/// };
/// let world_from_head = Mat4::from_translation(Vec3::new(0.0, 1.6, 0.0));
/// let target = Vec3::new(0.0, 1.6, -0.5); // half a metre ahead of the head
/// let gaze = Eye::BOTH.map(|eye| {
///     let in_eye = eyes.view(eye, world_from_head).transform_point3(target);
///     GazeSpace { fov: eyes.fov(eye) }.normalised(in_eye.as_dvec3())
/// });
/// assert!(gaze[0].x > 0.0 && gaze[1].x < 0.0); // each eye turns in
/// assert!((gaze[0].x + gaze[1].x).abs() < 1e-6 && gaze[0].y.abs() < 1e-6);
/// // `renderer.set_gaze(gaze)`, `layer.set_gaze(gaze)` or `FrameInput::with_gaze(gaze)`.
/// ```
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct GazeSpace {
    /// The eye's field, as tangents.
    pub fov: FovTangents,
}

impl GazeSpace {
    /// The unit direction the normalised gaze `g` looks along (−z ahead).
    pub fn direction(&self, g: Vec2) -> DVec3 {
        let t = gaze_tangent(self.fov, g);
        DVec3::new(t.x as f64, t.y as f64, -1.0).normalize()
    }

    /// The normalised gaze of a direction in front of the eye.
    pub fn normalised(&self, d: DVec3) -> Vec2 {
        let f = self.fov;
        let (tx, ty) = (d.x / -d.z, d.y / -d.z);
        let centre = (
            (f.right - f.left) as f64 / 2.0,
            (f.up - f.down) as f64 / 2.0,
        );
        let half = (
            (f.left + f.right) as f64 / 2.0,
            (f.up + f.down) as f64 / 2.0,
        );
        Vec2::new(
            ((tx - centre.0) / half.0) as f32,
            ((ty - centre.1) / half.1) as f32,
        )
    }

    /// Degrees between where two normalised gazes look.
    pub fn angle_deg(&self, a: Vec2, b: Vec2) -> f64 {
        self.direction(a)
            .angle_between(self.direction(b))
            .to_degrees()
    }

    /// The direction `angle_deg` from `from` towards `towards` (along the great circle; past it
    /// when the angle is larger than theirs).
    pub fn rotate_towards(&self, from: Vec2, towards: Vec2, angle_deg: f64) -> Vec2 {
        let (a, b) = (self.direction(from), self.direction(towards));
        let axis = a.cross(b);
        if axis.length() < 1e-12 {
            return from;
        }
        let q = glam::DQuat::from_axis_angle(axis.normalize(), angle_deg.to_radians());
        self.normalised(q * a)
    }
}

/// A deterministic stream of uniform numbers in 0..=1 from a seed (xorshift32).
pub struct SeededRng(u32);

impl SeededRng {
    /// The stream from `seed` (any value; 0 is as good as another).
    pub fn new(seed: u32) -> Self {
        SeededRng(seed.wrapping_mul(2_654_435_761).max(1))
    }

    /// The next number, in 0..=1.
    pub fn uniform(&mut self) -> f32 {
        let s = &mut self.0;
        *s ^= *s << 13;
        *s ^= *s >> 17;
        *s ^= *s << 5;
        *s as f32 / u32::MAX as f32
    }

    fn between(&mut self, lo: f64, hi: f64) -> f64 {
        lo + (hi - lo) * self.uniform() as f64
    }

    /// A standard normal number (Box–Muller).
    fn normal(&mut self) -> f64 {
        let u = (self.uniform() as f64).max(1e-12);
        let v = self.uniform() as f64;
        (-2.0 * u.ln()).sqrt() * (std::f64::consts::TAU * v).cos()
    }
}

/// Large saccades only, `seconds` at `rate` Hz in `space`, reproducible from `seed`: from the
/// centre, the first after 0.05–0.15 s and each later one after a fixation of 0.2–0.4 s, a
/// saccade of an amplitude drawn uniformly from
/// `amplitudes_deg` (e.g. 15–30°, the rarer large ones of natural viewing: Bahill, Adler &
/// Stark 1975) in a random direction that keeps the gaze inside ±0.8 × ±0.6 of the field,
/// with the main sequence's duration and a minimum-jerk profile. The gaze per frame.
pub fn large_saccade_trace(
    space: GazeSpace,
    seconds: f64,
    rate: f64,
    amplitudes_deg: (f64, f64),
    seed: u32,
) -> Vec<Vec2> {
    let mut rng = SeededRng::new(seed);
    let inside = |g: Vec2| g.x.abs() <= 0.8 && g.y.abs() <= 0.6;
    let (mut from, mut to) = (Vec2::ZERO, Vec2::ZERO);
    let (mut onset, mut duration) = (0.0, 0.0);
    // The first soon (0.05–0.15 s), so that even a short run sees a saccade land.
    let mut next_onset = rng.between(0.05, 0.15);
    (0..(seconds * rate).round() as usize)
        .map(|i| {
            let t = i as f64 / rate;
            if t >= next_onset {
                from = to;
                let amplitude = rng.between(amplitudes_deg.0, amplitudes_deg.1);
                // The first of 16 directions round from a random one that lands inside.
                let first = rng.between(0.0, std::f64::consts::TAU);
                to = (0..16)
                    .map(|k| first + k as f64 * std::f64::consts::TAU / 16.0)
                    .map(|a| from + Vec2::new(a.cos() as f32, a.sin() as f32) * 0.05)
                    .map(|towards| space.rotate_towards(from, towards, amplitude))
                    .find(|&g| inside(g))
                    .unwrap_or(Vec2::ZERO);
                onset = next_onset;
                duration = saccade_duration_s(space.angle_deg(from, to));
                next_onset = onset + duration + rng.between(0.2, 0.4);
            }
            let s = if duration > 0.0 {
                (t - onset) / duration
            } else {
                1.0
            };
            let amplitude = space.angle_deg(from, to);
            space.rotate_towards(from, to, amplitude * min_jerk(s))
        })
        .collect()
}

/// One saccade the model made: when it started and landed, and how far it went.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct SaccadeEvent {
    /// When it started (s).
    pub onset_s: f64,
    /// When it landed (s).
    pub landing_s: f64,
    /// How far it went (degrees).
    pub amplitude_deg: f64,
}

/// What the eye did, at 1 kHz: the true gaze (both eyes alike, the renderer's convention), each
/// sample invalid while the eye is closed, and the saccades it made (microsaccades left out).
#[derive(Clone, Debug, PartialEq)]
pub struct EyeTrace {
    /// The true gaze, at [`TRUTH_HZ`].
    pub truth: Vec<GazeSample>,
    /// The saccades made, in order.
    pub saccades: Vec<SaccadeEvent>,
}

/// The rate the model moves the eye at.
pub const TRUTH_HZ: f64 = 1000.0;

/// The eye-movement model's settings; `Default` is the cited behaviour above.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct EyeMovementModel {
    /// Fixation duration range (s).
    pub fixation_s: (f64, f64),
    /// Fraction of gaze shifts that are pursuits rather than saccades.
    pub pursuit_fraction: f64,
    /// Blinks per second.
    pub blinks_per_s: f64,
    /// How long a blink closes the eye (s).
    pub blink_s: f64,
    /// Microsaccades per second.
    pub microsaccades_per_s: f64,
    /// Drift per axis (°/√s).
    pub drift_deg_per_sqrt_s: f64,
    /// How far from the centre targets may lie, in normalised gaze (x, y).
    pub target_extent: Vec2,
}

impl Default for EyeMovementModel {
    fn default() -> Self {
        EyeMovementModel {
            fixation_s: (0.2, 0.4),
            pursuit_fraction: 0.15,
            blinks_per_s: 17.0 / 60.0,
            blink_s: 0.15,
            microsaccades_per_s: 1.5,
            drift_deg_per_sqrt_s: 0.13,
            target_extent: Vec2::new(0.8, 0.6),
        }
    }
}

/// What the eye is doing now.
enum Movement {
    Fixating,
    Saccade {
        from: Vec2,
        to: Vec2,
        amplitude: f64,
    },
    Pursuit {
        velocity: Vec2,
    },
}

impl EyeMovementModel {
    /// `seconds` of eye movement in `space`, starting at the centre, reproducible from `seed`.
    pub fn simulate(&self, space: GazeSpace, seconds: f64, seed: u32) -> EyeTrace {
        let mut rng = SeededRng::new(seed);
        let n = (seconds * TRUTH_HZ).round() as usize;
        let dt = 1.0 / TRUTH_HZ;
        let mut gaze = Vec2::ZERO;
        let mut movement = Movement::Fixating;
        let mut phase_start = 0.0;
        let mut phase_end = rng.between(self.fixation_s.0, self.fixation_s.1);
        let mut blink_end = f64::NEG_INFINITY;
        let mut micro: Option<(f64, Vec2, Vec2, f64)> = None;
        let (mut truth, mut saccades) = (Vec::with_capacity(n), Vec::new());
        for i in 0..n {
            let t = i as f64 * dt;
            if t >= phase_end {
                (movement, phase_end) = match movement {
                    Movement::Fixating => self.next_shift(&mut rng, space, gaze, t),
                    // A saccade or a pursuit ends in a fixation (a saccade exactly on target).
                    ended => {
                        if let Movement::Saccade { to, .. } = ended {
                            gaze = to;
                        }
                        let d = rng.between(self.fixation_s.0, self.fixation_s.1);
                        (Movement::Fixating, t + d)
                    }
                };
                phase_start = t;
                if let Movement::Saccade { amplitude, .. } = movement {
                    saccades.push(SaccadeEvent {
                        onset_s: t,
                        landing_s: phase_end,
                        amplitude_deg: amplitude,
                    });
                }
            }
            match movement {
                Movement::Fixating => {
                    gaze = self.fixational(&mut rng, space, gaze, t, &mut micro);
                }
                Movement::Saccade {
                    from,
                    to,
                    amplitude,
                } => {
                    let s = (t - phase_start) / (phase_end - phase_start);
                    gaze = space.rotate_towards(from, to, amplitude * min_jerk(s));
                }
                Movement::Pursuit { velocity } => {
                    let next = gaze + velocity * dt as f32;
                    gaze = next.clamp(-Vec2::ONE, Vec2::ONE);
                }
            }
            if (rng.uniform() as f64) < self.blinks_per_s * dt && t >= blink_end {
                blink_end = t + self.blink_s;
            }
            truth.push(GazeSample {
                t,
                left: gaze,
                right: gaze,
                valid: t >= blink_end,
            });
        }
        EyeTrace { truth, saccades }
    }

    /// The next gaze shift from `gaze` at `t`: a saccade to a new target or a pursuit.
    fn next_shift(
        &self,
        rng: &mut SeededRng,
        space: GazeSpace,
        gaze: Vec2,
        t: f64,
    ) -> (Movement, f64) {
        let angle = rng.between(0.0, std::f64::consts::TAU);
        if (rng.uniform() as f64) < self.pursuit_fraction {
            let speed_deg = rng.between(5.0, 20.0) * 0.9;
            let (s, c) = angle.sin_cos();
            // Normalised units per degree near this gaze.
            let step = space.rotate_towards(gaze, gaze + Vec2::new(c as f32, s as f32) * 0.1, 1.0);
            let velocity = (step - gaze) * speed_deg as f32;
            return (Movement::Pursuit { velocity }, t + rng.between(0.3, 0.6));
        }
        let amplitude = match rng.uniform() < 0.85 {
            true => rng.between(2.0, 15.0),
            false => rng.between(15.0, 30.0),
        };
        // A target inside the extent: the drawn direction, else the opposite one, else inward.
        let towards = |a: f64| gaze + Vec2::new(a.cos() as f32, a.sin() as f32) * 0.05;
        let extent = self.target_extent;
        let inside = |g: Vec2| g.abs().cmple(extent).all();
        let candidates = [angle, angle + std::f64::consts::PI];
        let to = candidates
            .iter()
            .map(|&a| space.rotate_towards(gaze, towards(a), amplitude))
            .find(|&g| inside(g))
            .unwrap_or_else(|| {
                space.rotate_towards(
                    gaze,
                    Vec2::ZERO,
                    amplitude.min(space.angle_deg(gaze, Vec2::ZERO)),
                )
            });
        let amplitude = space.angle_deg(gaze, to);
        let end = t + saccade_duration_s(amplitude);
        (
            Movement::Saccade {
                from: gaze,
                to,
                amplitude,
            },
            end,
        )
    }

    /// One step of fixation: drift, and now and then a microsaccade.
    fn fixational(
        &self,
        rng: &mut SeededRng,
        space: GazeSpace,
        gaze: Vec2,
        t: f64,
        micro: &mut Option<(f64, Vec2, Vec2, f64)>,
    ) -> Vec2 {
        let dt = 1.0 / TRUTH_HZ;
        if let Some((start, from, to, amplitude)) = *micro {
            let s = (t - start) / saccade_duration_s(amplitude);
            if s < 1.0 {
                return space.rotate_towards(from, to, amplitude * min_jerk(s));
            }
            *micro = None;
        }
        if (rng.uniform() as f64) < self.microsaccades_per_s * dt {
            let amplitude = rng.between(0.1, 0.5);
            let a = rng.between(0.0, std::f64::consts::TAU);
            let to = gaze + Vec2::new(a.cos() as f32, a.sin() as f32) * 0.05;
            let to = space.rotate_towards(gaze, to, amplitude);
            *micro = Some((t, gaze, to, amplitude));
            return gaze;
        }
        let sigma = self.drift_deg_per_sqrt_s * dt.sqrt();
        let (dx, dy) = (rng.normal() * sigma, rng.normal() * sigma);
        let right = space.rotate_towards(gaze, gaze + Vec2::X * 0.05, dx.abs());
        let up = space.rotate_towards(gaze, gaze + Vec2::Y * 0.05, dy.abs());
        let step = (right - gaze) * dx.signum() as f32 + (up - gaze) * dy.signum() as f32;
        (gaze + step).clamp(-Vec2::ONE, Vec2::ONE)
    }
}

impl EyeTrace {
    /// The true gaze at `t` (the latest sample at or before it; the first before the trace).
    pub fn at(&self, t: f64) -> Vec2 {
        let i = self.truth.partition_point(|s| s.t <= t + 1e-9);
        self.truth[i.saturating_sub(1)].left
    }

    /// What a tracker sampling at `rate` Hz reports: the truth at each sample time.
    pub fn sampled(&self, rate: f64) -> Vec<GazeSample> {
        let end = self.truth.last().map_or(0.0, |s| s.t);
        (0..)
            .map(|k| k as f64 / rate)
            .take_while(|&t| t <= end)
            .map(|t| {
                let i = ((t * TRUTH_HZ).round() as usize).min(self.truth.len() - 1);
                GazeSample { t, ..self.truth[i] }
            })
            .collect()
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    /// Every gaze shift of the large-saccade trace is one saccade of 15–30°, landing inside
    /// the field; between them the gaze holds. Mutation: the amplitude drawn but not used (a
    /// fixed step), or the profile never reaching 1, fails it.
    #[test]
    fn large_saccades_jump_15_to_30_degrees_and_hold_between() {
        let space = space();
        let trace = large_saccade_trace(space, 3.0, 90.0, (15.0, 30.0), 5);
        assert_eq!(trace.len(), 270);
        // Fixations: runs of equal gaze (two frames or more).
        let mut fixations = vec![trace[0]];
        for w in trace.windows(3) {
            if w[1] == w[2] && w[1] != *fixations.last().unwrap() {
                fixations.push(w[1]);
            }
        }
        assert!(fixations.len() >= 6, "{} fixations in 3 s", fixations.len());
        for pair in fixations.windows(2) {
            let jump = space.angle_deg(pair[0], pair[1]);
            assert!((14.9..=30.1).contains(&jump), "a saccade of {jump}°");
            assert!(
                pair[1].x.abs() <= 0.8 && pair[1].y.abs() <= 0.6,
                "{:?}",
                pair[1]
            );
        }
    }

    fn space() -> GazeSpace {
        GazeSpace {
            fov: FovTangents::from_angles_deg(52.0, 44.0, 48.0, 48.0),
        }
    }

    #[test]
    fn directions_round_trip_and_rotation_is_exact() {
        let s = space();
        for g in [Vec2::ZERO, Vec2::new(0.7, -0.4), Vec2::new(-0.9, 0.95)] {
            assert!((s.normalised(s.direction(g)) - g).length() < 1e-5, "{g}");
        }
        let (a, b) = (Vec2::new(-0.3, 0.2), Vec2::new(0.5, -0.1));
        let c = s.rotate_towards(a, b, 7.5);
        assert!((s.angle_deg(a, c) - 7.5).abs() < 1e-3);
        let along = s.angle_deg(a, c) + s.angle_deg(c, b);
        assert!(
            (along - s.angle_deg(a, b)).abs() < 1e-3,
            "on the great circle"
        );
    }

    /// The model's saccades, measured from its own samples, follow the cited main sequence:
    /// duration 2.2 ms/° · A + 21 ms and peak velocity 1.875 · A / D. Mutation: a saccade that
    /// moves linearly (peak = mean velocity) or a duration off by 10 ms fails it.
    #[test]
    fn generated_saccades_follow_the_main_sequence() {
        let s = space();
        let trace = EyeMovementModel::default().simulate(s, 20.0, 11);
        assert!(
            trace.saccades.len() >= 20,
            "{} saccades",
            trace.saccades.len()
        );
        for e in &trace.saccades {
            let i0 = (e.onset_s * TRUTH_HZ).round() as usize;
            let i1 = ((e.landing_s * TRUTH_HZ).round() as usize).min(trace.truth.len() - 1);
            let g = |i: usize| trace.truth[i].left;
            let amplitude = s.angle_deg(g(i0), g(i1));
            assert!(
                (amplitude - e.amplitude_deg).abs() < 0.2,
                "{amplitude} vs {e:?}"
            );
            let duration = e.landing_s - e.onset_s;
            let expected = 0.0022 * amplitude + 0.021;
            assert!(
                (duration - expected).abs() < 0.0015,
                "{duration} vs {expected}"
            );
            let peak = (i0..i1)
                .map(|i| s.angle_deg(g(i), g(i + 1)) * TRUTH_HZ)
                .fold(0.0, f64::max);
            let expected = 1.875 * amplitude / expected;
            assert!(
                (peak / expected - 1.0).abs() < 0.03,
                "{peak} vs {expected} °/s"
            );
        }
        let small = trace.saccades.iter().filter(|e| e.amplitude_deg <= 15.0);
        let fraction = small.count() as f64 / trace.saccades.len() as f64;
        assert!(fraction > 0.6, "{fraction} of saccades ≤ 15°");
    }

    #[test]
    fn traces_are_reproducible_stay_in_view_and_blink() {
        let model = EyeMovementModel::default();
        let trace = model.simulate(space(), 30.0, 5);
        assert_eq!(trace, model.simulate(space(), 30.0, 5), "deterministic");
        assert_ne!(trace.truth, model.simulate(space(), 30.0, 6).truth);
        assert!(trace
            .truth
            .iter()
            .all(|s| s.left.is_finite() && s.left.abs().max_element() <= 1.0));
        let invalid = trace.truth.iter().filter(|s| !s.valid).count() as f64 / TRUTH_HZ;
        // ≈ 17 blinks a minute of 150 ms: ≈ 1.3 s in 30 s.
        assert!(
            (0.3..3.0).contains(&invalid),
            "{invalid} s with the eye closed"
        );
        let sampled = trace.sampled(120.0);
        assert_eq!(sampled.len(), 3600);
        assert_eq!(sampled[120].t, 1.0);
        assert_eq!(sampled[120].left, trace.at(1.0));
    }

    #[test]
    fn the_main_sequence_inverts() {
        for a in [0.5, 5.0, 20.0, 40.0] {
            let v = saccade_peak_velocity(a);
            assert!((amplitude_for_peak_velocity(v).unwrap() - a).abs() < 1e-9);
        }
        assert_eq!(amplitude_for_peak_velocity(900.0), None);
    }
}
