#version 450

// Early tests make the counter below count only fragments that survive depth (and later
// stencil) testing: the fragments actually shaded.
layout(early_fragment_tests) in;

// The MFFR far pass writes near / depth into alpha (sky, cleared to 0, is infinitely far), so
// the depth-shift composite can reproject by depth without a second attachment.
layout(constant_id = 3) const bool DEPTH_IN_ALPHA = false;

layout(std140, set = 0, binding = 0) uniform Views {
    mat4 view_proj[5];
    vec4 light_dir;
} views;

layout(location = 0) in vec3 in_normal;
layout(location = 1) in vec3 in_color;
layout(location = 2) flat in uint in_view;
layout(location = 3) in float in_depth;

layout(location = 0) out vec4 out_color;

#ifdef COUNT_FRAGMENTS
#include "counter.glsl"
#endif

void main() {
    vec3 n = normalize(in_normal);
    float diffuse = max(dot(n, -views.light_dir.xyz), 0.0);
    float sky = 0.5 + 0.5 * n.y;
    vec3 lit = in_color * (0.25 * sky + 0.85 * diffuse);
    out_color = vec4(lit, DEPTH_IN_ALPHA ? clamp(views.light_dir.w / in_depth, 0.0, 1.0) : 1.0);
#ifdef COUNT_FRAGMENTS
    count_fragment(in_view);
#endif
}
