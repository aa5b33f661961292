#version 450
#extension GL_EXT_multiview : require

// The example engine's own vertex shader: its vertex layout (a position and a normal, 24 bytes),
// its per-frame block and its per-draw push constants; nothing of foveate's.

layout(location = 0) in vec3 in_position;
layout(location = 1) in vec3 in_normal;

layout(std140, set = 0, binding = 0) uniform Frame {
    // Every view of the frame (foveate's View::clip_from_world, View::index order).
    mat4 clip_from_world[4];
    // xyz: the direction the sunlight travels.
    vec4 light_dir;
    // Per view, a colour its surfaces are tinted with (alpha: how much).
    vec4 view_tint[4];
} frame;

layout(push_constant) uniform Draw {
    mat4 model;
    vec4 colour;
    // The frame view the pass's layer 0 is (DrawPass::views.start).
    uint first_view;
} draw;

layout(location = 0) out vec3 out_normal;
layout(location = 1) out vec3 out_colour;
// The frame view drawn (for its tint).
layout(location = 2) flat out uint out_view;

void main() {
    vec4 world = draw.model * vec4(in_position, 1.0);
    gl_Position = frame.clip_from_world[draw.first_view + gl_ViewIndex] * world;
    out_normal = mat3(draw.model) * in_normal;
    out_view = draw.first_view + gl_ViewIndex;
    out_colour = draw.colour.rgb;
}
