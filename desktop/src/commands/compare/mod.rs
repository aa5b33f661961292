//! `foveate compare`: every configuration asked for measured side by side with the full-quality
//! reference (stereo, 4×) — frame time, fragments, the tile-GPU workload — and judged against it
//! per region; then the picks (iso-error, iso-time, the frontier). `--gaze-latency` and `--table`
//! are its two other modes (`modes`).

mod modes;
mod priced;
mod report;

use std::path::PathBuf;

use anyhow::{Context, Result};
use clap::Args;
use foveate::foveation::{FoveationConfig, PeripheryFilter};
use foveate::gpu::GpuOptions;
use foveate::metrics::perceptual::{FrameAccuracy, Maps};
use foveate::metrics::Acuity;
use foveate::plan::{RadialDensity, RenderConfig};

use crate::commands::latency::LatencyArgs;
use crate::compared_frame::ComparedFrame;
use crate::side_by_side::{sweep, Group, Measured};
use crate::variants::{with_temporal, with_view_sets, Accumulation};
use modes::{latency, table};
use report::{csv, print_rows, report_picks, unfoveated_regions, write_heat_maps};

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
    /// Foveation ratios to compare (default 0.7,0.5,0.35; with --table 0.35,0.5): each as single
    /// frames and, unless --temporal asks for accumulated rows of its own, as the library's
    /// default foveation (`render --foveate R`: the periphery at 0.6 of the screen's density,
    /// accumulated over frames).
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
    /// Also price every row on this tile GPU's device (index or part of its name: Adreno's
    /// turnip, through scripts/adreno.sh): a formula, printed beside lavapipe's time as a
    /// ratio to the reference's (`foveate price` says how); the fovea's layout is the tile
    /// GPU's choice in every row.
    #[arg(long)]
    price_device: Option<String>,
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
    let twins = args.frame.prefilter || !args.frame.rings.is_empty();
    let own_rows = args.table || !args.latency.gaze_latency.is_empty();
    anyhow::ensure!(
        !(twins && own_rows),
        "--prefilter and --rings twin the compared rows: not with --table or --gaze-latency, which measure rows of their own"
    );
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
    let (gpu, pricer) = priced::devices(options, args.price_device.as_deref())?;
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
    let swept = sweep(&gpu, &group, acuity, maps)?;
    let (mut judged, failed) = (swept.judged, swept.failed);
    let total = configs.len() - 1;
    if judged.is_empty() {
        let nothing = "compare stopped before judging the reference: nothing written";
        return Err(crate::interrupt::stopped_by(failed, nothing));
    }
    let reference = judged.remove(0).measured;
    let devices = (&gpu, pricer.as_ref());
    let prices = priced::prices(devices, &scene, gaze, (&reference, &judged), &configs)?;
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
    print_rows(&rows, &measured, reference.frame_ms, &prices);
    println!(
        "(ratio: frame time to the reference, this run, frames without counters; output ms: the GPU time of the pass that makes what the display shows (with the periphery's accumulation where the row accumulates), median; fragments from a separate counting frame: the scene draws, and every pass (the output stage included); the tile-GPU workload from the plan: samples the in-pass MSAA resolves average and external traffic (attachment loads and stores, sampling, readback); on the output image ({}), both eyes, pixels the lens hides left out: PSNR in dB / SSIM per region against the reference ({}); FLIP: mean at the display's pixels per degree; eFLIP: the eccentricity-aware FLIP for the eye at the gaze (metrics::flip), mean and 99th percentile, then p99 per region)",
        base.output,
        unfoveated_regions(&rows)
    );
    if let Some(dir) = &args.heatmaps {
        println!("wrote {} heat maps into {}", rows.len(), dir.display());
    }
    if rows.len() < total {
        csv(&rows, &measured, reference.frame_ms, &prices)?.save(args.csv.as_deref())?;
        let done = format!(
            "compare stopped after judging {} of {total} configurations; the table above{} holds them",
            rows.len(),
            if args.csv.is_some() { " and the CSV" } else { "" }
        );
        return Err(crate::interrupt::stopped_by(failed, &done));
    }
    report_picks(args, &rows, &measured, &reference)?;
    gpu.check_validation()?;
    csv(&rows, &measured, reference.frame_ms, &prices)?.save(args.csv.as_deref())
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
        .unwrap_or(FoveationConfig::single_frame().blend_band_px);
    let mut variants = Vec::new();
    for &ratio in &ratios {
        let with = |blend_band_px, periphery_sharpen| FoveationConfig {
            ratio,
            blend_band_px,
            periphery_sharpen,
            ..FoveationConfig::single_frame()
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
    } else {
        // The library's default beside the single frames, as `render --foveate R` renders it.
        for &ratio in &ratios {
            let default = FoveationConfig {
                ratio,
                blend_band_px: default_band,
                ..FoveationConfig::default()
            };
            variants.push((default_row_name(ratio), default));
        }
    }
    for (_, f) in &variants {
        f.geometry(screen)?;
    }
    Ok(variants)
}

/// The name of the library's default foveation's row at `ratio`, in the words of the rows
/// `--densities` and `--temporal` name (with "the default" after them).
fn default_row_name(ratio: f32) -> String {
    let density = FoveationConfig::default()
        .periphery_density
        .unwrap_or(ratio);
    format!("foveated {ratio}, periphery {density}, temporal (the default)")
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
    let mut named = Vec::new();
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
    let mut named = crate::variants::with_twins(named, args.frame.prefilter, &args.frame.rings);
    named.insert(0, ("reference".to_string(), 4, reference));
    named
}
