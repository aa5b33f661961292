// The shaded-fragment counter of counting frames (never compiled into timed ones).
//
// Neither pipeline statistics (lavapipe counts raster blocks) nor occlusion queries (one sum
// for all views of a multiview pass) give exact per-view counts; an atomic per view does, and
// helper invocations never write it. Every counted step of the frame (mask fans, far
// composite, scene, probe, composition) owns seven slots — views 0-5 and the MFFR far view —
// starting at COUNTER_BASE, which the plan assigns.
layout(constant_id = 4) const uint COUNTER_BASE = 0;

layout(std430, set = 0, binding = 2) buffer FragmentCounts {
    uint fragments[];
};

void count_fragment(uint view) {
    atomicAdd(fragments[COUNTER_BASE + view], 1u);
}
