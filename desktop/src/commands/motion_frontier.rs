//! `foveate flicker --pareto`: per motion, each configuration's eFLIP p99 (the mean over the
//! judged frames) against its frame time along that motion (the median of its frames over the
//! reference's, the frames of every configuration interleaved), stereo and foveated points
//! marked and the Pareto frontier joined: a still frame's frontier, judged in motion.

use std::path::{Path, PathBuf};

use anyhow::Result;

use crate::commands::bench::accuracy::AccuracyPoint;
use crate::commands::bench::plots::accuracy_plot;
use crate::frontier::{pareto_frontier, Point};

/// One configuration along one motion, as the frontier needs it.
pub struct MotionPoint {
    pub name: String,
    pub foveated: bool,
    /// Median frame time over the motion's frames, and over the reference's (`None`: a
    /// counting row, not timed).
    pub frame_ms: Option<f64>,
    pub ratio: Option<f64>,
    /// The eFLIP mean and p99, the means over the judged frames.
    pub eflip_mean: f64,
    pub eflip_p99: f64,
}

/// Where the plot of `motion` goes: `<stem>-<motion>` (its spaces as dashes), `.png` and `.svg`.
pub fn plot_stem(stem: &Path, motion: &str) -> PathBuf {
    let name = stem
        .file_name()
        .map_or(String::new(), |n| n.to_string_lossy().into_owned());
    stem.with_file_name(format!("{name}-{}", motion.replace(' ', "-")))
}

/// Prints one motion's points, the frontier's marked, and plots them to `stem`'s file for the
/// motion.
pub fn report(motion: &str, points: &[MotionPoint], headset: &str, stem: &Path) -> Result<()> {
    let timed: Vec<&MotionPoint> = points.iter().filter(|p| p.ratio.is_some()).collect();
    let xy: Vec<Point> = (timed.iter())
        .map(|p| Point {
            time: p.ratio.unwrap_or(f64::NAN),
            error: p.eflip_p99,
        })
        .collect();
    let frontier = pareto_frontier(&xy);
    println!(
        "\n{motion}: eFLIP p99 against frame time (S stereo, F foveated; * on the Pareto frontier):"
    );
    let width = super::name_column_width(points.iter().map(|p| p.name.as_str()));
    println!(
        "  {:<width$} {:>9} {:>7} {:>8}",
        "configuration", "frame ms", "x ref", "p99"
    );
    for (i, p) in timed.iter().enumerate() {
        let kind = if p.foveated { "F" } else { "S" };
        let mark = if frontier.contains(&i) { "*" } else { " " };
        println!(
            "{kind}{mark}{:<width$} {:>9.1} {:>7.3} {:>8.4}",
            p.name,
            p.frame_ms.unwrap_or(f64::NAN),
            xy[i].time,
            p.eflip_p99
        );
    }
    let untimed: Vec<&str> = (points.iter())
        .filter(|p| p.ratio.is_none())
        .map(|p| p.name.as_str())
        .collect();
    if !untimed.is_empty() {
        println!("  (not timed, counting frames: {})", untimed.join("; "));
    }
    let accuracy: Vec<AccuracyPoint> = (timed.iter().zip(&xy))
        .map(|(p, f)| AccuracyPoint {
            family: if p.foveated { "foveated" } else { "stereo" },
            name: p.name.clone(),
            frame_ms: p.frame_ms.unwrap_or(f64::NAN),
            ratio: f.time,
            psnr_db: None,
            ssim: 1.0,
            flip_mean: p.eflip_mean,
            eccentric_flip_mean: p.eflip_mean,
            eccentric_flip_p99: p.eflip_p99,
        })
        .collect();
    let caption = format!(
        "{headset}, {motion}: eFLIP p99 (mean over judged frames) against frame time, frontier joined"
    );
    let stem = plot_stem(stem, motion);
    accuracy_plot(&accuracy, &caption, &stem)?;
    println!(
        "wrote {} and .svg",
        crate::outputs::plot_file(&stem, "png").display()
    );
    Ok(())
}
