//! What a soak measured: resident memory after every round of frames, each configuration's
//! frame times, gathered into windows; and the verdict on them (growth after the warm-up, the
//! frame time's p99 over its median in every window after it).

use std::fmt;
use std::time::Duration;

use anyhow::Result;

use crate::csv_out::CsvTable;

const MIB: f64 = 1024.0 * 1024.0;

/// What the run is held to.
#[derive(Clone, Copy, Debug)]
pub struct Limits {
    /// The warm-up, a fraction of the run.
    pub warm_up: f64,
    /// The most resident memory may grow after the warm-up, a fraction of its level then.
    pub max_growth: f64,
    /// The most a window's frame time p99 may be over its median (0: not judged).
    pub max_p99: f64,
    /// How long a window lasts.
    pub window: Duration,
}

/// A configuration's frame times in one window.
#[derive(Clone, Copy, Debug, Default)]
pub struct FrameTimes {
    pub frames: usize,
    pub median_ms: f64,
    pub p99_ms: f64,
}

/// One window of the run.
#[derive(Clone, Debug)]
pub struct Window {
    /// Seconds from the start to the window's end.
    pub end_s: f64,
    /// Whether any of its rounds was in the warm-up.
    pub warming: bool,
    /// The most resident memory sampled in it, in bytes.
    pub resident: u64,
    /// Each configuration's frame times.
    pub times: Vec<FrameTimes>,
    /// The median wall time of a round (one frame of each configuration), in milliseconds.
    pub round_ms: f64,
}

/// Samples as they come, and the windows closed so far.
pub struct SoakLog {
    names: Vec<String>,
    limits: Limits,
    validation: bool,
    windows: Vec<Window>,
    frames: Vec<Vec<f64>>,
    round_ms: Vec<f64>,
    resident: u64,
    warming: bool,
    window_end: Duration,
    /// Resident memory after the warm-up: seconds and bytes of each round's sample.
    after: Vec<(f64, u64)>,
    rounds: u64,
    elapsed: Duration,
}

impl SoakLog {
    pub fn new(names: Vec<String>, limits: Limits, validation: bool) -> Self {
        let n = names.len();
        SoakLog {
            names,
            limits,
            validation,
            windows: Vec::new(),
            frames: vec![Vec::new(); n],
            round_ms: Vec::new(),
            resident: 0,
            warming: false,
            window_end: limits.window,
            after: Vec::new(),
            rounds: 0,
            elapsed: Duration::ZERO,
        }
    }

    pub fn limits(&self) -> Limits {
        self.limits
    }

    /// A finished frame of configuration `k` took `ms`.
    pub fn frame(&mut self, k: usize, ms: f64) {
        self.frames[k].push(ms);
    }

    /// A round ended `elapsed` into the run after `took`, with `resident` bytes resident;
    /// `warming`: it began in the warm-up.
    pub fn round(&mut self, elapsed: Duration, took: Duration, resident: u64, warming: bool) {
        self.round_ms.push(took.as_secs_f64() * 1e3);
        self.resident = self.resident.max(resident);
        self.warming |= warming;
        if !warming {
            self.after.push((elapsed.as_secs_f64(), resident));
        }
        self.rounds += 1;
        self.elapsed = elapsed;
    }

    /// Closes the window once `elapsed` has passed its end; returns its line of progress.
    pub fn window_done(&mut self, elapsed: Duration) -> Option<String> {
        if elapsed < self.window_end {
            return None;
        }
        self.close(elapsed);
        while self.window_end <= elapsed {
            self.window_end += self.limits.window;
        }
        let w = self.windows.last()?;
        let growth = match (w.warming, self.after.first()) {
            (false, Some(&(_, base))) => format!(" ({:+.1} %)", percent(w.resident, base)),
            _ => " (warm-up)".to_string(),
        };
        let times: Vec<String> = self
            .names
            .iter()
            .zip(&w.times)
            .map(|(name, t)| format!("{name} {:.1}/{:.1}", t.median_ms, t.p99_ms))
            .collect();
        Some(format!(
            "{:>8}  resident {:.1} MiB{growth}  frame ms median/p99: {}",
            clock(w.end_s),
            w.resident as f64 / MIB,
            times.join(" · ")
        ))
    }

    fn close(&mut self, elapsed: Duration) {
        let times = self
            .frames
            .iter_mut()
            .map(std::mem::take)
            .map(|f| frame_times(&f))
            .collect();
        self.windows.push(Window {
            end_s: elapsed.as_secs_f64(),
            warming: self.warming,
            resident: self.resident,
            times,
            round_ms: median(&std::mem::take(&mut self.round_ms)),
        });
        self.resident = 0;
        self.warming = false;
    }

    /// The report: the last window closed if it holds any round.
    pub fn finish(mut self) -> SoakReport {
        if !self.round_ms.is_empty() {
            self.close(self.elapsed);
        }
        SoakReport {
            names: self.names,
            limits: self.limits,
            validation: self.validation,
            windows: self.windows,
            after: self.after,
            rounds: self.rounds,
            elapsed: self.elapsed,
        }
    }
}

/// A finished soak.
pub struct SoakReport {
    pub names: Vec<String>,
    pub limits: Limits,
    validation: bool,
    pub windows: Vec<Window>,
    /// Resident memory after the warm-up: seconds and bytes of each round's sample.
    pub after: Vec<(f64, u64)>,
    rounds: u64,
    elapsed: Duration,
}

/// How memory went after the warm-up.
struct Growth {
    /// The first sample after the warm-up: seconds, bytes.
    base: (f64, u64),
    /// The largest after it.
    peak: (f64, u64),
    /// The least-squares trend, bytes per minute.
    per_minute: f64,
}

impl SoakReport {
    fn growth(&self) -> Option<Growth> {
        let &base = self.after.first()?;
        let &peak = self.after.iter().max_by_key(|(_, b)| *b)?;
        Some(Growth {
            base,
            peak,
            per_minute: slope(&self.after) * 60.0,
        })
    }

    /// Each configuration's worst window after the warm-up: its p99 over its median, and when.
    fn worst_p99(&self) -> Vec<Option<(f64, f64)>> {
        (0..self.names.len())
            .map(|k| {
                self.windows
                    .iter()
                    .filter(|w| !w.warming && w.times[k].frames > 0)
                    .map(|w| (w.times[k].p99_ms / w.times[k].median_ms, w.end_s))
                    .max_by(|a, b| a.0.total_cmp(&b.0))
            })
            .collect()
    }

    /// Passed, or an error naming every limit the run broke.
    pub fn verdict(&self) -> Result<()> {
        let mut broken = Vec::new();
        match self.growth() {
            None => broken.push(
                "the run ended within its warm-up: no memory after it to judge (run longer)"
                    .to_string(),
            ),
            Some(g) if percent(g.peak.1, g.base.1) > self.limits.max_growth * 100.0 => {
                broken.push(format!(
                    "resident memory grew {:+.1} % after the warm-up ({:.1} MiB at {} to {:.1} MiB at {}; {:+.2} MiB a minute), beyond the bound of +{} %",
                    percent(g.peak.1, g.base.1),
                    g.base.1 as f64 / MIB,
                    clock(g.base.0),
                    g.peak.1 as f64 / MIB,
                    clock(g.peak.0),
                    g.per_minute / MIB,
                    self.limits.max_growth * 100.0
                ))
            }
            Some(_) => {}
        }
        if self.limits.max_p99 > 0.0 {
            for (name, worst) in self.names.iter().zip(self.worst_p99()) {
                if let Some((ratio, at)) = worst.filter(|w| w.0 > self.limits.max_p99) {
                    broken.push(format!(
                        "{name}: frame time p99 {ratio:.2}x its median in the window ending at {}, beyond {}x",
                        clock(at),
                        self.limits.max_p99
                    ));
                }
            }
        }
        match broken.is_empty() {
            true => Ok(()),
            false => anyhow::bail!("the soak failed: {}", broken.join("; ")),
        }
    }

    /// A row per window and configuration.
    pub fn csv(&self) -> Result<CsvTable> {
        let mut table = CsvTable::new(&[
            "elapsed_s",
            "warm_up",
            "resident_mib",
            "round_ms_median",
            "config",
            "frames",
            "frame_ms_median",
            "frame_ms_p99",
        ])?;
        for w in &self.windows {
            for (name, t) in self.names.iter().zip(&w.times) {
                table.row(&[
                    &format!("{:.1}", w.end_s),
                    &u8::from(w.warming),
                    &format!("{:.2}", w.resident as f64 / MIB),
                    &format!("{:.2}", w.round_ms),
                    name,
                    &t.frames,
                    &format!("{:.3}", t.median_ms),
                    &format!("{:.3}", t.p99_ms),
                ])?;
            }
        }
        Ok(table)
    }
}

impl fmt::Display for SoakReport {
    fn fmt(&self, f: &mut fmt::Formatter<'_>) -> fmt::Result {
        writeln!(
            f,
            "ran {} rounds in {} (each round a frame of every configuration)",
            self.rounds,
            clock(self.elapsed.as_secs_f64())
        )?;
        match self.growth() {
            Some(g) => writeln!(
                f,
                "resident memory: {:.1} MiB at the warm-up's end ({}), at most {:.1} MiB after ({:+.1} %, bound +{} %); trend {:+.2} MiB a minute",
                g.base.1 as f64 / MIB,
                clock(g.base.0),
                g.peak.1 as f64 / MIB,
                percent(g.peak.1, g.base.1),
                self.limits.max_growth * 100.0,
                g.per_minute / MIB
            )?,
            None => writeln!(f, "resident memory: no sample after the warm-up")?,
        }
        writeln!(
            f,
            "frame time (GPU, timestamps), worst window after the warm-up, p99 over median (bound {}):",
            match self.limits.max_p99 {
                m if m > 0.0 => format!("{m}x"),
                _ => "none".to_string(),
            }
        )?;
        let all: Vec<Vec<f64>> = (0..self.names.len())
            .map(|k| {
                self.windows
                    .iter()
                    .filter(|w| !w.warming)
                    .map(|w| w.times[k].median_ms)
                    .collect()
            })
            .collect();
        for ((name, worst), medians) in self.names.iter().zip(self.worst_p99()).zip(all) {
            match worst {
                Some((ratio, at)) => writeln!(
                    f,
                    "  {name:<14} {ratio:.2}x (window ending {}); window medians {:.2}–{:.2} ms",
                    clock(at),
                    medians.iter().copied().fold(f64::INFINITY, f64::min),
                    medians.iter().copied().fold(0.0, f64::max)
                )?,
                None => writeln!(f, "  {name:<14} no frame after the warm-up")?,
            }
        }
        write!(
            f,
            "validation: {}",
            match self.validation {
                true => "on, no message",
                false => "off (--validation turns it on)",
            }
        )
    }
}

fn frame_times(ms: &[f64]) -> FrameTimes {
    FrameTimes {
        frames: ms.len(),
        median_ms: median(ms),
        p99_ms: percentile(ms, 0.99),
    }
}

fn median(values: &[f64]) -> f64 {
    percentile(values, 0.5)
}

/// The nearest-rank percentile `p` (0 to 1) of `values`; 0 for none.
fn percentile(values: &[f64], p: f64) -> f64 {
    if values.is_empty() {
        return 0.0;
    }
    let mut sorted = values.to_vec();
    sorted.sort_by(f64::total_cmp);
    let rank = (p * sorted.len() as f64).ceil() as usize;
    sorted[rank.clamp(1, sorted.len()) - 1]
}

/// Growth of `now` over `base`, in percent.
fn percent(now: u64, base: u64) -> f64 {
    (now as f64 / base.max(1) as f64 - 1.0) * 100.0
}

/// The least-squares slope of bytes over seconds.
fn slope(points: &[(f64, u64)]) -> f64 {
    let n = points.len() as f64;
    if n < 2.0 {
        return 0.0;
    }
    let mx = points.iter().map(|p| p.0).sum::<f64>() / n;
    let my = points.iter().map(|p| p.1 as f64).sum::<f64>() / n;
    let sxy: f64 = points.iter().map(|p| (p.0 - mx) * (p.1 as f64 - my)).sum();
    let sxx: f64 = points.iter().map(|p| (p.0 - mx).powi(2)).sum();
    if sxx > 0.0 {
        sxy / sxx
    } else {
        0.0
    }
}

/// Seconds as `m:ss` (or `h:mm:ss`).
fn clock(seconds: f64) -> String {
    let s = seconds.round() as u64;
    match s >= 3600 {
        true => format!("{}:{:02}:{:02}", s / 3600, s / 60 % 60, s % 60),
        false => format!("{}:{:02}", s / 60, s % 60),
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn percentiles_are_nearest_rank() {
        let v: Vec<f64> = (1..=100).map(f64::from).collect();
        assert_eq!(percentile(&v, 0.5), 50.0);
        assert_eq!(percentile(&v, 0.99), 99.0);
        assert_eq!(percentile(&[3.0], 0.99), 3.0);
    }

    #[test]
    fn the_slope_follows_a_line() {
        let points: Vec<(f64, u64)> = (0..10).map(|i| (i as f64, 100 + 7 * i as u64)).collect();
        assert!((slope(&points) - 7.0).abs() < 1e-9);
    }
}
