#version 450

// Stencil-only: the pipeline writes no colour and no depth.
void main() {}
