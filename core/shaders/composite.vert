#version 450

// A full-view triangle with image coordinates (0..1, y down) for the composition pass.
layout(constant_id = 1) const float CLIP_XY_SCALE = 1.0;

layout(location = 0) out vec2 out_uv;

void main() {
    vec2 p = vec2(float((gl_VertexIndex << 1) & 2), float(gl_VertexIndex & 2)) * 2.0 - 1.0;
    out_uv = p * 0.5 + 0.5;
    gl_Position = vec4(p * CLIP_XY_SCALE, 0.0, 1.0);
}
