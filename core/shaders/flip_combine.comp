#version 450
// One ppd level's FLIP at every judged pixel, from the level's fields at the pixel's centre:
// read directly where the level is the judged resolution, else resampled with Catmull-Rom (along
// rows by `flip_resample.comp`, along columns here). Level 0 writes the plain FLIP and starts the
// eccentricity-aware sum; every level adds its share, interpolated in log ppd between the two
// levels around the pixel's own (a hat weight).
#include "flip_common.glsl"

// Field `k` at judged pixel `p`.
vec4 sampled(ivec2 p, int k) {
    if (pc.scale == 1.0) {
        return fields.v[4 * (p.y * pc.size.x + p.x) + k];
    }
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
    if (any(greaterThanEqual(p, pc.full))) {
        return;
    }
    int i = p.y * pc.full.x + p.x;
    float t = positions.t[i];
    if (t < 0.0) {
        if (pc.level == 0) {
            maps.v[i] = vec2(uintBitsToFloat(0x7fc00000u));
        }
        return;
    }
    float weight = max(0.0, 1.0 - abs(t - float(pc.level)));
    if (pc.level != 0 && weight == 0.0) {
        return;
    }
    float e = flipError(sampled(p, 0).xyz, sampled(p, 1).xyz, sampled(p, 2), sampled(p, 3));
    if (pc.level == 0) {
        maps.v[i] = vec2(e, weight * e);
    } else {
        maps.v[i].y += weight * e;
    }
}
