//! `compare`'s two other modes: the eye tracker's latency swept along a gaze trace
//! (`--gaze-latency`) and the foveation table (`--table`).

use anyhow::{Context, Result};
use foveate::foveation::FoveationConfig;
use foveate::gpu::{Gpu, GpuOptions};
use foveate::metrics::Acuity;
use foveate::plan::RenderConfig;
use foveate::scene::{named_scene, Shading};

use super::CompareArgs;
use crate::commands::latency::{latency_sweep, Sweep};
use crate::fovea_table::{self, TableSettings};

/// `--gaze-latency`: each ratio (and band) foveated at the last of `--msaa` as the library's
/// default foveates (or, with `--single-frame`, single frames), swept over the tracker's latency
/// along a gaze trace (`commands::latency`).
pub(super) fn latency(options: &GpuOptions, args: &CompareArgs, acuity: Acuity) -> Result<()> {
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
            let kind = if args.latency.single_frame {
                FoveationConfig::single_frame()
            } else {
                FoveationConfig::default()
            };
            let foveation = FoveationConfig {
                ratio,
                blend_band_px: band,
                ..kind
            };
            foveation.geometry(screen)?;
            let periphery = match foveation.periphery_density {
                Some(d) if !args.latency.single_frame => format!(", periphery {d} accumulated"),
                _ => String::new(),
            };
            let name = match i {
                0 => format!("foveated {ratio}{periphery}, MSAA {msaa}"),
                _ => format!("foveated {ratio}{periphery}, band {band}, MSAA {msaa}"),
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
pub(super) fn table(options: &GpuOptions, args: &CompareArgs) -> Result<()> {
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
