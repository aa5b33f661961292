//! Fragment counting (a technique of counting frames only): every step that shades fragments
//! gets five counter slots, in recording order, and one buffer holds them.

use super::model::*;

/// Every step that shades fragments, pass by pass in recording order: a pass's mask fans, its
/// far composite (far-first before the scene, near-first after it), its scene, its probe; the
/// composition pass's full-view draw.
fn counted_steps(passes: &[PassPlan]) -> Vec<CountedSlot> {
    passes
        .iter()
        .enumerate()
        .flat_map(|(pass, p)| {
            p.steps.iter().map(move |s| CountedSlot {
                pass,
                step: s.counted(),
            })
        })
        .collect()
}

/// A counting frame: every step counted, and the buffer holding its counters (and, where the
/// output accumulates, what became of each pixel's history).
pub(super) fn plan_counting(plan: &mut FramePlan) {
    plan.counted = counted_steps(&plan.passes);
    let steps = COUNTER_SLOTS_PER_STEP * plan.counted.len() as u32;
    let outcomes = match plan.output_accumulates() {
        true => HISTORY_OUTCOME_SLOTS,
        false => 0,
    };
    plan.buffers.push(BufferPlan {
        name: FRAGMENT_COUNTER,
        bytes: 4 * (steps + outcomes) as u64,
    });
}
