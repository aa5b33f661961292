//! `foveate judge`: what judging a frame costs, on the GPU beside the CPU. Renders the lit
//! atrium foveated (the library's defaults) and its full-quality reference (4× MSAA) at a
//! headset's panel, then judges both eyes with the GPU judge (timed over rounds, after one
//! that makes its pipelines and buffers) and, with `--cpu`, with NVIDIA's reference FLIP on the
//! CPU in the same run: each judgement's time, its figures, and how far the two maps lie apart.

use std::time::Instant;

use anyhow::{Context, Result};
use clap::Args;
use foveate::foveation::FoveationConfig;
use foveate::gpu::{Gpu, GpuOptions};
use foveate::judge::{reference_config, GpuFlip};
use foveate::metrics::flip::CpuFlip;
use foveate::metrics::perceptual::{perceptual_error, Maps, PerceptualError};
use foveate::metrics::{Acuity, ErrorSummary, EyePixels, FlipMapper, Stats};
use foveate::plan::RenderConfig;
use foveate::render::{FrameInput, Renderer, StereoImage};
use foveate::scene::{named_scene, Scene};
use glam::Vec2;

#[derive(Args)]
pub struct JudgeArgs {
    /// Headset profile whose panel and lens the frames are for.
    #[arg(long, default_value = "quest-pro")]
    hmd: String,
    /// Resolution per eye: N (square), WxH or `native` (the headset's panel).
    #[arg(long, default_value = "native")]
    res: String,
    /// Scene: a built-in name or a glTF file.
    #[arg(long, default_value = "atrium")]
    scene: String,
    /// Gaze X,Y in -1..1 (both eyes).
    #[arg(
        long,
        value_delimiter = ',',
        default_value = "0.3,-0.2",
        allow_hyphen_values = true
    )]
    gaze: Vec<f32>,
    /// Timed GPU judgements (after one that makes the judge's pipelines and buffers).
    #[arg(long, default_value_t = 3)]
    rounds: u32,
    /// Also judge on the CPU (NVIDIA's reference; about 40 s at a headset's panel on 2 cores).
    #[arg(long)]
    cpu: bool,
}

pub fn judge(options: &GpuOptions, args: &JudgeArgs) -> Result<()> {
    anyhow::ensure!(
        (1..=100).contains(&args.rounds),
        "invalid rounds = {}: 1 to 100",
        args.rounds
    );
    let gaze = crate::gaze_arg::gaze_from(&args.gaze)?;
    let scene = named_scene(&args.scene)?;
    let gpu = Gpu::new(options)?;
    let foveated = RenderConfig {
        hmd: args.hmd.clone(),
        resolution: crate::frame_args::parse_res(&args.res)?,
        foveation: Some(FoveationConfig::default()),
        ..RenderConfig::default()
    };
    let reference = reference_config(&foveated);
    let (_, want) = frame(&gpu, &scene, &reference, gaze)?;
    let (plan, got) = frame(&gpu, &scene, &foveated, gaze)?;
    let pixels = EyePixels::both(&plan, gaze, plan.foveation.as_ref());
    let judged: usize = pixels
        .iter()
        .map(|p| p.pixels.iter().flatten().count())
        .sum();
    println!(
        "device: {}; {} foveated (library defaults) against 4x MSAA stereo, {}x{} per eye, gaze {gaze}; \
         {judged} pixels the lens shows, {:.1} px/deg at its axis",
        gpu.info().name,
        args.scene,
        plan.eye_resolution.width,
        plan.eye_resolution.height,
        pixels[0].ppd
    );
    let mut on_gpu = GpuFlip::new(&gpu);
    let (first_ms, _) = timed(&mut on_gpu, &want, &got, &pixels, Maps::Drop)?;
    let mut times = Vec::new();
    let mut last = None;
    for _ in 0..args.rounds {
        let (ms, error) = timed(&mut on_gpu, &want, &got, &pixels, Maps::Drop)?;
        times.push(ms);
        last = Some(error);
    }
    gpu.check_validation()?;
    let gpu_error = last.context("at least one round")?;
    let gpu_time = Stats::of(&times).context("at least one round")?;
    println!(
        "GPU judge: {:.2} s per judgement of both eyes (median of {}; the first, making its \
         pipelines and buffers, {:.2} s)",
        gpu_time.median / 1000.0,
        args.rounds,
        first_ms / 1000.0
    );
    print_figures("  ", &gpu_error);
    if args.cpu {
        let (cpu_ms, cpu_error) = timed(&mut CpuFlip, &want, &got, &pixels, Maps::Keep)?;
        println!(
            "CPU judge (NVIDIA's reference FLIP): {:.2} s; the GPU judge takes {:.3}x its time",
            cpu_ms / 1000.0,
            gpu_time.median / cpu_ms
        );
        print_figures("  ", &cpu_error);
        // The timed judgements bring back histograms only; one more brings back the maps.
        let (_, gpu_maps) = timed(&mut on_gpu, &want, &got, &pixels, Maps::Keep)?;
        print_agreement(&gpu_maps, &cpu_error);
    }
    Ok(())
}

/// One frame of `config` at `gaze`: its plan and both eyes' images.
fn frame(
    gpu: &Gpu,
    scene: &Scene,
    config: &RenderConfig,
    gaze: Vec2,
) -> Result<(foveate::plan::FramePlan, StereoImage)> {
    let plan = foveate::plan(scene, config, gpu.caps())?;
    let mut renderer = Renderer::new(gpu, &plan, scene)?;
    renderer.render(&FrameInput::new(scene.head).with_gaze([gaze; 2]))?;
    Ok((plan, renderer.readback()?))
}

/// One judgement of both eyes and its wall time (ms).
fn timed(
    flip: &mut dyn FlipMapper,
    want: &StereoImage,
    got: &StereoImage,
    pixels: &[EyePixels; 2],
    maps: Maps,
) -> Result<(f64, PerceptualError)> {
    let start = Instant::now();
    let error = perceptual_error(
        want.eyes(),
        got.eyes(),
        pixels,
        Acuity::default(),
        flip,
        maps,
    )?;
    Ok((start.elapsed().as_secs_f64() * 1000.0, error))
}

fn print_figures(indent: &str, e: &PerceptualError) {
    let show = |s: Option<ErrorSummary>| {
        s.map_or("-".to_string(), |s| {
            format!("mean {:.4}, p99 {:.4}", s.mean, s.p99)
        })
    };
    println!("{indent}FLIP {}", show(e.flip));
    println!("{indent}eccentricity-aware FLIP {}", show(e.eccentric));
    for (region, s) in foveate::metrics::Region::ALL.iter().zip(e.regions) {
        println!("{indent}  {}: {}", region.name(), show(s));
    }
}

/// How far the GPU judge's eccentricity-aware maps lie from the CPU's, pixel by pixel.
fn print_agreement(gpu: &PerceptualError, cpu: &PerceptualError) {
    let (mut close, mut count, mut worst) = (0usize, 0usize, 0.0f32);
    let (Some(gpu_maps), Some(cpu_maps)) = (&gpu.maps, &cpu.maps) else {
        return;
    };
    for (g, c) in gpu_maps.iter().zip(cpu_maps) {
        for (a, b) in g
            .iter()
            .zip(c)
            .filter(|(a, b)| a.is_finite() && b.is_finite())
        {
            let d = (a - b).abs();
            close += (d <= 0.02) as usize;
            count += 1;
            worst = worst.max(d);
        }
    }
    println!(
        "agreement: {:.4} % of pixels within 0.02 (largest difference {worst:.4})",
        100.0 * close as f64 / count.max(1) as f64
    );
}
