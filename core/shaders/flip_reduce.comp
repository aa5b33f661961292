#version 450
// One coarser pyramid level, straight from the judged resolution: each texel the mean of the
// 2^p × 2^p pixels under it (YCxCz is linear in linear RGB, so this is the mean light). The
// level extends `pad` texels past the image, where the pixels read are the image's edge (the
// full-resolution filters' clamp), so the edge weighs as much here as it does there.
#include "flip_common.glsl"

void main() {
    ivec2 p = ivec2(gl_GlobalInvocationID.xy);
    if (any(greaterThanEqual(p, pc.size))) {
        return;
    }
    int block = int(pc.scale);
    int srcCount = pc.full.x * pc.full.y;
    int dstCount = pc.size.x * pc.size.y;
    ivec2 first = (p - pc.pad) * block;
    for (int image = 0; image < 2; image++) {
        vec4 sum = vec4(0.0);
        for (int dy = 0; dy < block; dy++) {
            for (int dx = 0; dx < block; dx++) {
                ivec2 q = clamp(first + ivec2(dx, dy), ivec2(0), pc.full - 1);
                sum += pyramid.texel[image * srcCount + q.y * pc.full.x + q.x];
            }
        }
        pyramid.texel[pc.dst + image * dstCount + p.y * pc.size.x + p.x] = sum / float(block * block);
    }
}
