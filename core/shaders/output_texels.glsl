// A renderer's output texels where `Renderer::record_output_copy` copied them (a buffer of
// words, `frames.w`, which the including shader declares), as the 8-bit sRGB colours a
// read-back frame has (`render::output_pixels`): an sRGB output as it is, a linear one (8-bit,
// or half floats) encoded. An image is described by an ivec4: its format (0 sRGB, 1 linear
// 8-bit, 2 linear half floats), its first word in `frames`, the first texel of the eye read, and
// its rows' pitch in texels.

// A linear value as its 8-bit sRGB code (scene::textures::encode_srgb).
uint srgb8(float linear) {
    float l = clamp(linear, 0.0, 1.0);
    float c = l <= 0.0031308 ? 12.92 * l : 1.055 * pow(l, 1.0 / 2.4) - 0.055;
    return uint(round(clamp(c, 0.0, 1.0) * 255.0));
}

// The 8-bit sRGB colour of texel `t` (counted from the image's start) of `image`.
uvec3 outputColour(ivec4 image, uint t) {
    uint base = uint(image.y);
    if (image.x == 2) {
        vec2 rg = unpackHalf2x16(frames.w[base + 2u * t]);
        vec2 ba = unpackHalf2x16(frames.w[base + 2u * t + 1u]);
        return uvec3(srgb8(rg.x), srgb8(rg.y), srgb8(ba.x));
    }
    uint w = frames.w[base + t];
    uvec3 c = uvec3(w & 0xffu, (w >> 8) & 0xffu, (w >> 16) & 0xffu);
    if (image.x == 1) {
        c = uvec3(srgb8(c.r / 255.0), srgb8(c.g / 255.0), srgb8(c.b / 255.0));
    }
    return c;
}

// The colour of pixel `p` of the eye whose first texel `image.z` names.
uvec3 eyeColour(ivec4 image, ivec2 p) {
    return outputColour(image, uint(image.z) + uint(p.y) * uint(image.w) + uint(p.x));
}
