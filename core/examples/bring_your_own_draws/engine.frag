#version 450

// The example engine's own fragment shader: a sun and a sky, on the surface's colour.

// Depth and stencil tested before shading, so what foveate's masks cut costs no shading
// (lavapipe tests late unless told; a tile GPU tests early when the shader lets it).
layout(early_fragment_tests) in;

layout(std140, set = 0, binding = 0) uniform Frame {
    mat4 clip_from_world[4];
    vec4 light_dir;
    vec4 view_tint[4];
} frame;

layout(location = 0) in vec3 in_normal;
layout(location = 1) in vec3 in_colour;
layout(location = 2) flat in uint in_view;

// Alpha 1: a surface that moves only with the head (nothing in this world moves on its own;
// foveate's accumulation reads alpha 0 as a surface that did).
layout(location = 0) out vec4 out_colour;

void main() {
    vec3 n = normalize(in_normal);
    float diffuse = max(dot(n, -frame.light_dir.xyz), 0.0);
    float sky = 0.5 + 0.5 * n.y;
    vec3 lit = in_colour * (0.25 * sky + 0.85 * diffuse);
    vec4 tint = frame.view_tint[in_view];
    out_colour = vec4(mix(lit, tint.rgb, tint.a), 1.0);
}
