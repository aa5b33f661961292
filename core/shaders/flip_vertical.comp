#version 450
// The separable filters' second half, along columns: the filtered colours (Cz's two Gaussians
// summed) and the features (dx, dy, ddx, ddy) of both images at one pyramid level. At the
// judged resolution the pass judges the pixel itself (its share of the level's error); on a
// coarse level it writes the fields for the resampling.
#include "flip_common.glsl"

void main() {
    ivec2 p = pc.origin + ivec2(gl_GlobalInvocationID.xy);
    if (any(greaterThanEqual(p, pc.size))) {
        return;
    }
    bool judged = pc.scale == 1.0;
    float weight;
    if (judged && !takesShare(p, weight)) {
        return;
    }
    vec4 colourRef = vec4(0.0);
    vec4 colourTest = vec4(0.0);
    for (int k = -pc.spatialRadius; k <= pc.spatialRadius; k++) {
        int y = clamp(p.y + k, 0, pc.size.y - 1);
        vec4 w = taps.t[pc.spatialTaps + k + pc.spatialRadius];
        int i = 4 * (y * pc.size.x + p.x);
        colourRef += w * mid.v[i];
        colourTest += w * mid.v[i + 1];
    }
    vec4 featRef = vec4(0.0);
    vec4 featTest = vec4(0.0);
    for (int k = -pc.featureRadius; k <= pc.featureRadius; k++) {
        int y = clamp(p.y + k, 0, pc.size.y - 1);
        vec3 w = taps.t[pc.featureTaps + k + pc.featureRadius].xyz;
        int i = 4 * (y * pc.size.x + p.x);
        vec3 r = mid.v[i + 2].xyz;
        vec3 t = mid.v[i + 3].xyz;
        // dx and ddx: the row sums smoothed by the Gaussian; dy and ddy: the Gaussian row sums
        // differentiated.
        featRef += vec4(w.x * r.x, w.y * r.z, w.x * r.y, w.z * r.z);
        featTest += vec4(w.x * t.x, w.y * t.z, w.x * t.y, w.z * t.z);
    }
    vec3 ref = vec3(colourRef.xy, colourRef.z + colourRef.w);
    vec3 test = vec3(colourTest.xy, colourTest.z + colourTest.w);
    if (judged) {
        addError(p, weight, flipError(ref, test, featRef, featTest));
        return;
    }
    int o = 4 * (p.y * pc.size.x + p.x);
    fields.v[o] = vec4(ref, 0.0);
    fields.v[o + 1] = vec4(test, 0.0);
    fields.v[o + 2] = featRef;
    fields.v[o + 3] = featTest;
}
