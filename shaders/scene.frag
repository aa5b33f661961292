#version 450

// Early tests make the counter below count only fragments that survive depth (and later
// stencil) testing: the fragments actually shaded.
layout(early_fragment_tests) in;

layout(std140, set = 0, binding = 0) uniform Views {
    mat4 view_proj[4];
    vec4 light_dir;
} views;

layout(location = 0) in vec3 in_normal;
layout(location = 1) in vec3 in_color;
layout(location = 2) flat in uint in_view;

layout(location = 0) out vec4 out_color;

#ifdef COUNT_FRAGMENTS
// Per-view shaded-fragment counter. Neither pipeline statistics (lavapipe counts raster
// blocks) nor occlusion queries (one sum for all views of a multiview pass) give exact
// per-view counts; an atomic per view does, and helper invocations never write it.
layout(std430, set = 0, binding = 2) buffer FragmentCounts {
    uint fragments[4];
};
#endif

void main() {
    vec3 n = normalize(in_normal);
    float diffuse = max(dot(n, -views.light_dir.xyz), 0.0);
    float sky = 0.5 + 0.5 * n.y;
    vec3 lit = in_color * (0.25 * sky + 0.85 * diffuse);
    out_color = vec4(lit, 1.0);
#ifdef COUNT_FRAGMENTS
    atomicAdd(fragments[in_view], 1u);
#endif
}
