//! `foveate view`: the frame in a window (winit; X11 or Wayland), presented through a Vulkan
//! swapchain (`foveate::gpu::Swapchain`, shared with the Android demo): the output stage's eye
//! images side by side, the mouse as the gaze, keys for the settings (`view_keys`), frame and
//! GPU times and fragments once a second in the title bar and on stdout.

use std::path::PathBuf;
use std::time::Instant;

use anyhow::{Context, Result};
use clap::Args;
use foveate::foveation::{DelayedGaze, GazeLatency, GazeSample, GazeSpace, Prediction};
use foveate::gpu::{Acquired, Gpu, GpuOptions, Presented, Swapchain};
use foveate::judge::{LiveJudge, LiveJudgement};
use foveate::metrics::perceptual::{heat_map, Maps};
use foveate::metrics::{PerSecond, RgbaImage};
use foveate::render::{FrameInput, FrameStats, FramesInFlight, Renderer};
use foveate::scene::Scene;
use glam::Vec2;
use winit::application::ApplicationHandler;
use winit::dpi::PhysicalSize;
use winit::event::{ElementState, WindowEvent};
use winit::event_loop::{ActiveEventLoop, ControlFlow, EventLoop};
use winit::keyboard::{Key, NamedKey};
use winit::raw_window_handle::{HasDisplayHandle, HasWindowHandle};
use winit::window::{Window, WindowId};

use crate::frame_args::ConfigArgs;
use crate::view_keys::{KeyAction, ViewSettings, KEYS};

/// Where `j` writes the last judgement's heat map.
const HEAT_MAP: &str = "view-heatmap.png";

#[derive(Args)]
pub struct ViewArgs {
    #[command(flatten)]
    pub config: ConfigArgs,
    /// Exit after presenting this many frames (default: run until closed).
    #[arg(long)]
    pub frames: Option<u64>,
    /// On exit, save the last presented image (read back from the swapchain) to this PNG.
    #[arg(long)]
    pub save: Option<PathBuf>,
    /// Window size in pixels, WxH (default: the two eyes side by side, at most 1600 wide).
    #[arg(long)]
    pub window: Option<String>,
    /// The mouse as an eye tracker with this latency (ms): the fovea follows where the mouse
    /// was this long ago, so the lag after a jump can be seen.
    #[arg(
        long,
        default_value_t = 0.0,
        value_name = "MS",
        allow_hyphen_values = true
    )]
    pub gaze_latency: f64,
    /// How the late gaze is predicted forward: none, linear or saccade-landing.
    #[arg(long, default_value = "none")]
    pub gaze_predict: Prediction,
    /// Frames recorded and submitted before the first of them is waited for (1 to 4): with 2,
    /// frame N+1 records while frame N runs on the GPU.
    #[arg(long, default_value_t = 2)]
    pub frames_in_flight: u32,
    /// Judge every Nth presented frame (every 10th when N is left out) against its full-quality
    /// reference (the same pose and gaze, drawn in full with 4× MSAA) on the GPU: the
    /// eccentricity-aware FLIP's 99th percentile per region in the title bar and on stdout, and
    /// `j` writes the last judgement's heat map. Judging runs between frames: its time is
    /// reported apart and is in no frame's time.
    #[arg(long, num_args = 0..=1, default_missing_value = "10", value_name = "N")]
    pub judge: Option<u32>,
}

pub fn view(options: &GpuOptions, args: &ViewArgs) -> Result<()> {
    anyhow::ensure!(
        args.frames != Some(0),
        "invalid frames = 0: at least 1 (or leave it out to run until closed)"
    );
    if let Some(path) = &args.save {
        crate::outputs::image(path)?;
    }
    if args.config.stereo == "all" {
        anyhow::bail!("invalid stereo = all: the viewer shows one stereo mode (s cycles them)");
    }
    let window_size = match &args.window {
        Some(s) => parse_size(s)?,
        None => None,
    };
    let scene = args.config.scene()?;
    let latency =
        GazeLatency::new(args.gaze_latency, args.gaze_predict).map_err(anyhow::Error::msg)?;
    let space = GazeSpace {
        fov: crate::frame_args::profile(&args.config.hmd)?.left_fov,
    };
    let config = crate::frame_args::with_frames_in_flight(
        args.config.config(args.config.stereo.parse()?)?,
        args.frames_in_flight,
    )?;
    let settings = ViewSettings::new(config, scene.shading());
    let event_loop = EventLoop::new().context(
        "cannot open a window: no display (set DISPLAY or WAYLAND_DISPLAY, or run under xvfb-run)",
    )?;
    let display = event_loop.display_handle()?.as_raw();
    let gpu = Gpu::new(&GpuOptions {
        display: Some(display),
        ..options.clone()
    })?;
    println!(
        "device: {}; frames in flight: {}",
        gpu.info().name,
        settings.config.frames_in_flight
    );
    println!(
        "keys: {}; the mouse moves the gaze",
        KEYS.iter()
            .map(|(k, what)| format!("{k} {what}"))
            .collect::<Vec<_>>()
            .join(", ")
    );
    if let Some(every) = args.judge {
        println!(
            "judge: every {every} frames against the full-quality reference; j writes the last judgement's heat map ({HEAT_MAP})"
        );
    }
    if latency != GazeLatency::NONE {
        println!(
            "gaze: the mouse through {} ms of tracker latency, predicted {}",
            args.gaze_latency,
            args.gaze_predict.name()
        );
    }
    let mut viewer = Viewer {
        gpu: &gpu,
        scene,
        settings,
        window_size,
        frames_wanted: args.frames,
        judge_every: args.judge,
        judged: None,
        save: args.save.clone(),
        swapchain: None,
        window: None,
        frame: None,
        gaze: Vec2::ZERO,
        tracker: DelayedGaze::new(latency, space),
        clock: Instant::now(),
        shown_gaze: Vec2::ZERO,
        presented: 0,
        second: PerSecond::default(),
        capture: None,
        finishing: false,
        error: None,
    };
    event_loop.set_control_flow(ControlFlow::Poll);
    event_loop.run_app(&mut viewer)?;
    if let Some(e) = viewer.error.take() {
        return Err(e);
    }
    drop(viewer.frame.take());
    drop(viewer.swapchain.take());
    if let (Some(path), Some(image)) = (&args.save, &viewer.capture) {
        image.save(path)?;
        println!(
            "saved {} ({}x{}, the last presented image)",
            path.display(),
            image.width,
            image.height
        );
    }
    println!("presented {} frames", viewer.presented);
    gpu.check_validation()?;
    Ok(())
}

fn parse_size(s: &str) -> Result<Option<(u32, u32)>> {
    let parsed = s
        .split_once('x')
        .and_then(|(w, h)| Some((w.parse::<u32>().ok()?, h.parse::<u32>().ok()?)));
    match parsed {
        Some((w, h)) if (1..=16384).contains(&w) && (1..=16384).contains(&h) => Ok(Some((w, h))),
        _ => anyhow::bail!("invalid window = {s:?}: WxH, each 1 to 16384 pixels"),
    }
}

/// The renderers of the current settings: the timed one the window shows, and one with
/// counters for the once-a-second fragment count (timed frames carry no counters).
struct Frame {
    /// The timed renderer's frames in flight (declared first: dropped, so waited for, before
    /// the renderers their commands use).
    frames: FramesInFlight,
    timed: Renderer,
    counting: Renderer,
    pass_names: Vec<&'static str>,
    scene: Scene,
    /// `--judge`: the timed renderer's frames against their reference.
    judge: Option<LiveJudge>,
}

struct Viewer<'g> {
    gpu: &'g Gpu,
    /// The scene as loaded; each shading is derived from it.
    scene: Scene,
    settings: ViewSettings,
    window_size: Option<(u32, u32)>,
    frames_wanted: Option<u64>,
    /// `--judge N`.
    judge_every: Option<u32>,
    /// The last judgement: its figures for the title bar, its heat maps.
    judged: Option<LiveJudgement>,
    save: Option<PathBuf>,
    // Dropped in this order: renderers, swapchain, then the window it presents to.
    frame: Option<Frame>,
    swapchain: Option<Swapchain>,
    window: Option<Window>,
    /// Where the mouse points.
    gaze: Vec2,
    /// The mouse as a tracker with latency, sampled each frame; the fovea follows it.
    tracker: DelayedGaze,
    clock: Instant,
    shown_gaze: Vec2,
    presented: u64,
    second: PerSecond,
    capture: Option<RgbaImage>,
    /// Quitting: one more frame is presented (and captured with --save), then the loop ends.
    finishing: bool,
    error: Option<anyhow::Error>,
}

impl<'g> Viewer<'g> {
    fn fail(&mut self, event_loop: &ActiveEventLoop, e: anyhow::Error) {
        self.error = Some(e);
        event_loop.exit();
    }

    /// The renderers for the current settings, made when missing.
    fn frame(&mut self) -> Result<&mut Frame> {
        if self.frame.is_none() {
            let scene = self.scene.clone().with_shading(self.settings.shading);
            let config = &self.settings.config;
            let plan = foveate::plan(&scene, config, self.gpu.caps())?;
            let counting_plan = foveate::plan(&scene, &config.counting(), self.gpu.caps())?;
            let pass_names = plan.passes.iter().map(|p| p.name).collect();
            let timed = Renderer::new(self.gpu, &plan, &scene)?;
            let judge = self
                .judge_every
                .map(|every| LiveJudge::new(self.gpu, &scene, config, every))
                .transpose()?;
            self.frame = Some(Frame {
                frames: FramesInFlight::new(&timed)?,
                timed,
                counting: Renderer::new(self.gpu, &counting_plan, &scene)?,
                pass_names,
                scene,
                judge,
            });
        }
        Ok(self.frame.as_mut().expect("made above"))
    }

    fn key(&mut self, key: char) {
        if key == 'j' && self.judge_every.is_some() {
            if let Err(e) = self.save_heat_map() {
                println!("heat map: {e:#}");
            }
            return;
        }
        let before = self.settings.clone();
        match self.settings.key(key) {
            KeyAction::Quit => self.finishing = true,
            KeyAction::Ignored => {}
            KeyAction::Changed(what) => {
                self.frame = None;
                // The last judgement was of other settings.
                self.judged = None;
                // A combination the planner refuses is reported and undone.
                if let Err(e) = self.frame() {
                    println!("{what}: refused ({e:#}); back to the previous settings");
                    self.settings = before;
                    self.frame = None;
                } else {
                    println!("{what}");
                }
                self.second = PerSecond::default();
                if let Some(w) = &self.window {
                    w.request_redraw();
                }
            }
        }
    }

    fn draw(&mut self, event_loop: &ActiveEventLoop) -> Result<()> {
        let now = self.clock.elapsed().as_secs_f64();
        self.tracker.push(GazeSample {
            t: now,
            left: self.gaze,
            right: self.gaze,
            valid: true,
        });
        self.shown_gaze = self.tracker.gaze_at(now);
        let gaze = [self.shown_gaze; 2];
        let capture = self.save.is_some()
            && (self.finishing || self.frames_wanted == Some(self.presented + 1));
        let started = Instant::now();
        let gpu = self.gpu;
        self.frame()?;
        let frame = self.frame.as_mut().expect("made above");
        let swapchain = self.swapchain.as_mut().expect("a window has a swapchain");
        // The frame that held this slot before is waited for here: with frames in flight,
        // the CPU records this one while the GPU still runs the one before.
        let (begun, finished) = frame.frames.begin(&mut frame.timed)?;
        // SAFETY: `begin` waited for the frame that acquired with this slot before.
        let acquired = unsafe { swapchain.acquire(gpu, begun.slot)? };
        let input = FrameInput::new(frame.scene.head).with_gaze(gaze);
        // SAFETY: the slot's buffer, begun by `begin`, whose previous frame finished.
        let record = unsafe { frame.timed.record(begun.cmd, &input)? };
        let image = match acquired {
            Acquired::Image(image) => image,
            Acquired::Skipped => {
                // SAFETY: the renderer outlives its frames (`Frame` drops `frames` first).
                unsafe { frame.frames.submit(begun, record, &[], &[])? };
                return Ok(());
            }
            Acquired::Lost => anyhow::bail!("the window's surface is gone"),
        };
        let sources = frame.timed.present_sources()?;
        // SAFETY: recorded after the frame into its buffer; the outputs live with the renderer.
        unsafe { swapchain.record_copy(gpu, begun.cmd, &image, &sources, capture)? };
        // SAFETY: as above; the image's semaphores are waited for and signalled once each.
        unsafe {
            frame
                .frames
                .submit(begun, record, &image.waits(), &image.signals())?
        };
        if swapchain.present(gpu, image)? == Presented::Lost {
            anyhow::bail!("the window's surface is gone");
        }
        self.presented += 1;
        if capture {
            frame.frames.wait_last()?;
            self.capture = swapchain.captured();
        }
        if let Some(stats) = finished {
            self.second
                .push(started.elapsed().as_secs_f64() * 1e3, stats.gpu_pass_ms);
        }
        if self.second.due() {
            self.report()?;
        }
        self.judge_last(&input)?;
        let done = self.frames_wanted.is_some_and(|n| self.presented >= n);
        if done || (self.finishing && (self.save.is_none() || self.capture.is_some())) {
            event_loop.exit();
        }
        Ok(())
    }

    /// Once a second: median frame time, median GPU time per pass (summed: GPU) and a counting
    /// frame's fragments, in the title bar and on stdout.
    fn report(&mut self) -> Result<()> {
        let Some(second) = self.second.take() else {
            return Ok(());
        };
        let gaze = [self.shown_gaze; 2];
        let summary = self.settings.summary();
        let frame = self.frame()?;
        frame.counting.set_gaze(gaze)?;
        let counted: FrameStats = frame.counting.render_frame(frame.scene.head)?;
        let fragments: u64 =
            counted.fragments.iter().sum::<u64>() + counted.far_fragments.unwrap_or(0);
        let line = format!(
            "{}, {:.2} M scene fragments — {summary}",
            second.describe(&frame.pass_names),
            fragments as f64 / 1e6
        );
        println!("view: {line}");
        let judged = self
            .judged
            .as_ref()
            .map_or(String::new(), |j| format!(" | {j}"));
        if let Some(w) = &self.window {
            w.set_title(&format!("foveate view — {line}{judged}"));
        }
        Ok(())
    }

    /// `--judge`: the last frame judged against its reference when one is due, between frames
    /// (every frame in flight waited for first, so no frame's time holds the judge's).
    fn judge_last(&mut self, input: &FrameInput) -> Result<()> {
        let Some(frame) = self.frame.as_mut() else {
            return Ok(());
        };
        let Some(judge) = frame.judge.as_mut() else {
            return Ok(());
        };
        if !judge.due() {
            return Ok(());
        }
        frame.frames.wait_all()?;
        let judgement = judge.judge(&frame.timed, input, Maps::Keep)?;
        println!(
            "judge: {judgement}; reference {:.0} ms, judging {:.0} ms, apart from the frame times",
            judgement.reference_ms, judgement.judge_ms
        );
        self.judged = Some(judgement);
        Ok(())
    }

    /// `j`: the last judgement's eccentricity-aware maps as a heat map, eyes side by side.
    fn save_heat_map(&self) -> Result<()> {
        let Some(judgement) = &self.judged else {
            println!("heat map: no frame judged yet");
            return Ok(());
        };
        let Some(maps) = &judgement.error.maps else {
            return Ok(());
        };
        let [left, right] = [0, 1].map(|eye| heat_map(&maps[eye], &judgement.pixels[eye]));
        RgbaImage::side_by_side(&left, &right).save(HEAT_MAP.as_ref())?;
        println!(
            "wrote {HEAT_MAP} (the last judged frame's eccentricity-aware FLIP, left | right)"
        );
        Ok(())
    }

    fn open_window(&mut self, event_loop: &ActiveEventLoop) -> Result<()> {
        let config = &self.settings.config;
        let eye = config
            .resolution
            .map(|r| (r.width, r.height))
            .unwrap_or((1024, 1024));
        let (w, h) = self.window_size.unwrap_or_else(|| {
            let scale = (1600.0 / (2 * eye.0) as f64).min(1.0);
            (
                ((2 * eye.0) as f64 * scale) as u32,
                (eye.1 as f64 * scale) as u32,
            )
        });
        let window = event_loop.create_window(
            Window::default_attributes()
                .with_title("foveate view")
                .with_inner_size(PhysicalSize::new(w, h)),
        )?;
        let size = window.inner_size();
        // SAFETY: the window lives in `self.window`, which drops after `self.swapchain`.
        let swapchain = unsafe {
            Swapchain::new(
                self.gpu,
                window.display_handle()?.as_raw(),
                window.window_handle()?.as_raw(),
                (size.width, size.height),
            )
        }?;
        self.swapchain = Some(swapchain);
        self.window = Some(window);
        Ok(())
    }
}

impl ApplicationHandler for Viewer<'_> {
    fn resumed(&mut self, event_loop: &ActiveEventLoop) {
        if self.window.is_none() {
            if let Err(e) = self.open_window(event_loop) {
                self.fail(event_loop, e);
            }
        }
    }

    fn window_event(&mut self, event_loop: &ActiveEventLoop, _id: WindowId, event: WindowEvent) {
        match event {
            WindowEvent::CloseRequested => {
                self.finishing = true;
                if self.save.is_none() {
                    event_loop.exit();
                }
            }
            WindowEvent::Resized(size) => {
                if let Some(s) = &mut self.swapchain {
                    s.resize((size.width, size.height));
                }
            }
            WindowEvent::CursorMoved { position, .. } => {
                if let Some((_, g)) = self
                    .swapchain
                    .as_ref()
                    .and_then(|s| s.locate(position.x, position.y))
                {
                    self.gaze = Vec2::from(g);
                }
            }
            WindowEvent::KeyboardInput { event, .. } if event.state == ElementState::Pressed => {
                match event.logical_key {
                    Key::Named(NamedKey::Escape) => self.key('q'),
                    Key::Character(s) => {
                        if let Some(c) = s.chars().next() {
                            self.key(c.to_ascii_lowercase());
                        }
                    }
                    _ => {}
                }
            }
            WindowEvent::RedrawRequested => {
                let minimised = self.window.as_ref().is_some_and(|w| {
                    let size = w.inner_size();
                    w.is_minimized() == Some(true) || size.width == 0 || size.height == 0
                });
                if !minimised {
                    if let Err(e) = self.draw(event_loop) {
                        self.fail(event_loop, e);
                    }
                }
            }
            _ => {}
        }
    }

    fn about_to_wait(&mut self, _event_loop: &ActiveEventLoop) {
        if let Some(w) = &self.window {
            w.request_redraw();
        }
    }
}
