//! What `compare` prints and writes of its rows: the table, the heat maps, the picks and the
//! frontier, the CSV.

use anyhow::Result;
use foveate::metrics::perceptual::{heat_map, FrameAccuracy};
use foveate::metrics::{ErrorSummary, RgbaImage};
use foveate::plan::{PassKind, RenderConfig};

use super::{CompareArgs, Row};
use crate::commands::bench::accuracy::AccuracyPoint;
use crate::commands::bench::plots::accuracy_plot;
use crate::counts::mib;
use crate::csv_out::{opt, CsvTable};
use crate::file_names::slug;
use crate::frontier::{cheapest_within_error, most_accurate_within_time, pareto_frontier, Point};
use crate::side_by_side::Measured;

/// One eFLIP heat map per judged row (both eyes side by side), named after the row.
pub(super) fn write_heat_maps(
    dir: &std::path::Path,
    named: &[(String, u32, RenderConfig)],
    judged: &[crate::side_by_side::Judged],
) -> Result<()> {
    for ((name, ..), j) in named.iter().skip(1).zip(judged) {
        let (Some(maps), pixels) = (&j.accuracy.perceptual.maps, &j.pixels) else {
            continue;
        };
        let picture = RgbaImage::side_by_side(
            &heat_map(&maps[0], &pixels[0]),
            &heat_map(&maps[1], &pixels[1]),
        );
        picture.save(&dir.join(format!("{}.png", slug(name))))?;
    }
    Ok(())
}

/// The picks the arguments ask for: iso-error, iso-time, the Pareto frontier and its plot.
pub(super) fn report_picks(
    args: &CompareArgs,
    rows: &[Row],
    measured: &[FrameAccuracy],
    reference: &Measured,
) -> Result<()> {
    let points: Vec<Point> = rows
        .iter()
        .zip(measured)
        .map(|(r, m)| Point {
            time: r.run.frame_ms / reference.frame_ms,
            error: m.perceptual.eccentric.map_or(0.0, |e| e.p99),
        })
        .collect();
    let say = |what: &str, pick: Option<usize>| match pick {
        Some(i) => println!(
            "{what}: {} — {:.2} ms ({:.3}x the reference), eFLIP p99 {:.4}",
            rows[i].name, rows[i].run.frame_ms, points[i].time, points[i].error
        ),
        None => println!("{what}: no configuration measured"),
    };
    if let Some(budget) = args.recommend {
        let what = format!("iso-error, the cheapest within eFLIP p99 ≤ {budget}");
        say(&what, cheapest_within_error(&points, budget));
    }
    if let Some(budget) = args.iso_time {
        let what = format!("iso-time, the most accurate within {budget}x the reference's time");
        say(&what, most_accurate_within_time(&points, budget));
    }
    if let Some(plot) = &args.pareto {
        print_frontier(rows, &points);
        // The target: foveation as accurate as aliased stereo, for less time.
        let aliased = rows.iter().position(|r| r.name == "stereo, MSAA 1");
        if let Some(s) = aliased {
            let foveated: Vec<Point> = rows
                .iter()
                .zip(&points)
                .map(|(r, p)| match r.run.plan.foveation {
                    Some(_) => *p,
                    None => Point {
                        time: f64::INFINITY,
                        ..*p
                    },
                })
                .collect();
            let what = format!(
                "the cheapest foveated row as accurate as stereo without MSAA (eFLIP p99 ≤ {:.4}, {:.3}x)",
                points[s].error, points[s].time
            );
            say(&what, cheapest_within_error(&foveated, points[s].error));
        }
        if let Some(plot) = plot {
            let family = |r: &Row| match r.run.plan.foveation {
                Some(_) => "foveated",
                None => "stereo",
            };
            let accuracy: Vec<AccuracyPoint> = rows
                .iter()
                .zip(measured)
                .zip(&points)
                .map(|((r, m), p)| AccuracyPoint {
                    family: family(r),
                    name: r.name.clone(),
                    frame_ms: r.run.frame_ms,
                    ratio: p.time,
                    psnr_db: None,
                    ssim: 1.0,
                    flip_mean: m.perceptual.flip.map_or(0.0, |f| f.mean),
                    eccentric_flip_mean: m.perceptual.eccentric.map_or(0.0, |e| e.mean),
                    eccentric_flip_p99: p.error,
                })
                .collect();
            let caption = format!(
                "{}: eFLIP p99 against frame time (stereo MSAA 4 = 1.0), frontier joined",
                crate::frame_args::headset_line(&reference.plan)
            );
            accuracy_plot(&accuracy, &caption, plot)?;
            println!(
                "wrote {} and .svg",
                crate::outputs::plot_file(plot, "png").display()
            );
        }
    }
    Ok(())
}

/// Where the legend says the regions of rows without a fovea (stereo, radial density) lie: the
/// sweep judges them where the first foveated row puts the fovea.
pub(super) fn unfoveated_regions(rows: &[Row]) -> String {
    match rows.iter().find(|r| r.run.plan.foveation.is_some()) {
        Some(first) => format!("rows without a fovea at the regions of {}", first.name),
        None => "rows without a fovea: all periphery".to_string(),
    }
}

/// The GPU time of the passes that make what the display shows from what the scene passes
/// rendered: the output pass, and the periphery's accumulation at its own texels where it has
/// a pass of its own (medians, side by side with the other rows). `None` without either (a
/// stereo frame with no lens has no output pass). With and without accumulation, rows apart.
fn output_pass_ms(run: &Measured) -> Option<f64> {
    let times: Vec<f64> = run
        .plan
        .passes
        .iter()
        .zip(&run.gpu_pass_ms)
        .filter(|(p, _)| matches!(p.kind, PassKind::Output | PassKind::Accumulate))
        .map(|(_, &ms)| ms)
        .collect();
    (!times.is_empty()).then(|| times.iter().sum())
}

/// Each row's price on the tile GPU (`compare --price-device`).
pub(super) type Prices = [super::priced::RowPrice];

pub(super) fn print_rows(
    rows: &[Row],
    measured: &[FrameAccuracy],
    reference_ms: f64,
    prices: &Prices,
) {
    print_table(rows, measured, reference_ms);
    if prices.is_empty() {
        return;
    }
    let width = super::super::name_column_width(rows.iter().map(|r| r.name.as_str()));
    println!(
        "\nthe tile GPU's price (a formula), beside lavapipe's time:\n{:<width$} {:>9} {:>10} {:>9}",
        "configuration", "ratio", "price ms", "x ref"
    );
    for (row, p) in rows.iter().zip(prices) {
        println!(
            "{:<width$} {:>9.3} {:>10.3} {:>9.3}",
            row.name,
            row.run.frame_ms / reference_ms,
            p.ms,
            p.ms / p.reference_ms
        );
    }
}

fn print_table(rows: &[Row], measured: &[FrameAccuracy], reference_ms: f64) {
    let width = super::super::name_column_width(rows.iter().map(|r| r.name.as_str()));
    println!(
        "\n{:<width$} {:>9} {:>6} {:>9} {:>11} {:>11} {:>11} {:>9} {:>14} {:>14} {:>14} {:>7} {:>7} {:>7} {:>21}",
        "configuration",
        "frame ms",
        "ratio",
        "output ms",
        "scene frags",
        "total frags",
        "resolved",
        "MiB moved",
        "fovea dB/SSIM",
        "band dB/SSIM",
        "perif. dB/SSIM",
        "FLIP",
        "eFLIP",
        "p99",
        "p99 fov/band/perif"
    );
    for (row, m) in rows.iter().zip(measured) {
        let psnr = |p: Option<f64>| match p {
            None => "-".to_string(),
            Some(v) if v.is_infinite() => "inf".into(),
            Some(v) => format!("{v:.1}"),
        };
        let ssim = |s: Option<f64>| s.map_or("-".to_string(), |v| format!("{v:.3}"));
        let cells: Vec<String> = (0..3)
            .map(|i| format!("{} / {}", psnr(m.region_psnr[i]), ssim(m.region_ssim[i])))
            .collect();
        let e = &m.perceptual;
        let mean =
            |s: Option<ErrorSummary>| s.map_or("-".to_string(), |s| format!("{:.4}", s.mean));
        let p99 = |s: Option<ErrorSummary>| s.map_or("-".to_string(), |s| format!("{:.3}", s.p99));
        println!(
            "{:<width$} {:>9.2} {:>6.3} {:>9} {:>11} {:>11} {:>11} {:>9.1} {:>14} {:>14} {:>14} {:>7} {:>7} {:>7} {:>21}",
            row.name,
            row.run.frame_ms,
            row.run.frame_ms / reference_ms,
            output_pass_ms(&row.run).map_or("-".to_string(), |ms| format!("{ms:.2}")),
            row.run.scene_fragments(),
            row.run.total_fragments,
            row.run.plan.resolved_samples(),
            mib(row.run.plan.external_traffic_bytes()),
            cells[0],
            cells[1],
            cells[2],
            mean(e.flip),
            mean(e.eccentric),
            p99(e.eccentric),
            e.regions.map(p99).join("/"),
        );
    }
}

/// The rows no other row beats on both time and error, fastest first, with the tile-GPU
/// workload beside each time.
fn print_frontier(rows: &[Row], points: &[Point]) {
    println!("\nPareto frontier (eFLIP p99 against frame time; S stereo, F foveated):");
    let width = super::super::name_column_width(rows.iter().map(|r| r.name.as_str()));
    println!(
        "  {:<width$} {:>7} {:>8} {:>12} {:>12} {:>10}",
        "configuration", "x ref", "p99", "fragments", "resolved", "MiB moved"
    );
    for i in pareto_frontier(points) {
        let (r, p) = (&rows[i], points[i]);
        let kind = if r.run.plan.foveation.is_some() {
            "F"
        } else {
            "S"
        };
        println!(
            "{kind} {:<width$} {:>7.3} {:>8.4} {:>12} {:>12} {:>10.1}",
            r.name,
            p.time,
            p.error,
            r.run.total_fragments,
            r.run.plan.resolved_samples(),
            mib(r.run.plan.external_traffic_bytes())
        );
    }
}

pub(super) fn csv(
    rows: &[Row],
    measured: &[FrameAccuracy],
    reference_ms: f64,
    prices: &Prices,
) -> Result<CsvTable> {
    let mut csv = CsvTable::new(&[
        "config",
        "msaa",
        "ratio",
        "blend_band_px",
        "sharpen",
        "periphery_density",
        "periphery_msaa",
        "frame_ms",
        "time_ratio",
        "output_pass_ms",
        "scene_fragments",
        "total_fragments",
        "resolved_samples",
        "external_traffic_bytes",
        "psnr_fovea",
        "psnr_band",
        "psnr_periphery",
        "ssim_fovea",
        "ssim_band",
        "ssim_periphery",
        "flip_mean",
        "eccentric_flip_mean",
        "eccentric_flip_p95",
        "eccentric_flip_p99",
        "eccentric_flip_p99_fovea",
        "eccentric_flip_p99_band",
        "eccentric_flip_p99_periphery",
        "price_ms",
        "price_ratio",
        "price_alu_ms",
        "price_memory_ms",
        "price_instructions",
    ])?;
    for (i, (row, m)) in rows.iter().zip(measured).enumerate() {
        let price = prices.get(i);
        let f = row.run.plan.foveation;
        let e = &m.perceptual;
        let p99 = |s: Option<ErrorSummary>| opt(s.map(|s| s.p99), 5);
        csv.row(&[
            &row.name,
            &row.msaa,
            &opt(f.map(|f| f.ratio as f64), 4),
            &opt(f.map(|f| f.blend_band_px as f64), 1),
            &opt(f.map(|f| f.periphery_sharpen as f64), 2),
            &opt(row.run.plan.periphery_density(), 4),
            &opt(f.map(|f| f.periphery_samples(row.msaa) as f64), 0),
            &format!("{:.3}", row.run.frame_ms),
            &format!("{:.4}", row.run.frame_ms / reference_ms),
            &opt(output_pass_ms(&row.run), 3),
            &row.run.scene_fragments(),
            &row.run.total_fragments,
            &row.run.plan.resolved_samples(),
            &row.run.plan.external_traffic_bytes(),
            &opt(m.region_psnr[0], 4),
            &opt(m.region_psnr[1], 4),
            &opt(m.region_psnr[2], 4),
            &opt(m.region_ssim[0], 4),
            &opt(m.region_ssim[1], 4),
            &opt(m.region_ssim[2], 4),
            &opt(e.flip.map(|s| s.mean), 5),
            &opt(e.eccentric.map(|s| s.mean), 5),
            &opt(e.eccentric.map(|s| s.p95), 5),
            &p99(e.eccentric),
            &p99(e.regions[0]),
            &p99(e.regions[1]),
            &p99(e.regions[2]),
            &opt(price.map(|p| p.ms), 4),
            &opt(price.map(|p| p.ms / p.reference_ms), 4),
            &opt(price.map(|p| p.alu_ms), 4),
            &opt(price.map(|p| p.memory_ms), 4),
            &opt(price.map(|p| p.instructions), 0),
        ])?;
    }
    Ok(csv)
}
