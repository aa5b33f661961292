#version 450
#extension GL_EXT_multiview : require

// Composition of a foveated frame, per eye (gl_ViewIndex): the periphery view upscaled
// bilinearly, and over it the fovea view inside the fovea circle, blended with smoothstep
// across the band at the circle's edge (seed 001 §3.3, §3.6.1).
layout(set = 0, binding = 0) uniform sampler2DArray views; // 0, 1 periphery; 2, 3 fovea

#ifdef COUNT_FRAGMENTS
layout(early_fragment_tests) in;
#include "counter.glsl"
#endif

layout(std140, set = 0, binding = 1) uniform Composite {
    vec4 periphery[2]; // tangents left, right, up, down per eye
    vec4 fovea[2];
    vec4 params;       // fovea diameter (screen px), band (px), debug tint (0/1), unused
    vec4 screen;       // width, height (px)
} c;

layout(location = 0) in vec2 in_uv;
layout(location = 0) out vec4 out_color;

void main() {
    uint eye = gl_ViewIndex;
    vec4 p = c.periphery[eye];
    vec4 f = c.fovea[eye];
    // This pixel as a tangent-space direction (x right, y up).
    vec2 t = vec2(-p.x + in_uv.x * (p.x + p.y), p.z - in_uv.y * (p.z + p.w));
    vec2 fovea_uv = vec2((t.x + f.x) / (f.x + f.y), (f.z - t.y) / (f.z + f.w));
    vec2 fovea_centre = vec2((f.y - f.x) * 0.5, (f.z - f.w) * 0.5);
    vec2 px_per_tangent = c.screen.xy / vec2(p.x + p.y, p.z + p.w);
    float d = length((t - fovea_centre) * px_per_tangent);
    float radius = c.params.x * 0.5;
    float band = c.params.y;
    // 1 in the fovea, 0 in the periphery, smooth across the band.
    float w = band > 0.0 ? 1.0 - smoothstep(radius - band, radius, d) : float(d < radius);

    // Fetch only what contributes: most pixels are periphery only, a few fovea only.
    vec3 color = vec3(0.0);
    if (w < 1.0) {
        color += (1.0 - w) * texture(views, vec3(in_uv, float(eye))).rgb;
    }
    if (w > 0.0) {
        color += w * texture(views, vec3(fovea_uv, float(2u + eye))).rgb;
    }
    if (c.params.z > 0.5) {
        vec3 tint = w >= 1.0 ? vec3(0.2, 1.0, 0.2) : (w > 0.0 ? vec3(1.0, 0.9, 0.1) : vec3(0.2, 0.4, 1.0));
        color = mix(color, tint, 0.35);
    }
    out_color = vec4(color, 1.0);
#ifdef COUNT_FRAGMENTS
    count_fragment(eye);
#endif
}
