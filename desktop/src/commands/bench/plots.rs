//! The bench's pictures, each as PNG and SVG: frame times along the rails per configuration
//! (the thesis' Figures 6.2–6.21), the individual optimisations against the baseline and the
//! best configurations, every configuration's ratio to the baseline, and the accuracy-vs-time
//! curve.

use std::path::Path;

use anyhow::Result;
use plotters::coord::Shift;
use plotters::prelude::*;

use super::accuracy::AccuracyPoint;
use super::report::{FrameSample, Report};
use crate::outputs::plot_file;

pub(crate) const FONT: &str = "sans-serif";
const SERIES: [(&str, RGBColor); 4] = [
    ("frame", RGBColor(20, 20, 20)),
    ("gpu", RGBColor(31, 119, 180)),
    ("cpu", RGBColor(255, 127, 14)),
    ("cull", RGBColor(44, 160, 44)),
];
pub(crate) const PALETTE: [RGBColor; 10] = [
    RGBColor(31, 119, 180),
    RGBColor(255, 127, 14),
    RGBColor(44, 160, 44),
    RGBColor(214, 39, 40),
    RGBColor(148, 103, 189),
    RGBColor(140, 86, 75),
    RGBColor(227, 119, 194),
    RGBColor(127, 127, 127),
    RGBColor(188, 189, 34),
    RGBColor(23, 190, 207),
];

pub(crate) fn plot_error<E: std::fmt::Debug>(e: E) -> anyhow::Error {
    anyhow::anyhow!("drawing a plot: {e:?}")
}

/// Draws one plot, `$draw` called with a drawing area, into memory twice (a bitmap, an SVG
/// string) and writes each file atomically: a failed run never leaves a half-drawn plot over
/// the last good one. A macro because the drawing functions are generic over the backend.
macro_rules! plot_files {
    ($png:expr, $svg:expr, $size:expr, $draw:expr) => {{
        let size: (u32, u32) = $size;
        let mut rgb = vec![0u8; size.0 as usize * size.1 as usize * 3];
        $draw(BitMapBackend::with_buffer(&mut rgb, size).into_drawing_area())?;
        write_png(&rgb, size, $png)?;
        let mut svg = String::new();
        $draw(SVGBackend::with_string(&mut svg, size).into_drawing_area())?;
        foveate::write_atomic($svg, svg.as_bytes())?;
    }};
}
pub(crate) use plot_files;

/// An RGB bitmap as a PNG, atomically.
pub(crate) fn write_png(rgb: &[u8], size: (u32, u32), path: &Path) -> Result<()> {
    let data = rgb
        .chunks_exact(3)
        .flat_map(|p| [p[0], p[1], p[2], 255])
        .collect();
    let image = foveate::metrics::RgbaImage {
        width: size.0,
        height: size.1,
        data,
    };
    Ok(image.save(path)?)
}

/// Every plot, as `<name>.png` and `<name>.svg` in `out`.
pub fn all(report: &Report, out: &Path) -> Result<()> {
    // The bitmap backend draws text with a font it is given; DejaVu Sans ships inside the binary.
    let _ = plotters::style::register_font(FONT, FontStyle::Normal, dejavu::sans::regular());
    // Each plot drawn by one generic function, once per backend.
    macro_rules! both {
        ($name:literal, $size:expr, $draw:ident) => {{
            let png = out.join(concat!($name, ".png"));
            let svg = out.join(concat!($name, ".svg"));
            plot_files!(&png, &svg, $size, |area| $draw(report, area));
        }};
    }
    both!("rails", (1800, 1400), rails_grid);
    both!("rails-compare", (1400, 700), rails_compare);
    both!("ratios", (1200, 900), ratios);
    if !report.accuracy.is_empty() {
        accuracy_plot(
            &report.accuracy,
            "What accuracy costs: eccentricity-aware FLIP (99th percentile, lens-visible pixels) against frame time (reference = 1.0, error 0)",
            &out.join("accuracy"),
        )?;
    }
    Ok(())
}

/// The error-against-time plot of `points` (one colour per family, the frontier joined) as
/// `<stem>.png` and `<stem>.svg`.
pub fn accuracy_plot(points: &[AccuracyPoint], caption: &str, stem: &Path) -> Result<()> {
    let _ = plotters::style::register_font(FONT, FontStyle::Normal, dejavu::sans::regular());
    let (png, svg) = (plot_file(stem, "png"), plot_file(stem, "svg"));
    plot_files!(&png, &svg, (1400, 900), |area| accuracy(
        points, caption, area
    ));
    Ok(())
}

fn frames_of(report: &Report, config: usize) -> Vec<&FrameSample> {
    report
        .samples
        .iter()
        .filter(|s| s.config == config)
        .collect()
}

/// A y range that shows every configuration's typical frames (the 99th percentile of all).
fn y_max(report: &Report) -> f64 {
    let mut v: Vec<f64> = report.samples.iter().map(|s| s.frame_ms).collect();
    v.sort_by(f64::total_cmp);
    v.get(((v.len() as f64 * 0.99) as usize).min(v.len().saturating_sub(1)))
        .copied()
        .unwrap_or(1.0)
        * 1.1
}

fn x_max(report: &Report) -> u64 {
    report
        .samples
        .iter()
        .map(|s| s.rail_frame)
        .max()
        .unwrap_or(1)
        .max(1)
}

/// One small panel per configuration: frame, GPU, CPU and cull time along the rails.
fn rails_grid<DB: DrawingBackend>(report: &Report, root: DrawingArea<DB, Shift>) -> Result<()> {
    root.fill(&WHITE).map_err(plot_error)?;
    let (title, body) = root.split_vertically(50);
    title
        .titled(
            "Per-frame times along the rails (ms): frame (black), GPU (blue), CPU (orange), cull (green)",
            (FONT, 24),
        )
        .map_err(plot_error)?;
    let n = report.rows.len();
    let cols = 5;
    let rows = n.div_ceil(cols);
    let panels = body.split_evenly((rows, cols));
    let (ymax, xmax) = (y_max(report), x_max(report));
    for (i, panel) in panels.iter().enumerate().take(n) {
        let mut chart = ChartBuilder::on(panel)
            .caption(&report.rows[i].name, (FONT, 15))
            .margin(6)
            .x_label_area_size(22)
            .y_label_area_size(40)
            .build_cartesian_2d(0..xmax, 0.0..ymax)
            .map_err(plot_error)?;
        chart
            .configure_mesh()
            .x_labels(4)
            .y_labels(5)
            .label_style((FONT, 11))
            .light_line_style(WHITE.mix(0.0))
            .draw()
            .map_err(plot_error)?;
        let frames = frames_of(report, i);
        for (k, (_, colour)) in SERIES.iter().enumerate() {
            let points = frames.iter().map(|s| {
                let v = [s.frame_ms, s.gpu_ms, s.cpu_ms, s.cull_ms][k];
                (s.rail_frame, if v.is_finite() { v } else { 0.0 })
            });
            chart
                .draw_series(LineSeries::new(points, colour.stroke_width(1)))
                .map_err(plot_error)?;
        }
    }
    root.present().map_err(plot_error)
}

/// Frame time along the rails: the baseline, each optimisation alone, and the best rows.
fn rails_compare<DB: DrawingBackend>(report: &Report, root: DrawingArea<DB, Shift>) -> Result<()> {
    root.fill(&WHITE).map_err(plot_error)?;
    let mut picked: Vec<usize> = (0..report.rows.len())
        .filter(|&i| {
            report.rows[i]
                .toggles
                .is_some_and(|t| !t.foveate && t.thesis_switches() <= 1)
        })
        .collect();
    for foveated in [false, true] {
        let best = (0..report.rows.len())
            .filter(|&i| {
                report.rows[i]
                    .toggles
                    .is_some_and(|t| t.foveate == foveated)
            })
            .min_by(|&a, &b| {
                report.rows[a]
                    .ratio_median
                    .total_cmp(&report.rows[b].ratio_median)
            });
        if let Some(b) = best.filter(|b| !picked.contains(b)) {
            picked.push(b);
        }
    }
    let mut chart = ChartBuilder::on(&root)
        .caption(
            "Frame time along the rails: baseline, each optimisation alone, the best without and with foveation",
            (FONT, 20),
        )
        .margin(12)
        .x_label_area_size(40)
        .y_label_area_size(60)
        .build_cartesian_2d(0..x_max(report), 0.0..y_max(report))
        .map_err(plot_error)?;
    chart
        .configure_mesh()
        .x_desc("frame along the rails")
        .y_desc("frame time (ms)")
        .label_style((FONT, 14))
        .draw()
        .map_err(plot_error)?;
    for (k, &i) in picked.iter().enumerate() {
        let colour = PALETTE[k % PALETTE.len()];
        let r = &report.rows[i];
        chart
            .draw_series(LineSeries::new(
                frames_of(report, i)
                    .iter()
                    .map(|s| (s.rail_frame, s.frame_ms)),
                colour.stroke_width(2),
            ))
            .map_err(plot_error)?
            .label(format!(
                "{} (median {:.1} ms, {:.2}x)",
                r.name, r.frame_ms.median, r.ratio_median
            ))
            .legend(move |(x, y)| PathElement::new([(x, y), (x + 20, y)], colour.stroke_width(2)));
    }
    legend_and_present(&mut chart, &root)
}

/// The series' legend in the upper right, then the picture written out.
pub(crate) fn legend_and_present<'a, DB: DrawingBackend + 'a, CT: CoordTranslate>(
    chart: &mut ChartContext<'a, DB, CT>,
    root: &DrawingArea<DB, Shift>,
) -> Result<()> {
    chart
        .configure_series_labels()
        .label_font((FONT, 14))
        .background_style(WHITE.mix(0.85))
        .border_style(BLACK)
        .position(SeriesLabelPosition::UpperRight)
        .draw()
        .map_err(plot_error)?;
    root.present().map_err(plot_error)
}

/// Every row's median frame time over the baseline's, with the 0.40 target.
fn ratios<DB: DrawingBackend>(report: &Report, root: DrawingArea<DB, Shift>) -> Result<()> {
    root.fill(&WHITE).map_err(plot_error)?;
    let n = report.rows.len();
    let xmax = report
        .rows
        .iter()
        .map(|r| r.ratio_median)
        .fold(1.2, f64::max);
    let mut chart = ChartBuilder::on(&root)
        .caption(
            "Median frame time over the baseline's (dashed: the 0.40 target)",
            (FONT, 22),
        )
        .margin(12)
        .x_label_area_size(40)
        .y_label_area_size(300)
        .build_cartesian_2d(0.0..xmax, (0..n).into_segmented())
        .map_err(plot_error)?;
    chart
        .configure_mesh()
        .y_labels(n)
        .y_label_formatter(&|v| match v {
            SegmentValue::CenterOf(i) if *i < n => report.rows[n - 1 - i].name.clone(),
            _ => String::new(),
        })
        .x_desc("ratio to the baseline")
        .label_style((FONT, 13))
        .draw()
        .map_err(plot_error)?;
    chart
        .draw_series(report.rows.iter().enumerate().map(|(k, r)| {
            let y = n - 1 - k;
            let colour = match r.toggles {
                None => RGBColor(127, 127, 127),
                Some(t) if t.foveate => RGBColor(44, 160, 44),
                Some(_) => RGBColor(31, 119, 180),
            };
            let mut bar = Rectangle::new(
                [
                    (0.0, SegmentValue::Exact(y)),
                    (r.ratio_median, SegmentValue::Exact(y + 1)),
                ],
                colour.mix(0.8).filled(),
            );
            bar.set_margin(3, 3, 0, 0);
            bar
        }))
        .map_err(plot_error)?;
    for x in [0.4, 1.0] {
        chart
            .draw_series(DashedLineSeries::new(
                [(x, SegmentValue::Exact(0)), (x, SegmentValue::Exact(n))],
                6,
                4,
                RED.stroke_width(2),
            ))
            .map_err(plot_error)?;
    }
    root.present().map_err(plot_error)
}

/// Error against time for every approximation: the eccentricity-aware FLIP's 99th percentile
/// (what the eye at the gaze can see at its worst); the Pareto frontier joins the points no
/// other point beats on both.
fn accuracy<DB: DrawingBackend>(
    points: &[AccuracyPoint],
    caption: &str,
    root: DrawingArea<DB, Shift>,
) -> Result<()> {
    root.fill(&WHITE).map_err(plot_error)?;
    let y = |p: &AccuracyPoint| p.eccentric_flip_p99;
    let ymax = points.iter().map(y).fold(0.1, f64::max) * 1.1;
    let xmax = points.iter().map(|p| p.ratio).fold(1.1, f64::max) * 1.05;
    let mut chart = ChartBuilder::on(&root)
        .caption(caption, (FONT, 18))
        .margin(14)
        .x_label_area_size(44)
        .y_label_area_size(60)
        .build_cartesian_2d(0.0..xmax, 0.0..ymax)
        .map_err(plot_error)?;
    chart
        .configure_mesh()
        .x_desc("frame time / reference frame time (left is faster)")
        .y_desc("eccentricity-aware FLIP p99 (down is more accurate)")
        .label_style((FONT, 14))
        .draw()
        .map_err(plot_error)?;
    chart
        .draw_series(LineSeries::new(
            pareto_frontier(points),
            BLACK.mix(0.4).stroke_width(1),
        ))
        .map_err(plot_error)?;
    let mut families: Vec<&str> = Vec::new();
    for p in points {
        if !families.contains(&p.family) {
            families.push(p.family);
        }
    }
    for (k, family) in families.iter().enumerate() {
        let colour = PALETTE[k % PALETTE.len()];
        let mine: Vec<&AccuracyPoint> = points.iter().filter(|p| p.family == *family).collect();
        chart
            .draw_series(mine.iter().map(|p| {
                EmptyElement::at((p.ratio, y(p)))
                    + Circle::new((0, 0), 5, colour.filled())
                    + Text::new(p.name.clone(), (7, -6), (FONT, 11))
            }))
            .map_err(plot_error)?
            .label(*family)
            .legend(move |(x, y)| Circle::new((x + 8, y), 5, colour.filled()));
    }
    legend_and_present(&mut chart, &root)
}

/// The points (time ratio, eFLIP p99) no other point beats on both, fastest first.
fn pareto_frontier(points: &[AccuracyPoint]) -> Vec<(f64, f64)> {
    let xy: Vec<crate::frontier::Point> = points
        .iter()
        .map(|p| crate::frontier::Point {
            time: p.ratio,
            error: p.eccentric_flip_p99,
        })
        .collect();
    crate::frontier::pareto_frontier(&xy)
        .into_iter()
        .map(|i| (xy[i].time, xy[i].error))
        .collect()
}

/// One line of [`latency_plot`]: a tracking's error after each saccade, (ms since landing,
/// eFLIP p99) per saccade.
pub struct LatencyCurve {
    pub label: String,
    pub saccades: Vec<Vec<(f64, f64)>>,
}

/// eFLIP p99 against time since landing, one colour per tracking (every saccade a line of it),
/// the budget dashed, as `<stem>.png` and `<stem>.svg`.
pub fn latency_plot(
    curves: &[LatencyCurve],
    budget: f64,
    caption: &str,
    stem: &Path,
) -> Result<()> {
    let _ = plotters::style::register_font(FONT, FontStyle::Normal, dejavu::sans::regular());
    let (png, svg) = (plot_file(stem, "png"), plot_file(stem, "svg"));
    plot_files!(&png, &svg, (1400, 900), |area| latency(
        curves, budget, caption, area
    ));
    Ok(())
}

fn latency<DB: DrawingBackend>(
    curves: &[LatencyCurve],
    budget: f64,
    caption: &str,
    root: DrawingArea<DB, Shift>,
) -> Result<()> {
    root.fill(&WHITE).map_err(plot_error)?;
    let points = || curves.iter().flat_map(|c| c.saccades.iter().flatten());
    let (x0, x1) = points().fold((0.0, 0.0), |(lo, hi): (f64, f64), p| {
        (lo.min(p.0), hi.max(p.0))
    });
    let ymax = points().map(|p| p.1).fold(budget, f64::max) * 1.1;
    let mut chart = ChartBuilder::on(&root)
        .caption(caption, (FONT, 18))
        .margin(14)
        .x_label_area_size(44)
        .y_label_area_size(60)
        .build_cartesian_2d(x0..x1, 0.0..ymax)
        .map_err(plot_error)?;
    chart
        .configure_mesh()
        .x_desc("ms since the saccade landed (negative: during it)")
        .y_desc("eccentricity-aware FLIP p99 at the true gaze")
        .label_style((FONT, 14))
        .draw()
        .map_err(plot_error)?;
    chart
        .draw_series(DashedLineSeries::new(
            [(x0, budget), (x1, budget)],
            8,
            6,
            BLACK.stroke_width(1),
        ))
        .map_err(plot_error)?
        .label(format!("budget {budget:.3}"))
        .legend(|(x, y)| PathElement::new([(x, y), (x + 20, y)], BLACK.stroke_width(1)));
    for (k, curve) in curves.iter().enumerate() {
        let colour = PALETTE[k % PALETTE.len()];
        for (i, saccade) in curve.saccades.iter().enumerate() {
            let series = chart
                .draw_series(LineSeries::new(
                    saccade.iter().copied(),
                    colour.stroke_width(2),
                ))
                .map_err(plot_error)?;
            if i == 0 {
                series.label(curve.label.clone()).legend(move |(x, y)| {
                    PathElement::new([(x, y), (x + 20, y)], colour.stroke_width(2))
                });
            }
        }
    }
    legend_and_present(&mut chart, &root)
}
