#version 450
#extension GL_EXT_multiview : require

#ifdef COUNT_FRAGMENTS
// Counted like every other step; early tests keep the count to what the mask fan shades.
layout(early_fragment_tests) in;
#include "counter.glsl"
#endif

// Stencil-only: the pipeline writes no colour and no depth.
void main() {
#ifdef COUNT_FRAGMENTS
    count_fragment(gl_ViewIndex);
#endif
}
