use std::fmt::Write as _;
use std::path::PathBuf;

use anyhow::Result;
use clap::Args;
use foveate::foveation::{arm_table, FoveationConfig, PixelBudget};
use foveate::gpu::{Gpu, GpuOptions};
use foveate::plan::{RenderConfig, Resolution, StereoMode};
use foveate::render::Renderer;
use foveate::scene::Scene;

#[derive(Args)]
pub struct PixelsArgs {
    /// Screen resolution per eye (Arm: 1024).
    #[arg(long, default_value_t = 1024)]
    res: u32,
    /// Foveated rows as VIEW:RATIO, comma-separated (Arm: 716:0.7,512:0.5,366:0.35).
    #[arg(
        long,
        value_delimiter = ',',
        default_value = "716:0.7,512:0.5,366:0.35"
    )]
    rows: Vec<String>,
    /// Fixed fovea size in screen pixels for the third table (Arm's Table 4: 256).
    #[arg(long, default_value_t = 256)]
    fovea_size: u32,
    /// Blend band in screen pixels kept by the periphery (Arm's tables: 0).
    #[arg(long, default_value_t = 0.0)]
    blend_band: f32,
    /// Also write the tables as CSV to this file.
    #[arg(long)]
    csv: Option<PathBuf>,
}

fn parse_row(s: &str) -> Result<(u32, f32)> {
    let bad = || anyhow::anyhow!("invalid rows = {s}: VIEW:RATIO, e.g. 716:0.7");
    let (v, r) = s.split_once(':').ok_or_else(bad)?;
    Ok((
        v.trim().parse().map_err(|_| bad())?,
        r.trim().parse().map_err(|_| bad())?,
    ))
}

/// Pixels each view renders, measured by the coverage probe in one frame of an empty scene.
pub(crate) fn coverage(gpu: &Gpu, config: &RenderConfig) -> Result<Vec<u64>> {
    let scene = Scene::empty();
    let config = RenderConfig {
        msaa: 1,
        coverage_probe: true,
        count_fragments: true,
        timestamps: false,
        ..config.clone()
    };
    let plan = foveate::plan(&scene, &config, gpu.caps())?;
    let mut renderer = Renderer::new(gpu, &plan, &scene)?;
    let stats = renderer.render_frame(scene.head)?;
    Ok(stats.fragments)
}

pub fn pixels(options: &GpuOptions, args: &PixelsArgs) -> Result<()> {
    let rows = args
        .rows
        .iter()
        .map(|r| parse_row(r))
        .collect::<Result<Vec<_>>>()?;
    let gpu = Gpu::new(options)?;
    let screen = Resolution::square(args.res);
    let base = RenderConfig {
        resolution: Some(screen),
        stereo: StereoMode::Multiview,
        ..RenderConfig::default()
    };
    let stereo = coverage(&gpu, &base)?;
    let stereo_total: u64 = stereo.iter().sum();
    println!(
        "device: {}; pixels per frame, both eyes, measured by a coverage probe on the GPU",
        gpu.info().name
    );
    println!(
        "stereo {}x{} x 2 views: {stereo_total} measured, {} analytic",
        args.res,
        args.res,
        2 * screen.pixels()
    );
    let mut csv = String::from("table,view,ratio,fovea_measured,fovea_analytic,fovea_arm,periphery_measured,periphery_analytic,periphery_arm,total_measured,reduction_measured,reduction_arm\n");
    let tables = [
        (2, "Table 2: without stencil mask", false, None),
        (3, "Table 3: with stencil mask", true, None),
        (
            4,
            "Table 4: with stencil mask, fixed fovea",
            true,
            Some(args.fovea_size),
        ),
    ];
    for (number, title, stencil, fovea_size) in tables {
        let title = match fovea_size {
            Some(f) => format!("{title} {f}x{f}"),
            None => title.to_string(),
        };
        println!("\n{title} (measured | analytic | Arm's printed)");
        println!(
            "{:>9} {:>5} {:>32} {:>32} {:>11} {:>15}",
            "view", "views", "fovea pixels", "periphery pixels", "total", "reduction %"
        );
        for &(view, ratio) in &rows {
            let foveation = FoveationConfig {
                ratio,
                view_resolution: Some(view),
                stencil,
                fovea_size,
                blend_band_px: args.blend_band,
                debug_tint: false,
            };
            let config = RenderConfig {
                views: 4,
                foveation: Some(foveation),
                ..base.clone()
            };
            let counts = coverage(&gpu, &config)?;
            let geometry = foveation.geometry(screen)?;
            let analytic = PixelBudget::of(&geometry);
            let (periphery, fovea) = (
                (counts[0] + counts[1]) as f64,
                (counts[2] + counts[3]) as f64,
            );
            let total = fovea + periphery;
            let reduction = 100.0 * (1.0 - total / stereo_total as f64);
            let arm = (args.res == 1024)
                .then(|| {
                    arm_table(number)
                        .iter()
                        .find(|r| r.view == view && (r.ratio - ratio as f64).abs() < 1e-6)
                })
                .flatten();
            let printed = |x: Option<f64>| x.map_or("-".to_string(), |v| format!("{v:.0}"));
            println!(
                "{:>9} {:>5} {:>10.0} | {:>9.0} | {:>9} {:>10.0} | {:>9.0} | {:>9} {:>11.0} {:>6.1} | {:>6}",
                format!("{view}x{view}"),
                4,
                fovea,
                analytic.fovea,
                printed(arm.map(|r| r.fovea)),
                periphery,
                analytic.periphery,
                printed(arm.map(|r| r.periphery)),
                total,
                reduction,
                arm.map_or("-".to_string(), |r| format!("{:.1}", r.reduction_percent)),
            );
            let _ = writeln!(
                csv,
                "{number},{view},{ratio},{fovea},{:.1},{},{periphery},{:.1},{},{total},{reduction:.2},{}",
                analytic.fovea,
                arm.map_or(String::new(), |r| r.fovea.to_string()),
                analytic.periphery,
                arm.map_or(String::new(), |r| r.periphery.to_string()),
                arm.map_or(String::new(), |r| r.reduction_percent.to_string()),
            );
        }
    }
    println!("\n(analytic: the formulas with the true pi; Arm's tables used pi = 3.14 and truncate their percentages)");
    gpu.check_validation()?;
    crate::cli::write_csv(args.csv.as_deref(), &csv)
}
