#version 450

// Early tests make the counter below count only fragments that survive depth (and later
// stencil) testing: the fragments actually shaded. A scene with alpha-masked materials
// (glTF's MASK) discards, and a discarded fragment must not write depth, so its build tests
// late; its counter then also counts fragments that later fail the depth test.
#ifndef ALPHA_MASK
layout(early_fragment_tests) in;
#endif

// The MFFR far pass writes near / depth into alpha (sky, cleared to 0, is infinitely far), so
// the depth-shift composite can reproject by depth without a second attachment.
layout(constant_id = 3) const bool DEPTH_IN_ALPHA = false;
// Otherwise, where the periphery's accumulation clips by them (HistoryClip::Moved), alpha 0
// marks an instance that moves on its own: the head's motion alone cannot reproject it.
layout(constant_id = 7) const bool MARK_MOVING = false;

layout(std140, set = 0, binding = 0) uniform Views {
    mat4 view_proj[7];
    vec4 light_dir;
    vec4 eye_pos[7];
    vec4 ray_dx[7];    // how each view's ray at unit depth moves per pixel right (world)
    vec4 ray_dy[7];    // ... and per pixel down
} views;

layout(location = 0) in vec3 in_normal;
layout(location = 1) in vec3 in_color;
layout(location = 2) flat in uint in_view;
layout(location = 3) in float in_depth;
layout(location = 4) in vec3 in_world;
layout(location = 5) in vec2 in_uv;
layout(location = 6) flat in uint in_material;
layout(location = 7) in vec4 in_tangent;
layout(location = 8) flat in uint in_moves;

layout(location = 0) out vec4 out_color;

#ifdef COUNT_FRAGMENTS
#include "counter.glsl"
#endif

#ifdef LIT
#include "lit.glsl"
#endif

void main() {
    vec3 n = normalize(in_normal);
#ifdef LIT
    vec4 lit = shade_lit(n, in_tangent, in_world, in_uv, in_material, in_color,
                         views.eye_pos[in_view].xyz, in_depth, views.ray_dx[in_view].xyz,
                         views.ray_dy[in_view].xyz, views.ray_dx[in_view].w,
                         views.light_dir.xyz);
#ifdef ALPHA_MASK
    if (lit.a < materials[in_material].params.w) {
        discard;
    }
#endif
    vec3 shaded = lit.rgb;
#else
    float diffuse = max(dot(n, -views.light_dir.xyz), 0.0);
    float sky = 0.5 + 0.5 * n.y;
    vec3 shaded = in_color * (0.25 * sky + 0.85 * diffuse);
#endif
    float alpha = MARK_MOVING && in_moves != 0u ? 0.0 : 1.0;
    out_color = vec4(shaded, DEPTH_IN_ALPHA ? clamp(views.light_dir.w / in_depth, 0.0, 1.0) : alpha);
#ifdef COUNT_FRAGMENTS
    count_fragment(in_view);
#endif
}
