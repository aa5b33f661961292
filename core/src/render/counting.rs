//! Fragment counting in counting frames: the counters each counted step added to (the shaders'
//! `counter.glsl`), read back per step and view. Timed frames have no counter.

use super::stats::StepFragments;
use crate::gpu::Buffer;
use crate::plan::{FramePlan, COUNTER_SLOTS_PER_STEP};

/// Each counted step's counts, in the plan's order, from the counter buffer.
pub(super) fn read_counts(plan: &FramePlan, counter: &mut Buffer) -> Vec<StepFragments> {
    let per_step = COUNTER_SLOTS_PER_STEP as usize;
    let counts = counter.read_u32s(per_step * plan.counted.len());
    plan.counted
        .iter()
        .zip(counts.chunks_exact(per_step))
        .map(|(slot, views)| StepFragments {
            pass: plan.passes[slot.pass].name,
            step: slot.step,
            views: std::array::from_fn(|v| u64::from(views[v])),
        })
        .collect()
}
