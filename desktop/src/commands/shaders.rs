//! `foveate shaders`: what the device's own compiler made of every pipeline of the frame, per
//! pass and step, where the device reports it (`VK_KHR_pipeline_executable_properties`: Mesa's
//! turnip for Adreno, through `scripts/adreno.sh`; RADV; NVIDIA's driver). Creating the
//! renderer compiles every pipeline, so the command is also the check that a driver accepts
//! them all: any pipeline it refuses fails the run, naming the error.

use std::path::PathBuf;

use anyhow::Result;
use clap::Args;
use foveate::gpu::{Gpu, GpuOptions, ShaderExecutable};
use foveate::render::{Renderer, StepShaders};

use crate::csv_out::CsvTable;
use crate::frame_args::ConfigArgs;
use crate::gaze_arg::gaze_from;

#[derive(Args)]
pub struct ShadersArgs {
    #[command(flatten)]
    pub config: ConfigArgs,
    /// Print every statistic the driver reports, one line each (default: a table of the main
    /// ones, where the driver names them as turnip or RADV does).
    #[arg(long)]
    pub all: bool,
    /// Also write every statistic as CSV: a row per mode, pass, step, executable and statistic.
    #[arg(long)]
    pub csv: Option<PathBuf>,
    /// Then record and submit this many whole frames of each configuration, with no timestamp
    /// or counting query (a device that runs nothing, as turnip on the drm-shim, never writes
    /// one): what the driver decides for each pass.
    #[arg(long, default_value_t = 0)]
    pub frames: u32,
}

/// The table's columns: a header, and the names drivers give the statistics summed into it
/// (turnip's, then RADV's where it has one): ALU is turnip's cat2 and cat3 instructions, SFU
/// its special functions (cat4), tex its texture instructions (cat5), stall its estimated
/// cycles stalled on the SS and SY sync bits.
const COLUMNS: [(&str, &[&[&str]]); 9] = [
    ("instr", &[&["Instruction Count"], &["Instructions"]]),
    ("nops", &[&["NOPs Count"]]),
    ("alu", &[&["cat2 instructions", "cat3 instructions"]]),
    ("sfu", &[&["cat4 instructions"]]),
    ("tex", &[&["cat5 instructions"]]),
    (
        "stall",
        &[&[
            "Estimated cycles stalled on SS",
            "Estimated cycles stalled on SY",
        ]],
    ),
    ("regs", &[&["Registers used"], &["VGPRs"]]),
    ("half", &[&["Half-registers used"]]),
    ("waves", &[&["Max Waves Per Core"], &["Subgroups per SIMD"]]),
];

pub fn shaders(options: &GpuOptions, args: &ShadersArgs) -> Result<()> {
    let modes = args.config.stereo_modes()?;
    let configs = modes
        .iter()
        .map(|&m| Ok((m, args.config.config(m)?)))
        .collect::<Result<Vec<_>>>()?;
    let gaze = args.config.gaze.as_deref().map(gaze_from).transpose()?;
    crate::outputs::files(&[args.csv.as_deref()])?;
    let scene = args.config.scene()?;
    // The driver's own trace of the frames, where it writes one (Mesa's u_trace).
    let trace = (args.frames > 0).then(crate::tile_trace::request).flatten();
    let mut csv = CsvTable::new(&[
        "mode",
        "pass_index",
        "pass",
        "step",
        "pipeline",
        "samples",
        "views",
        "executable",
        "statistic",
        "value",
    ])?;
    // Each mode's passes, in the order its frames recorded them. The device goes before the
    // trace is read: the driver finishes writing it as the device ends.
    let mut recorded = Vec::new();
    {
        let gpu = Gpu::new(options)?;
        println!("device: {} ({})", gpu.info().name, gpu.info().driver);
        for (mode, config) in &configs {
            let config = foveate::plan::RenderConfig {
                timestamps: false,
                ..config.clone()
            };
            let plan = foveate::plan(&scene, &config, gpu.caps())?;
            // Creating the renderer compiles every pipeline the frame uses.
            let mut renderer = Renderer::new(&gpu, &plan, &scene)?;
            let pipelines = plan.passes.iter().map(|p| p.pipelines.len()).sum::<usize>();
            println!("\n{mode}: {pipelines} pipelines compiled");
            if let Some(g) = gaze {
                renderer.set_gaze([g; 2])?;
            }
            for _ in 0..args.frames {
                renderer.render_frame(scene.head)?;
            }
            if args.frames > 0 {
                println!(
                    "  {} frame{} recorded and submitted, without queries (no time, no counts)",
                    args.frames,
                    if args.frames == 1 { "" } else { "s" }
                );
            }
            let names: Vec<&'static str> = plan.passes.iter().map(|p| p.name).collect();
            recorded.push((mode.name(), names));
            let statistics = renderer.layer().shader_statistics();
            if let Some(s) = statistics
                .iter()
                .flatten()
                .find(|s| s.executables.is_empty())
            {
                anyhow::bail!(
                    "{mode}: the driver reported no executable for pass {} ({}), step {}",
                    s.pass_index,
                    s.pass,
                    s.step.name()
                );
            }
            for s in statistics.iter().flatten() {
                csv_rows(&mut csv, mode.name(), s)?;
            }
            match statistics {
                None => println!(
                    "  the device does not report its compiler's statistics (no VK_KHR_pipeline_executable_properties)"
                ),
                Some(steps) if args.all => print_all(&steps),
                Some(steps) => print_table(&steps),
            }
        }
        judges(&gpu, args.all)?;
        gpu.check_validation()?;
    }
    if let Some(path) = trace {
        crate::tile_trace::report(&path, &recorded, args.frames)?;
    }
    csv.save(args.csv.as_deref())?;
    Ok(())
}

/// The frame judges' compute pipelines (eFLIP's and flicker's), compiled and reported too.
fn judges(gpu: &Gpu, all: bool) -> Result<()> {
    let flip = foveate::judge::FlipJudge::new(gpu, 64, 64)?;
    let flicker = foveate::judge::GpuFlicker::new(gpu)?;
    let shaders: Vec<_> = flip
        .shader_statistics()
        .into_iter()
        .chain(flicker.shader_statistics())
        .collect();
    println!(
        "\nthe judges (eFLIP, flicker): {} compute pipelines compiled",
        shaders.len()
    );
    if gpu.shader_statistics_offered() {
        if let Some((name, _)) = shaders.iter().find(|s| s.1.is_empty()) {
            anyhow::bail!("the driver reported no executable for the judge's {name}");
        }
        println!("  {:<29}{}", "shader", header());
        for (name, executables) in &shaders {
            for e in *executables {
                if all {
                    print_executable(e);
                } else {
                    println!(
                        "  {:<21}{:<8}{}",
                        name.trim_end_matches(".spv"),
                        e.name,
                        values(e)
                    );
                }
            }
        }
    }
    Ok(())
}

fn csv_rows(csv: &mut CsvTable, mode: &str, s: &StepShaders) -> Result<()> {
    for e in s.executables {
        for stat in &e.statistics {
            csv.row(&[
                &mode,
                &s.pass_index,
                &s.pass,
                &s.step.name(),
                &s.pipeline,
                &s.samples,
                &s.views(),
                &e.name,
                &stat.name,
                &stat.value,
            ])?;
        }
    }
    Ok(())
}

/// A column's value: the first set of names the driver reports all of, summed.
fn column(e: &ShaderExecutable, names: &[&[&str]]) -> String {
    names
        .iter()
        .find_map(|set| {
            set.iter()
                .map(|n| e.statistic(n).map(|v| v.as_f64()))
                .sum::<Option<f64>>()
        })
        .map_or("-".into(), |v| format!("{v}"))
}

/// The table's column headers.
fn header() -> String {
    COLUMNS.iter().map(|c| format!("{:>6}", c.0)).collect()
}

/// An executable's row of the table.
fn values(e: &ShaderExecutable) -> String {
    COLUMNS
        .iter()
        .map(|c| format!("{:>6}", column(e, c.1)))
        .collect()
}

fn print_table(steps: &[StepShaders]) {
    println!(
        "  {:<15} {:>3} {:>5}  {:<11}{}",
        "step",
        "spp",
        "views",
        "executable",
        header()
    );
    let mut pass = None;
    for s in steps {
        if pass != Some(s.pass_index) {
            println!("  {}", s.pass);
            pass = Some(s.pass_index);
        }
        for e in s.executables {
            println!(
                "    {:<13} {:>3} {:>5}  {:<11}{}",
                s.step.name(),
                s.samples,
                s.views(),
                e.name,
                values(e)
            );
        }
    }
}

fn print_all(steps: &[StepShaders]) {
    for s in steps {
        println!(
            "  {} / {} ({} spp, {} views): {}",
            s.pass,
            s.step.name(),
            s.samples,
            s.views(),
            s.pipeline
        );
        for e in s.executables {
            print_executable(e);
        }
    }
}

fn print_executable(e: &ShaderExecutable) {
    println!("    {} ({}):", e.name, e.description);
    for stat in &e.statistics {
        println!("      {}: {}", stat.name, stat.value);
    }
}
