//! One configuration of a soak: its renderer, its frames in flight, and what changes from frame
//! to frame (the head sways, an instance slides, a foveated frame's gaze sweeps).

use std::f32::consts::TAU;
use std::fmt;
use std::str::FromStr;

use anyhow::Result;
use foveate::foveation::FoveationConfig;
use foveate::gpu::Gpu;
use foveate::plan::RenderConfig;
use foveate::render::{FrameInput, FramesInFlight, Renderer};
use foveate::scene::{Scene, Shading};
use glam::{Mat4, Vec2, Vec3};

use super::SoakArgs;

/// Lit or flat shading, stereo or the library's default foveation.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub struct SoakConfig {
    pub lit: bool,
    pub foveated: bool,
}

impl FromStr for SoakConfig {
    type Err = anyhow::Error;

    fn from_str(s: &str) -> Result<Self> {
        let (lit, foveated) = match s.trim() {
            "lit-stereo" => (true, false),
            "lit-foveated" => (true, true),
            "flat-stereo" => (false, false),
            "flat-foveated" => (false, true),
            other => anyhow::bail!(
                "invalid configs = {other}: each one of lit-stereo, lit-foveated, flat-stereo, flat-foveated"
            ),
        };
        Ok(SoakConfig { lit, foveated })
    }
}

impl fmt::Display for SoakConfig {
    fn fmt(&self, f: &mut fmt::Formatter<'_>) -> fmt::Result {
        let shading = if self.lit { "lit" } else { "flat" };
        let frame = if self.foveated { "foveated" } else { "stereo" };
        write!(f, "{shading} {frame}")
    }
}

/// A renderer kept rendering. (Its frames in flight drop first: they wait for the frames
/// still running, which use the renderer's objects.)
pub struct Soaked {
    frames: FramesInFlight,
    renderer: Renderer,
    pub config: SoakConfig,
    head: Mat4,
    /// The instance that slides, and where the scene put it.
    moving: Option<(usize, Mat4)>,
}

impl Soaked {
    pub fn new(gpu: &Gpu, scene: &Scene, config: SoakConfig, args: &SoakArgs) -> Result<Self> {
        let shading = if config.lit {
            Shading::Lit
        } else {
            Shading::Flat
        };
        let scene = scene.clone().with_shading(shading);
        let render = RenderConfig {
            hmd: args.hmd.clone(),
            resolution: crate::frame_args::parse_res(&args.res)?,
            msaa: args.msaa,
            foveation: config.foveated.then(FoveationConfig::default),
            frames_in_flight: 2,
            moving_instances: true,
            ..RenderConfig::default()
        };
        let plan = foveate::plan(&scene, &render, gpu.caps())?;
        let renderer = Renderer::new(gpu, &plan, &scene)?;
        let frames = FramesInFlight::new(&renderer)?;
        let moving = scene.flat_instances().first().map(|i| (0, i.model));
        Ok(Soaked {
            frames,
            renderer,
            config,
            head: scene.head,
            moving,
        })
    }

    /// Records and submits frame `round` (at 90 Hz: the head sways 5 cm every 4 s, the instance
    /// slides half a metre every 3 s, the gaze sweeps every 5 s); returns the GPU time of the
    /// frame that last held its slot (`None` while the slots fill; the plan always has
    /// timestamps, it refuses a device without them).
    pub fn frame(&mut self, round: u64) -> Result<Option<f64>> {
        let t = round as f32 / 90.0;
        let wave = |period: f32| (TAU * t / period).sin();
        if let Some((index, model)) = self.moving {
            let slide = Mat4::from_translation(Vec3::new(0.5 * wave(3.0), 0.0, 0.0));
            self.renderer.move_instance(index, slide * model)?;
        }
        let sway = Mat4::from_translation(Vec3::new(0.05 * wave(4.0), 0.0, 0.0));
        let mut input = FrameInput::new(self.head * sway);
        if self.config.foveated {
            let gaze = Vec2::new(0.3 * wave(5.0), 0.2 * (TAU * t / 5.0).cos());
            input.gaze = Some([gaze, gaze]);
        }
        let finished = self.frames.render(&mut self.renderer, &input)?;
        Ok(finished.and_then(|stats| stats.gpu_ms))
    }

    /// Waits for the frames still in flight.
    pub fn finish(&mut self) -> Result<()> {
        Ok(self.frames.wait_all()?)
    }
}
