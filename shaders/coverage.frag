#version 450
#extension GL_EXT_multiview : require

layout(early_fragment_tests) in;

layout(std430, set = 0, binding = 2) buffer FragmentCounts {
    uint fragments[4];
};

void main() {
    atomicAdd(fragments[gl_ViewIndex], 1u);
}
