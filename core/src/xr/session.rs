//! A session with the runtime: its array swapchain, into which the frame's last pass renders
//! directly, the runtime's hidden-area mesh, and the frame loop ([`XrSession`] is the
//! lifecycle's backend).

use std::time::Instant;

use ash::vk::{self, Handle};
use glam::Vec2;
use openxr as xr;

use super::error::{XrError, XrResultExt};
use super::gaze::eye_gazes;
use super::lifecycle::{FrameOutcome, SessionBackend};
use super::pixels::check_pixels;
use super::runtime::{XrRuntime, STEREO};
use super::summary::{Judged, XrSummary};
use super::tracker::EyeTracker;
use super::views::{fit_eyes, fov_tangents, FittedEyes, Pose};
use super::visibility::{hidden_areas, MaskFractions};
use crate::foveation::{GazeFilter, GazeSample};
use crate::gpu::Gpu;
use crate::judge::LiveJudge;
use crate::metrics::perceptual::Maps;
use crate::metrics::PerSecond;
use crate::plan::{FramePlan, OutputStage, RenderConfig, Resolution};
use crate::render::{output_image_desc, FrameInput, FramesInFlight, Renderer};
use crate::scene::Scene;
use crate::view::{Eye, EyeParams, FovTangents, HiddenArea};

/// The swapchain's format and usage, which the plan's output image must have: rendered into,
/// and read back by `--check-pixels`.
const SWAPCHAIN_FORMAT: vk::Format = vk::Format::R8G8B8A8_SRGB;
const SWAPCHAIN_USAGE: vk::ImageUsageFlags = vk::ImageUsageFlags::from_raw(
    vk::ImageUsageFlags::COLOR_ATTACHMENT.as_raw() | vk::ImageUsageFlags::TRANSFER_SRC.as_raw(),
);

/// Where each eye looks.
pub enum GazeSource {
    /// Both eyes at one normalised point (−1…1, x right, y up).
    Fixed(Vec2),
    /// A recorded or simulated trace, sampled at each frame's time through the gaze filter.
    Trace(Vec<GazeSample>),
}

/// How `foveate xr` runs.
pub struct XrSettings {
    /// The frame as the user configured it; the runtime sets its size, fields and IPD.
    pub config: RenderConfig,
    /// Where the gaze comes from.
    pub gaze: GazeSource,
    /// Check the first rendered frame's submitted image against a render of the same views.
    pub check_pixels: bool,
    /// Judge every Nth rendered frame's submitted image against its full-quality reference
    /// (`judge::LiveJudge`), before the image goes back to the runtime; its time is taken out
    /// of the frame's.
    pub judge: Option<u32>,
}

/// A session with the runtime on `gpu`: the lifecycle's backend.
pub struct XrSession<'g> {
    gpu: &'g Gpu,
    scene: &'g Scene,
    settings: XrSettings,
    session: xr::Session<xr::Vulkan>,
    waiter: xr::FrameWaiter,
    stream: xr::FrameStream<xr::Vulkan>,
    local: xr::Space,
    recommended: Resolution,
    /// The runtime offers `XR_KHR_visibility_mask`.
    visibility_mask: bool,
    /// Each eye's hidden-area mesh, when the HMD mask takes the runtime's.
    hidden_area: Option<[HiddenArea; 2]>,
    // Declared in drop order: the frames' command buffers record the renderer's objects, and
    // the renderer's framebuffers view the swapchain's images.
    frames: Option<FramesInFlight>,
    renderer: Option<Renderer>,
    swapchain: Option<xr::Swapchain<xr::Vulkan>>,
    /// `judge`: the reference's renderer and the GPU judge, made with the renderer.
    judge: Option<LiveJudge>,
    filter: GazeFilter,
    /// The runtime's eye tracker, when the system has one and it could be set up.
    tracker: Option<EyeTracker>,
    started: Option<Instant>,
    last_display_time: Option<i64>,
    second: PerSecond,
    /// What the run measured so far.
    pub summary: XrSummary,
}

impl<'g> XrSession<'g> {
    /// A session on `runtime` rendering `scene` on `gpu`, as `settings` say.
    pub fn new(
        runtime: &XrRuntime,
        gpu: &'g Gpu,
        scene: &'g Scene,
        settings: XrSettings,
    ) -> Result<Self, XrError> {
        let h = gpu.raw_handles();
        let info = xr::vulkan::SessionCreateInfo {
            instance: h.instance.as_raw() as _,
            physical_device: h.physical.as_raw() as _,
            device: h.device.as_raw() as _,
            queue_family_index: h.queue_family,
            queue_index: h.queue_index,
        };
        // SAFETY: the handles are the runtime's own (made through it) and outlive the session:
        // the `Gpu` is borrowed for the session's life.
        let (session, waiter, stream) = unsafe {
            runtime
                .instance
                .create_session::<xr::Vulkan>(runtime.system, &info)
        }
        .xr("xrCreateSession")?;
        let local = session
            .create_reference_space(xr::ReferenceSpaceType::LOCAL, xr::Posef::IDENTITY)
            .xr("xrCreateReferenceSpace")?;
        let tracker = match runtime.report.eye_gaze {
            false => None,
            true => EyeTracker::new(&runtime.instance, &session)
                .map_err(|e| {
                    log::warn!(
                        "the eye tracker could not be set up ({e}): using the configured gaze"
                    )
                })
                .ok(),
        };
        Ok(XrSession {
            tracker,
            gpu,
            scene,
            settings,
            session,
            waiter,
            stream,
            local,
            recommended: runtime.report.recommended,
            visibility_mask: runtime.visibility_mask,
            hidden_area: None,
            frames: None,
            renderer: None,
            swapchain: None,
            judge: None,
            filter: GazeFilter::new(0.1),
            started: None,
            last_display_time: None,
            second: PerSecond::default(),
            summary: XrSummary::default(),
        })
    }

    /// An array swapchain of two layers, made as the plan's output image.
    fn make_swapchain(&self) -> Result<xr::Swapchain<xr::Vulkan>, XrError> {
        let formats = self
            .session
            .enumerate_swapchain_formats()
            .xr("xrEnumerateSwapchainFormats")?;
        let wanted = SWAPCHAIN_FORMAT.as_raw() as u32;
        if !formats.contains(&wanted) {
            return Err(XrError::NoSwapchainFormat(formats));
        }
        let r = self.recommended;
        let swapchain = self
            .session
            .create_swapchain(&xr::SwapchainCreateInfo {
                create_flags: xr::SwapchainCreateFlags::EMPTY,
                // SWAPCHAIN_USAGE in OpenXR's bits (which are not Vulkan's).
                usage_flags: xr::SwapchainUsageFlags::COLOR_ATTACHMENT
                    | xr::SwapchainUsageFlags::TRANSFER_SRC,
                format: wanted,
                sample_count: 1,
                width: r.width,
                height: r.height,
                face_count: 1,
                array_size: 2,
                mip_count: 1,
            })
            .xr("xrCreateSwapchain")?;
        Ok(swapchain)
    }

    /// The frame's configuration for eyes `fitted`: the runtime's size, fields and IPD, into
    /// the runtime's images.
    fn config(&self, eyes: &EyeParams) -> RenderConfig {
        let (l, r) = (eyes.left_fov, eyes.right_fov.mirrored());
        // One field for both eyes (the right mirrors the left): the union of the two.
        let fov = FovTangents {
            left: l.left.max(r.left),
            right: l.right.max(r.right),
            up: l.up.max(r.up),
            down: l.down.max(r.down),
        };
        RenderConfig {
            resolution: Some(self.recommended),
            fov: Some(fov),
            ipd_m: Some(eyes.ipd_m),
            cant_deg: Some(eyes.cant_rad.to_degrees()),
            output: OutputStage::Undistorted,
            external_output: true,
            hidden_area_mesh: self.mesh_mask(),
            ..self.settings.config.clone()
        }
    }

    fn plan_for(&self, eyes: &EyeParams) -> Result<FramePlan, XrError> {
        let config = self.config(eyes);
        let plan = crate::plan(self.scene, &config, self.gpu.caps())?;
        // The swapchain was made before the plan: what the plan renders must be what it holds.
        let desc = output_image_desc(&plan);
        let r = self.recommended;
        let swapchain = (r.width, r.height, 2, SWAPCHAIN_FORMAT, SWAPCHAIN_USAGE);
        let output = (
            desc.width,
            desc.height,
            desc.layers,
            desc.format,
            desc.usage,
        );
        if output != swapchain {
            return Err(XrError::OutputMismatch(format!(
                "the plan's output {output:?} against the swapchain's {swapchain:?}"
            )));
        }
        Ok(plan)
    }

    /// Each eye's gaze at `t` seconds into the run.
    fn gaze(&mut self, t: f64, fitted: &FittedEyes, time: xr::Time) -> [Vec2; 2] {
        if let Some(tracker) = &self.tracker {
            // The gaze's direction in the runtime's space, turned into the fitted head's.
            match tracker.direction(&self.session, &self.local, time) {
                Ok(direction) => {
                    let head = direction
                        .map(|d| fitted.world_from_head.inverse().transform_vector3(d))
                        .and_then(|d| eye_gazes(&fitted.eyes, d));
                    let sample = GazeSample {
                        t,
                        left: head.map_or(Vec2::NAN, |g| g[0]),
                        right: head.map_or(Vec2::NAN, |g| g[1]),
                        valid: head.is_some(),
                    };
                    return self.filter.update(&sample);
                }
                Err(e) => {
                    log::warn!(
                        "the eye tracker failed ({e}): using the configured gaze from now on"
                    );
                    self.tracker = None;
                }
            }
        }
        match &self.settings.gaze {
            GazeSource::Fixed(g) => [*g; 2],
            GazeSource::Trace(samples) => {
                let i = samples.partition_point(|s| s.t <= t).saturating_sub(1);
                match samples.get(i) {
                    Some(s) => self.filter.update(s),
                    None => [Vec2::ZERO; 2],
                }
            }
        }
    }

    /// The located `views` fitted to foveate's eye model; how far they lie from it is kept
    /// (and said once when it exceeds a millimetre).
    fn fit(&mut self, views: &[xr::View]) -> FittedEyes {
        let pose = |v: &xr::View| {
            let (o, p) = (v.pose.orientation, v.pose.position);
            Pose {
                orientation: [o.x, o.y, o.z, o.w],
                position: [p.x, p.y, p.z],
            }
            .matrix()
        };
        let fov = |v: &xr::View| {
            let f = v.fov;
            fov_tangents(f.angle_left, f.angle_right, f.angle_up, f.angle_down)
        };
        let fitted = fit_eyes(
            [pose(&views[0]), pose(&views[1])],
            [fov(&views[0]), fov(&views[1])],
        );
        let error = &mut self.summary.eye_fit_error;
        if fitted.position_error_m > 1e-3 && error.0 <= 1e-3 {
            log::warn!(
                "the runtime's eyes lie {:.1} mm, {:.2}° from foveate's eye model (IPD and cant only)",
                fitted.position_error_m * 1e3,
                fitted.angle_error_deg
            );
        }
        error.0 = error.0.max(fitted.position_error_m);
        error.1 = error.1.max(fitted.angle_error_deg);
        fitted
    }

    /// A renderer for `eyes`: the current one when they fit its plan, else a new plan and
    /// renderer into the swapchain's images (a replan, counted).
    fn renderer_for(&mut self, eyes: EyeParams) -> Result<(), XrError> {
        let fits = self.renderer.as_mut().map(|r| r.set_eyes(eyes));
        if let Some(Ok(())) = fits {
            return Ok(());
        }
        if let Some(Err(why)) = fits {
            log::info!("replanning: this frame's eyes do not fit the plan ({why})");
            self.summary.replans += 1;
            // The old renderer's frames may still run.
            self.gpu.wait_idle()?;
        }
        self.frames = None;
        self.renderer = None;
        let plan = self.plan_for(&eyes)?;
        log::info!("{}", plan.to_string().lines().next().unwrap_or_default());
        log::debug!("{plan}");
        let swapchain = self.swapchain.as_ref().expect("made at begin");
        let images: Vec<vk::Image> = swapchain
            .enumerate_images()
            .xr("xrEnumerateSwapchainImages")?
            .into_iter()
            .map(vk::Image::from_raw)
            .collect();
        let mut renderer = Renderer::with_output_images(self.gpu, &plan, self.scene, &images)?;
        renderer.set_eyes(eyes)?;
        if let Some(areas) = &self.hidden_area {
            renderer.set_hidden_area(areas.clone())?;
            self.summary.mask_hidden = Some(MaskFractions {
                mesh: Eye::BOTH.map(|e| areas[e.index()].hidden_fraction(eyes.fov(e))),
                ellipse: plan
                    .hmd_mask
                    .map(|r| r.map(|l| l.hidden_fraction()))
                    .unwrap_or_default(),
                published: plan.hmd.hidden_area_fraction,
                profile: plan.hmd.name,
            });
        }
        let config = self.config(&eyes);
        let judge = self.settings.judge;
        self.judge = judge
            .map(|every| LiveJudge::new(self.gpu, self.scene, &config, every))
            .transpose()?;
        let frames = FramesInFlight::new(&renderer)?;
        self.summary.frames_in_flight = frames.len();
        self.frames = Some(frames);
        self.renderer = Some(renderer);
        Ok(())
    }

    /// Renders a frame of the located `views` into the next swapchain image (planning first
    /// when there is no plan, or the eyes outgrew it); each pass's GPU time.
    fn render(&mut self, views: &[xr::View], time: xr::Time) -> Result<Vec<f64>, XrError> {
        let fitted = self.fit(views);
        self.renderer_for(fitted.eyes)?;
        let t = self
            .started
            .get_or_insert_with(Instant::now)
            .elapsed()
            .as_secs_f64();
        let gaze = self.gaze(t, &fitted, time);
        let world_from_head = self.scene.head * fitted.world_from_head;
        // Only the first frame is checked: only it needs the reference's configuration.
        let check = (self.settings.check_pixels && self.summary.pixels.is_none())
            .then(|| self.config(&fitted.eyes));
        let swapchain = self.swapchain.as_mut().expect("made at begin");
        let index = swapchain.acquire_image().xr("xrAcquireSwapchainImage")?;
        swapchain
            .wait_image(xr::Duration::INFINITE)
            .xr("xrWaitSwapchainImage")?;
        let renderer = self.renderer.as_mut().expect("made above");
        let frames = self.frames.as_mut().expect("made with the renderer");
        let input = FrameInput::new(world_from_head).with_gaze(gaze);
        let finished = renderer
            .select_output(index as usize)
            .and_then(|()| frames.render(renderer, &input));
        let checked = match (&finished, check) {
            (Ok(_), Some(config)) => Some(frames.wait_last().and_then(|()| {
                check_pixels(
                    self.gpu,
                    self.scene,
                    &config,
                    renderer,
                    self.hidden_area.as_ref(),
                    world_from_head,
                )
            })),
            _ => None,
        };
        // Judged while the image is still the app's: read back before it is released.
        let judging = Instant::now();
        let due = finished.is_ok() && self.judge.as_mut().is_some_and(|j| j.due());
        let judged = match self.judge.as_mut() {
            Some(judge) if due => Some(
                frames
                    .wait_last()
                    .map_err(XrError::from)
                    .and_then(|()| Ok(judge.judge(renderer, &input, Maps::Drop)?)),
            ),
            _ => None,
        };
        let judge_ms = judging.elapsed().as_secs_f64() * 1e3;
        // The image goes back to the runtime whatever happened to the frame: its commands
        // are submitted, and the runtime's use of the image follows them on the queue.
        swapchain.release_image().xr("xrReleaseSwapchainImage")?;
        let finished = finished?;
        if let Some(check) = checked {
            let check = check?;
            log::info!("{check}");
            self.summary.pixels = Some(check);
        }
        if let Some(result) = judged {
            let judgement = result?;
            let judged = &mut self.summary.judged;
            judged.frames += 1;
            judged.last = Some(judgement);
            judged.ms += judge_ms;
        }
        // The figures of the frame that finished meanwhile (frames in flight earlier).
        Ok(finished.map_or(Vec::new(), |stats| {
            self.summary.draws = (stats.draw_calls, stats.triangles);
            stats.gpu_pass_ms
        }))
    }

    /// Whether the HMD mask takes the runtime's mesh: asked for, and offered.
    fn mesh_mask(&self) -> bool {
        self.settings.config.hmd_mask && self.visibility_mask
    }

    /// Fetches each eye's hidden-area mesh (at the session's start, and again when the
    /// runtime says it changed) and hands it to the renderer.
    pub fn load_hidden_area(&mut self) -> Result<(), XrError> {
        if !self.mesh_mask() {
            return Ok(());
        }
        let areas = hidden_areas(&self.session)?;
        log::info!(
            "the runtime's hidden-area meshes: {} and {} triangles",
            areas[0].triangles.len(),
            areas[1].triangles.len()
        );
        if let Some(r) = &mut self.renderer {
            r.set_hidden_area(areas.clone())?;
        }
        self.hidden_area = Some(areas);
        Ok(())
    }

    fn pass_names(&self) -> Vec<&'static str> {
        self.renderer.as_ref().map_or(Vec::new(), |r| {
            r.plan().passes.iter().map(|p| p.name).collect()
        })
    }
}

impl SessionBackend for XrSession<'_> {
    type Error = XrError;

    fn begin(&mut self) -> Result<(), XrError> {
        self.session.begin(STEREO).xr("xrBeginSession")?;
        self.load_hidden_area()?;
        self.swapchain = Some(self.make_swapchain()?);
        Ok(())
    }

    fn end(&mut self) -> Result<(), XrError> {
        self.gpu.wait_idle()?;
        self.frames = None;
        self.renderer = None;
        self.swapchain = None;
        self.session.end().xr("xrEndSession")?;
        Ok(())
    }

    fn frame(&mut self) -> Result<FrameOutcome, XrError> {
        let state = self.waiter.wait().xr("xrWaitFrame")?;
        let start = Instant::now();
        let period_ms = state.predicted_display_period.as_nanos() as f64 / 1e6;
        let time = state.predicted_display_time.as_nanos();
        if let Some(last) = self.last_display_time {
            let gap = (time - last) as f64 / 1e6;
            if period_ms > 0.0 && gap > 1.5 * period_ms {
                self.summary.pacing.late += ((gap / period_ms).round() as u64).saturating_sub(1);
            }
        }
        self.last_display_time = Some(time);
        self.summary.pacing.display_period_ms = period_ms;
        self.stream.begin().xr("xrBeginFrame")?;
        let located = if state.should_render {
            let (flags, views) = self
                .session
                .locate_views(STEREO, state.predicted_display_time, &self.local)
                .xr("xrLocateViews")?;
            let valid = flags.contains(xr::ViewStateFlags::ORIENTATION_VALID)
                && flags.contains(xr::ViewStateFlags::POSITION_VALID);
            valid.then_some(views)
        } else {
            None
        };
        let Some(views) = located else {
            self.stream
                .end(
                    state.predicted_display_time,
                    xr::EnvironmentBlendMode::OPAQUE,
                    &[],
                )
                .xr("xrEndFrame")?;
            return Ok(FrameOutcome::Skipped);
        };
        let judging_before = self.summary.judged.ms;
        let gpu_pass_ms = self.render(&views, state.predicted_display_time)?;
        // The judge's time is the judge's: not the frame's.
        let judge_ms = self.summary.judged.ms - judging_before;
        let r = self.recommended;
        let rect = xr::Rect2Di {
            offset: xr::Offset2Di { x: 0, y: 0 },
            extent: xr::Extent2Di {
                width: r.width as i32,
                height: r.height as i32,
            },
        };
        let swapchain = self.swapchain.as_ref().expect("made at begin");
        let projection_views = [0u32, 1].map(|i| {
            let v = &views[i as usize];
            xr::CompositionLayerProjectionView::new()
                .pose(v.pose)
                .fov(v.fov)
                .sub_image(
                    xr::SwapchainSubImage::new()
                        .swapchain(swapchain)
                        .image_array_index(i)
                        .image_rect(rect),
                )
        });
        let layer = xr::CompositionLayerProjection::new()
            .space(&self.local)
            .views(&projection_views);
        let ending = Instant::now();
        self.stream
            .end(
                state.predicted_display_time,
                xr::EnvironmentBlendMode::OPAQUE,
                &[&layer],
            )
            .xr("xrEndFrame")?;
        // How long the runtime held the frame in xrEndFrame (a runtime that waits there for
        // the frame's GPU work leaves frames in flight nothing to overlap).
        log::debug!("xrEndFrame {:.1} ms", ending.elapsed().as_secs_f64() * 1e3);
        self.summary.frames_rendered += 1;
        let ms = start.elapsed().as_secs_f64() * 1e3 - judge_ms;
        self.summary.frame_ms.push(ms);
        self.second.push(ms, gpu_pass_ms);
        if self.second.due() {
            if let Some(second) = self.second.take() {
                let pacing = self.summary.pacing;
                let judged = match &self.summary.judged {
                    Judged {
                        frames,
                        last: Some(last),
                        ms,
                    } => format!("; {last} ({frames} judged, {ms:.0} ms judging)"),
                    _ => String::new(),
                };
                log::info!(
                    "{}; display period {:.1} ms, {} late so far{judged}",
                    second.describe(&self.pass_names()),
                    pacing.display_period_ms,
                    pacing.late
                );
            }
        }
        Ok(FrameOutcome::Submitted)
    }

    fn request_exit(&mut self) -> Result<(), XrError> {
        self.session.request_exit().xr("xrRequestExitSession")
    }

    fn abandon(&mut self) {
        let _ = self.gpu.wait_idle();
        self.frames = None;
        self.renderer = None;
        self.swapchain = None;
    }
}
