#version 450
#extension GL_EXT_multiview : require

// Stencil mask geometry, written per view at the start of a foveated pass: a fan of
// SEGMENTS triangles around an ellipse in NDC, one shape per view (gl_ViewIndex). Shape set 0
// holds what each view keeps (written as 1), set 1 what it drops (written as 0) — the fovea
// views keep their inset circle, the periphery views keep everything but the fovea's hole.
layout(constant_id = 1) const float CLIP_XY_SCALE = 1.0;

// The frame view this pass's view 0 is (2 in the fovea pass of the two-pass fovea layout).
layout(constant_id = 5) const uint FIRST_VIEW = 0;

const uint SEGMENTS = 128u;

layout(std140, set = 0, binding = 3) uniform Masks {
    // (centre x, centre y, radius x, radius y) in NDC; [0..4) keep, [4..8) drop.
    vec4 shapes[8];
} masks;

layout(push_constant) uniform Push {
    uint shape_set;
} pc;

void main() {
    vec4 shape = masks.shapes[pc.shape_set * 4u + FIRST_VIEW + gl_ViewIndex];
    uint triangle = uint(gl_VertexIndex) / 3u;
    uint corner = uint(gl_VertexIndex) % 3u;
    vec2 p = shape.xy;
    if (corner != 0u) {
        // The circumscribed polygon, so the shape holds the whole ellipse.
        float a = 6.28318530718 * float(triangle + corner - 1u) / float(SEGMENTS);
        p += shape.zw * vec2(cos(a), sin(a)) / cos(3.14159265359 / float(SEGMENTS));
    }
    gl_Position = vec4(p * CLIP_XY_SCALE, 0.5, 1.0);
}
