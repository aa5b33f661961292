use std::path::PathBuf;

use anyhow::Result;
use clap::Args;
use foveate::foveation::{arm_table, ArmRow, FoveationConfig, PixelBudget, ARM_TABLE4_FOVEA};
use foveate::gpu::{Gpu, GpuOptions};
use foveate::plan::{CountedStep, RenderConfig, Resolution, StereoMode};
use foveate::render::counting_frame;
use glam::Vec2;

use crate::csv_out::CsvTable;
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

/// Pixels each view renders, measured by the coverage probe in one counting frame of an empty
/// scene.
pub(crate) fn coverage(gpu: &Gpu, config: &RenderConfig) -> Result<Vec<u64>> {
    let scene = Scene::empty();
    let config = RenderConfig {
        msaa: 1,
        coverage_probe: true,
        ..config.clone()
    };
    let stats = counting_frame(gpu, &scene, &config, [Vec2::ZERO; 2], scene.head)?;
    Ok(stats.per_view(CountedStep::Probe)[..config.view_count() as usize].to_vec())
}

pub fn pixels(options: &GpuOptions, args: &PixelsArgs) -> Result<()> {
    crate::outputs::files(&[args.csv.as_deref()])?;
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
    let mut csv = CsvTable::new(&[
        "table",
        "view",
        "ratio",
        "fovea_measured",
        "fovea_analytic",
        "fovea_arm",
        "periphery_measured",
        "periphery_analytic",
        "periphery_arm",
        "total_measured",
        "total_arm",
        "reduction_measured",
        "reduction_arm",
    ])?;
    let mut notes = Vec::new();
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
            "{:>9} {:>5} {:>32} {:>32} {:>21} {:>15}",
            "view", "views", "fovea pixels", "periphery pixels", "total", "reduction %"
        );
        for &(view, ratio) in &rows {
            let foveation = FoveationConfig {
                ratio,
                view_resolution: Some(view),
                stencil,
                // Arm's masks: cut at the edges (foveate's keep the filters' margins).
                mask_margins: false,
                fovea_size,
                blend_band_px: args.blend_band,
                ..FoveationConfig::single_frame()
            };
            let config = RenderConfig {
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
            // Arm's cells exist for their screen (and, in Table 4, their fixed fovea) only.
            let arm = (args.res == 1024 && fovea_size.is_none_or(|f| f == ARM_TABLE4_FOVEA))
                .then(|| {
                    arm_table(number)
                        .iter()
                        .find(|r| r.view == view && (r.ratio - ratio as f64).abs() < 1e-6)
                })
                .flatten();
            let row = MeasuredRow {
                number,
                view,
                ratio,
                fovea,
                periphery,
                analytic,
                reduction,
                arm,
            };
            report_row(&row, &mut csv, &mut notes)?;
        }
    }
    println!("\n(analytic: the formulas with the true pi; Arm's tables used pi = 3.14 and truncate their percentages; every cell Arm printed is shown as printed)");
    for note in &notes {
        println!("note: {note}");
    }
    gpu.check_validation()?;
    csv.save(args.csv.as_deref())
}

/// One measured row of a table: its view, the pixels measured, the formula's and Arm's.
struct MeasuredRow {
    number: u32,
    view: u32,
    ratio: f32,
    fovea: f64,
    periphery: f64,
    analytic: PixelBudget,
    reduction: f64,
    arm: Option<&'static ArmRow>,
}

/// Prints `row`, adds it to `csv`, and notes where Arm's own cells disagree with their
/// formulas.
fn report_row(row: &MeasuredRow, csv: &mut CsvTable, notes: &mut Vec<String>) -> Result<()> {
    let MeasuredRow {
        number,
        view,
        ratio,
        fovea,
        periphery,
        ref analytic,
        reduction,
        arm,
    } = *row;
    let total = fovea + periphery;
    let printed = |x: Option<f64>| x.map_or("-".to_string(), |v| format!("{v:.0}"));
    println!(
        "{:>9} {:>5} {:>10.0} | {:>9.0} | {:>9} {:>10.0} | {:>9.0} | {:>9} {:>9.0} | {:>9} {:>6.1} | {:>6}",
        format!("{view}x{view}"),
        4,
        fovea,
        analytic.fovea,
        printed(arm.map(|r| r.fovea)),
        periphery,
        analytic.periphery,
        printed(arm.map(|r| r.periphery)),
        total,
        printed(arm.map(|r| r.total)),
        reduction,
        arm.map_or("-".to_string(), |r| format!("{:.1}", r.reduction_percent)),
    );
    let arm_cell = |f: fn(&ArmRow) -> f64| arm.map_or(String::new(), |r| f(r).to_string());
    csv.row(&[
        &number,
        &view,
        &ratio,
        &fovea,
        &format!("{:.1}", analytic.fovea),
        &arm_cell(|r| r.fovea),
        &periphery,
        &format!("{:.1}", analytic.periphery),
        &arm_cell(|r| r.periphery),
        &total,
        &arm_cell(|r| r.total),
        &format!("{reduction:.2}"),
        &arm_cell(|r| r.reduction_percent),
    ])?;
    if let Some(r) = arm {
        let found = r.discrepancies(number);
        if !found.is_empty() {
            notes.push(format!(
                "Table {number}, {view}x{view}: Arm's own cells are inconsistent: {}",
                found.join("; ")
            ));
        }
    }
    Ok(())
}
