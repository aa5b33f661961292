//! Measuring configurations side by side: every renderer of a group renders one frame in turn,
//! round after round, so a noisy machine's drift hits them all alike.

use anyhow::Result;
use foveate::gpu::Gpu;
use foveate::metrics::Stats;
use foveate::plan::RenderConfig;
use foveate::render::{counting_frame, Renderer, StereoImage};
use foveate::scene::Scene;

/// One configuration's measurements over the counted rounds.
pub struct Measured {
    pub frame_ms: f64,
    /// Median GPU time of each planned pass.
    pub gpu_pass_ms: Vec<f64>,
    /// Fragments the scene draws shaded in the eye views and in the MFFR far view, and every
    /// pass together (a separate counting frame).
    pub eye_fragments: u64,
    pub far_fragments: u64,
    pub total_fragments: u64,
    pub image: StereoImage,
}

/// Renders `rounds` frames of each configuration, interleaved (the first round is a warm-up and
/// not counted), and reads back the last frame of each. `label` is shown in the progress line.
pub fn measure_group(
    gpu: &Gpu,
    scene: &Scene,
    configs: &[RenderConfig],
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
            Ok(Renderer::new(
                gpu,
                &foveate::plan(scene, c, gpu.caps())?,
                scene,
            )?)
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
                frame_ms: median(&|x| x.frame_ms),
                gpu_pass_ms: (0..passes).map(|i| median(&|x| x.gpu_pass_ms[i])).collect(),
                eye_fragments: counts.fragments.iter().sum(),
                far_fragments: counts.far_fragments.unwrap_or(0),
                total_fragments: counts.total_fragments(),
                image: r.readback()?,
            })
        })
        .collect()
}
