use std::path::{Path, PathBuf};

use anyhow::Result;
use clap::Args;
use foveate::foveation::{parse_gaze_csv, simulated_trace, GazeFilter, GazeSample};
use foveate::gpu::{Gpu, GpuOptions};
use foveate::metrics::perceptual::{frame_accuracy, FrameAccuracy, Maps};
use foveate::metrics::Acuity;
use foveate::metrics::{ErrorSummary, EyePixels, Stats};
use foveate::plan::StereoMode;
use foveate::render::{counting_frame, FrameStats, Renderer};
use glam::Vec2;

use crate::frame_args::ConfigArgs;
use crate::gaze_arg::gaze_from;

#[derive(Args)]
pub struct RenderArgs {
    #[command(flatten)]
    pub config: ConfigArgs,
    /// Drive the gaze from a trace: a CSV file (`time,left_x,left_y,right_x,right_y,valid`) or
    /// `sim` for simulated fixations and saccades; frame i uses the sample at i / 90 s, filtered
    /// (bad samples keep the last good gaze, then return to the centre).
    #[arg(long)]
    pub gaze_trace: Option<String>,
    /// Frames to render (the first is a warm-up and not counted in the statistics).
    #[arg(long, default_value_t = 10)]
    pub frames: u32,
    /// Where to write the side-by-side PNG (with `--stereo all`, one file per mode is written,
    /// the mode's name inserted before the extension).
    #[arg(long, default_value = "frame.png")]
    pub out: PathBuf,
    /// With `--foveate`: also render the stereo reference (the same frame, foveation off), write
    /// it below the foveated frame in one PNG and compare the two (time ratio, fragments,
    /// per-pass times).
    #[arg(long)]
    pub reference: bool,
}

/// What one run (a stereo mode, or the stereo reference) measured.
struct ModeResult {
    /// The stereo mode, or "stereo reference".
    label: String,
    frame: Stats,
    gpu: Option<Stats>,
    /// Median GPU time per pass, with the pass's name.
    passes: Vec<(&'static str, f64)>,
    record: Stats,
    /// CPU time culling and choosing levels per frame (0 when nothing is culled).
    cull: Stats,
    /// Draw commands and triangles the last timed frame recorded.
    draw_calls: u64,
    triangles: u64,
    /// A separate, untimed counting frame of the same configuration and gaze.
    counts: FrameStats,
}

/// Everything the user typed, checked before the device starts and the frames render: the
/// modes (each one's configuration), the output images, the gaze and the gaze trace.
#[allow(clippy::type_complexity)]
fn checked_inputs(
    args: &RenderArgs,
) -> Result<(Vec<StereoMode>, Option<Vec2>, Option<Vec<GazeSample>>)> {
    anyhow::ensure!(
        args.frames >= 1,
        "invalid frames = {}: at least 1",
        args.frames
    );
    let modes = args.config.stereo_modes()?;
    anyhow::ensure!(
        !args.reference || (args.config.foveate.is_some() && modes.len() == 1),
        "invalid reference = true: compares a foveated frame (--foveate) in one stereo mode"
    );
    for &mode in &modes {
        args.config.config(mode)?;
        crate::outputs::image(&output_path(
            &args.out,
            mode,
            modes.len() > 1 && !args.reference,
        ))?;
    }
    let gaze = args.config.gaze.as_deref().map(gaze_from).transpose()?;
    let trace = match args.gaze_trace.as_deref() {
        None => None,
        Some("sim") => Some(simulated_trace(args.frames as f64 / 90.0 + 1.0, 90.0, 1)),
        Some(path) => Some(parse_gaze_csv(Path::new(path))?),
    };
    if let (Some(trace), Some(path)) = (&trace, &args.gaze_trace) {
        // A trace that starts after the run ends would leave every frame at the centre.
        let last = (args.frames - 1) as f64 / 90.0;
        anyhow::ensure!(
            trace[0].t <= last,
            "invalid gaze-trace = {path}: its first sample is at {} s, after the run's last frame at {last:.3} s ({} frames at 90 Hz): no sample would be used",
            trace[0].t,
            args.frames
        );
    }
    Ok((modes, gaze, trace))
}

pub fn render(options: &GpuOptions, args: &RenderArgs) -> Result<()> {
    let (modes, gaze, trace) = checked_inputs(args)?;
    let gpu = Gpu::new(options)?;
    let scene = args.config.scene()?;
    println!("device: {}", gpu.info().name);
    // Each run: its label, its configuration, where its image goes.
    let mut runs: Vec<(String, foveate::plan::RenderConfig, PathBuf)> = Vec::new();
    if args.reference {
        let foveated = args.config.config(modes[0])?;
        let reference = foveate::plan::RenderConfig {
            foveation: None,
            ..foveated.clone()
        };
        runs.push(("stereo reference".into(), reference, args.out.clone()));
        runs.push((format!("foveated {}", modes[0]), foveated, args.out.clone()));
    } else {
        for &mode in &modes {
            let out = output_path(&args.out, mode, modes.len() > 1);
            runs.push((mode.name().to_string(), args.config.config(mode)?, out));
        }
    }
    let mut results = Vec::new();
    // Each run's image, plan and final gaze, for the reference's comparison.
    let mut images = Vec::new();
    for (label, config, out) in &runs {
        let plan = foveate::plan(&scene, config, gpu.caps())?;
        println!("{plan}\n");
        let mut renderer = Renderer::new(&gpu, &plan, &scene)?;
        if let Some(g) = gaze {
            renderer.set_gaze([g; 2])?;
        }
        // An accumulated periphery is timed and shown as it looks once its history settled.
        crate::side_by_side::settle(&mut renderer, scene.head)?;
        let transient = plan.attachments.iter().filter(|a| a.transient).count();
        println!(
            "transient attachments in lazily allocated memory: {} of {transient}{}",
            renderer.lazy_attachments(),
            if gpu.caps().lazily_allocated_memory {
                ""
            } else {
                " (this device has none)"
            }
        );
        let frames = timed_frames(&mut renderer, &scene, args, trace.as_deref(), label)?;
        let image = renderer.readback()?;
        if !args.reference {
            save(&image.side_by_side(), out, "left eye | right eye")?;
        }
        images.push((image, plan.clone(), renderer.gaze()[0]));
        gpu.check_validation()?;
        let counts = counting_frame(&gpu, &scene, config, renderer.gaze(), scene.head)?;
        gpu.check_validation()?;
        results.push(mode_result(label, &plan, &frames, counts));
        // Per pixel of the eye views the scene pass renders (a foveated frame's periphery).
        let pixels = plan
            .foveation
            .map_or(plan.eye_resolution, |g| g.periphery_view)
            .pixels();
        print_result(results.last().expect("just pushed"), pixels);
    }
    if args.reference {
        save_beside_reference(args, &images, &mut *crate::metric::flip_mapper(&gpu))?;
    }
    if results.len() > 1 {
        print_comparison(&results);
    }
    Ok(())
}

/// The timed frames of one run (the first dropped as a warm-up unless it is the only one),
/// the gaze following `trace` at 90 Hz when there is one.
fn timed_frames(
    renderer: &mut Renderer,
    scene: &foveate::scene::Scene,
    args: &RenderArgs,
    trace: Option<&[GazeSample]>,
    label: &str,
) -> Result<Vec<FrameStats>> {
    let mut filter = GazeFilter::new(0.5);
    let mut frames: Vec<FrameStats> = Vec::new();
    let bar = crate::progress::bar(label, args.frames as u64);
    for i in 0..args.frames {
        if let Some(trace) = trace {
            // The latest sample at or before this frame's time (90 Hz).
            let t = i as f64 / 90.0;
            let k = trace.partition_point(|s| s.t <= t);
            if k > 0 {
                renderer.set_gaze(filter.update(&trace[k - 1]))?;
            }
        }
        let stats = renderer.render_frame(scene.head)?;
        if i > 0 || args.frames == 1 {
            frames.push(stats);
        }
        bar.inc(1);
    }
    bar.finish_and_clear();
    Ok(frames)
}

/// One run's figures: medians of its timed frames, each pass's median GPU time by name, the
/// last frame's draws, and the counting frame's counts.
fn mode_result(
    label: &str,
    plan: &foveate::plan::FramePlan,
    frames: &[FrameStats],
    counts: FrameStats,
) -> ModeResult {
    let series = |f: fn(&FrameStats) -> f64| frames.iter().map(f).collect::<Vec<_>>();
    let last = frames.last().expect("at least one frame");
    ModeResult {
        label: label.to_string(),
        frame: Stats::of(&series(|f| f.frame_ms)).expect("at least one frame"),
        gpu: Stats::of(&frames.iter().filter_map(|f| f.gpu_ms).collect::<Vec<_>>()),
        record: Stats::of(&series(|f| f.cpu_record_ms)).expect("at least one frame"),
        cull: Stats::of(&series(|f| f.cpu_cull_ms)).expect("at least one frame"),
        passes: plan
            .passes
            .iter()
            .enumerate()
            .filter_map(|(i, p)| {
                let times: Vec<f64> = frames
                    .iter()
                    .filter_map(|f| f.gpu_pass_ms.get(i).copied())
                    .collect();
                Stats::of(&times).map(|s| (p.name, s.median))
            })
            .collect(),
        draw_calls: last.draw_calls,
        triangles: last.triangles,
        counts,
    }
}

/// `--reference`: the foveated frame saved above its stereo reference, and its accuracy
/// against it (not on a tinted frame).
fn save_beside_reference(
    args: &RenderArgs,
    images: &[(
        foveate::render::StereoImage,
        foveate::plan::FramePlan,
        glam::Vec2,
    )],
    flip: &mut dyn foveate::metrics::FlipMapper,
) -> Result<()> {
    // The foveated frame above its stereo reference.
    let ((reference, reference_plan, _), (foveated, plan, gaze)) = (&images[0], &images[1]);
    let both =
        foveate::metrics::RgbaImage::stacked(&foveated.side_by_side(), &reference.side_by_side());
    save(
        &both,
        &args.out,
        "foveated above, stereo reference below; left eye | right eye",
    )?;
    if args.config.tint {
        println!(
            "\naccuracy against the reference: not measured on a tinted frame (leave out --tint)"
        );
    } else {
        let pixels = EyePixels::both(reference_plan, *gaze, plan.foveation.as_ref());
        let a = frame_accuracy(
            reference.eyes(),
            foveated.eyes(),
            &pixels,
            Acuity::default(),
            flip,
            Maps::Drop,
        )?;
        print_accuracy(&a, *gaze);
    }
    Ok(())
}

fn save(image: &foveate::metrics::RgbaImage, out: &Path, layout: &str) -> Result<()> {
    image.save(out)?;
    println!(
        "wrote {} ({}x{}, {layout})",
        out.display(),
        image.width,
        image.height
    );
    Ok(())
}

fn output_path(out: &Path, mode: StereoMode, per_mode: bool) -> PathBuf {
    if !per_mode {
        return out.to_path_buf();
    }
    let stem = out.file_stem().and_then(|s| s.to_str()).unwrap_or("frame");
    let ext = out.extension().and_then(|s| s.to_str()).unwrap_or("png");
    out.with_file_name(format!("{stem}-{mode}.{ext}"))
}

fn print_result(r: &ModeResult, eye_pixels: u64) {
    let gpu = r
        .gpu
        .map_or("n/a".to_string(), |g| format!("{:.2} ms", g.median));
    println!(
        "{}: frame time median {:.2} ms (mean {:.2}, p95 {:.2}, {} frames, one in flight, no counters); GPU {gpu}; CPU cull {:.3} ms, record {:.3} ms; {} draw calls, {} triangles recorded",
        r.label, r.frame.median, r.frame.mean, r.frame.p95, r.frame.count, r.cull.median, r.record.median, r.draw_calls, r.triangles
    );
    for (name, ms) in &r.passes {
        println!("  GPU {name}: {ms:.2} ms");
    }
    let names: Vec<&str> = r.passes.iter().map(|(name, _)| *name).collect();
    crate::counts::print_fragments(&r.counts, eye_pixels, &names);
}

fn print_comparison(results: &[ModeResult]) {
    let base = &results[0];
    println!(
        "\n{:<20} {:>12} {:>8} {:>12} {:>8} {:>14} {:>8} {:>12} {:>12}",
        "run",
        "frame ms",
        "ratio",
        "GPU ms",
        "ratio",
        "CPU record ms",
        "ratio",
        "scene frags",
        "total frags"
    );
    for r in results {
        let gpu = |s: &Option<Stats>| s.map_or(f64::NAN, |g| g.median);
        println!(
            "{:<20} {:>12.2} {:>8.2} {:>12.2} {:>8.2} {:>14.3} {:>8.2} {:>12} {:>12}",
            r.label,
            r.frame.median,
            r.frame.median / base.frame.median,
            gpu(&r.gpu),
            gpu(&r.gpu) / gpu(&base.gpu),
            r.record.median,
            r.record.median / base.record.median,
            r.counts.scene_fragments(),
            r.counts.total_fragments()
        );
    }
    println!(
        "(ratios to {}, medians from this run; fragments from a separate counting frame)",
        base.label
    );
}

/// What foveation costs in accuracy, against the stereo reference (`--reference`).
fn print_accuracy(a: &FrameAccuracy, gaze: Vec2) {
    let db = |p: Option<f64>| match p {
        None => "-".to_string(),
        Some(v) if v.is_infinite() => "identical".into(),
        Some(v) => format!("{v:.1} dB"),
    };
    let e = &a.perceptual;
    let p99 = |s: Option<ErrorSummary>| s.map_or("-".to_string(), |s| format!("{:.3}", s.p99));
    println!(
        "\naccuracy against the reference (output image, lens-visible pixels, gaze {gaze}):\n  PSNR fovea {}, band {}, periphery {}\n  FLIP mean {}; eccentricity-aware FLIP mean {}, p99 {} (fovea {}, band {}, periphery {})",
        db(a.region_psnr[0]),
        db(a.region_psnr[1]),
        db(a.region_psnr[2]),
        e.flip.map_or("-".to_string(), |s| format!("{:.4}", s.mean)),
        e.eccentric.map_or("-".to_string(), |s| format!("{:.4}", s.mean)),
        p99(e.eccentric),
        p99(e.regions[0]),
        p99(e.regions[1]),
        p99(e.regions[2]),
    );
}
