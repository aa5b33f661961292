#version 450
#extension GL_EXT_multiview : require
#extension GL_GOOGLE_include_directive : require

// The radial density mask: a full-view draw that keeps (stencil-writes) only the fragments of
// skipped quads; the scene then skips them by their stencil bit. No early fragment tests: the
// stencil write must follow the discard. Every invocation is counted (each one ran).
#include "radial_density.glsl"

#ifdef COUNT_FRAGMENTS
#include "counter.glsl"
#endif

void main() {
#ifdef COUNT_FRAGMENTS
    count_fragment(gl_ViewIndex);
#endif
    if (!quad_skipped(ivec2(gl_FragCoord.xy) >> 1, gl_ViewIndex)) {
        discard;
    }
}
