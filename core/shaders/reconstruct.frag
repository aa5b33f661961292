#version 450
#extension GL_EXT_multiview : require
#extension GL_GOOGLE_include_directive : require

// Radial density reconstruction: every pixel of a skipped quad takes the inverse-square-distance
// weighted mean of the nearest pixel of each kept quad around it (3x3 quads); kept pixels are
// copied. Linear light: the views are sampled from an sRGB image.
#include "radial_density.glsl"

layout(set = 0, binding = 0) uniform sampler2DArray views; // one layer per eye

#ifdef COUNT_FRAGMENTS
layout(early_fragment_tests) in;
#include "counter.glsl"
#endif

layout(location = 0) in vec2 in_uv;
layout(location = 0) out vec4 out_color;

void main() {
    uint eye = gl_ViewIndex;
    ivec2 p = ivec2(gl_FragCoord.xy);
    ivec2 quad = p >> 1;
    ivec2 size = ivec2(VIEW_WIDTH, VIEW_HEIGHT);
    if (!quad_skipped(quad, eye)) {
        out_color = vec4(texelFetch(views, ivec3(p, eye), 0).rgb, 1.0);
    } else {
        vec3 sum = vec3(0.0);
        float weight = 0.0;
        for (int dy = -1; dy <= 1; dy++) {
            for (int dx = -1; dx <= 1; dx++) {
                ivec2 q = quad + ivec2(dx, dy);
                if ((dx == 0 && dy == 0) || any(lessThan(q, ivec2(0)))
                    || any(greaterThanEqual(q * 2, size)) || quad_skipped(q, eye)) {
                    continue;
                }
                // The pixel of quad q nearest to p.
                ivec2 nearest = clamp(p, q * 2, min(q * 2 + 1, size - 1));
                vec2 d = vec2(nearest - p);
                float w = 1.0 / dot(d, d);
                sum += w * texelFetch(views, ivec3(nearest, eye), 0).rgb;
                weight += w;
            }
        }
        out_color = vec4(weight > 0.0 ? sum / weight : vec3(0.0), 1.0);
    }
#ifdef COUNT_FRAGMENTS
    count_fragment(eye);
#endif
}
