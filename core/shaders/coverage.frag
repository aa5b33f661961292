#version 450
#extension GL_EXT_multiview : require

layout(early_fragment_tests) in;
// The frame view this pass's view 0 is (2 in the fovea pass of the two-pass fovea layout).
layout(constant_id = 5) const uint FIRST_VIEW = 0;

#include "counter.glsl"

void main() {
    count_fragment(FIRST_VIEW + gl_ViewIndex);
}
