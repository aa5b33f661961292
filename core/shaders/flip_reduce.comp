#version 450
// One coarser pyramid level, straight from the judged resolution: each texel a tent-weighted
// mean of the 2s × 2s pixels around its centre (s = 2^p judged pixels per texel; weights fall
// linearly to zero one texel away). YCxCz is linear in linear RGB, so this averages light; the
// tent, unlike a box of s × s, keeps what lies past the coarse level's Nyquist frequency from
// folding back into the frequencies the filters keep. The level extends `pad` texels past the
// image, where the pixels read are the image's edge (the full-resolution filters' clamp), so
// the edge weighs as much here as it does there.
#include "flip_common.glsl"

void main() {
    ivec2 p = ivec2(gl_GlobalInvocationID.xy);
    if (any(greaterThanEqual(p, pc.size))) {
        return;
    }
    int s = int(pc.scale);
    int srcCount = pc.full.x * pc.full.y;
    int dstCount = pc.size.x * pc.size.y;
    // The texel's centre in judged pixels, and the first of the 2s pixels on each axis.
    vec2 centre = (vec2(p - pc.pad) + 0.5) * pc.scale;
    ivec2 first = ivec2(centre) - s;
    for (int image = 0; image < 2; image++) {
        vec4 sum = vec4(0.0);
        for (int dy = 0; dy < 2 * s; dy++) {
            float wy = 1.0 - abs(float(first.y + dy) + 0.5 - centre.y) / pc.scale;
            vec4 row = vec4(0.0);
            for (int dx = 0; dx < 2 * s; dx++) {
                float wx = 1.0 - abs(float(first.x + dx) + 0.5 - centre.x) / pc.scale;
                ivec2 q = clamp(first + ivec2(dx, dy), ivec2(0), pc.full - 1);
                row += wx * pyramid.texel[image * srcCount + q.y * pc.full.x + q.x];
            }
            sum += wy * row;
        }
        pyramid.texel[pc.dst + image * dstCount + p.y * pc.size.x + p.x] = sum / (pc.scale * pc.scale);
    }
}
