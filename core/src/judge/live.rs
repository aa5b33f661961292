//! Judging while rendering: a renderer's last frame against the full-quality reference of the
//! same head pose, eyes and gaze, with the GPU judge — what `foveate view --judge` shows. The
//! reference is rendered and the frame judged apart from the frames being timed: the caller
//! calls [`LiveJudge::judge`] between frames, after the judged frame has finished.

use std::fmt;
use std::time::Instant;

use super::GpuFlip;
use crate::gpu::{Gpu, GpuError};
use crate::metrics::perceptual::{Maps, PerceptualError};
use crate::metrics::{Acuity, ErrorSummary, EyePixels, JudgeError, Region};
use crate::plan::{ConfigError, RenderConfig, StereoMode};
use crate::render::{FrameInput, Renderer};
use crate::scene::Scene;

/// The most frames between two judgements ([`LiveJudge::new`]'s `every`).
pub const MAX_JUDGE_INTERVAL: u32 = 100_000;

/// The full-quality reference a frame of `config` is judged against: the same headset, panel,
/// eyes, lens and output stage, drawn in full (no foveation, far-field sharing, radial density,
/// level of detail or culling) in one multiview pass with 4× MSAA, into an image of its own,
/// one frame in flight. It is not timed: timestamps and fragment counts are off, so its
/// frames' figures carry no GPU times (turn `timestamps` back on to time the reference).
pub fn reference_config(config: &RenderConfig) -> RenderConfig {
    RenderConfig {
        stereo: StereoMode::Multiview,
        views: None,
        msaa: 4,
        count_fragments: false,
        timestamps: false,
        foveation: None,
        mffr: None,
        radial_density: None,
        coverage_probe: false,
        culling: None,
        lod: None,
        external_output: false,
        hidden_area_mesh: false,
        frames_in_flight: 1,
        ..config.clone()
    }
}

/// One judgement of a frame.
#[derive(Clone, Debug)]
pub struct LiveJudgement {
    /// FLIP and the eccentricity-aware FLIP, whole and per region, and the maps if asked for.
    pub error: PerceptualError,
    /// What each eye's pixels are: seen or hidden, their angle from the gaze, their region
    /// (for [`crate::metrics::perceptual::heat_map`]).
    pub pixels: [EyePixels; 2],
    /// Wall time reading the frame back and rendering and reading back the reference (ms).
    pub reference_ms: f64,
    /// Wall time judging both eyes (ms).
    pub judge_ms: f64,
}

impl fmt::Display for LiveJudgement {
    /// The eccentricity-aware FLIP's 99th percentile per region and over every pixel the lens
    /// shows: `eFLIP p99 fovea 0.004, band 0.167, periphery 0.134 (all 0.134)`.
    fn fmt(&self, f: &mut fmt::Formatter<'_>) -> fmt::Result {
        let p99 = |s: Option<ErrorSummary>| s.map_or("-".into(), |s| format!("{:.3}", s.p99));
        write!(f, "eFLIP p99")?;
        for (i, (region, s)) in Region::ALL.iter().zip(self.error.regions).enumerate() {
            let comma = if i == 0 { "" } else { "," };
            write!(f, "{comma} {} {}", region.name(), p99(s))?;
        }
        write!(f, " (all {})", p99(self.error.eccentric))
    }
}

/// Judges every `every`th frame of a renderer against its full-quality reference
/// ([`reference_config`]), on the GPU: the reference's renderer and the judge's pipelines are
/// made once.
pub struct LiveJudge {
    every: u32,
    since: u32,
    reference: Renderer,
    flip: GpuFlip,
    acuity: Acuity,
}

impl LiveJudge {
    /// A judge of frames of `config` (the judged renderer's configuration) drawing `scene`, one
    /// frame in `every` (1 to [`MAX_JUDGE_INTERVAL`]).
    pub fn new(
        gpu: &Gpu,
        scene: &Scene,
        config: &RenderConfig,
        every: u32,
    ) -> Result<Self, GpuError> {
        if !(1..=MAX_JUDGE_INTERVAL).contains(&every) {
            let limit = format!("1 to {MAX_JUDGE_INTERVAL} frames");
            return Err(ConfigError::new("judge every", every, limit).into());
        }
        let plan = crate::plan(scene, &reference_config(config), gpu.caps())?;
        Ok(LiveJudge {
            every,
            since: 0,
            reference: Renderer::new(gpu, &plan, scene)?,
            flip: GpuFlip::new(gpu),
            acuity: Acuity::default(),
        })
    }

    /// Counts a frame; whether it is one to judge (the first, then every `every`th).
    pub fn due(&mut self) -> bool {
        let due = self.since == 0;
        self.since = (self.since + 1) % self.every;
        due
    }

    /// Judges `renderer`'s last frame, whose `input` is given again (its head pose; its gaze
    /// and eyes are the ones the renderer kept from it): renders the reference for the same
    /// pose, eyes and gaze, and judges both eyes over the pixels the lens shows, regions as the
    /// judged frame's foveation draws them; the eccentricity-aware maps come back as `maps`
    /// says (a heat map's worth of reading back, else a few histograms). The frame must have
    /// finished (say, `FramesInFlight::wait_last`).
    pub fn judge(
        &mut self,
        renderer: &Renderer,
        input: &FrameInput,
        maps: Maps,
    ) -> Result<LiveJudgement, JudgeError> {
        let started = Instant::now();
        let gaze = renderer.gaze();
        let reference_input = FrameInput::new(input.world_from_head)
            .with_gaze(gaze)
            .with_eyes(renderer.plan().eyes);
        self.reference.render(&reference_input)?;
        let pixels = EyePixels::both(
            self.reference.plan(),
            gaze[0],
            renderer.plan().foveation.as_ref(),
        );
        let reference_ms = started.elapsed().as_secs_f64() * 1e3;
        let started = Instant::now();
        // Both frames judged where they lie: neither is read back.
        let error =
            (self.flip).frame_errors(&self.reference, renderer, &pixels, self.acuity, maps)?;
        Ok(LiveJudgement {
            error,
            pixels,
            reference_ms,
            judge_ms: started.elapsed().as_secs_f64() * 1e3,
        })
    }
}
