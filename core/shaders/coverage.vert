#version 450

// One triangle covering the whole view: the coverage probe that counts, per view, every pixel
// a pass renders under its stencil masks.
layout(constant_id = 1) const float CLIP_XY_SCALE = 1.0;

void main() {
    vec2 p = vec2(float((gl_VertexIndex << 1) & 2), float(gl_VertexIndex & 2)) * 2.0 - 1.0;
    gl_Position = vec4(p * CLIP_XY_SCALE, 0.0, 1.0);
}
