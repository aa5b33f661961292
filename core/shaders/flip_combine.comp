#version 450
// One ppd level's FLIP at every judged pixel, from the level's fields sampled bilinearly at the
// pixel's centre (exact where the level is the judged resolution): level 0 writes the plain FLIP
// and starts the eccentricity-aware sum; every level adds its share, interpolated in log ppd
// between the two levels around the pixel's own (a hat weight).
#include "flip_common.glsl"

vec4 field(ivec2 q, int k) {
    q = clamp(q, ivec2(0), pc.size - 1);
    return fields.v[4 * (q.y * pc.size.x + q.x) + k];
}

// Catmull-Rom weights of the four texels around a sample at fraction f past the second.
vec4 catmullRom(float f) {
    float f2 = f * f;
    float f3 = f2 * f;
    return vec4(-0.5 * f3 + f2 - 0.5 * f, 1.5 * f3 - 2.5 * f2 + 1.0,
                -1.5 * f3 + 2.0 * f2 + 0.5 * f, 0.5 * f3 - 0.5 * f2);
}

// The fields at level coordinate `u`: exact on a texel (the judged resolution), else
// Catmull-Rom over the 4×4 texels around it.
vec4 sampled(vec2 u, int k) {
    ivec2 q = ivec2(floor(u));
    vec2 f = u - vec2(q);
    if (f == vec2(0.0)) {
        return field(q, k);
    }
    vec4 wx = catmullRom(f.x);
    vec4 wy = catmullRom(f.y);
    vec4 sum = vec4(0.0);
    for (int j = 0; j < 4; j++) {
        vec4 row = vec4(0.0);
        for (int i = 0; i < 4; i++) {
            row += wx[i] * field(q + ivec2(i - 1, j - 1), k);
        }
        sum += wy[j] * row;
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
    vec2 u = (vec2(p) + 0.5) / pc.scale + float(pc.pad) - 0.5;
    float e = flipError(sampled(u, 0).xyz, sampled(u, 1).xyz, sampled(u, 2), sampled(u, 3));
    if (pc.level == 0) {
        maps.v[i] = vec2(e, weight * e);
    } else {
        maps.v[i].y += weight * e;
    }
}
