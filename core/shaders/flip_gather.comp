#version 450
// One eye of both renderers' outputs, where they were copied on the device, into the judge's
// 8-bit sRGB inputs, as a read-back frame would be uploaded: the test's pixels the lens hides
// taken from the reference (metrics::perceptual's hidden_as_reference), so that FLIP's filters
// carry no difference no one sees into the visible pixels around them.
#include "flip_common.glsl"
#include "output_texels.glsl"

uint packed(uvec3 c) {
    return c.r | (c.g << 8) | (c.b << 16) | (255u << 24);
}

void main() {
    ivec2 p = ivec2(gl_GlobalInvocationID.xy);
    if (any(greaterThanEqual(p, pc.full))) {
        return;
    }
    int i = p.y * pc.full.x + p.x;
    int n = pc.full.x * pc.full.y;
    uvec3 reference = eyeColour(pc.reference, p);
    uint label = (labels.l[i >> 2] >> (8 * (i & 3))) & 0xffu;
    uvec3 test = label > 2u ? reference : eyeColour(pc.test, p);
    inputs.rgba[i] = packed(reference);
    inputs.rgba[n + i] = packed(test);
}
