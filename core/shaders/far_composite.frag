#version 450
#extension GL_EXT_multiview : require

// MFFR: the far image composited into a view (Preißner 2020 §4.3). Each pixel's ray is carried into
// the far image: at infinity (rotation only) or, for depth shift, at the depth the far image
// holds there, found by fixed-point iteration (Preißner 2020 §4.3.6). Stencil decides which pixels
// receive it (near-first) or the near field overwrites it (far-first).
layout(constant_id = 0) const uint VIEW_SOURCE = 0; // 0: gl_ViewIndex, 1: push constant
layout(constant_id = 2) const bool DEPTH_SHIFT = false;
// The frame view this pass's view 0 is (2 in the fovea pass of the two-pass fovea layout).
layout(constant_id = 5) const uint FIRST_VIEW = 0;

layout(set = 0, binding = 0) uniform sampler2D far_image; // rgb, alpha = far near / depth

#ifdef COUNT_FRAGMENTS
// Early tests: only the pixels the stencil lets through are shaded (and counted).
layout(early_fragment_tests) in;
#include "counter.glsl"
#endif

layout(std140, set = 0, binding = 1) uniform FarComposite {
    mat4 direction[4]; // far clip of the ray through view NDC (x, y) at depth 1: M·(x, y, 1, 0)
    vec4 origin[4];    // far clip of the view's eye point
    vec4 params;       // x: far pass near plane
} c;

layout(push_constant) uniform Push {
    uint view;
} pc;

layout(location = 0) in vec2 in_uv;
layout(location = 0) out vec4 out_color;

vec2 far_uv(vec4 clip) {
    return clip.xy / clip.w * 0.5 + 0.5;
}

void main() {
    uint view = VIEW_SOURCE == 0u ? FIRST_VIEW + gl_ViewIndex : pc.view;
    vec2 ndc = in_uv * 2.0 - 1.0;
    vec4 dir = c.direction[view] * vec4(ndc, 1.0, 0.0);
    vec2 uv = far_uv(dir);
    if (DEPTH_SHIFT) {
        for (int i = 0; i < 3; i++) {
            float a = texture(far_image, uv).a;
            if (a <= 0.0) {
                break; // sky: infinitely far, rotation only is exact
            }
            uv = far_uv(c.origin[view] + (c.params.x / a) * dir);
        }
    }
    out_color = vec4(texture(far_image, uv).rgb, 1.0);
#ifdef COUNT_FRAGMENTS
    count_fragment(view);
#endif
}
