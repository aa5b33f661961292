#version 450
#extension GL_GOOGLE_include_directive : require

// A resolved view copied texel for texel into its layer of the image the frame samples it
// from: on a driver whose in-pass resolve lands in layer 0 whatever the target's base layer
// (`DriverQuirks::layered_resolve_ignores_base_layer`), a view's pass resolves into an image
// of its own and this full-view draw puts it where it belongs.
layout(constant_id = 5) const uint FIRST_VIEW = 0;

layout(set = 0, binding = 0) uniform sampler2DArray resolved; // one layer

#ifdef COUNT_FRAGMENTS
layout(early_fragment_tests) in;
#include "counter.glsl"
#endif

layout(location = 0) out vec4 out_color;

void main() {
    out_color = texelFetch(resolved, ivec3(gl_FragCoord.xy, 0), 0);
#ifdef COUNT_FRAGMENTS
    count_fragment(FIRST_VIEW);
#endif
}
