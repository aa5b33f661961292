#version 450
#extension GL_EXT_multiview : require

layout(early_fragment_tests) in;

#include "counter.glsl"

void main() {
    count_fragment(gl_ViewIndex);
}
