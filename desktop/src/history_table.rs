//! What became of the accumulated periphery's history along a motion (`render::HistoryOutcomes`,
//! counted by counting frames): the share of pixels per outcome and region over every frame,
//! the worst frame's rejected share, and every frame's counts as CSV.

use std::path::Path;

use anyhow::Result;
use foveate::metrics::Region;
use foveate::render::{HistoryOutcome, HistoryOutcomes};

use crate::csv_out::CsvTable;

/// One accumulated configuration's outcomes along one motion, frame by frame (its history
/// settled before the motion's first frame).
pub struct OutcomesAlong {
    pub motion: &'static str,
    pub config: String,
    pub frames: Vec<HistoryOutcomes>,
}

impl OutcomesAlong {
    fn sum(&self) -> HistoryOutcomes {
        let mut sum = HistoryOutcomes::default();
        self.frames.iter().for_each(|f| sum.add(f));
        sum
    }

    /// The largest share of `region`'s accumulated pixels one frame rejected, and which frame.
    fn worst(&self, region: Region) -> (f64, usize) {
        let rejected = |f: &HistoryOutcomes| -> f64 {
            (HistoryOutcome::ALL.iter())
                .filter(|o| o.rejected())
                .map(|&o| f.share(o, region))
                .sum()
        };
        (self.frames.iter().enumerate())
            .map(|(i, f)| (rejected(f), i))
            .fold((0.0, 0), |a, b| if b.0 > a.0 { b } else { a })
    }
}

/// The outcomes shown as columns: every one but the hole (not accumulated).
fn columns() -> impl Iterator<Item = HistoryOutcome> {
    (HistoryOutcome::ALL.into_iter()).filter(|&o| o != HistoryOutcome::Hole)
}

pub fn print(runs: &[OutcomesAlong]) {
    if runs.is_empty() {
        return;
    }
    let width = runs.iter().map(|r| r.config.len()).max().unwrap_or(0);
    let header: Vec<String> = columns().map(|o| format!("{:>11}", o.name())).collect();
    println!(
        "\nhistory (accumulated rows, counting frames):\n{:<14} {:<width$} {:<9} {} {:>13}",
        "motion",
        "configuration",
        "region",
        header.join(" "),
        "worst frame"
    );
    for run in runs {
        let sum = run.sum();
        for region in Region::ALL {
            let shares: Vec<String> = columns()
                .map(|o| format!("{:>10.2}%", 100.0 * sum.share(o, region)))
                .collect();
            let (worst, frame) = run.worst(region);
            println!(
                "{:<14} {:<width$} {:<9} {} {:>8.2}% ({frame})",
                run.motion,
                run.config,
                region.name(),
                shares.join(" "),
                100.0 * worst,
            );
        }
    }
    println!(
        "(history: what each accumulated pixel did with the history, as a share of the region's accumulated pixels over every frame of the motion, both eyes. kept: used as it was; clipped: used, clipped towards the periphery's neighbourhood; from fovea: used, and it held what the fovea showed over the periphery's hole; reset: the whole history dropped; off-screen: the frame before did not see that direction; disoccluded: the frame before saw another surface there (the depth test); empty: the history there held nothing; beyond reach: past the accumulation's reach, the frame's periphery shown as it is. worst frame: the largest share one frame dropped (reset, off-screen, disoccluded or empty), and which frame (from 0). Regions at each frame's gaze; the fovea region's pixels accumulate under the fovea, unseen. Counting frames count with atomics: the accumulated rows' rendering time is no timing)"
    );
}

/// Every frame's counts, a row per motion, configuration, frame and outcome, to `path`.
pub fn write_csv(runs: &[OutcomesAlong], path: &Path) -> Result<()> {
    let mut csv = CsvTable::new(&[
        "motion",
        "config",
        "frame",
        "outcome",
        "fovea",
        "band",
        "periphery",
    ])?;
    for run in runs {
        for (i, frame) in run.frames.iter().enumerate() {
            for outcome in HistoryOutcome::ALL {
                let [fovea, band, periphery] = Region::ALL.map(|r| frame.get(outcome, r));
                csv.row(&[
                    &run.motion,
                    &run.config,
                    &i,
                    &outcome.name(),
                    &fovea,
                    &band,
                    &periphery,
                ])?;
            }
        }
    }
    csv.save(Some(path))
}
