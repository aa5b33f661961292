#version 450
#extension GL_EXT_multiview : require

#ifdef COUNT_FRAGMENTS
// The frame view this pass's view 0 is (2 in the fovea pass of the two-pass fovea layout).
layout(constant_id = 5) const uint FIRST_VIEW = 0;
// Counted like every other step; early tests keep the count to what the mask fan shades.
layout(early_fragment_tests) in;
#include "counter.glsl"
#endif

// Stencil-only: the pipeline writes no colour and no depth.
void main() {
#ifdef COUNT_FRAGMENTS
    count_fragment(FIRST_VIEW + gl_ViewIndex);
#endif
}
