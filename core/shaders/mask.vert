#version 450
#extension GL_EXT_multiview : require

// Stencil mask geometry, written per view at the start of a foveated pass: a fan of
// SEGMENTS triangles around an ellipse in NDC, one shape per view (gl_ViewIndex). Shape set 0
// holds what each view keeps (written as 1), set 1 what it drops (written as 0) — the fovea
// views keep their inset circle, the periphery views keep everything but the fovea's hole (the
// ring's, with a parafoveal ring, whose views keep their circle and drop the fovea's hole).
// Shape set 2 is a runtime's hidden-area mesh (dropped, in the eye views only): triangle
// corners in NDC, two per vec4, MAX_HIDDEN_TRIANGLES per eye; unused ones are all zero, so
// they cover nothing.
layout(constant_id = 1) const float CLIP_XY_SCALE = 1.0;

// The frame view this pass's view 0 is (2 in the fovea pass of the two-pass fovea layout).
layout(constant_id = 5) const uint FIRST_VIEW = 0;

const uint SEGMENTS = 128u;
const uint MAX_HIDDEN_TRIANGLES = 128u;
const uint HIDDEN_CORNERS = 3u * MAX_HIDDEN_TRIANGLES;

layout(std140, set = 0, binding = 3) uniform Masks {
    // (centre x, centre y, radius x, radius y) in NDC; [0..6) keep, [6..12) drop (six views:
    // periphery, fovea, parafoveal ring).
    vec4 shapes[12];
    // Each eye's hidden triangles' corners in NDC, two per element: the left eye's, then the
    // right's.
    vec4 hidden[HIDDEN_CORNERS];
} masks;

layout(push_constant) uniform Push {
    uint shape_set;
} pc;

void main() {
    if (pc.shape_set == 2u) {
        uint view = FIRST_VIEW + gl_ViewIndex;
        uint corner = min(view, 1u) * HIDDEN_CORNERS + uint(gl_VertexIndex);
        vec4 pair = masks.hidden[corner / 2u];
        vec2 p = (corner % 2u == 0u) ? pair.xy : pair.zw;
        // The fovea and ring views (2-5) have no hidden area: every corner at one point covers nothing.
        gl_Position = vec4(view < 2u ? p * CLIP_XY_SCALE : vec2(0.0), 0.5, 1.0);
        return;
    }
    vec4 shape = masks.shapes[pc.shape_set * 6u + FIRST_VIEW + gl_ViewIndex];
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
