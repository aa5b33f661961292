//! `foveate xr`: the frame on an OpenXR runtime's headset. The runtime makes the Vulkan
//! instance and device, locates the eyes each frame, and takes an array swapchain that the
//! frame's last pass renders into directly; the session's lifecycle (`foveate::xr::Lifecycle`)
//! decides when frames run. Logs the runtime's offer once and the frames once a second; at the
//! end, a summary (and, with `--check-pixels`, the proof of what the runtime received).

use std::path::PathBuf;
use std::sync::{Arc, Mutex};
use std::time::{Duration, Instant};

use anyhow::{bail, Result};
use clap::Args;
use foveate::foveation::simulated_trace;
use foveate::gpu::GpuOptions;
use foveate::metrics::Stats;
use foveate::xr::{
    Ended, GazeSource, Lifecycle, RuntimeReport, SessionState, Watchdog, XrRuntime, XrSession,
    XrSettings,
};

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
    /// Frames recorded and submitted before the first of them is waited for (1 to 4): with 2,
    /// frame N+1 records while frame N runs on the GPU, as runtimes expect to be fed.
    #[arg(long, default_value_t = 2)]
    pub frames_in_flight: u32,
    /// Judge every Nth rendered frame (every 10th when N is left out) against its full-quality
    /// reference (the same views and gaze drawn in full with 4× MSAA) on the GPU: the submitted
    /// image, read back before it goes to the runtime. The eccentricity-aware FLIP's 99th
    /// percentile per region is logged once a second and in the summary; judging's time is
    /// taken out of the frame times (but the runtime sees the judged frames late).
    #[arg(long, num_args = 0..=1, default_missing_value = "10", value_name = "N")]
    pub judge: Option<u32>,
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
    let config = crate::frame_args::with_frames_in_flight(
        args.config.config(args.config.stereo.parse()?)?,
        args.frames_in_flight,
    )?;
    let gaze = gaze_source(args)?;
    crate::interrupt::install();
    let runtime = XrRuntime::new(&())?;
    print_offer(&runtime.report, args);
    let gpu = runtime.gpu(options)?;
    println!("device (chosen by the runtime): {}", gpu.info().name);
    let settings = XrSettings {
        config,
        gaze,
        check_pixels: args.check_pixels,
        judge: args.judge,
    };
    let mut life = Lifecycle::new(XrSession::new(&runtime, &gpu, &scene, settings)?);
    let started = Instant::now();
    // What the watchdog prints if the runtime stops answering: the summary so far.
    let snapshot = Arc::new(Mutex::new(String::new()));
    let watchdog = {
        let snapshot = snapshot.clone();
        let timeout = args.timeout;
        Watchdog::new(Duration::from_secs_f64(timeout), move |stall| {
            println!("{}", snapshot.lock().unwrap_or_else(|e| e.into_inner()));
            eprintln!(
                "error: the runtime stopped answering: {} has not returned for {:.1} s (--timeout {timeout}); is the headset's compositor running?",
                stall.call,
                stall.waited.as_secs_f64()
            );
            std::process::exit(1);
        })
    };
    let mut run = Run {
        runtime: &runtime,
        args,
        started,
        snapshot: &snapshot,
        saved: false,
        interrupted: false,
    };
    let result = run.frames(&mut life, &watchdog);
    drop(watchdog);
    // Whatever ended the run, what it made is written and said before the verdict: a lost
    // session keeps its picture and its summary.
    let saved = run.save_checked(&life);
    println!("{}", summary(&life, args, started.elapsed().as_secs_f64()));
    result?;
    saved?;
    match life.ended() {
        Some(Ended::Exited) if run.interrupted => {
            return Err(crate::interrupt::stopped(
                "the session was ended at the signal; the summary above is the run so far",
            ))
        }
        Some(Ended::Exited) => {}
        Some(Ended::SessionLost) => bail!(
            "the runtime lost the session (XR_SESSION_STATE_LOSS_PENDING): the headset went away"
        ),
        Some(Ended::InstanceLost) => {
            bail!("the runtime is going away (XrEventDataInstanceLossPending)")
        }
        None if run.interrupted => {
            return Err(crate::interrupt::stopped(
                "the session had not begun; nothing was rendered",
            ))
        }
        None => bail!("the frame loop ended before the session did"),
    }
    gpu.check_validation()?;
    if args.check_pixels {
        let Some(check) = &life.backend().summary.pixels else {
            bail!("--check-pixels: no frame was rendered to check");
        };
        println!("{check}");
        anyhow::ensure!(check.passed(), "the pixel check failed: {check}");
    }
    Ok(())
}

/// The runtime's offer, once: what it is, what it offers that foveate uses or leaves.
fn print_offer(report: &RuntimeReport, args: &XrArgs) {
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
}

/// The frame loop's state beside the lifecycle.
struct Run<'a> {
    runtime: &'a XrRuntime,
    args: &'a XrArgs,
    started: Instant,
    snapshot: &'a Mutex<String>,
    /// The checked frame is written (`--save`).
    saved: bool,
    /// Ctrl-C or SIGTERM asked the run to end.
    interrupted: bool,
}

impl Run<'_> {
    /// Runs frames until the session ends: the runtime's events drive the lifecycle, every
    /// frame runs under the watchdog, and `--timeout` bounds a runtime that lets no frame run.
    fn frames(&mut self, life: &mut Lifecycle<XrSession>, watchdog: &Watchdog) -> Result<()> {
        let (args, mut last_frame, mut last_snapshot) = (self.args, Instant::now(), None);
        let mut mask_changed = false;
        loop {
            // Events (and what they begin or end) go through the runtime too: watched as well.
            watchdog.watch("xrPollEvent and the session's begin or end", || {
                while let Some(event) = self.runtime.poll(&mut mask_changed)? {
                    life.handle(event)?;
                }
                if std::mem::take(&mut mask_changed) {
                    log::info!("the runtime's visibility mask changed: fetching it again");
                    life.backend_mut().load_hidden_area()?;
                }
                anyhow::Ok(())
            })?;
            if life.ended().is_some() {
                return Ok(());
            }
            if crate::interrupt::requested() && !self.interrupted {
                self.interrupted = true;
                log::warn!("interrupted: asking the runtime to end the session");
                if life.state() == SessionState::Idle {
                    return Ok(());
                }
            }
            if self.interrupted || args.frames.is_some_and(|n| life.frames().0 >= n) {
                life.stop()?;
            }
            if watchdog.watch(
                "a frame (xrWaitFrame, xrWaitSwapchainImage, render, submit)",
                || life.frame(),
            )? {
                last_frame = Instant::now();
                self.save_checked(life)?;
                // Every frame at first (the summary of a run that stalls early is its first
                // frames), then once a second.
                let early = life.frames().0 <= 100;
                if early || last_snapshot.is_none_or(|t: Instant| t.elapsed().as_secs_f64() >= 1.0)
                {
                    let wall = self.started.elapsed().as_secs_f64();
                    *self.snapshot.lock().unwrap_or_else(|e| e.into_inner()) =
                        summary(life, args, wall);
                    last_snapshot = Some(Instant::now());
                }
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
    }

    /// Writes the checked frame as submitted (`--save`) once it exists, and only once.
    fn save_checked(&mut self, life: &Lifecycle<XrSession>) -> Result<()> {
        if let (false, Some(check), Some(path)) =
            (self.saved, &life.backend().summary.pixels, &self.args.save)
        {
            check.submitted.side_by_side().save(path)?;
            self.saved = true;
            println!("wrote {} (the checked frame as submitted)", path.display());
        }
        Ok(())
    }
}

/// The run's summary: frames and pacing, the workload, the eyes' fit, the HMD mask.
fn summary(life: &Lifecycle<XrSession>, args: &XrArgs, wall: f64) -> String {
    let summary = &life.backend().summary;
    let (rendered, skipped) = life.frames();
    let median = Stats::of(&summary.frame_ms).map_or(0.0, |s| s.median);
    let mut text = format!(
        "{rendered} frames rendered and submitted ({skipped} submitted without rendering) in {wall:.1} s, {} in flight; median frame {median:.1} ms (locate, record, submit); display period {:.1} ms, {} late\n",
        summary.frames_in_flight, summary.pacing.display_period_ms, summary.pacing.late
    );
    text += &format!(
        "workload: {} draw calls, {} triangles recorded per frame (the last one)\n",
        summary.draws.0, summary.draws.1
    );
    text += &format!(
        "eyes: {} replan(s); the runtime's eyes lie within {:.2} mm and {:.3}° of foveate's eye model",
        summary.replans,
        summary.eye_fit_error.0 * 1e3,
        summary.eye_fit_error.1
    );
    match &summary.mask_hidden {
        Some(m) => text += &format!(
            "\nHMD mask from the runtime's hidden-area mesh: hides {:.1} % / {:.1} % of the eyes (the mesh's area); the {} profile's ellipse would hide {:.1} % / {:.1} %{}",
            100.0 * m.mesh[0],
            100.0 * m.mesh[1],
            m.profile,
            100.0 * m.ellipse[0],
            100.0 * m.ellipse[1],
            m.published.map_or(String::new(), |p| format!(" (published: {:.1} %)", 100.0 * p))
        ),
        None if args.config.hmd_mask => text += "\nHMD mask: the profile's ellipse (the runtime offers no visibility mask)",
        None => {}
    }
    let judged = &summary.judged;
    if let Some(last) = &judged.last {
        text += &format!(
            "\njudge: {} frames judged against the full-quality reference ({:.0} ms each, not in the frame times); the last: {last}",
            judged.frames,
            judged.ms / judged.frames as f64
        );
    }
    text
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
