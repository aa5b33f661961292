//! The soak's curves, as PNG and SVG: resident memory over the run with the warm-up's end and
//! the bound above it, and each configuration's frame time (window medians, p99 dashed).

use std::path::Path;

use anyhow::Result;
use plotters::coord::types::RangedCoordf64;
use plotters::coord::Shift;
use plotters::prelude::*;

use super::log::SoakReport;
use crate::commands::bench::plots::{
    legend_and_present, plot_error, plot_files, write_png, FONT, PALETTE,
};
use crate::outputs::plot_file;

const MIB: f64 = 1024.0 * 1024.0;

/// Writes `<stem>.png` and `<stem>.svg`.
pub fn draw(report: &SoakReport, stem: &Path) -> Result<()> {
    let _ = plotters::style::register_font(FONT, FontStyle::Normal, dejavu::sans::regular());
    let (png, svg) = (plot_file(stem, "png"), plot_file(stem, "svg"));
    plot_files!(&png, &svg, (1200, 900), |area| both(report, area));
    println!("wrote {} and {}", png.display(), svg.display());
    Ok(())
}

fn both<DB: DrawingBackend>(report: &SoakReport, root: DrawingArea<DB, Shift>) -> Result<()> {
    root.fill(&WHITE).map_err(plot_error)?;
    let (top, bottom) = root.split_vertically(450);
    memory(report, &top)?;
    frame_times(report, &bottom)?;
    root.present().map_err(plot_error)
}

fn minutes(seconds: f64) -> f64 {
    seconds / 60.0
}

fn x_max(report: &SoakReport) -> f64 {
    report
        .windows
        .last()
        .map_or(1.0, |w| minutes(w.end_s))
        .max(1e-3)
}

/// A chart of minutes (0 to `x_max`) against 0 to `y_max`, its axes drawn.
fn over_minutes<'a, DB: DrawingBackend>(
    area: &DrawingArea<DB, Shift>,
    caption: &str,
    x_max: f64,
    y_max: f64,
) -> Result<ChartContext<'a, DB, Cartesian2d<RangedCoordf64, RangedCoordf64>>> {
    let mut chart = ChartBuilder::on(area)
        .caption(caption, (FONT, 20))
        .margin(12)
        .x_label_area_size(36)
        .y_label_area_size(60)
        .build_cartesian_2d(0.0..x_max, 0.0..y_max)
        .map_err(plot_error)?;
    chart
        .configure_mesh()
        .x_desc("minutes")
        .label_style((FONT, 13))
        .draw()
        .map_err(plot_error)?;
    Ok(chart)
}

fn memory<DB: DrawingBackend>(report: &SoakReport, area: &DrawingArea<DB, Shift>) -> Result<()> {
    let base = report.after.first().map(|&(_, b)| b as f64 / MIB);
    let bound = base.map(|b| b * (1.0 + report.limits.max_growth));
    let peak = report
        .windows
        .iter()
        .map(|w| w.resident as f64 / MIB)
        .fold(bound.unwrap_or(0.0), f64::max);
    let caption =
        "Resident memory, most per window (MiB); dashed: the bound over the warm-up's end";
    let mut chart = over_minutes(area, caption, x_max(report), peak * 1.1)?;
    let points = report
        .windows
        .iter()
        .map(|w| (minutes(w.end_s), w.resident as f64 / MIB));
    chart
        .draw_series(LineSeries::new(points, BLACK.stroke_width(2)))
        .map_err(plot_error)?
        .label("resident")
        .legend(|(x, y)| PathElement::new([(x, y), (x + 20, y)], BLACK.stroke_width(2)));
    if let (Some(bound), Some(&(start, _))) = (bound, report.after.first()) {
        let line = [(minutes(start), bound), (x_max(report), bound)];
        chart
            .draw_series(DashedLineSeries::new(line, 8, 6, RED.stroke_width(2)))
            .map_err(plot_error)?
            .label(format!("+{} % bound", report.limits.max_growth * 100.0))
            .legend(|(x, y)| PathElement::new([(x, y), (x + 20, y)], RED.stroke_width(2)));
    }
    legend_and_present(&mut chart, area)
}

fn frame_times<DB: DrawingBackend>(
    report: &SoakReport,
    area: &DrawingArea<DB, Shift>,
) -> Result<()> {
    // After the warm-up only: its first frames compile pipelines and would flatten the rest.
    let top = report
        .windows
        .iter()
        .filter(|w| !w.warming)
        .flat_map(|w| w.times.iter().map(|t| t.p99_ms))
        .fold(1.0, f64::max);
    let caption = "Frame time per window after the warm-up (GPU, ms): median, p99 dashed";
    let mut chart = over_minutes(area, caption, x_max(report), top * 1.1)?;
    for (k, name) in report.names.iter().enumerate() {
        let colour = PALETTE[k % PALETTE.len()];
        let series = |p99: bool| {
            let after = report.windows.iter().filter(|w| !w.warming);
            after.filter(|w| w.times[k].frames > 0).map(move |w| {
                let t = w.times[k];
                (minutes(w.end_s), if p99 { t.p99_ms } else { t.median_ms })
            })
        };
        chart
            .draw_series(LineSeries::new(series(false), colour.stroke_width(2)))
            .map_err(plot_error)?
            .label(name.as_str())
            .legend(move |(x, y)| PathElement::new([(x, y), (x + 20, y)], colour.stroke_width(2)));
        chart
            .draw_series(DashedLineSeries::new(
                series(true),
                6,
                4,
                colour.stroke_width(1),
            ))
            .map_err(plot_error)?;
    }
    legend_and_present(&mut chart, area)
}
