#version 450
#extension GL_EXT_multiview : require

// Where this vertex's view comes from; one shader serves every stereo mode so the
// modes differ only in how the frame is submitted, never in what is shaded.
//   0: multiview (gl_ViewIndex)
//   1: push constant (two-pass and per-object modes)
//   2: instanced stereo (instance index low bit; Wilson 2015's clip-space half viewport)
layout(constant_id = 0) const uint VIEW_SOURCE = 0;
// Emulated guard band (1/K, see PassPlan::guard_band): the viewport is K times larger than the
// render area, so x and y shrink by K to land on the same pixels.
layout(constant_id = 1) const float CLIP_XY_SCALE = 1.0;
// The frame view this pass's view 0 is (2 in the fovea pass of the two-pass fovea layout).
layout(constant_id = 5) const uint FIRST_VIEW = 0;
// The one-pass fovea layout: each culled id's top bit says whether the fovea superfrustum keeps
// its instance; an instance it misses emits no primitives in the fovea views (2, 3).
layout(constant_id = 6) const bool FOVEA_TAGS = false;
const uint FOVEA_TAG = 0x80000000u;

layout(std140, set = 0, binding = 0) uniform Views {
    mat4 view_proj[7]; // up to 6 eye views, then the MFFR far view
    vec4 light_dir;    // xyz: light direction; w: the far view's near plane
    vec4 eye_pos[7];   // each view's eye in world space (lit shading's view vector)
    vec4 ray_dx[7];    // lit shading's per-pixel ray steps (see shaders/lit.glsl)
    vec4 ray_dy[7];
} views;

struct Instance {
    mat4 model;
    vec4 color;
    uvec4 material; // x: index into the lit materials; y: 1 when the renderer moved or added it
};
layout(std430, set = 0, binding = 1) readonly buffer Instances {
    Instance instances[];
};
#ifdef INDIRECT_INSTANCES
// Culled draws (MFFR's near and far sets): the instance index picks an entry of the per-frame
// id list instead of the instance itself. A separate build, so that without culling the shader
// declares no binding the pipeline lacks.
layout(std430, set = 0, binding = 4) readonly buffer InstanceIds {
    uint ids[];
};
#endif

layout(push_constant) uniform Push {
    uint view;
} pc;

layout(location = 0) in vec3 in_position;
layout(location = 1) in vec3 in_normal;
layout(location = 2) in vec2 in_uv;
layout(location = 3) in vec4 in_tangent;

layout(location = 0) out vec3 out_normal;
layout(location = 1) out vec3 out_color;
layout(location = 2) flat out uint out_view;
layout(location = 3) out float out_depth;
layout(location = 4) out vec3 out_world;
layout(location = 5) out vec2 out_uv;
layout(location = 6) flat out uint out_material;
layout(location = 7) out vec4 out_tangent;
layout(location = 8) flat out uint out_moves;

out gl_PerVertex {
    vec4 gl_Position;
    float gl_ClipDistance[1];
};

void main() {
    uint view;
    uint instance;
    if (VIEW_SOURCE == 2u) {
        // The draw doubled instanceCount and firstInstance, so each object shows up as two
        // consecutive instances: even ones for the left eye, odd ones for the right.
        view = uint(gl_InstanceIndex) & 1u;
        instance = uint(gl_InstanceIndex) >> 1;
    } else {
        view = VIEW_SOURCE == 0u ? FIRST_VIEW + gl_ViewIndex : pc.view;
        instance = uint(gl_InstanceIndex);
    }

#ifdef INDIRECT_INSTANCES
    uint entry = ids[instance];
    instance = entry & ~FOVEA_TAG;
    if (FOVEA_TAGS && view >= 2u && (entry & FOVEA_TAG) == 0u) {
        // Every vertex of the triangle at one point outside the clip volume: a degenerate
        // triangle, rejected before clipping or rasterisation (no clipping quirk can touch it).
        gl_Position = vec4(2.0, 2.0, 2.0, 1.0);
        gl_ClipDistance[0] = 1.0;
        out_normal = vec3(0.0);
        out_color = vec3(0.0);
        out_view = view;
        out_depth = 1.0;
        out_world = vec3(0.0);
        out_uv = vec2(0.0);
        out_material = 0u;
        out_tangent = vec4(0.0);
        out_moves = 0u;
        return;
    }
#endif
    Instance inst = instances[instance];
    vec4 world = inst.model * vec4(in_position, 1.0);
    vec4 clip = views.view_proj[view] * world;

    if (VIEW_SOURCE == 2u) {
        // Keep each eye inside its half: clip against the inner edge of its own frustum
        // (x <= w for the left eye, x >= -w for the right), then squeeze x into that half.
        gl_ClipDistance[0] = view == 0u ? clip.w - clip.x : clip.w + clip.x;
        clip.x = clip.x * 0.5 + (view == 0u ? -0.5 : 0.5) * clip.w;
    } else {
        gl_ClipDistance[0] = 1.0;
    }

    clip.xy *= CLIP_XY_SCALE;
    gl_Position = clip;
    out_normal = mat3(inst.model) * in_normal;
    out_color = inst.color.rgb;
    out_view = view;
    out_depth = clip.w; // view-space depth: every projection here has w = −z_view
    out_world = world.xyz;
    out_uv = in_uv;
    out_material = inst.material.x;
    out_moves = inst.material.y;
    out_tangent = vec4(mat3(inst.model) * in_tangent.xyz, in_tangent.w);
}
