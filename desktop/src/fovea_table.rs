//! The foveation table: stereo against foveation at each ratio in each fovea layout, on every
//! scene variant asked for, the output stage on for every row — measured side by side in one
//! run through the one measurement engine (`side_by_side`: every row's renderer alive together,
//! frames interleaved round-robin so machine noise hits all rows alike): frame and per-pass GPU time, fragments and primitives from separate
//! counting frames, and the ratio to stereo. `compare --table` prints it and the bench records
//! it.

use std::fmt::Write as _;

use anyhow::{Context, Result};
use foveate::foveation::FoveationConfig;
use foveate::gpu::Gpu;
use foveate::plan::{FoveaLayout, OutputStage, RenderConfig, Resolution};
use foveate::scene::{LodSettings, Scene, Shading};

use crate::csv_out::CsvTable;
use crate::side_by_side::{measure_group, Group};

/// What the table measures.
pub struct TableSettings {
    /// (scene name, shading) pairs, in order.
    pub scenes: Vec<(String, Shading)>,
    pub ratios: Vec<f32>,
    pub resolution: Resolution,
    /// Headset profile name.
    pub hmd: String,
    pub msaa: u32,
    pub output: OutputStage,
    /// Timed frames per row (after one warm-up frame each).
    pub frames: u32,
    /// Level of detail on every row, stereo included (`None`: full meshes).
    pub lod: Option<LodSettings>,
}

/// One measured row.
pub struct TableRow {
    pub scene: String,
    pub shading: Shading,
    /// `stereo`, or `foveated R one-pass|two-pass`.
    pub name: String,
    /// Whether `auto` would pick this row's layout (foveated rows).
    pub auto_pick: bool,
    pub frame_ms: f64,
    pub ratio: f64,
    /// (pass name, median GPU ms), in plan order.
    pub passes: Vec<(&'static str, f64)>,
    pub scene_fragments: u64,
    pub total_fragments: u64,
    /// Primitives rasterised over every pass (pipeline statistics), when the device has them.
    pub primitives: Option<u64>,
}

/// A row's configuration: stereo, or foveated at `ratio` in `layout`.
fn row_config(base: &RenderConfig, foveated: Option<(f32, FoveaLayout)>) -> RenderConfig {
    match foveated {
        None => base.clone(),
        Some((ratio, layout)) => RenderConfig {
            foveation: Some(FoveationConfig {
                ratio,
                ..FoveationConfig::single_frame()
            }),
            fovea_layout: layout,
            ..base.clone()
        },
    }
}

/// Measures the table; `load` makes a scene by name.
pub fn measure(
    gpu: &Gpu,
    settings: &TableSettings,
    load: &dyn Fn(&str, Shading) -> Result<Scene>,
) -> Result<Vec<TableRow>> {
    let base = RenderConfig {
        resolution: Some(settings.resolution),
        hmd: settings.hmd.clone(),
        msaa: settings.msaa,
        output: settings.output,
        lod: settings.lod,
        ..RenderConfig::default()
    };
    let mut variants: Vec<Option<(f32, FoveaLayout)>> = vec![None];
    for &ratio in &settings.ratios {
        for layout in [FoveaLayout::OnePass, FoveaLayout::TwoPass] {
            variants.push(Some((ratio, layout)));
        }
    }
    let bar = crate::progress::bar(
        "foveation table",
        (settings.scenes.len() * variants.len()) as u64,
    );
    let mut table = Vec::new();
    for (name, shading) in &settings.scenes {
        // Ctrl-C or SIGTERM: the scenes finished so far are the table (the caller says so).
        if crate::interrupt::requested() {
            break;
        }
        let scene = load(name, *shading)?;
        let configs: Vec<RenderConfig> = variants.iter().map(|v| row_config(&base, *v)).collect();
        let group = Group {
            scene: &scene,
            configs: &configs,
            gaze: glam::Vec2::ZERO,
            rounds: settings.frames + 1,
            label: name,
        };
        let measured = match measure_group(gpu, &group) {
            Err(_) if crate::interrupt::requested() => break,
            measured => measured.with_context(|| name.clone())?,
        };
        let auto = foveate::plan(
            &scene,
            &row_config(&base, Some((0.35, FoveaLayout::Auto))),
            gpu.caps(),
        )?
        .fovea_layout
        .map(|c| c.layout);
        let stereo_ms = measured[0].frame_ms;
        for (variant, m) in variants.iter().zip(&measured) {
            let names = m.plan.passes.iter().map(|p| p.name);
            table.push(TableRow {
                scene: name.clone(),
                shading: *shading,
                name: match variant {
                    None => "stereo".to_string(),
                    Some((ratio, layout)) => format!("foveated {ratio} {layout}"),
                },
                auto_pick: variant.is_some_and(|(_, layout)| Some(layout) == auto),
                frame_ms: m.frame_ms,
                ratio: m.frame_ms / stereo_ms,
                passes: names.zip(m.gpu_pass_ms.iter().copied()).collect(),
                scene_fragments: m.scene_fragments(),
                total_fragments: m.total_fragments,
                primitives: m.primitives,
            });
            bar.inc(1);
        }
        gpu.check_validation()?;
    }
    bar.finish_and_clear();
    Ok(table)
}

/// The per-pass times of a row, short: "periphery 81.3 + fovea 91.4 + output 24.6".
fn pass_times(row: &TableRow) -> String {
    row.passes
        .iter()
        .map(|(name, ms)| {
            let short = name
                .trim_start_matches("scene (")
                .split([' ', ')', ','])
                .next()
                .unwrap_or(name);
            format!("{short} {ms:.1}")
        })
        .collect::<Vec<_>>()
        .join(" + ")
}

/// The table as Markdown (for BENCHMARKS.md and `tables.md`).
pub fn markdown(rows: &[TableRow]) -> String {
    let mut s = String::from(
        "| scene | shading | row | frame ms | × stereo | GPU ms per pass | scene fragments | all fragments | primitives |\n|---|---|---|---:|---:|---|---:|---:|---:|\n",
    );
    for r in rows {
        let _ = writeln!(
            s,
            "| {} | {} | {}{} | {:.1} | {:.3} | {} | {} | {} | {} |",
            r.scene,
            r.shading,
            r.name,
            if r.auto_pick { " (auto)" } else { "" },
            r.frame_ms,
            r.ratio,
            pass_times(r),
            r.scene_fragments,
            r.total_fragments,
            r.primitives.map_or("n/a".to_string(), |p| p.to_string())
        );
    }
    s
}

/// Prints the table.
pub fn print(rows: &[TableRow]) {
    println!(
        "{:<8} {:<5} {:<28} {:>9} {:>8} {:>12} {:>12} {:>11}  GPU ms per pass",
        "scene", "shade", "row", "frame ms", "x stereo", "scene frags", "all frags", "primitives"
    );
    for r in rows {
        println!(
            "{:<8} {:<5} {:<28} {:>9.1} {:>8.3} {:>12} {:>12} {:>11}  {}",
            r.scene,
            r.shading.name(),
            format!("{}{}", r.name, if r.auto_pick { " (auto)" } else { "" }),
            r.frame_ms,
            r.ratio,
            r.scene_fragments,
            r.total_fragments,
            r.primitives.map_or("n/a".to_string(), |p| p.to_string()),
            pass_times(r)
        );
    }
}

/// The table as CSV.
pub fn csv(rows: &[TableRow]) -> Result<CsvTable> {
    let mut t = CsvTable::new(&[
        "scene",
        "shading",
        "row",
        "auto_pick",
        "frame_ms",
        "ratio_to_stereo",
        "gpu_ms_per_pass",
        "scene_fragments",
        "total_fragments",
        "primitives",
    ])?;
    for r in rows {
        t.row(&[
            &r.scene,
            &r.shading,
            &r.name,
            &r.auto_pick,
            &format!("{:.3}", r.frame_ms),
            &format!("{:.4}", r.ratio),
            &pass_times(r),
            &r.scene_fragments,
            &r.total_fragments,
            &r.primitives.map_or(String::new(), |p| p.to_string()),
        ])?;
    }
    Ok(t)
}
