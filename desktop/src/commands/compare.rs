use std::path::PathBuf;

use anyhow::{Context, Result};
use clap::Args;
use foveate::foveation::{FoveationConfig, PeripheryFilter};
use foveate::gpu::{Gpu, GpuOptions};
use foveate::metrics::perceptual::{heat_map, FrameAccuracy, Maps};
use foveate::metrics::Acuity;
use foveate::metrics::{ErrorSummary, RgbaImage};
use foveate::plan::{RadialDensity, RenderConfig};
use foveate::scene::{named_scene, Shading};

use crate::commands::bench::accuracy::AccuracyPoint;
use crate::commands::bench::plots::accuracy_plot;
use crate::commands::latency::{latency_sweep, LatencyArgs, Sweep};
use crate::counts::mib;
use crate::csv_out::{opt, CsvTable};
use crate::file_names::slug;
use crate::fovea_table::{self, TableSettings};
use crate::frame_args::ComparedFrame;
use crate::frontier::{cheapest_within_error, most_accurate_within_time, pareto_frontier, Point};
use crate::side_by_side::{sweep, Group, Measured};
use crate::variants::{with_temporal, with_view_sets, Accumulation};

#[derive(Args)]
pub struct CompareArgs {
    /// Screen resolution per eye: N (square), WxH, or `native` (the headset's panel).
    #[arg(long, default_value = "1024")]
    res: String,
    /// Scene: default, fill, city, thesis or atrium.
    #[arg(long, default_value = "default")]
    scene: String,
    #[command(flatten)]
    frame: ComparedFrame,
    /// Foveation ratios to compare (default 0.7,0.5,0.35; with --table 0.35,0.5).
    #[arg(long, value_delimiter = ',')]
    ratios: Option<Vec<f32>>,
    /// The foveation table instead: stereo against each ratio in both fovea layouts, on every
    /// scene of --scenes, flat and lit, MSAA 4 (the first of --msaa), side by side in one run
    /// (with --clusters and --lod on every row, stereo included).
    #[arg(long)]
    table: bool,
    /// Scenes of the table.
    #[arg(
        long,
        value_delimiter = ',',
        default_value = "default,fill,city,thesis,atrium"
    )]
    scenes: Vec<String>,
    /// Shadings of the table's scenes.
    #[arg(long, value_delimiter = ',', default_value = "flat,lit")]
    shadings: Vec<String>,
    /// MSAA sample counts to compare (the table uses the last).
    #[arg(long, value_delimiter = ',', default_value = "1,4")]
    msaa: Vec<u32>,
    /// Gaze of both eyes, normalised X,Y in -1..1.
    #[arg(
        long,
        value_delimiter = ',',
        allow_hyphen_values = true,
        default_value = "0,0"
    )]
    gaze: Vec<f32>,
    /// Blend band in screen pixels (default: an eighth of the fovea).
    #[arg(long)]
    blend_band: Option<f32>,
    /// Also compare each ratio with these blend band widths (screen pixels), one row each.
    #[arg(long, value_delimiter = ',')]
    bands: Vec<f32>,
    /// Also compare each ratio with the periphery sharpened at these strengths (0..1], one row
    /// each.
    #[arg(long, value_delimiter = ',')]
    sharpen: Vec<f32>,
    /// Also compare each ratio with the periphery upscaled by Catmull-Rom, one row each.
    #[arg(long)]
    catmull_rom: bool,
    /// Also each foveated row with the periphery at these densities (fractions of the screen's
    /// pixels per side, independent of the fovea's ratio), one row each.
    #[arg(long, value_delimiter = ',')]
    densities: Vec<f32>,
    /// Also each foveated row with the periphery views at these MSAA counts (the fovea keeps
    /// the row's), one row each.
    #[arg(long, value_delimiter = ',')]
    periphery_msaa: Vec<u32>,
    /// Also each plain foveated row (every density) with its periphery accumulated over frames
    /// (1x, jittered; the fovea keeps the row's MSAA), one row each. Such a row is judged after
    /// its history has settled on the still frame (two jitter cycles, untimed).
    #[arg(long)]
    temporal: bool,
    #[command(flatten)]
    accumulation: Accumulation,
    /// Iso-error: name the cheapest configuration measured whose eccentricity-aware FLIP (99th
    /// percentile) stays within this budget (`--recommend` is the same).
    #[arg(long, alias = "iso-error")]
    recommend: Option<f64>,
    /// Iso-time: name the most accurate configuration whose frame time stays within this
    /// fraction of the reference's (stereo, MSAA 4).
    #[arg(long)]
    iso_time: Option<f64>,
    /// Print the Pareto frontier of error against time (stereo and foveated rows marked), and
    /// the cheapest foveated row as accurate as stereo without MSAA; with a path, also plot it
    /// as PATH.png and PATH.svg.
    #[arg(long, num_args = 0..=1, value_name = "PATH")]
    pareto: Option<Option<PathBuf>>,
    /// The eccentricity-aware FLIP's acuity falloff: arcmin of minimum angle of resolution per
    /// degree of eccentricity (Guenter et al. 2012 measured 1.32–1.65).
    #[arg(long, default_value_t = Acuity::default().slope_arcmin_per_deg)]
    mar_slope: f64,
    /// Write each configuration's eccentricity-aware FLIP map (both eyes, gaze ringed) as a PNG
    /// into this folder.
    #[arg(long)]
    heatmaps: Option<PathBuf>,
    /// Also price radial density masking (its default radii) at each MSAA count.
    #[arg(long)]
    radial_density: bool,
    /// Frames per configuration, the first a warm-up (at least 2); with `--table`, timed frames
    /// after one warm-up. Every configuration is measured side by side, frames interleaved.
    #[arg(long, default_value_t = 5)]
    frames: u32,
    /// Also write the table as CSV to this file.
    #[arg(long)]
    csv: Option<PathBuf>,
    #[command(flatten)]
    latency: LatencyArgs,
}

/// One measured configuration of `compare`.
struct Row {
    name: String,
    msaa: u32,
    run: Measured,
}

pub fn compare(options: &GpuOptions, args: &CompareArgs) -> Result<()> {
    crate::interrupt::install();
    let acuity = checked_acuity(args)?;
    if args.table {
        return table(options, args);
    }
    if !args.latency.gaze_latency.is_empty() {
        return latency(options, args, acuity);
    }
    anyhow::ensure!(
        args.frames >= 2,
        "invalid frames = {}: at least 2 (the first is a warm-up)",
        args.frames
    );
    let gaze = crate::gaze_arg::gaze_from(&args.gaze)?;
    let scene = args.frame.scene(&args.scene)?;
    let screen = args.frame.screen(&args.res)?;
    let base = args.frame.base(&args.res)?;
    // Every foveated variant, checked before anything renders.
    let variants = foveated_variants(args, screen)?;
    if let Some(dir) = &args.heatmaps {
        std::fs::create_dir_all(dir).with_context(|| format!("creating {}", dir.display()))?;
    }
    let gpu = Gpu::new(options)?;
    // The reference first (full meshes, whatever `--lod` asks of the rows), then every row:
    // all measured side by side in one group.
    let named = compared_rows(args, &base, &variants);
    let configs: Vec<RenderConfig> = named
        .iter()
        .map(|(_, msaa, c)| RenderConfig {
            msaa: *msaa,
            ..c.clone()
        })
        .collect();
    let group = Group {
        scene: &scene,
        configs: &configs,
        gaze,
        rounds: args.frames,
        label: "compare",
    };
    let maps = if args.heatmaps.is_some() {
        Maps::Keep
    } else {
        Maps::Drop
    };
    let mut judged = sweep(&gpu, &group, acuity, maps)?;
    let total = configs.len() - 1;
    if judged.is_empty() {
        return Err(crate::interrupt::stopped(
            "compare stopped before judging the reference: nothing written",
        ));
    }
    let reference = judged.remove(0).measured;
    if let Some(dir) = &args.heatmaps {
        write_heat_maps(dir, &named, &judged)?;
    }
    let (rows, measured): (Vec<Row>, Vec<FrameAccuracy>) = named
        .into_iter()
        .skip(1)
        .zip(judged)
        .map(|((name, msaa, _), j)| {
            let row = Row {
                name,
                msaa,
                run: j.measured,
            };
            (row, j.accuracy)
        })
        .unzip();
    println!(
        "device: {}; scene {}, {}, gaze {gaze}; eFLIP: MAR = {}′ + {}′/° · eccentricity",
        gpu.info().name,
        args.scene,
        crate::frame_args::headset_line(&reference.plan),
        acuity.mar0_arcmin,
        acuity.slope_arcmin_per_deg
    );
    println!(
        "reference: stereo multiview, MSAA 4: {:.2} ms, {} scene fragments, {} in all passes",
        reference.frame_ms,
        reference.scene_fragments(),
        reference.total_fragments
    );
    print_rows(&rows, &measured, reference.frame_ms);
    println!(
        "(ratio: frame time to the reference, this run, frames without counters; fragments from a separate counting frame: the scene draws, and every pass (the output stage included); the tile-GPU workload from the plan: samples the in-pass MSAA resolves average and external traffic (attachment loads and stores, sampling, readback); on the output image ({}), both eyes, pixels the lens hides left out: PSNR in dB / SSIM per region against the reference ({}); FLIP: mean at the display's pixels per degree; eFLIP: the eccentricity-aware FLIP for the eye at the gaze (metrics::flip), mean and 99th percentile, then p99 per region)",
        base.output,
        unfoveated_regions(&rows)
    );
    if let Some(dir) = &args.heatmaps {
        println!("wrote {} heat maps into {}", rows.len(), dir.display());
    }
    if rows.len() < total {
        csv(&rows, &measured, reference.frame_ms)?.save(args.csv.as_deref())?;
        return Err(crate::interrupt::stopped(&format!(
            "compare stopped after judging {} of {total} configurations; the table above{} holds them",
            rows.len(),
            if args.csv.is_some() { " and the CSV" } else { "" }
        )));
    }
    report_picks(args, &rows, &measured, &reference)?;
    gpu.check_validation()?;
    csv(&rows, &measured, reference.frame_ms)?.save(args.csv.as_deref())
}

/// The arguments `compare` checks before anything opens; the eye's acuity they set.
fn checked_acuity(args: &CompareArgs) -> Result<Acuity> {
    anyhow::ensure!(args.frames >= 1, "invalid frames = 0: at least 1");
    crate::outputs::files(&[args.csv.as_deref(), args.latency.frames_csv.as_deref()])?;
    if let Some(Some(stem)) = &args.pareto {
        crate::outputs::plot(stem)?;
    }
    if let Some(dir) = &args.heatmaps {
        crate::outputs::folder(dir)?;
    }
    if let Some(stem) = &args.latency.latency_plot {
        crate::outputs::plot(stem)?;
    }
    if let Some(budget) = args.recommend {
        anyhow::ensure!(
            budget.is_finite() && budget > 0.0,
            "invalid recommend = {budget}: a FLIP budget above 0 (FLIP runs 0..1)"
        );
    }
    anyhow::ensure!(
        args.mar_slope.is_finite() && args.mar_slope > 0.0 && args.mar_slope <= 10.0,
        "invalid mar-slope = {}: 0 < slope ≤ 10 arcmin per degree (Guenter et al.: 1.32–1.65)",
        args.mar_slope
    );
    let acuity = Acuity {
        slope_arcmin_per_deg: args.mar_slope,
        ..Acuity::default()
    };
    Ok(acuity)
}

/// Every foveated configuration the arguments ask for, each checked against the screen.
fn foveated_variants(
    args: &CompareArgs,
    screen: foveate::plan::Resolution,
) -> Result<Vec<(String, FoveationConfig)>> {
    let ratios = args.ratios.clone().unwrap_or(vec![0.7, 0.5, 0.35]);
    let default_band = args
        .blend_band
        .unwrap_or(FoveationConfig::default().blend_band_px);
    let mut variants = Vec::new();
    for &ratio in &ratios {
        let with = |blend_band_px, periphery_sharpen| FoveationConfig {
            ratio,
            blend_band_px,
            periphery_sharpen,
            ..Default::default()
        };
        variants.push((format!("foveated {ratio}"), with(default_band, 0.0)));
        for &band in &args.bands {
            variants.push((format!("foveated {ratio}, band {band}"), with(band, 0.0)));
        }
        for &sharpen in &args.sharpen {
            anyhow::ensure!(
                sharpen > 0.0,
                "invalid sharpen = {sharpen}: 0 < sharpen ≤ 1 (leave it out for none)"
            );
            let name = format!("foveated {ratio}, sharpen {sharpen}");
            variants.push((name, with(default_band, sharpen)));
        }
        if args.catmull_rom {
            let f = FoveationConfig {
                periphery_filter: PeripheryFilter::CatmullRom,
                ..with(default_band, 0.0)
            };
            variants.push((format!("foveated {ratio}, catmull-rom"), f));
        }
    }
    variants = with_view_sets(variants, &args.densities, &args.periphery_msaa);
    if args.temporal {
        variants = with_temporal(variants, &args.accumulation)?;
    }
    for (_, f) in &variants {
        f.geometry(screen)?;
    }
    Ok(variants)
}

/// The rows measured, each named with its sample count: the reference (stereo, 4×, full
/// meshes) first, then per MSAA stereo, radial density when asked, and every foveated
/// variant.
fn compared_rows(
    args: &CompareArgs,
    base: &RenderConfig,
    variants: &[(String, FoveationConfig)],
) -> Vec<(String, u32, RenderConfig)> {
    let reference = RenderConfig {
        lod: None,
        ..base.clone()
    };
    let mut named = vec![("reference".to_string(), 4, reference)];
    for &msaa in &args.msaa {
        named.push((format!("stereo, MSAA {msaa}"), msaa, base.clone()));
        if args.radial_density {
            let config = RenderConfig {
                radial_density: Some(RadialDensity::default()),
                ..base.clone()
            };
            named.push((format!("radial density, MSAA {msaa}"), msaa, config));
        }
        // A periphery sample count equal to the row's is the row itself (unless accumulated).
        let distinct = variants.iter().filter(|(_, f)| {
            f.periphery_temporal.is_some() || f.periphery_msaa.is_none_or(|m| m != msaa)
        });
        for (name, foveation) in distinct {
            let config = RenderConfig {
                foveation: Some(*foveation),
                ..base.clone()
            };
            named.push((format!("{name}, MSAA {msaa}"), msaa, config));
        }
    }
    named
}

/// One eFLIP heat map per judged row (both eyes side by side), named after the row.
fn write_heat_maps(
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
fn report_picks(
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
fn unfoveated_regions(rows: &[Row]) -> String {
    match rows.iter().find(|r| r.run.plan.foveation.is_some()) {
        Some(first) => format!("rows without a fovea at the regions of {}", first.name),
        None => "rows without a fovea: all periphery".to_string(),
    }
}

fn print_rows(rows: &[Row], measured: &[FrameAccuracy], reference_ms: f64) {
    let width = super::name_column_width(rows.iter().map(|r| r.name.as_str()));
    println!(
        "\n{:<width$} {:>9} {:>6} {:>11} {:>11} {:>11} {:>9} {:>14} {:>14} {:>14} {:>7} {:>7} {:>7} {:>21}",
        "configuration",
        "frame ms",
        "ratio",
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
            "{:<width$} {:>9.2} {:>6.3} {:>11} {:>11} {:>11} {:>9.1} {:>14} {:>14} {:>14} {:>7} {:>7} {:>7} {:>21}",
            row.name,
            row.run.frame_ms,
            row.run.frame_ms / reference_ms,
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
    let width = super::name_column_width(rows.iter().map(|r| r.name.as_str()));
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

fn csv(rows: &[Row], measured: &[FrameAccuracy], reference_ms: f64) -> Result<CsvTable> {
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
    ])?;
    for (row, m) in rows.iter().zip(measured) {
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
        ])?;
    }
    Ok(csv)
}

/// A file name for a configuration: lower case, runs of anything else as one '-'.
/// `--gaze-latency`: each ratio (and band) foveated at the last of `--msaa`, swept over the
/// tracker's latency along a gaze trace (`commands::latency`).
fn latency(options: &GpuOptions, args: &CompareArgs, acuity: Acuity) -> Result<()> {
    anyhow::ensure!(
        args.frames >= 2,
        "invalid frames = {}: at least 2 (the first is a warm-up)",
        args.frames
    );
    let scene = args.frame.scene(&args.scene)?;
    let screen = args.frame.screen(&args.res)?;
    let base = args.frame.base(&args.res)?;
    let msaa = *args
        .msaa
        .last()
        .context("invalid msaa: give at least one")?;
    let bands = std::iter::once(args.blend_band.unwrap_or(-1.0)).chain(args.bands.iter().copied());
    let bands: Vec<f32> = bands.collect();
    let mut foveated = Vec::new();
    for &ratio in args.ratios.as_deref().unwrap_or(&[0.7, 0.5, 0.35]) {
        for (i, &band) in bands.iter().enumerate() {
            let foveation = FoveationConfig {
                ratio,
                blend_band_px: band,
                ..Default::default()
            };
            foveation.geometry(screen)?;
            let name = match i {
                0 => format!("foveated {ratio}, MSAA {msaa}"),
                _ => format!("foveated {ratio}, band {band}, MSAA {msaa}"),
            };
            let config = RenderConfig {
                msaa,
                foveation: Some(foveation),
                ..base.clone()
            };
            foveated.push((name, ratio, config));
        }
    }
    let profile = crate::frame_args::profile(&args.frame.hmd)?;
    let gpu = Gpu::new(options)?;
    let sweep = Sweep {
        scene: &scene,
        scene_name: &args.scene,
        base: &base,
        foveated,
        budget: args.recommend,
        acuity,
        timing_rounds: args.frames,
        csv: args.csv.clone(),
        hmd_refresh_hz: profile.refresh_hz,
        hmd_tracker_hz: profile.eye_tracker.and_then(|t| t.rate_hz),
    };
    latency_sweep(&gpu, &args.latency, &sweep)
}

/// `compare --table`: the foveation table (see `fovea_table`).
fn table(options: &GpuOptions, args: &CompareArgs) -> Result<()> {
    let gpu = Gpu::new(options)?;
    let mut scenes = Vec::new();
    for name in &args.scenes {
        for shading in &args.shadings {
            scenes.push((name.clone(), shading.parse::<Shading>()?));
        }
    }
    let settings = TableSettings {
        scenes,
        ratios: args.ratios.clone().unwrap_or(vec![0.35, 0.5]),
        resolution: args.frame.screen(&args.res)?,
        hmd: args.frame.hmd.clone(),
        msaa: *args.msaa.last().unwrap_or(&4),
        output: args.frame.output.parse()?,
        frames: args.frames,
        lod: args.frame.clusters.lod()?,
    };
    println!(
        "device: {}; {} {} per eye, MSAA {}, output {}, gaze centred; {} timed frames per row, rows interleaved; clusters {}, level of detail {} on every row",
        gpu.info().name,
        args.frame.hmd,
        settings.resolution,
        settings.msaa,
        settings.output,
        settings.frames,
        args.frame.clusters.clusters.map_or("off".into(), |n| format!("of {n} triangles")),
        settings.lod.map_or("off".into(), |l| format!("within {} px", l.max_error_px)),
    );
    let rows = fovea_table::measure(&gpu, &settings, &|name, shading| {
        args.frame
            .clusters
            .apply(named_scene(name)?.with_shading(shading))
    })?;
    fovea_table::print(&rows);
    println!(
        "(x stereo: frame time to the same scene's stereo row in this run; fragments and primitives from separate counting frames; (auto): the layout `--fovea-layout auto` picks on this device)"
    );
    fovea_table::csv(&rows)?.save(args.csv.as_deref())?;
    if crate::interrupt::requested() {
        return Err(crate::interrupt::stopped(
            "the table stopped early; the scenes finished before it are above",
        ));
    }
    Ok(())
}
