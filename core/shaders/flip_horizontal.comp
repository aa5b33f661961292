#version 450
// The separable filters' first half, along rows at one pyramid level: the colour (CSF) filter
// on Y, Cx and Cz (two Gaussians), and the edge and point filters on the normalised lightness.
// One loop over the wider filter's reach reads each texel once for both.
#include "flip_common.glsl"

void main() {
    ivec2 p = pc.origin + ivec2(gl_GlobalInvocationID.xy);
    if (any(greaterThanEqual(p, pc.size))) {
        return;
    }
    int n = pc.size.x * pc.size.y;
    int row = pc.src + p.y * pc.size.x;
    vec4 colourRef = vec4(0.0);
    vec4 colourTest = vec4(0.0);
    vec3 featRef = vec3(0.0);
    vec3 featTest = vec3(0.0);
    int reach = max(pc.spatialRadius, pc.featureRadius);
    for (int k = -reach; k <= reach; k++) {
        int x = clamp(p.x + k, 0, pc.size.x - 1);
        vec3 r = pyramid.texel[row + x].xyz;
        vec3 t = pyramid.texel[row + n + x].xyz;
        if (abs(k) <= pc.spatialRadius) {
            vec4 w = taps.t[pc.spatialTaps + k + pc.spatialRadius];
            colourRef += w * r.xyzz;
            colourTest += w * t.xyzz;
        }
        if (abs(k) <= pc.featureRadius) {
            vec3 w = taps.t[pc.featureTaps + k + pc.featureRadius].xyz;
            featRef += vec3(w.y, w.z, w.x) * ((r.x + 16.0) / 116.0);
            featTest += vec3(w.y, w.z, w.x) * ((t.x + 16.0) / 116.0);
        }
    }
    int i = 4 * (p.y * pc.size.x + p.x);
    mid.v[i] = colourRef;
    mid.v[i + 1] = colourTest;
    mid.v[i + 2] = vec4(featRef, 0.0);
    mid.v[i + 3] = vec4(featTest, 0.0);
}
