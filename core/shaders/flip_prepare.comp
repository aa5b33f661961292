#version 450
// Both 8-bit sRGB images to YCxCz, into the pyramid's first level.
#include "flip_common.glsl"

void main() {
    ivec2 p = ivec2(gl_GlobalInvocationID.xy);
    if (any(greaterThanEqual(p, pc.full))) {
        return;
    }
    int i = p.y * pc.full.x + p.x;
    int n = pc.full.x * pc.full.y;
    pyramid.texel[i] = vec4(srgbToYCxCz(unpackUnorm4x8(inputs.rgba[i])), 0.0);
    pyramid.texel[n + i] = vec4(srgbToYCxCz(unpackUnorm4x8(inputs.rgba[n + i])), 0.0);
}
