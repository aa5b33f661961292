//! Rendering and judging each foveated configuration along the trace: single frames render
//! each distinct gaze once; a configuration that accumulates over frames (the library's
//! default) renders each tracking's display frames in order, as a headset would, so its
//! history holds what those frames left.

use std::collections::HashMap;

use anyhow::Result;
use foveate::plan::FramePlan;
use foveate::render::{Renderer, StereoImage};
use glam::Vec2;

use super::trace::Sequences;
use super::{Frame, FrameError, Sweep, UNJUDGED};

/// Judges a rendered image of `plan` at a frame's true gaze with the fovea at the displayed one.
pub(super) type Judge<'a> = dyn Fn(&StereoImage, &FramePlan, Vec2, Vec2) -> Result<FrameError> + 'a;

/// Every foveated configuration's error per tracking and judged frame.
pub(super) fn judge_foveated(
    gpu: &foveate::gpu::Gpu,
    sweep: &Sweep,
    plans: &[FramePlan],
    shown: &[Vec<Vec2>],
    frames: &[Frame],
    sequences: &Sequences,
    judge: &Judge,
) -> Result<Vec<Vec<Vec<FrameError>>>> {
    let mut judged = Vec::new();
    for (c, (name, _, config)) in sweep.foveated.iter().enumerate() {
        let plan = &plans[c + 2];
        let stopped = || {
            // Its tables compare every configuration at once: no partial table is a result.
            crate::interrupt::stopped(&format!(
                "the latency sweep stopped in configuration {} of {}: nothing written",
                c + 1,
                sweep.foveated.len()
            ))
        };
        let accumulates = config
            .foveation
            .as_ref()
            .is_some_and(|f| f.periphery_temporal.is_some());
        let rows = if accumulates {
            in_order(gpu, sweep, plan, name, sequences, frames, judge, &stopped)?
        } else {
            each_gaze_once(gpu, sweep, plan, name, shown, frames, judge, &stopped)?
        };
        judged.push(rows);
    }
    Ok(judged)
}

/// Each distinct gaze the trackings displayed rendered once, and judged for every frame that
/// showed it.
#[allow(clippy::too_many_arguments)]
fn each_gaze_once(
    gpu: &foveate::gpu::Gpu,
    sweep: &Sweep,
    plan: &FramePlan,
    name: &str,
    shown: &[Vec<Vec2>],
    frames: &[Frame],
    judge: &Judge,
    stopped: &dyn Fn() -> anyhow::Error,
) -> Result<Vec<Vec<FrameError>>> {
    // Which (tracking, frame) showed each distinct gaze.
    let mut by_gaze: HashMap<[u32; 2], Vec<(usize, usize)>> = HashMap::new();
    for (k, gazes) in shown.iter().enumerate() {
        for (i, g) in gazes.iter().enumerate() {
            by_gaze
                .entry(g.to_array().map(f32::to_bits))
                .or_default()
                .push((k, i));
        }
    }
    let mut gazes: Vec<[u32; 2]> = by_gaze.keys().copied().collect();
    gazes.sort();
    let mut renderer = Renderer::new(gpu, plan, sweep.scene)?;
    let bar = crate::progress::bar(&format!("latency: {name}"), gazes.len() as u64);
    let mut rows = vec![vec![UNJUDGED; frames.len()]; shown.len()];
    for key in &gazes {
        if crate::interrupt::requested() {
            return Err(stopped());
        }
        let g = Vec2::from_array(key.map(f32::from_bits));
        renderer.set_gaze([g; 2])?;
        renderer.render_frame(sweep.scene.head)?;
        let image = renderer.readback()?;
        for &(k, i) in &by_gaze[key] {
            rows[k][i] = judge(&image, plan, frames[i].truth, g)?;
        }
        bar.inc(1);
    }
    bar.finish_and_clear();
    Ok(rows)
}

/// Each tracking's display frames rendered in order from a fresh history (`Sequences`), the
/// judged ones read back and judged.
#[allow(clippy::too_many_arguments)]
fn in_order(
    gpu: &foveate::gpu::Gpu,
    sweep: &Sweep,
    plan: &FramePlan,
    name: &str,
    sequences: &Sequences,
    frames: &[Frame],
    judge: &Judge,
    stopped: &dyn Fn() -> anyhow::Error,
) -> Result<Vec<Vec<FrameError>>> {
    let total: usize = sequences.gazes.iter().map(Vec::len).sum();
    let bar = crate::progress::bar(&format!("latency: {name}, frames in order"), total as u64);
    let mut rows = Vec::new();
    for gazes in &sequences.gazes {
        let mut renderer = Renderer::new(gpu, plan, sweep.scene)?;
        let mut row = vec![UNJUDGED; frames.len()];
        let mut next = 0;
        for (n, &g) in gazes.iter().enumerate() {
            if crate::interrupt::requested() {
                return Err(stopped());
            }
            renderer.set_gaze([g; 2])?;
            renderer.render_frame(sweep.scene.head)?;
            if sequences.judged_at.get(next) == Some(&n) {
                let image = renderer.readback()?;
                row[next] = judge(&image, plan, frames[next].truth, g)?;
                next += 1;
            }
            bar.inc(1);
        }
        rows.push(row);
    }
    bar.finish_and_clear();
    Ok(rows)
}
