//! What a finished sweep writes: its table as CSV, its plots, its frames.

use anyhow::Result;
use foveate::foveation::SaccadeEvent;
use glam::Vec2;

use super::windows::Summary;
use super::{Frame, FrameError, Sweep, Tracking};
use crate::commands::bench::plots::{latency_plot, LatencyCurve};
use crate::csv_out::{opt, CsvTable};

/// What a finished sweep writes: its table as CSV, its plots, its frames.
pub(super) struct SweepOutputs<'a> {
    pub(super) trackings: &'a [Tracking],
    pub(super) sweep: &'a Sweep<'a>,
    pub(super) frames: &'a [Frame],
    pub(super) saccades: &'a [SaccadeEvent],
    pub(super) shown: &'a [Vec<Vec2>],
    pub(super) judged: &'a [Vec<Vec<FrameError>>],
    pub(super) summaries: &'a [Vec<Summary>],
    pub(super) times: &'a [f64],
    pub(super) budget: f64,
}

impl SweepOutputs<'_> {
    /// One row per tracking and configuration (to `--csv`, or stdout).
    pub(super) fn summary_csv(&self) -> Result<()> {
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
    pub(super) fn plots(&self, stem: &std::path::Path) -> Result<()> {
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
    pub(super) fn frames_csv(&self, path: &std::path::Path) -> Result<()> {
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
