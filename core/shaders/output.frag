#version 450
#extension GL_EXT_multiview : require

// The output stage, per eye (gl_ViewIndex): what the display shows. For the lens, each display
// pixel is first undistorted — the direction the eye sees it in through the lens, a radial
// polynomial in tangent units — then fetched from what the frame rendered. A foveated frame's
// composition happens here too: the periphery view upscaled bilinearly and the fovea view
// over it inside the fovea circle, blended with smoothstep across the band at the circle's
// edge (Di Donato 2017 §3.3, §3.6.1). Built with TEMPORAL, the periphery is accumulated over
// frames here too (`accumulate.glsl`), and the next history written as a second attachment.

// Where each eye's image is (plan::OutputSource): 0 layer `eye` of `images`; 1 both eyes side
// by side in `images`; 2 `images` for the left eye, `second` for the right; 3 foveated: the
// periphery is layer `eye` of `images`, the fovea layer FOVEA_LAYER + eye of `second`.
layout(constant_id = 30) const bool LENS = false;
layout(constant_id = 31) const uint SOURCE = 0;
layout(constant_id = 32) const uint FOVEA_LAYER = 2;
// Sharpen the upscaled periphery (strength in params.w).
layout(constant_id = 33) const bool SHARPEN = false;
// Upscale the periphery with Catmull-Rom instead of bilinearly.
layout(constant_id = 34) const bool CATMULL_ROM = false;
// The periphery accumulated alone at its own texels (HistoryAt::Periphery), before the output
// pass composes it: this pass writes the accumulated periphery, and keeps in the history over
// the periphery's hole what the fovea shows there (the fovea's place and band in its texels).
layout(constant_id = 39) const bool PERIPHERY_ONLY = false;
// A parafoveal ring between the fovea and the periphery: layers FOVEA_LAYER + 2 + eye of
// `second`, blended over the periphery at its edge as the fovea is over the ring.
layout(constant_id = 42) const bool RING = false;

layout(set = 0, binding = 0) uniform sampler2DArray images;
layout(set = 0, binding = 3) uniform sampler2DArray second;

#ifdef COUNT_FRAGMENTS
layout(early_fragment_tests) in;
#include "counter.glsl"
#endif

layout(std140, set = 0, binding = 1) uniform Output {
    vec4 periphery[2]; // the rendered field: tangents left, right, up, down per eye
    vec4 fovea[2];     // the fovea views' tangents
    vec4 display[2];   // the display's field as the lens model places it (LENS)
    vec4 params;       // fovea diameter (screen px), band (px), debug tint (0/1), sharpening
    vec4 screen;       // width, height (px); lens k1, k2
    // Temporal accumulation (TEMPORAL only):
    mat4 previous_from_view[2]; // the previous frame's clip space from this frame's eye space
    vec4 jitter;                // xy: this frame's offset (periphery px, x right, y down);
                                // z: a new sample's weight; w: 1 drops the whole history
    vec4 depth;                 // x, y: reverse-Z depth = y / distance − x; z: hole radius (px);
                                // w: 1 / frames since the history was dropped (a young history
                                // takes new samples at their mean's weight)
    vec4 clip;                  // x: the history's box around the neighbourhood's mean, in
                                // standard deviations (huge: its range alone; < 0: no clip);
                                // y: 1 tests the history against the frame before's depth,
                                // 2 too and clips only where the point moved;
                                // zw: the frame before's jitter
    vec4 still;                 // x: a new sample's weight where nothing moved; y, z: the
                                // cosines of the eccentricities where the accumulation ends
                                // and where it starts to fade (reach_weight)
    vec4 ring[2];               // RING: the parafoveal ring views' tangents
    vec4 ring_params;           // RING: the ring's diameter, its band (screen px)
} c;

layout(location = 0) in vec2 in_uv;
layout(location = 0) out vec4 out_color;

#ifdef TEMPORAL
#include "accumulate.glsl"
#endif

vec3 eye_image(uint eye, vec2 uv) {
    if (SOURCE == 1u) {
        // Keep the bilinear footprint inside this eye's half.
        float half_texel = 0.5 / float(textureSize(images, 0).x / 2);
        uv.x = (clamp(uv.x, half_texel, 1.0 - half_texel) + float(eye)) * 0.5;
        return texture(images, vec3(uv, 0.0)).rgb;
    }
    if (SOURCE == 2u && eye == 1u) {
        return texture(second, vec3(uv, 0.0)).rgb;
    }
    return texture(images, vec3(uv, SOURCE == 2u ? 0.0 : float(eye))).rgb;
}

// The periphery at `uv` upscaled with the Catmull-Rom spline (Keys 1981, "Cubic convolution
// interpolation for digital image processing", a = -0.5; Catmull & Rom 1974): the 4×4 texels
// around it, each axis weighted by the cubic that passes through the texel centres with
// continuous slope. It keeps more of the periphery's contrast than bilinear's 2×2 tent, and it
// can overshoot at edges, so the result is clamped to the displayable range. Texels past the
// image's edge repeat the edge (as the bilinear sampler's clamp does).
vec3 catmull_rom(uint eye, vec2 uv) {
    ivec2 size = textureSize(images, 0).xy;
    vec2 pos = uv * vec2(size) - 0.5;
    vec2 base = floor(pos);
    vec2 t = pos - base;
    vec2 w0 = ((-0.5 * t + 1.0) * t - 0.5) * t;
    vec2 w1 = (1.5 * t - 2.5) * t * t + 1.0;
    vec2 w2 = ((-1.5 * t + 2.0) * t + 0.5) * t;
    vec2 w3 = (0.5 * t - 0.5) * t * t;
    vec2 w[4] = vec2[4](w0, w1, w2, w3);
    vec3 sum = vec3(0.0);
    for (int j = 0; j < 4; j++) {
        for (int i = 0; i < 4; i++) {
            ivec2 texel = clamp(ivec2(base) + ivec2(i - 1, j - 1), ivec2(0), size - 1);
            sum += w[i].x * w[j].y * texelFetch(images, ivec3(texel, int(eye)), 0).rgb;
        }
    }
    return clamp(sum, 0.0, 1.0);
}

// The periphery at `uv`, upscaled bilinearly (or with CATMULL_ROM, by `catmull_rom`) and, with SHARPEN, sharpened contrast-adaptively:
// AMD FidelityFX CAS's filter (Lottes 2019) on the cross of bilinear taps one periphery texel
// apart. Its negative lobe shrinks where the neighbourhood already spans the range (strong
// edges) and grows where contrast is low, so it restores what bilinear upscaling softens
// without the halos a fixed unsharp mask rings with; five taps, one pass, no extra image.
vec3 periphery(uint eye, vec2 uv) {
    vec3 centre = CATMULL_ROM ? catmull_rom(eye, uv) : texture(images, vec3(uv, float(eye))).rgb;
    if (!SHARPEN) {
        return centre;
    }
    vec2 texel = 1.0 / vec2(textureSize(images, 0).xy);
    vec3 n = texture(images, vec3(uv - vec2(0.0, texel.y), float(eye))).rgb;
    vec3 s = texture(images, vec3(uv + vec2(0.0, texel.y), float(eye))).rgb;
    vec3 w = texture(images, vec3(uv - vec2(texel.x, 0.0), float(eye))).rgb;
    vec3 e = texture(images, vec3(uv + vec2(texel.x, 0.0), float(eye))).rgb;
    vec3 lo = min(min(min(n, s), min(w, e)), centre);
    vec3 hi = max(max(max(n, s), max(w, e)), centre);
    vec3 amp = sqrt(clamp(min(lo, 1.0 - hi) / max(hi, vec3(1e-5)), 0.0, 1.0));
    vec3 lobe = amp * (-1.0 / mix(8.0, 5.0, c.params.w));
    return clamp((centre + (n + s + w + e) * lobe) / (1.0 + 4.0 * lobe), 0.0, 1.0);
}

// Beyond the fovea with a parafoveal ring: the ring inside its circle, blended over the
// periphery across its band, as the fovea is over the ring; `w` the ring's weight.
vec3 ring_over_periphery(uint eye, vec2 uv, vec2 t, vec2 px_per_tangent, out float w) {
    vec4 r = c.ring[eye];
    vec2 centre = vec2((r.y - r.x) * 0.5, (r.z - r.w) * 0.5);
    float dist = length((t - centre) * px_per_tangent);
    float radius = c.ring_params.x * 0.5;
    w = 1.0 - smoothstep(radius - c.ring_params.y, radius, dist);
    vec3 color = vec3(0.0);
    if (w < 1.0) {
        color += (1.0 - w) * periphery(eye, uv);
    }
    if (w > 0.0) {
        vec2 ring_uv = vec2((t.x + r.x) / (r.x + r.y), (r.z - t.y) / (r.z + r.w));
        color += w * texture(second, vec3(ring_uv, float(FOVEA_LAYER + 2u + eye))).rgb;
    }
    return color;
}

void main() {
    uint eye = gl_ViewIndex;
    vec4 p = c.periphery[eye];
    vec2 uv = in_uv;
    // This pixel's direction in the rendered field, as tangents (x right, y up); through the
    // lens, `td` is its place on the display (display tangents).
    vec2 t;
    vec2 td = vec2(0.0);
    if (LENS) {
        vec4 d = c.display[eye];
        td = vec2(-d.x + in_uv.x * (d.x + d.y), d.z - in_uv.y * (d.z + d.w));
        float r2 = dot(td, td);
        t = td * (1.0 + r2 * (c.screen.z + c.screen.w * r2));
        uv = vec2((t.x + p.x) / (p.x + p.y), (p.z - t.y) / (p.z + p.w));
    } else {
        t = vec2(-p.x + in_uv.x * (p.x + p.y), p.z - in_uv.y * (p.z + p.w));
    }

    vec3 color = vec3(0.0);
#ifdef TEMPORAL
    out_history = NOTHING;
#endif
    if (LENS && (any(lessThan(uv, vec2(0.0))) || any(greaterThan(uv, vec2(1.0))))) {
        // Seen through the lens beyond what was rendered: black, as on a headset.
    } else if (SOURCE != 3u) {
        color = eye_image(eye, uv);
    } else {
        vec4 f = c.fovea[eye];
        vec2 fovea_uv = vec2((t.x + f.x) / (f.x + f.y), (f.z - t.y) / (f.z + f.w));
        vec2 fovea_centre = vec2((f.y - f.x) * 0.5, (f.z - f.w) * 0.5);
        vec2 px_per_tangent = c.screen.xy / vec2(p.x + p.y, p.z + p.w);
        float dist = length((t - fovea_centre) * px_per_tangent);
        float radius = c.params.x * 0.5;
        float band = c.params.y;
        // 1 in the fovea, 0 in the periphery, smooth across the band.
        float w = band > 0.0 ? 1.0 - smoothstep(radius - band, radius, dist) : float(dist < radius);
        float ring_w = 0.0;
#ifdef TEMPORAL
        // Accumulated wherever the periphery was rendered, shown or not (under the fovea's
        // edge it is ready when the gaze moves), out to the reach.
        vec3 accumulated = accumulate_within_reach(eye, uv, t, td, fovea_centre, out_history);
        color += PERIPHERY_ONLY ? accumulated : (1.0 - w) * accumulated;
#ifdef COUNT_FRAGMENTS
        count_history_outcome(w);
#endif
#else
        // Fetch only what contributes: most pixels are periphery only, a few fovea only.
        if (w < 1.0) {
            color += (1.0 - w) * (RING ? ring_over_periphery(eye, uv, t, px_per_tangent, ring_w)
                                       : periphery(eye, uv));
        }
#endif
        // Accumulating the periphery alone, the fovea is read only where the history keeps it.
        vec4 fovea = vec4(0.0, 0.0, 0.0, 1.0);
        if (w > 0.0 && (!PERIPHERY_ONLY || w >= 1.0)) {
            fovea = texture(second, vec3(fovea_uv, float(FOVEA_LAYER + eye)));
            color += PERIPHERY_ONLY ? vec3(0.0) : w * fovea.rgb;
        }
#ifdef TEMPORAL
        // Over the periphery's hole the history keeps what the fovea shows: when the gaze moves
        // on, those pixels start from it rather than from the bilinear periphery. Not where an
        // instance that moves shows (alpha below 1): no depth test would catch its trail.
        if (w >= 1.0 && out_history.a == 0.0 && fovea.a >= MOVER_ALPHA) {
            out_history = to_history(fovea.rgb, FROM_FOVEA);
        }
#endif
        if (c.params.z > 0.5) {
            // Fovea green, its band yellow, a parafoveal ring orange, the periphery blue.
            vec3 tint = w >= 1.0 ? vec3(0.2, 1.0, 0.2) : (w > 0.0 ? vec3(1.0, 0.9, 0.1) : vec3(0.2, 0.4, 1.0));
            tint = w <= 0.0 && ring_w > 0.0 ? mix(tint, vec3(1.0, 0.5, 0.1), ring_w) : tint;
            color = mix(color, tint, 0.35);
        }
    }
    out_color = vec4(color, 1.0);
#ifdef COUNT_FRAGMENTS
    count_fragment(eye);
#endif
}
