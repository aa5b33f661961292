#version 450
// One coarse ppd level's FLIP at every judged pixel that takes a share of it, from the level's
// fields resampled with Catmull-Rom at the pixel's centre (along rows by `flip_resample.comp`,
// along columns here). Levels at the judged resolution are judged by the vertical pass itself.
#include "flip_common.glsl"

// Field `k` at judged pixel `p`.
vec4 sampled(ivec2 p, int k) {
    float v = levelCoordinate(vec2(p)).y;
    int q = int(floor(v));
    vec4 w = catmullRom(v - float(q));
    int column = p.x - pc.rowsOrigin.x;
    vec4 sum = vec4(0.0);
    for (int j = 0; j < 4; j++) {
        int row = clamp(q + j - 1, 0, pc.size.y - 1) - pc.rowsOrigin.y;
        sum += w[j] * mid.v[4 * (row * pc.rowsSize.x + column) + k];
    }
    return sum;
}

void main() {
    ivec2 p = pc.origin + ivec2(gl_GlobalInvocationID.xy);
    float weight;
    if (any(greaterThanEqual(p, pc.full)) || !takesShare(p, weight)) {
        return;
    }
    float e = flipError(sampled(p, 0).xyz, sampled(p, 1).xyz, sampled(p, 2), sampled(p, 3));
    addError(p, weight, e);
}
