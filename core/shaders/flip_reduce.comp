#version 450
// One coarser pyramid level from the level before it: each texel the tent-weighted mean of the
// 4 × 4 texels around its centre (weights 1, 3, 3, 1 over 8 on each axis: a tent falling to zero
// two source texels away). YCxCz is linear in linear RGB, so this averages light; the tent,
// unlike a 2 × 2 box, keeps what lies past the coarse level's Nyquist frequency from folding
// back into the frequencies the filters keep, and the cascade of tents tends to a Gaussian.
// The level extends `pad` texels past the image; where the source is read past its own extent
// the nearest texel stands in: at the judged resolution, the image's edge pixel (as the
// full-resolution filters clamp), on a coarser level its padding, made the same way.
#include "flip_common.glsl"

const float TENT[4] = float[4](0.125, 0.375, 0.375, 0.125);

void main() {
    ivec2 p = ivec2(gl_GlobalInvocationID.xy);
    if (any(greaterThanEqual(p, pc.size))) {
        return;
    }
    int srcCount = pc.full.x * pc.full.y;
    int dstCount = pc.size.x * pc.size.y;
    // The texel covers source texels 2i and 2i + 1 (image coordinates); its tent the one
    // before and the one after too.
    ivec2 first = 2 * (p - pc.pad) - 1 + pc.srcPad;
    for (int image = 0; image < 2; image++) {
        vec4 sum = vec4(0.0);
        for (int dy = 0; dy < 4; dy++) {
            vec4 row = vec4(0.0);
            for (int dx = 0; dx < 4; dx++) {
                ivec2 q = clamp(first + ivec2(dx, dy), ivec2(0), pc.full - 1);
                row += TENT[dx] * pyramid.texel[pc.src + image * srcCount + q.y * pc.full.x + q.x];
            }
            sum += TENT[dy] * row;
        }
        pyramid.texel[pc.dst + image * dstCount + p.y * pc.size.x + p.x] = sum;
    }
}
