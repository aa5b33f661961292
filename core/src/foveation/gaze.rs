//! Gaze input: trace files, simulated traces, and a filter that turns bad samples into a
//! sensible gaze instead of a panic.

use std::path::Path;

use glam::Vec2;

use crate::vocab::{read_bounded, ConfigError};

/// Largest gaze trace read: an hour at 1000 Hz is about 150 MB.
const MAX_TRACE_BYTES: u64 = 1 << 30;

/// One eye-tracker sample: time in seconds, each eye's gaze in normalised image coordinates
/// (−1…1, x right, y up; 0 is the image centre), and the tracker's validity flag.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct GazeSample {
    /// Time in seconds.
    pub t: f64,
    /// The left eye's gaze.
    pub left: Vec2,
    /// The right eye's gaze.
    pub right: Vec2,
    /// The tracker's validity flag (false while the eye is closed or lost).
    pub valid: bool,
}

#[derive(Debug, thiserror::Error)]
/// Why a gaze trace could not be read.
pub enum GazeError {
    /// The cause is in the message (not a separate source), so an error chain says it once.
    #[error("gaze trace {path}: {why}")]
    Io {
        /** The trace file. */
        path: String,
        /** What went wrong. */
        why: String,
    },
    #[error("gaze trace {path}, line {line}: {message} (expected `time,left_x,left_y,right_x,right_y,valid`)")]
    /// A line is not a sample.
    Parse {
        /// The trace file.
        path: String,
        /// The line, from 1.
        line: usize,
        /// What is wrong with it.
        message: String,
    },
    #[error("gaze trace {path}: {usable} usable samples of {samples} (valid, finite, in -1..1); a trace needs at least two")]
    /// Fewer than two usable samples.
    TooFewSamples {
        /// The trace file.
        path: String,
        /// Samples read.
        samples: usize,
        /// Of those, usable ones.
        usable: usize,
    },
}

/// Reads a CSV trace: `time,left_x,left_y,right_x,right_y,valid` per line, an optional header,
/// `#` comments. Times must not go backwards. NaN coordinates are accepted (the filter handles
/// them); malformed lines are errors naming the line, and a trace with fewer than two usable
/// samples ([`GazeFilter::is_good`]: an empty or header-only file, say) is an error too.
pub fn parse_gaze_csv(path: &Path) -> Result<Vec<GazeSample>, GazeError> {
    let name = path.display().to_string();
    // A regular file of bounded size: `/dev/zero` or a named pipe must not hang the run.
    let bytes =
        read_bounded(path, MAX_TRACE_BYTES, "foveate reads of a gaze trace").map_err(|why| {
            GazeError::Io {
                path: name.clone(),
                why,
            }
        })?;
    let text = String::from_utf8_lossy(&bytes);
    let mut samples: Vec<GazeSample> = Vec::new();
    for (i, line) in text.lines().enumerate() {
        let line = line.trim();
        if line.is_empty()
            || line.starts_with('#')
            || (i == 0 && line.starts_with(|c: char| c.is_alphabetic()))
        {
            continue;
        }
        let err = |message: String| GazeError::Parse {
            path: name.clone(),
            line: i + 1,
            message,
        };
        let fields: Vec<&str> = line.split(',').map(str::trim).collect();
        if fields.len() != 6 {
            return Err(err(format!("{} fields", fields.len())));
        }
        let num = |k: usize| {
            fields[k]
                .parse::<f64>()
                .map_err(|_| err(format!("field {} = `{}` is not a number", k + 1, fields[k])))
        };
        let valid = match fields[5] {
            "1" | "true" => true,
            "0" | "false" => false,
            v => return Err(err(format!("valid = `{v}`: 0/1 or true/false"))),
        };
        let t = num(0)?;
        if !t.is_finite() || samples.last().is_some_and(|s| t < s.t) {
            return Err(err(format!(
                "time = {t}: finite and not before the previous sample"
            )));
        }
        let v = |a: usize| Ok::<_, GazeError>(Vec2::new(num(a)? as f32, num(a + 1)? as f32));
        samples.push(GazeSample {
            t,
            left: v(1)?,
            right: v(3)?,
            valid,
        });
    }
    let usable = samples.iter().filter(|s| GazeFilter::is_good(s)).count();
    if usable < 2 {
        return Err(GazeError::TooFewSamples {
            path: name,
            samples: samples.len(),
            usable,
        });
    }
    Ok(samples)
}

/// Checks a gaze the renderer is handed (`Renderer::set_gaze`, the CLI's `--gaze`): each
/// component finite and within −1…1, the view's edges. The one policy everywhere: a bad gaze is
/// an error naming the eye, the value and the limit, never clamped or passed on silently. Raw
/// tracker samples, which are bad now and then by nature, go through a [`GazeFilter`] first.
pub fn check_gaze(gaze: [Vec2; 2]) -> Result<(), ConfigError> {
    for (eye, g) in ["left gaze", "right gaze"].into_iter().zip(gaze) {
        if !g.is_finite() {
            return Err(ConfigError::new(
                eye,
                format!("{},{}", g.x, g.y),
                "finite numbers in -1..1 (filter raw tracker samples with GazeFilter)",
            ));
        }
        if g.x.abs() > 1.0 || g.y.abs() > 1.0 {
            return Err(ConfigError::new(
                eye,
                format!("{},{}", g.x, g.y),
                "X and Y in -1..1 (the view's edges)",
            ));
        }
    }
    Ok(())
}

/// Turns raw samples into the gaze to render with: a sample that is invalid, NaN or outside
/// −1…1 is replaced by the last good gaze; after `timeout` seconds without a good one, the gaze
/// returns to the centre.
#[derive(Clone, Debug, PartialEq)]
pub struct GazeFilter {
    /// Seconds without a good sample before the gaze returns to the centre.
    pub timeout: f64,
    last_good: Option<(f64, [Vec2; 2])>,
}

impl GazeFilter {
    /// A filter that returns to the centre after `timeout` seconds without a good sample.
    pub fn new(timeout: f64) -> Self {
        GazeFilter {
            timeout,
            last_good: None,
        }
    }

    /// Whether a sample is one the filter passes through: valid, finite and inside −1…1.
    pub fn is_good(s: &GazeSample) -> bool {
        let ok = |v: Vec2| v.is_finite() && v.x.abs() <= 1.0 && v.y.abs() <= 1.0;
        s.valid && ok(s.left) && ok(s.right)
    }

    /// The gaze to render with after sample `s`, each eye.
    pub fn update(&mut self, s: &GazeSample) -> [Vec2; 2] {
        if Self::is_good(s) {
            self.last_good = Some((s.t, [s.left, s.right]));
            return [s.left, s.right];
        }
        match self.last_good {
            Some((t, gaze)) if s.t - t <= self.timeout => gaze,
            _ => [Vec2::ZERO; 2],
        }
    }
}

/// A deterministic simulated trace at `rate` Hz for `seconds`: fixations of 200–400 ms joined by
/// 40 ms linear saccades, both eyes together — the simple trace `flicker` measures along (its
/// published figures were made with it); `EyeMovementModel` is the realistic eye.
pub fn simulated_trace(seconds: f64, rate: f64, seed: u32) -> Vec<GazeSample> {
    let mut rng = super::SeededRng::new(seed);
    let mut next = || rng.uniform();
    let mut target = Vec2::ZERO;
    let mut from = Vec2::ZERO;
    let (mut fixation_end, mut saccade_end) = (0.0, 0.0);
    let n = (seconds * rate).round() as usize;
    (0..n)
        .map(|i| {
            let t = i as f64 / rate;
            if t >= fixation_end {
                from = target;
                target = Vec2::new(next() * 1.6 - 0.8, next() * 1.2 - 0.6);
                saccade_end = t + 0.04;
                fixation_end = saccade_end + 0.2 + 0.2 * next() as f64;
            }
            let k = if t < saccade_end {
                (1.0 - (saccade_end - t) / 0.04) as f32
            } else {
                1.0
            };
            let g = from.lerp(target, k);
            GazeSample {
                t,
                left: g,
                right: g,
                valid: true,
            }
        })
        .collect()
}

#[cfg(test)]
mod tests {
    use super::*;

    fn sample(t: f64, x: f32, valid: bool) -> GazeSample {
        GazeSample {
            t,
            left: Vec2::new(x, 0.1),
            right: Vec2::new(x, 0.1),
            valid,
        }
    }

    #[test]
    fn bad_samples_fall_back_to_last_good_then_centre() {
        let mut f = GazeFilter::new(0.5);
        assert_eq!(
            f.update(&sample(0.0, f32::NAN, true)),
            [Vec2::ZERO; 2],
            "nothing good yet: centre"
        );
        assert_eq!(f.update(&sample(0.1, 0.4, true))[0], Vec2::new(0.4, 0.1));
        assert_eq!(
            f.update(&sample(0.2, f32::NAN, true))[0],
            Vec2::new(0.4, 0.1),
            "NaN"
        );
        assert_eq!(
            f.update(&sample(0.3, 3.0, true))[0],
            Vec2::new(0.4, 0.1),
            "out of range"
        );
        assert_eq!(
            f.update(&sample(0.4, 0.2, false))[0],
            Vec2::new(0.4, 0.1),
            "invalid"
        );
        assert_eq!(
            f.update(&sample(0.7, f32::INFINITY, true)),
            [Vec2::ZERO; 2],
            "timed out: centre"
        );
        assert_eq!(
            f.update(&sample(0.8, -0.3, true))[0],
            Vec2::new(-0.3, 0.1),
            "recovers"
        );
    }

    #[test]
    fn csv_round_trip_and_errors_name_the_line() {
        let dir = std::env::temp_dir().join(format!("foveate-gaze-{}", std::process::id()));
        std::fs::create_dir_all(&dir).unwrap();
        let good = dir.join("good.csv");
        std::fs::write(
            &good,
            "time,lx,ly,rx,ry,valid\n# comment\n0.0,0.1,0.2,0.1,0.2,1\n0.01,NaN,0,0,0,0\n0.02,0.1,0.2,0.1,0.2,1\n",
        )
        .unwrap();
        let s = parse_gaze_csv(&good).unwrap();
        assert_eq!(s.len(), 3);
        assert!(s[1].left.x.is_nan() && !s[1].valid);
        let bad = dir.join("bad.csv");
        std::fs::write(&bad, "0.0,0.1,0.2,0.1,0.2,1\n0.01,x,0,0,0,1\n").unwrap();
        let e = parse_gaze_csv(&bad).unwrap_err().to_string();
        assert!(e.contains("line 2") && e.contains("`x`"), "{e}");
        std::fs::write(&bad, "0.5,0,0,0,0,1\n0.1,0,0,0,0,1\n").unwrap();
        assert!(parse_gaze_csv(&bad)
            .unwrap_err()
            .to_string()
            .contains("line 2"));
        assert!(parse_gaze_csv(&dir.join("missing.csv"))
            .unwrap_err()
            .to_string()
            .contains("missing.csv"));
        // Empty, header-only, and one usable sample among bad ones: too few to follow.
        for (text, samples, usable) in [
            ("", 0, 0),
            ("time,lx,ly,rx,ry,valid\n", 0, 0),
            (
                "0,0.1,0.2,0.1,0.2,1\n0.01,NaN,0,0,0,1\n0.02,9,9,9,9,1\n",
                3,
                1,
            ),
        ] {
            std::fs::write(&bad, text).unwrap();
            let e = parse_gaze_csv(&bad).unwrap_err().to_string();
            let expected = format!("{usable} usable samples of {samples}");
            assert!(e.contains(&expected) && e.contains("at least two"), "{e}");
        }
        let _ = std::fs::remove_dir_all(dir);
    }

    #[test]
    fn simulated_traces_fixate_and_saccade_within_range() {
        let trace = simulated_trace(3.0, 120.0, 7);
        assert_eq!(trace.len(), 360);
        assert!(trace
            .iter()
            .all(|s| s.valid && s.left.abs().max_element() <= 1.0));
        let jumps = trace
            .windows(2)
            .filter(|w| (w[1].left - w[0].left).length() > 0.01)
            .count();
        assert!(jumps > 10 && jumps < 200, "{jumps} moving samples");
        assert_eq!(trace, simulated_trace(3.0, 120.0, 7), "deterministic");
    }
}
