#version 450
// Flicker on the device (metrics::temporal's measure): per pixel, how much more the
// approximation's luma changed since the previous frame than the reference's did,
// max(0, |ΔT| − |ΔR|), counted into a histogram per region (metrics::ErrorHistogram's bins).
// Both frames are read where the renderers' outputs were copied, in their own formats; each
// pixel's luma is kept for the next frame. Luma is Rec. 709's weights on the 8-bit sRGB values
// (RgbaImage::luma), computed in integers (weights × 10000) so that equal changes cancel
// exactly, as they do in the CPU measure's doubles.
layout(local_size_x = 16, local_size_y = 16) in;

layout(push_constant) uniform Params {
    ivec2 size;       // one eye's pixels
    int bins;         // histogram bins over (0, 1], besides the one for exact zeros
    int compare;      // 1 once a previous frame's luma is kept
    ivec4 reference;  // format (0 sRGB, 1 linear 8-bit, 2 linear half floats), first word, eye 1's first texel, row pitch in texels
    ivec4 test;       // the same for the approximation
} pc;

// Both frames' texels, as copied: the reference's, then the approximation's.
layout(std430, set = 0, binding = 0) readonly buffer Frames { uint w[]; } frames;
// The previous frame's luma (× 10000 × 255): the reference's eyes, then the approximation's.
layout(std430, set = 0, binding = 1) buffer Luma { uint v[]; } luma;
// Each pixel's region (0 fovea, 1 band, 2 periphery, 3 hidden), a byte each, eye by eye.
layout(std430, set = 0, binding = 2) readonly buffer Labels { uint l[]; } labels;
// The histograms: one per region, `bins` + 1 counts each (exact zeros first).
layout(std430, set = 0, binding = 3) buffer Counts { uint c[]; } counts;

#include "output_texels.glsl"

// Luma × 10000 × 255 of pixel `p` of `eye`.
uint luma_of(ivec4 image, ivec2 p, uint eye) {
    uint t = eye * uint(image.z) + uint(p.y) * uint(image.w) + uint(p.x);
    uvec3 c = outputColour(image, t);
    return 2126u * c.r + 7152u * c.g + 722u * c.b;
}

uint bin(float v) {
    return v <= 0.0 ? 0u : 1u + min(uint(min(v, 1.0) * float(pc.bins)), uint(pc.bins) - 1u);
}

void main() {
    ivec2 p = ivec2(gl_GlobalInvocationID.xy);
    uint eye = gl_GlobalInvocationID.z;
    if (any(greaterThanEqual(p, pc.size))) {
        return;
    }
    uint pixels = uint(pc.size.x * pc.size.y);
    uint i = eye * pixels + uint(p.y * pc.size.x + p.x);
    uint r = luma_of(pc.reference, p, eye);
    uint t = luma_of(pc.test, p, eye);
    if (pc.compare == 1) {
        uint label = (labels.l[i >> 2] >> (8u * (i & 3u))) & 0xffu;
        if (label <= 2u) {
            uint r0 = luma.v[i];
            uint t0 = luma.v[2u * pixels + i];
            int excess = abs(int(t) - int(t0)) - abs(int(r) - int(r0));
            float e = float(max(excess, 0)) / (10000.0 * 255.0);
            atomicAdd(counts.c[label * uint(pc.bins + 1) + bin(e)], 1u);
        }
    }
    luma.v[i] = r;
    luma.v[2u * pixels + i] = t;
}
