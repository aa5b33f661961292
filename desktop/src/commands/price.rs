//! `foveate price`: a frame's price on a tile GPU — a formula (`foveate::tile_price`), beside
//! its time measured on the device that runs it. Two devices in one run: the one that renders
//! (lavapipe: timed frames, then a counting frame for the fragments and triangles) and the tile
//! GPU's own driver, which compiles the same configuration's pipelines (Mesa's turnip on the
//! drm-shim: `scripts/adreno.sh price`). The configuration is priced beside stereo at 4× and
//! aliased stereo (1×), the yardsticks, each as a ratio to stereo 4×.

use anyhow::{Context, Result};
use clap::Args;
use foveate::gpu::{Gpu, GpuOptions};
use foveate::plan::RenderConfig;
use foveate::render::{counting_frame, Renderer};
use foveate::tile_price::{FramePrice, PassWork};
use glam::Vec2;

use crate::frame_args::ConfigArgs;
use crate::gaze_arg::gaze_from;
use crate::tile_pricer::Priced;

#[derive(Args)]
pub struct PriceArgs {
    #[command(flatten)]
    pub config: ConfigArgs,
    /// The tile GPU's device: index or part of its name (its driver compiles the pipelines and
    /// reports their statistics).
    #[arg(long, default_value = "Adreno")]
    pub price_device: String,
    /// Timed frames on the rendering device (`--device`; default: the first device that is
    /// not the tile GPU's), after a warm-up and, for an accumulated periphery, its settling.
    #[arg(long, default_value_t = 5)]
    pub frames: u32,
    /// Print each row's passes: fragments, instructions, bytes, both bounds.
    #[arg(long)]
    pub passes: bool,
}

/// One row: its label, its median GPU time on the rendering device, and its price.
struct Row {
    label: String,
    gpu_ms: f64,
    price: FramePrice,
    work: Vec<PassWork>,
}

pub fn price(options: &GpuOptions, args: &PriceArgs) -> Result<()> {
    anyhow::ensure!(
        (1..=1000).contains(&args.frames),
        "invalid frames = {}: 1 to 1000",
        args.frames
    );
    let modes = args.config.stereo_modes()?;
    anyhow::ensure!(
        modes.len() == 1,
        "invalid stereo = all: price takes one stereo mode"
    );
    let asked = args.config.config(modes[0])?;
    let gaze = args.config.gaze.as_deref().map(gaze_from).transpose()?;
    let scene = args.config.scene()?;
    let (runner, tile) = crate::tile_pricer::open(options, &args.price_device)?;
    println!("{}", tile.describe(&runner));
    let gaze = [gaze.unwrap_or(Vec2::ZERO); 2];
    let mut rows = Vec::new();
    for (label, config) in rows_to_price(&asked) {
        let (gpu_ms, runner_plan) = timed(&runner, &scene, &config, gaze, args.frames)?;
        let counted = counting_frame(&runner, &scene, &config, gaze, scene.head)?;
        let counts = (&counted, &runner_plan);
        let Priced { price, work } = tile.price(&runner, &scene, &config, gaze, counts)?;
        rows.push(Row {
            label,
            gpu_ms,
            price,
            work,
        });
    }
    runner.check_validation()?;
    tile.gpu.check_validation()?;
    print_rows(&rows, args.passes);
    Ok(())
}

/// The configuration asked for, after the two yardsticks: plain stereo at 4x and 1x, every
/// effect off (itself left out where it is one).
fn rows_to_price(asked: &RenderConfig) -> Vec<(String, RenderConfig)> {
    let stereo = |msaa| RenderConfig {
        foveation: None,
        hmd_mask: false,
        mffr: None,
        radial_density: None,
        culling: None,
        msaa,
        ..asked.clone()
    };
    let mut rows = vec![
        ("stereo 4x".to_string(), stereo(4)),
        ("stereo 1x (aliased)".to_string(), stereo(1)),
    ];
    if rows.iter().all(|(_, c)| c != asked) {
        rows.push(("asked".to_string(), asked.clone()));
    }
    rows
}

/// The median GPU time of `frames` frames of `config` on `gpu`, after a warm-up and settling,
/// and the plan they rendered.
fn timed(
    gpu: &Gpu,
    scene: &foveate::scene::Scene,
    config: &RenderConfig,
    gaze: [Vec2; 2],
    frames: u32,
) -> Result<(f64, foveate::plan::FramePlan)> {
    let plan = foveate::plan(scene, config, gpu.caps())?;
    let mut renderer = Renderer::new(gpu, &plan, scene)?;
    renderer.set_gaze(gaze)?;
    renderer.render_frame(scene.head)?;
    crate::side_by_side::settle(&mut renderer, scene.head)?;
    let mut times = Vec::new();
    for _ in 0..frames {
        let stats = renderer.render_frame(scene.head)?;
        times.push(stats.gpu_ms.context("the frame has no GPU time")?);
    }
    let median = foveate::metrics::Stats::of(&times)
        .context("no timed frame")?
        .median;
    Ok((median, plan))
}

fn print_rows(rows: &[Row], passes: bool) {
    let (base_gpu, base_price) = (rows[0].gpu_ms, rows[0].price.ms());
    println!(
        "\n{:<22} {:>12} {:>9}   {:>10} {:>9} {:>8} {:>8} {:>8} {:>7} {:>7}",
        "row",
        "lavapipe ms",
        "x st 4x",
        "price ms",
        "x st 4x",
        "ALU ms",
        "mem ms",
        "MiB",
        "frag G",
        "vert M"
    );
    for r in rows {
        let alu: f64 = r.price.passes.iter().map(|p| p.alu_ms).sum();
        let memory: f64 = r.price.passes.iter().map(|p| p.memory_ms).sum();
        let bytes: u64 = r.work.iter().map(|w| w.bytes).sum();
        let fragment: f64 = r.work.iter().map(PassWork::fragment_instructions).sum();
        let all: f64 = r.work.iter().map(PassWork::instructions).sum();
        println!(
            "{:<22} {:>12.2} {:>9.3}   {:>10.3} {:>9.3} {:>8.3} {:>8.3} {:>8.1} {:>7.2} {:>7.1}",
            r.label,
            r.gpu_ms,
            r.gpu_ms / base_gpu,
            r.price.ms(),
            r.price.ms() / base_price,
            alu,
            memory + r.price.display_read_ms,
            bytes as f64 / (1 << 20) as f64,
            fragment / 1e9,
            (all - fragment) / 1e6
        );
    }
    println!("(frag G, vert M: billions and millions of instructions the fragment and vertex shaders ran, the binning pass's included)");
    if passes {
        for r in rows {
            println!("\n{}: per pass", r.label);
            for (w, p) in r.work.iter().zip(&r.price.passes) {
                println!(
                    "  {:<60} {:>10} fragments {:>8.1} G instr {:>7.1} MiB  ALU {:.3} ms, memory {:.3} ms ({:?}-bound)",
                    w.name,
                    w.fragments(),
                    w.instructions() / 1e9,
                    w.bytes as f64 / (1 << 20) as f64,
                    p.alu_ms,
                    p.memory_ms,
                    p.bound()
                );
            }
            println!("  display read: {:.3} ms", r.price.display_read_ms);
        }
    }
}
