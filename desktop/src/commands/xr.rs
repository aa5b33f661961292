//! `foveate xr`: the frame on an OpenXR runtime's headset. The runtime makes the Vulkan
//! instance and device, locates the eyes each frame, and takes an array swapchain that the
//! frame's last pass renders into directly; the session's lifecycle (`foveate::xr::Lifecycle`)
//! decides when frames run. Logs the runtime's offer once and the frames once a second; at the
//! end, a summary (and, with `--check-pixels`, the proof of what the runtime received).

use std::path::PathBuf;
use std::time::{Duration, Instant};

use anyhow::{bail, Result};
use clap::Args;
use foveate::foveation::simulated_trace;
use foveate::gpu::GpuOptions;
use foveate::metrics::Stats;
use foveate::xr::{Ended, GazeSource, Lifecycle, XrRuntime, XrSession, XrSettings};

use crate::frame_args::ConfigArgs;
use crate::gaze_arg::gaze_from;

#[derive(Args)]
pub struct XrArgs {
    /// The frame (foveation, MFFR, the HMD mask, MSAA…). The runtime sets the image size, each
    /// eye's field and the IPD (`--res`, `--ipd-mm`, `--cant` are ignored); the output is
    /// undistorted, as a runtime distorts for its lens itself.
    #[command(flatten)]
    pub config: ConfigArgs,
    /// Ask the runtime to end the session after this many rendered frames (default: run until
    /// the runtime ends it).
    #[arg(long)]
    pub frames: Option<u64>,
    /// Where the eyes look when the runtime has no eye tracker: `trace` (a simulated trace of
    /// fixations and saccades) or `fixed` (at `--gaze X,Y`, the centre by default).
    #[arg(long, default_value = "trace")]
    pub gaze_source: String,
    /// Read back the first rendered frame from the runtime's swapchain image and compare it
    /// with the same frame rendered into an image of foveate's own (as `foveate render` does);
    /// fail when any pixel differs.
    #[arg(long)]
    pub check_pixels: bool,
    /// With --check-pixels: write the submitted image (both eyes side by side) to this PNG.
    #[arg(long)]
    pub save: Option<PathBuf>,
    /// Give up when the runtime lets no frame run for this long (seconds).
    #[arg(long, default_value_t = 30.0)]
    pub timeout: f64,
}

pub fn xr(options: &GpuOptions, args: &XrArgs) -> Result<()> {
    anyhow::ensure!(
        args.frames != Some(0),
        "invalid frames = 0: at least 1 (or leave it out to run until the runtime ends the session)"
    );
    anyhow::ensure!(
        args.save.is_none() || args.check_pixels,
        "--save writes the checked frame: add --check-pixels"
    );
    anyhow::ensure!(
        args.timeout.is_finite() && args.timeout > 0.0,
        "invalid timeout = {}: a finite number of seconds above 0",
        args.timeout
    );
    if let Some(path) = &args.save {
        crate::outputs::image(path)?;
    }
    let scene = args.config.scene()?;
    let config = args.config.config(args.config.stereo.parse()?)?;
    let gaze = gaze_source(args)?;
    let runtime = XrRuntime::new(&())?;
    let report = &runtime.report;
    println!("runtime: {} — {}", report.runtime, report.system);
    println!(
        "  extensions of interest offered: {}",
        report.extensions.join(", ")
    );
    println!(
        "  view configurations: {}",
        report.view_configurations.join(", ")
    );
    println!(
        "  recommended {}x{} per eye (max {}x{})",
        report.recommended.width, report.recommended.height, report.max.width, report.max.height
    );
    let inset = report
        .view_configurations
        .iter()
        .any(|c| c.contains("FOVEATED_INSET"))
        || report.extensions.contains(&"XR_VARJO_quad_views");
    if inset {
        println!("  the runtime offers quad views: foveate renders stereo with its own composition (quad-view submission is not built yet)");
    }
    if report
        .extensions
        .contains(&"XR_KHR_composition_layer_depth")
    {
        println!("  XR_KHR_composition_layer_depth offered, not used: the output stage writes colour only");
    }
    if report.eye_gaze {
        println!("  eye gaze: the system's eye tracker (XR_EXT_eye_gaze_interaction) through the gaze filter");
    } else {
        println!(
            "  eye gaze: none from the runtime; using --gaze-source {}",
            args.gaze_source
        );
    }
    let gpu = runtime.gpu(options)?;
    println!("device (chosen by the runtime): {}", gpu.info().name);
    let settings = XrSettings {
        config,
        gaze,
        check_pixels: args.check_pixels,
    };
    let mut life = Lifecycle::new(XrSession::new(&runtime, &gpu, &scene, settings)?);
    let started = Instant::now();
    let mut last_frame = Instant::now();
    let mut mask_changed = false;
    loop {
        while let Some(event) = runtime.poll(&mut mask_changed)? {
            life.handle(event)?;
        }
        if std::mem::take(&mut mask_changed) {
            log::info!("the runtime's visibility mask changed: fetching it again");
            life.backend_mut().load_hidden_area()?;
        }
        if life.ended().is_some() {
            break;
        }
        if args.frames.is_some_and(|n| life.frames().0 >= n) {
            life.stop()?;
        }
        if life.frame()? {
            last_frame = Instant::now();
        } else {
            if last_frame.elapsed().as_secs_f64() > args.timeout {
                bail!(
                    "the runtime ran no frame for {} s (session {:?}): is the headset's compositor running?",
                    args.timeout,
                    life.state()
                );
            }
            std::thread::sleep(Duration::from_millis(5));
        }
    }
    let wall = started.elapsed().as_secs_f64();
    let summary = &life.backend().summary;
    let (rendered, skipped) = life.frames();
    let median = Stats::of(&summary.frame_ms).map_or(0.0, |s| s.median);
    println!(
        "{rendered} frames rendered and submitted ({skipped} submitted without rendering) in {wall:.1} s; median frame {median:.1} ms (locate, render, submit); display period {:.1} ms, {} late",
        summary.pacing.display_period_ms, summary.pacing.late
    );
    println!(
        "workload: {} draw calls, {} triangles recorded per frame (the last one)",
        summary.draws.0, summary.draws.1
    );
    println!(
        "eyes: {} replan(s); the runtime's eyes lie within {:.2} mm and {:.3}° of foveate's eye model",
        summary.replans,
        summary.eye_fit_error.0 * 1e3,
        summary.eye_fit_error.1
    );
    match &summary.mask_hidden {
        Some(m) => println!(
            "HMD mask from the runtime's hidden-area mesh: hides {:.1} % / {:.1} % of the eyes (the mesh's area); the {} profile's ellipse would hide {:.1} % / {:.1} %{}",
            100.0 * m.mesh[0],
            100.0 * m.mesh[1],
            m.profile,
            100.0 * m.ellipse[0],
            100.0 * m.ellipse[1],
            m.published.map_or(String::new(), |p| format!(" (published: {:.1} %)", 100.0 * p))
        ),
        None if args.config.hmd_mask => println!("HMD mask: the profile's ellipse (the runtime offers no visibility mask)"),
        None => {}
    }
    // What the run made is written before any verdict: a lost session keeps its picture.
    if let (Some(check), Some(path)) = (&summary.pixels, &args.save) {
        check.submitted.side_by_side().save(path)?;
        println!("wrote {} (the checked frame as submitted)", path.display());
    }
    match life.ended() {
        Some(Ended::Exited) => {}
        Some(Ended::SessionLost) => bail!(
            "the runtime lost the session (XR_SESSION_STATE_LOSS_PENDING): the headset went away"
        ),
        Some(Ended::InstanceLost) => {
            bail!("the runtime is going away (XrEventDataInstanceLossPending)")
        }
        None => unreachable!("the loop ends with the run"),
    }
    gpu.check_validation()?;
    if args.check_pixels {
        let Some(check) = &summary.pixels else {
            bail!("--check-pixels: no frame was rendered to check");
        };
        println!("{check}");
        anyhow::ensure!(check.passed(), "the pixel check failed: {check}");
    }
    Ok(())
}

fn gaze_source(args: &XrArgs) -> Result<GazeSource> {
    match args.gaze_source.as_str() {
        "trace" => {
            anyhow::ensure!(
                args.config.gaze.is_none(),
                "--gaze places a fixed gaze: add --gaze-source fixed"
            );
            // An hour at 200 Hz, seeded: every run sees the same eye movements.
            Ok(GazeSource::Trace(simulated_trace(3600.0, 200.0, 7)))
        }
        "fixed" => Ok(GazeSource::Fixed(match &args.config.gaze {
            Some(g) => gaze_from(g)?,
            None => glam::Vec2::ZERO,
        })),
        other => bail!("invalid gaze-source = {other}: trace or fixed"),
    }
}
