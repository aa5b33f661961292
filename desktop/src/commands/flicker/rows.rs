//! The rows of `foveate flicker`: one configuration along one motion, printed and as CSV.

use anyhow::Result;
use foveate::metrics::temporal::FlickerSummary;
use foveate::metrics::ErrorSummary;

use crate::commands::motion_frontier::MotionPoint;
use crate::counts::mib;
use crate::csv_out::{opt, CsvTable};
use crate::history_table::OutcomesAlong;

/// The rows as CSV, to `path` or stdout.
pub(super) fn write_csv(results: &[Row], path: Option<&std::path::Path>) -> Result<()> {
    let mut csv = CsvTable::new(&[
        "motion",
        "config",
        "frame_ms",
        "x_ref",
        "external_traffic_bytes",
        "changes",
        "flicker_mean",
        "flicker_p99",
        "flicker_mean_fovea",
        "flicker_mean_band",
        "flicker_mean_periphery",
        "eflip_mean",
        "eflip_p99",
        "eflip_p99_worst",
        "eflip_p99_fovea",
        "eflip_p99_band",
        "eflip_p99_periphery",
    ])?;
    for row in results {
        let (s, a) = (&row.flicker, row.accuracy);
        let mean = |e: Option<ErrorSummary>| opt(e.map(|e| e.mean), 6);
        csv.row(&[
            &row.motion,
            &row.name,
            &opt(row.frame_ms, 3),
            &opt(row.ratio, 4),
            &row.traffic_bytes,
            &s.changes,
            &mean(s.all),
            &opt(s.all.map(|e| e.p99), 6),
            &mean(s.regions[0]),
            &mean(s.regions[1]),
            &mean(s.regions[2]),
            &opt(a.map(|a| a.mean), 6),
            &opt(a.map(|a| a.p99), 6),
            &opt(a.map(|a| a.worst_p99), 6),
            &opt(a.and_then(|a| a.region_p99[0]), 6),
            &opt(a.and_then(|a| a.region_p99[1]), 6),
            &opt(a.and_then(|a| a.region_p99[2]), 6),
        ])?;
    }
    csv.save(path)
}

/// One configuration along one motion.
pub(super) struct Row {
    pub(super) motion: &'static str,
    pub(super) name: String,
    pub(super) flicker: FlickerSummary,
    pub(super) accuracy: Option<AlongMotion>,
    /// What became of the history, frame by frame (`--history-outcomes`, accumulated rows).
    pub(super) history: Option<OutcomesAlong>,
    pub(super) foveated: bool,
    /// The median frame time along the motion, and over the reference's (counting rows: none).
    pub(super) frame_ms: Option<f64>,
    pub(super) ratio: Option<f64>,
    /// What a tile GPU would move per frame by the plan's rule (a formula, not a measurement).
    pub(super) traffic_bytes: u64,
}

impl Row {
    /// The row as a point of its motion's frontier, when judged.
    pub(super) fn point(&self) -> Option<MotionPoint> {
        let accuracy = self.accuracy?;
        Some(MotionPoint {
            name: self.name.clone(),
            foveated: self.foveated,
            frame_ms: self.frame_ms,
            ratio: self.ratio,
            eflip_mean: accuracy.mean,
            eflip_p99: accuracy.p99,
        })
    }
}

/// A judged frame's eccentricity-aware FLIP: over every pixel the lens shows, and per region
/// at the frame's gaze (`Region::ALL`'s order; none where the region has no pixel).
pub(super) type Judged = (ErrorSummary, [Option<ErrorSummary>; 3]);

/// The eccentricity-aware FLIP of a configuration's frames along a motion: the means over the
/// frames of each frame's mean and 99th percentile, the largest 99th percentile, and the mean
/// of each region's 99th percentile over the frames where it has pixels (where the error is).
#[derive(Clone, Copy)]
pub(super) struct AlongMotion {
    mean: f64,
    p99: f64,
    worst_p99: f64,
    region_p99: [Option<f64>; 3],
}

impl AlongMotion {
    /// `None` when no frame was judged.
    pub(super) fn of(frames: &[Judged]) -> Option<Self> {
        let average = |values: Vec<f64>| {
            let n = values.len() as f64;
            (!values.is_empty()).then(|| values.iter().sum::<f64>() / n)
        };
        let region = |r: usize| {
            average(
                frames
                    .iter()
                    .filter_map(|f| f.1[r])
                    .map(|e| e.p99)
                    .collect(),
            )
        };
        (!frames.is_empty()).then(|| AlongMotion {
            mean: average(frames.iter().map(|f| f.0.mean).collect()).unwrap_or(0.0),
            p99: average(frames.iter().map(|f| f.0.p99).collect()).unwrap_or(0.0),
            worst_p99: frames.iter().map(|f| f.0.p99).fold(0.0, f64::max),
            region_p99: [0, 1, 2].map(region),
        })
    }
}

pub(super) fn print_table(rows: &[Row]) {
    let width = super::super::name_column_width(rows.iter().map(|r| r.name.as_str()));
    let judged = rows.iter().any(|r| r.accuracy.is_some());
    let eflip = match judged {
        true => format!(
            " {:>10} {:>10} {:>10} {:>10} {:>10} {:>10}",
            "eFLIP mean", "eFLIP p99", "worst p99", "p99 fovea", "p99 band", "p99 periph"
        ),
        false => String::new(),
    };
    println!(
        "\n{:<10} {:<width$} {:>9} {:>6} {:>7} {:>10} {:>8} {:>10} {:>10} {:>10}{eflip}",
        "motion",
        "configuration",
        "frame ms",
        "x ref",
        "MiB",
        "mean",
        "p99",
        "fovea",
        "band",
        "periphery"
    );
    let mean = |e: Option<ErrorSummary>| e.map_or("-".to_string(), |e| format!("{:.5}", e.mean));
    for row in rows {
        let s = &row.flicker;
        let eflip = match row.accuracy {
            Some(a) => {
                let region = |r: Option<f64>| r.map_or("-".to_string(), |p| format!("{p:.4}"));
                format!(
                    " {:>10.4} {:>10.4} {:>10.4} {:>10} {:>10} {:>10}",
                    a.mean,
                    a.p99,
                    a.worst_p99,
                    region(a.region_p99[0]),
                    region(a.region_p99[1]),
                    region(a.region_p99[2])
                )
            }
            None => String::new(),
        };
        let time =
            |t: Option<f64>, digits: usize| t.map_or("-".to_string(), |t| format!("{t:.digits$}"));
        println!(
            "{:<10} {:<width$} {:>9} {:>6} {:>7.1} {:>10} {:>8} {:>10} {:>10} {:>10}{eflip}",
            row.motion,
            row.name,
            time(row.frame_ms, 1),
            time(row.ratio, 3),
            mib(row.traffic_bytes),
            mean(s.all),
            s.all.map_or("-".to_string(), |e| format!("{:.4}", e.p99)),
            mean(s.regions[0]),
            mean(s.regions[1]),
            mean(s.regions[2]),
        );
    }
    let untimed = match rows.iter().any(|r| r.frame_ms.is_none()) {
        true => "; -: its frames count --history-outcomes, so they are no timing",
        false => "",
    };
    println!(
        "(time: the median frame time along the motion, every configuration's frames interleaved with the reference's (stereo, MSAA 4), none carrying an instrument; x ref: over the reference's median{untimed}; MiB: what a tile GPU moves per frame by the plan's rule, attachment loads and stores, sampling and readback, a formula as `foveate plan` prints it)"
    );
    println!(
        "(flicker: per pixel and frame, how much more the output's luma (0..1) changed from the previous frame than the reference's (stereo, MSAA 4) did — max(0, |ΔT| − |ΔR|) — over the pixels the lens shows, both eyes; mean and 99th percentile, then the mean per region at each frame's gaze (a stereo row's regions: where the first foveated row puts its fovea); metrics::temporal)"
    );
    if judged {
        println!(
            "(eFLIP: each frame against the reference's frame, the eccentricity-aware FLIP for the eye at that frame's gaze (metrics::flip); the mean over the frames of each frame's mean and 99th percentile, and the worst frame's 99th percentile; then each region's 99th percentile at the frame's gaze, its mean over the frames; a stereo row's regions: where the first foveated row puts its fovea)"
        );
    }
}
