#version 450
#extension GL_EXT_multiview : require

// Temporal accumulation of the periphery, per eye (gl_ViewIndex), one fragment per screen
// pixel of the rendered field (Di Donato 2017 §3.6; Yang, Nehab & Sander 2009 "Amortized
// supersampling"; Karis 2014 "High quality temporal supersampling"). The periphery views were
// rendered shifted by a sub-pixel jitter (Halton 2, 3), so over frames their samples land all
// over each screen pixel: the history, kept at the screen's density, gathers them, and so holds
// detail one low-resolution frame cannot.
//
// For this pixel: its direction, the nearest periphery sample and where it was taken, and that
// sample's depth; the point it sees, projected into the previous frame's eye, finds its place in
// the history. History taps that saw something else (a depth 10 % off: disocclusion) or nothing
// (the fovea covered them, or never rendered) are dropped; what remains is clamped to the
// periphery's 3x3 neighbourhood (so a moving or changed surface cannot leave a trail) and the new
// sample blended in with a weight that falls with its distance from the pixel's centre. With no
// usable history, the pixel starts from the bilinear periphery. Alpha keeps the pixel's depth
// for the next frame (0: nothing usable).

layout(set = 0, binding = 0) uniform sampler2DArray periphery;
layout(set = 0, binding = 3) uniform sampler2DArray history;
layout(set = 0, binding = 4) uniform sampler2DArray periphery_depth;

#ifdef COUNT_FRAGMENTS
layout(early_fragment_tests) in;
#include "counter.glsl"
#endif

layout(std140, set = 0, binding = 1) uniform Accumulate {
    mat4 previous_from_view[2]; // the previous frame's clip space from this frame's eye space
    vec4 field[2];              // the rendered field: tangents left, right, up, down
    vec4 fovea[2];              // the fovea views' tangents (the periphery's hole is theirs)
    vec4 jitter;                // xy: this frame's offset (periphery px, x right, y down);
                                // z: a new sample's weight; w: 1 drops the whole history
    vec4 depth;                 // x, y: reverse-Z depth = y / distance − x; z: hole radius (px);
                                // w: 1 / frames since the history was dropped (a young history
                                // takes new samples at their mean's weight)
} c;

layout(location = 0) in vec2 in_uv;
layout(location = 0) out vec4 out_color;

// The depth a pixel that sees the sky keeps (half floats reach 65504).
const float SKY = 60000.0;

bool same_surface(float kept, float expected) {
    if (expected >= SKY) {
        return kept >= SKY;
    }
    return kept > 0.0 && kept < SKY && abs(kept - expected) <= 0.1 * expected;
}

void main() {
    uint eye = gl_ViewIndex;
    vec2 screen = vec2(textureSize(history, 0).xy);
    vec2 uv = gl_FragCoord.xy / screen;
    vec4 p = c.field[eye];
    vec2 t = vec2(-p.x + uv.x * (p.x + p.y), p.z - uv.y * (p.z + p.w));

    // Inside the periphery's hole nothing was rendered: nothing to keep.
    vec4 f = c.fovea[eye];
    vec2 fovea_centre = vec2((f.y - f.x) * 0.5, (f.z - f.w) * 0.5);
    vec2 px_per_tangent = screen / vec2(p.x + p.y, p.z + p.w);
    if (length((t - fovea_centre) * px_per_tangent) < c.depth.z) {
        out_color = vec4(0.0);
        return;
    }

    ivec2 size = textureSize(periphery, 0).xy;
    vec2 q = uv * vec2(size);
    vec2 j = c.jitter.xy;
    ivec2 texel = clamp(ivec2(floor(q + j)), ivec2(0), size - 1);
    vec3 nearest = texelFetch(periphery, ivec3(texel, eye), 0).rgb;
    vec3 lo = nearest;
    vec3 hi = nearest;
    for (int dy = -1; dy <= 1; dy++) {
        for (int dx = -1; dx <= 1; dx++) {
            ivec2 n = clamp(texel + ivec2(dx, dy), ivec2(0), size - 1);
            vec3 s = texelFetch(periphery, ivec3(n, eye), 0).rgb;
            lo = min(lo, s);
            hi = max(hi, s);
        }
    }
    float d = texelFetch(periphery_depth, ivec3(texel, eye), 0).r;
    bool sky = d <= 0.0;
    float distance = sky ? SKY : c.depth.y / (d + c.depth.x);
    vec4 seen = sky ? vec4(t, -1.0, 0.0) : vec4(t * distance, -distance, 1.0);

    // The bilinear periphery at this pixel's centre (the jitter undone).
    vec3 result = texture(periphery, vec3((q + j) / vec2(size), float(eye))).rgb;
    vec4 clip = c.previous_from_view[eye] * seen;
    if (c.jitter.w < 0.5 && clip.w > 0.0) {
        float expected = sky ? SKY : clip.w;
        vec2 at = (clip.xy / clip.w * 0.5 + 0.5) * screen - 0.5;
        ivec2 base = ivec2(floor(at));
        vec2 frac = at - floor(at);
        vec3 sum = vec3(0.0);
        float weight = 0.0;
        for (int k = 0; k < 4; k++) {
            ivec2 o = ivec2(k & 1, k >> 1);
            ivec2 tap = base + o;
            if (any(lessThan(tap, ivec2(0))) || any(greaterThanEqual(tap, ivec2(screen)))) {
                continue;
            }
            vec4 h = texelFetch(history, ivec3(tap, eye), 0);
            if (!same_surface(h.a, expected)) {
                continue;
            }
            vec2 w2 = mix(1.0 - frac, frac, vec2(o));
            sum += w2.x * w2.y * h.rgb;
            weight += w2.x * w2.y;
        }
        if (weight > 0.01) {
            vec3 kept = clamp(sum / weight, lo, hi);
            // How far the new sample lies from this pixel's centre, in screen pixels.
            vec2 off = (vec2(texel) + 0.5 - j - q) * screen / vec2(size);
            float trust = max(c.jitter.z, c.depth.w) * exp(-2.0 * dot(off, off));
            result = mix(kept, nearest, trust);
        }
    }
    out_color = vec4(result, distance);
#ifdef COUNT_FRAGMENTS
    count_fragment(eye);
#endif
}
