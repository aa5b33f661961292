#version 450
#extension GL_EXT_multiview : require

// Temporal accumulation's second pass: the accumulated periphery, pixel for pixel, becomes the
// next frame's history (the accumulate pass samples the history, so it cannot write it).

layout(set = 0, binding = 0) uniform sampler2DArray accumulated;

#ifdef COUNT_FRAGMENTS
layout(early_fragment_tests) in;
#include "counter.glsl"
#endif

layout(location = 0) in vec2 in_uv;
layout(location = 0) out vec4 out_color;

void main() {
    out_color = texelFetch(accumulated, ivec3(ivec2(gl_FragCoord.xy), gl_ViewIndex), 0);
#ifdef COUNT_FRAGMENTS
    count_fragment(gl_ViewIndex);
#endif
}
