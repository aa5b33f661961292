// What became of each accumulated pixel's history, counted per foveation region in counting
// frames (never compiled into timed ones): the causes behind ghosting, disocclusion and the
// hole re-converging, measured where they happen. Slots: outcome × region (fovea, band,
// periphery), starting at HISTORY_OUTCOME_BASE in the fragment counter, summed over both eyes.
// `render::HistoryOutcome` names them in this order.
layout(constant_id = 35) const uint HISTORY_OUTCOME_BASE = 0;

const uint OUTCOME_KEPT = 0u;        // the history used as it was
const uint OUTCOME_CLIPPED = 1u;     // the history used, clipped towards the neighbourhood
const uint OUTCOME_FROM_FOVEA = 2u;  // the history used: what the fovea showed over the hole
const uint OUTCOME_RESET = 3u;       // the whole history dropped (first frame, teleport)
const uint OUTCOME_OFF_SCREEN = 4u;  // the frame before did not see this direction
const uint OUTCOME_DISOCCLUDED = 5u; // the frame before saw another surface there
const uint OUTCOME_EMPTY = 6u;       // the history there holds nothing (lens-hidden, hole)
const uint OUTCOME_HOLE = 7u;        // in the periphery's hole: nothing to accumulate
const uint OUTCOME_BEYOND = 8u;      // beyond the reach: this frame's periphery, no history

uint history_outcome = OUTCOME_KEPT;

// Counts this pixel's outcome; `w` is the fovea's weight there (1 fovea, 0 periphery).
void count_history_outcome(float w) {
    uint region = w >= 1.0 ? 0u : (w > 0.0 ? 1u : 2u);
    atomicAdd(fragments[HISTORY_OUTCOME_BASE + history_outcome * 3u + region], 1u);
}
