//! The one measurement engine: configurations measured side by side. Every renderer of a group
//! is alive at once and renders one frame in turn, round after round (the first round a warm-up),
//! so a noisy machine's drift hits them all alike; times are medians of the timed frames, which
//! carry no instruments; counts come from a separate counting frame per configuration. Every
//! command that reports a time or a ratio measures through here.

use anyhow::Result;
use foveate::gpu::Gpu;
use foveate::metrics::perceptual::{frame_accuracy, FrameAccuracy, Maps};
use foveate::metrics::Acuity;
use foveate::metrics::{EyePixels, Stats};
use foveate::plan::{FramePlan, RenderConfig};
use foveate::render::{counting_frame, Renderer, StereoImage};
use foveate::scene::Scene;
use glam::{Mat4, Vec2};

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
    /// The counting frame itself (every step's fragments, each pass's triangles): what a tile
    /// GPU's price is made from.
    pub counts: foveate::render::FrameStats,
    pub image: StereoImage,
}

impl Measured {
    /// Fragments the scene draws shaded, eye views and MFFR far view together.
    pub fn scene_fragments(&self) -> u64 {
        self.eye_fragments + self.far_fragments
    }
}

/// What a group measures: `configs` over `scene` with both eyes' gaze at `gaze`, `rounds`
/// frames each (the first a warm-up); `label` is shown in the progress line.
pub struct Group<'a> {
    pub scene: &'a Scene,
    pub configs: &'a [RenderConfig],
    pub gaze: Vec2,
    pub rounds: u32,
    pub label: &'a str,
}

/// Renders the group's frames, interleaved (the warm-up round not counted), and reads back the
/// last frame of each configuration; a configuration with a temporal history first lets it
/// settle on the still frame, untimed.
pub fn measure_group(gpu: &Gpu, group: &Group) -> Result<Vec<Measured>> {
    let Group {
        scene,
        configs,
        gaze,
        rounds,
        label,
    } = *group;
    anyhow::ensure!(
        rounds >= 2,
        "invalid frames = {rounds}: at least 2 (one warm-up)"
    );
    let mut renderers = configs
        .iter()
        .map(|c| {
            let mut r = Renderer::new(gpu, &foveate::plan(scene, c, gpu.caps())?, scene)?;
            r.set_gaze([gaze; 2])?;
            Ok(r)
        })
        .collect::<Result<Vec<_>>>()?;
    for r in &mut renderers {
        settle(r, scene.head)?;
    }
    let mut samples = vec![Vec::new(); configs.len()];
    let bar = crate::progress::bar(label, rounds as u64);
    for round in 0..rounds {
        bar.inc(1);
        if crate::interrupt::requested() {
            // Interleaved: no configuration is complete before the last round.
            return Err(crate::interrupt::stopped(&format!(
                "{label} stopped in timed round {round} of {rounds}, before any configuration was complete: nothing written"
            )));
        }
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
                counts,
            })
        })
        .collect()
}

/// Lets a renderer with a temporal history settle on the still frame at `head` before it is
/// measured (two jitter cycles, untimed, unjudged); a renderer without one renders nothing.
pub fn settle(renderer: &mut Renderer, head: Mat4) -> Result<()> {
    let temporal = renderer.plan().foveation.and_then(|f| f.temporal);
    for _ in 0..temporal.map_or(0, |t| 2 * t.jitter_cycle) {
        renderer.render_frame(head)?;
    }
    Ok(())
}

/// A configuration of a sweep: measured, and its output judged against the reference's.
pub struct Judged {
    pub measured: Measured,
    /// The pixels its error is measured over: those the lens shows, by region for the eye at
    /// the gaze.
    pub pixels: [EyePixels; 2],
    pub accuracy: FrameAccuracy,
}

/// The one accuracy sweep: `configs[0]` is the full-quality reference; every configuration (the
/// reference too, which scores perfectly) is measured side by side through [`measure_group`]
/// and its output image judged against the reference's with `acuity`, its eccentricity-aware
/// maps kept as `maps` says. Region by region, a configuration without a fovea is judged where
/// the first foveated configuration puts it ([`crate::region_maps::regions_of`]); with none
/// foveated, all its pixels are periphery. Every command that prices
/// an approximation in time and error sweeps through here. After Ctrl-C or SIGTERM
/// ([`crate::interrupt`]) it stops judging and returns the configurations judged so far, in
/// order: fewer than the group's; so it does when a judgement fails (a lost device), with the
/// failure beside them.
pub fn sweep(gpu: &Gpu, group: &Group, acuity: Acuity, maps: Maps) -> Result<Swept> {
    let measured = measure_group(gpu, group)?;
    let (gaze, label, total) = (group.gaze, group.label, measured.len());
    let reference_plan = measured[0].plan.clone();
    let reference_image = measured[0].image.clone();
    // Where each row's regions lie: a stereo row has no fovea of its own, so its error is
    // judged region by region where the first foveated row puts the fovea.
    let plans: Vec<FramePlan> = measured.iter().map(|m| m.plan.clone()).collect();
    let placements: Vec<_> = (plans.iter())
        .map(|p| crate::region_maps::regions_of(p, &plans).copied())
        .collect();
    let bar = crate::progress::bar(&format!("{label}: FLIP"), total as u64);
    let mut judged = Vec::new();
    let mut failed = None;
    let mut flip = crate::metric::flip_mapper(gpu);
    for (m, placement) in measured.into_iter().zip(placements) {
        if crate::interrupt::requested() {
            break;
        }
        let pixels = EyePixels::both(&reference_plan, gaze, placement.as_ref());
        let accuracy = frame_accuracy(
            reference_image.eyes(),
            m.image.eyes(),
            &pixels,
            acuity,
            &mut *flip,
            maps,
        );
        let accuracy = match accuracy {
            Ok(a) => a,
            Err(e) => {
                let at = format!("{label}: judging configuration {}", judged.len());
                failed = Some(anyhow::Error::new(e).context(at));
                break;
            }
        };
        bar.inc(1);
        judged.push(Judged {
            measured: m,
            pixels,
            accuracy,
        });
        log::info!("{label}: judged {} of {total}", judged.len());
    }
    bar.finish_and_clear();
    Ok(Swept { judged, failed })
}

/// What a sweep judged, in order, and the failure that stopped it, if one did.
pub struct Swept {
    pub judged: Vec<Judged>,
    pub failed: Option<anyhow::Error>,
}

impl Swept {
    /// The configurations judged, or the failure that stopped the sweep (for a command that
    /// has no use for part of a sweep).
    pub fn whole(self) -> Result<Vec<Judged>> {
        match self.failed {
            Some(e) => Err(e),
            None => Ok(self.judged),
        }
    }
}
