//! Recording one frame: the plan's passes and their steps, in order, through
//! [`Recorder`]. Each technique's executor records its own steps; this decides nothing: what it
//! records follows from the plan and the frame's draws.

use super::recorder::{FrameDraws, Recorder, Rect};
use crate::plan::{ClearValue, FramePlan, PassPlan, Step};

/// Records the frame `plan` describes into `rec`.
pub fn record_frame(plan: &FramePlan, draws: &FrameDraws, rec: &mut dyn Recorder) {
    let timestamps = plan.timestamp_queries > 0;
    let counting = plan.count_fragments();
    if timestamps {
        rec.reset_queries(plan.timestamp_pool_slots());
        rec.timestamp(0);
    }
    let statistics = plan.statistics_queries > 0;
    if counting {
        rec.clear_counters(plan.statistics_pool_slots());
    }
    for (index, pass) in plan.passes.iter().enumerate() {
        if statistics {
            rec.begin_statistics(index);
        }
        // One clear value per attachment, in `uses()` order (the render pass's), up to the
        // last one the plan clears: none for a pass that clears nothing.
        let uses: Vec<_> = pass.uses().collect();
        let cleared = uses
            .iter()
            .rposition(|u| u.clear.is_some())
            .map_or(0, |i| i + 1);
        let clears: Vec<ClearValue> = uses[..cleared]
            .iter()
            .map(|u| {
                u.clear.unwrap_or(ClearValue::DepthStencil {
                    depth: 0.0,
                    stencil: 0,
                })
            })
            .collect();
        rec.begin_pass(index, &clears, &pass.barriers.wait);
        let area = pass_area(plan, pass);
        for (step_index, step) in pass.steps.iter().enumerate() {
            rec.bind_step(index, step_index);
            match *step {
                Step::MaskFans {
                    stencil,
                    hidden_area,
                } => super::masks::record_mask_fans(pass, stencil, hidden_area, area, rec),
                Step::FarComposite { .. } => super::mffr::record_far_composite(pass, area, rec),
                Step::Scene { cull_slot, .. } => match draws.of(cull_slot) {
                    Some(draws) => super::stereo_scene::record_scene(plan, pass, area, draws, rec),
                    None => rec.engine_draws(index, step_index),
                },
                Step::Probe { .. } => super::probe::record_probe(pass, area, rec),
                Step::Output(_) => super::output::record_output(pass, area, rec),
                Step::RadialMask { .. } => {
                    super::radial_density::record_radial_mask(pass, area, rec)
                }
                Step::Reconstruct => super::radial_density::record_reconstruction(pass, area, rec),
                Step::LayerCopy { .. } => super::layer_copy::record_layer_copy(pass, area, rec),
            }
        }
        rec.end_pass(index, &pass.barriers.signal);
        if statistics {
            rec.end_statistics(index);
        }
        if counting {
            rec.counters_barrier();
        }
        if timestamps {
            rec.timestamp(index as u32 + 1);
        }
    }
    if counting {
        rec.counters_to_host();
    }
}

/// A pass's render area: its colour attachment's extent.
fn pass_area(plan: &FramePlan, pass: &PassPlan) -> Rect {
    let a = &plan.attachments[pass.color.attachment];
    Rect {
        x: 0,
        y: 0,
        width: a.width,
        height: a.height,
    }
}
