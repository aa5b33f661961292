//! The one measurement engine: configurations measured side by side. Every renderer of a group
//! is alive at once and renders one frame in turn, round after round (the first round a warm-up),
//! so a noisy machine's drift hits them all alike; times are medians of the timed frames, which
//! carry no instruments; counts come from a separate counting frame per configuration. Every
//! command that reports a time or a ratio measures through here.

use anyhow::Result;
use foveate::gpu::Gpu;
use foveate::metrics::Stats;
use foveate::plan::{FramePlan, RenderConfig};
use foveate::render::{counting_frame, Renderer, StereoImage};
use foveate::scene::Scene;
use glam::Vec2;

/// One configuration's measurements over the counted rounds.
pub struct Measured {
    /// The configuration as planned.
    pub plan: FramePlan,
    pub frame_ms: f64,
    /// Median GPU time of each planned pass.
    pub gpu_pass_ms: Vec<f64>,
    /// Fragments the scene draws shaded in the eye views and in the MFFR far view, and every
    /// pass together (a separate counting frame).
    pub eye_fragments: u64,
    pub far_fragments: u64,
    pub total_fragments: u64,
    /// Primitives rasterised over every pass (pipeline statistics, from the counting frame),
    /// when the device has them.
    pub primitives: Option<u64>,
    pub image: StereoImage,
}

impl Measured {
    /// Fragments the scene draws shaded, eye views and MFFR far view together.
    pub fn scene_fragments(&self) -> u64 {
        self.eye_fragments + self.far_fragments
    }
}

/// Renders `rounds` frames of each configuration with both eyes' gaze at `gaze`, interleaved
/// (the first round is a warm-up and not counted), and reads back the last frame of each.
/// `label` is shown in the progress line.
pub fn measure_group(
    gpu: &Gpu,
    scene: &Scene,
    configs: &[RenderConfig],
    gaze: Vec2,
    rounds: u32,
    label: &str,
) -> Result<Vec<Measured>> {
    anyhow::ensure!(
        rounds >= 2,
        "invalid frames = {rounds}: at least 2 (one warm-up)"
    );
    let mut renderers = configs
        .iter()
        .map(|c| {
            let mut r = Renderer::new(gpu, &foveate::plan(scene, c, gpu.caps())?, scene)?;
            r.set_gaze([gaze; 2]);
            Ok(r)
        })
        .collect::<Result<Vec<_>>>()?;
    let mut samples = vec![Vec::new(); configs.len()];
    let bar = crate::progress::bar(label, rounds as u64);
    for round in 0..rounds {
        bar.inc(1);
        for (r, s) in renderers.iter_mut().zip(&mut samples) {
            let stats = r.render_frame(scene.head)?;
            if round > 0 {
                s.push(stats);
            }
        }
    }
    bar.finish_and_clear();
    renderers
        .iter_mut()
        .zip(samples)
        .zip(configs)
        .map(|((r, s), config)| {
            let median = |f: &dyn Fn(&foveate::render::FrameStats) -> f64| {
                Stats::of(&s.iter().map(f).collect::<Vec<_>>()).map_or(f64::NAN, |x| x.median)
            };
            let passes = s[0].gpu_pass_ms.len();
            let counts = counting_frame(gpu, scene, config, r.gaze(), scene.head)?;
            Ok(Measured {
                plan: r.plan().clone(),
                frame_ms: median(&|x| x.frame_ms),
                gpu_pass_ms: (0..passes).map(|i| median(&|x| x.gpu_pass_ms[i])).collect(),
                eye_fragments: counts.fragments.iter().sum(),
                far_fragments: counts.far_fragments.unwrap_or(0),
                total_fragments: counts.total_fragments(),
                primitives: (!counts.pass_statistics.is_empty())
                    .then(|| counts.pass_statistics.iter().map(|p| p.rasterised).sum()),
                image: r.readback()?,
            })
        })
        .collect()
}
