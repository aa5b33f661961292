//! Fragment counting in counting frames: the counters each counted step added to (the shaders'
//! `counter.glsl`), read back per step and view, and where the output accumulates, what became
//! of each pixel's history. Timed frames have no counter.

use super::history_outcomes::HistoryOutcomes;
use super::stats::StepFragments;
use crate::gpu::Buffer;
use crate::plan::{FramePlan, COUNTER_SLOTS_PER_STEP, HISTORY_OUTCOME_SLOTS};

/// Each counted step's counts, in the plan's order, from the counter buffer; and the history
/// outcomes, when the plan counts them.
pub(super) fn read_counts(
    plan: &FramePlan,
    counter: &mut Buffer,
) -> (Vec<StepFragments>, Option<HistoryOutcomes>) {
    let per_step = COUNTER_SLOTS_PER_STEP as usize;
    let outcome_slots = match plan.history_outcome_base() {
        Some(_) => HISTORY_OUTCOME_SLOTS as usize,
        None => 0,
    };
    let counts = counter.read_u32s(per_step * plan.counted.len() + outcome_slots);
    let steps = plan
        .counted
        .iter()
        .zip(counts.chunks_exact(per_step))
        .map(|(slot, views)| StepFragments {
            pass: plan.passes[slot.pass].name,
            step: slot.step,
            views: std::array::from_fn(|v| u64::from(views[v])),
        })
        .collect();
    (steps, HistoryOutcomes::from_counters(plan, &counts))
}
