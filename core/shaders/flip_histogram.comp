#version 450
// Both maps reduced to histograms where they were computed, so that only the counts travel to
// the host: the plain FLIP of every visible pixel, and the eccentricity-aware FLIP by region.
// The bins are `metrics::ErrorHistogram`'s: exact zeros, then `bins` equal bins over (0, 1].
#include "flip_common.glsl"

uint bin(float v) {
    return v <= 0.0 ? 0u : 1u + min(uint(min(v, 1.0) * float(pc.bins)), uint(pc.bins) - 1u);
}

void count(uint histogram, float v) {
    if (!isnan(v) && !isinf(v)) {
        atomicAdd(counts.c[histogram * uint(pc.bins + 1) + bin(v)], 1u);
    }
}

void main() {
    ivec2 p = ivec2(gl_GlobalInvocationID.xy);
    if (any(greaterThanEqual(p, pc.full))) {
        return;
    }
    int i = p.y * pc.full.x + p.x;
    uint label = (labels.l[i >> 2] >> (8 * (i & 3))) & 0xffu;
    if (label > 2u) {
        return;
    }
    vec2 e = maps.v[i];
    count(0u, e.x);
    count(1u + label, e.y);
}
