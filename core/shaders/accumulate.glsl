// Temporal accumulation of the periphery, folded into the output stage (Di Donato 2017 §3.6;
// Yang, Nehab & Sander 2009 "Amortized supersampling"; Karis 2014 "High quality temporal
// supersampling"; Salvi 2016 "An excursion in temporal supersampling"). The periphery views were
// rendered shifted by a sub-pixel jitter (Halton 2, 3), so over frames their samples land all
// over each output pixel: the history, kept at the output's pixels, gathers them, and so holds
// detail one low-resolution frame cannot.
//
// For this pixel: its direction, the nearest periphery sample and where it was taken, and that
// sample's depth; the point it sees, projected into the previous frame's eye (and, for the lens,
// distorted as that frame's output pixels were), finds its place in the history — if the frame
// before's periphery saw the same surface there (its depth within 10 %: in the texel the point
// lay in when it moved, in any of the 2×2 around it when it did not; where the fovea covered
// the periphery's hole the history holds what the fovea showed, and no depth lies beside it).
// History taps that hold nothing (the lens hid them, never rendered) are dropped; what
// remains is clipped towards the periphery's 3x3 neighbourhood (or its cross) in YCoCg — its
// mean, within its spread (Salvi's variance clipping): a surface that moved or changed cannot
// leave a trail, and unlike a min/max clamp the box does not widen with every outlier — and the
// new sample is blended in with a weight that falls with its distance from the pixel's centre
// (Yang, Nehab & Sander's sample weight): the nearest periphery texel, or (NewSample::Weighted)
// where the point moved the 3×3 texels around the pixel, each weighted so, from the box's reads:
// which texel is nearest switches as the head turns, and its colour enters at once, where with
// every neighbour weighed what enters changes smoothly (the walk's flicker in the periphery 2 %
// lower at density 0.6, for no time measurable on lavapipe; 20 % at the screen's, for 3 %:
// BENCHMARKS.md).
// With no usable history, the pixel starts from the bilinear periphery.

// Read the history with Catmull-Rom where the point moved (HistoryFilter::CatmullRom).
layout(constant_id = 36) const bool HISTORY_CATMULL_ROM = false;
// The clip's box from the texel and its four edge neighbours rather than the 3×3
// (ClipNeighbourhood::Cross): five reads instead of nine.
layout(constant_id = 37) const bool CROSS_NEIGHBOURHOOD = false;
// The new sample from the 3×3 periphery texels around the pixel, each weighted by its distance
// (NewSample::Weighted): nine reads where the nearest texel alone takes one.
layout(constant_id = 38) const bool WEIGHTED_NEW_SAMPLE = false;
// The periphery accumulates only within a reach of the gaze (TemporalConfig::within_deg); without
// it none of the reach's work is compiled in (lavapipe would run it under a mask everywhere).
layout(constant_id = 40) const bool REACH = false;
// The scene passes mark instances that move (alpha below 1; scene.frag): only then are they
// looked for in the neighbourhood, and only then is the box needed where nothing moved.
layout(constant_id = 7) const bool MARK_MOVING = false;
// The history keeps luma alone in one byte (HistoryFormat::Luma): code 0 holds nothing, 1 to 255
// the square root of linear luma; the chroma comes from this frame's periphery.
layout(constant_id = 44) const bool LUMA_HISTORY = false;

layout(set = 0, binding = 4) uniform sampler2DArray history;
layout(set = 0, binding = 5) uniform sampler2DArray periphery_depth;
layout(set = 0, binding = 6) uniform sampler2DArray previous_depth;
layout(location = 1) out vec4 out_history;

// The history holds the square root of linear light in 10 bits (its steps finer than an 8-bit
// display's down to the darks, so a small blend of a new sample is not rounded away); alpha 0
// marks a pixel that holds nothing, 2/3 one that holds what the fovea showed over the
// periphery's hole (no periphery depth lies beside it), 1 the accumulated periphery, 1/3 the
// same where an instance that moves lay (the next frame clips it: that instance left it).
const vec4 NOTHING = vec4(0.0);
const float FROM_FOVEA = 2.0 / 3.0;
const float MOVER = 1.0 / 3.0;
// A scene pixel's alpha below this: an instance that moves covers some of it (scene.frag).
const float MOVER_ALPHA = 1.0 - 0.5 / 255.0;

// What became of this pixel's history (counting frames only: `history_outcomes.glsl` counts
// it per region; timed frames compile none of it).
#ifdef COUNT_FRAGMENTS
#include "history_outcomes.glsl"
#define NOTE_OUTCOME(o) history_outcome = (o)
#else
#define NOTE_OUTCOME(o)
#endif

vec4 to_history(vec3 linear, float kind) {
    if (!LUMA_HISTORY) {
        return vec4(round(sqrt(clamp(linear, 0.0, 1.0)) * 1023.0) / 1023.0, kind);
    }
    if (kind == 0.0) {
        return NOTHING;
    }
    // YCoCg's luma, rounded up with the probability of its fraction (interleaved gradient
    // noise, Jimenez 2014, moved every frame with the jitter): in 254 steps a still blend of
    // 0.05 moves a pixel by under half a step, which plain rounding would undo every frame.
    float s = sqrt(clamp(dot(linear, vec3(0.25, 0.5, 0.25)), 0.0, 1.0)) * 254.0;
    vec2 at = gl_FragCoord.xy + 67.0 * c.jitter.xy;
    float noise = fract(52.9829189 * fract(dot(at, vec2(0.06711056, 0.00583715))));
    return vec4((min(floor(s + noise), 254.0) + 1.0) / 255.0);
}

// A history texel as the colour history keeps it (the square root of linear light, its kind in
// alpha); a luma history's as grey, its kind the accumulated periphery's or nothing's.
vec4 history_texel(ivec2 texel, uint eye) {
    vec4 h = texelFetch(history, ivec3(texel, eye), 0);
    if (!LUMA_HISTORY) {
        return h;
    }
    float code = round(h.r * 255.0);
    return code < 0.5 ? NOTHING : vec4(vec3((code - 1.0) / 254.0), 1.0);
}

vec3 to_ycocg(vec3 c) {
    return vec3(0.25 * c.r + 0.5 * c.g + 0.25 * c.b, 0.5 * (c.r - c.b), 0.5 * c.g - 0.25 * (c.r + c.b));
}

vec3 from_ycocg(vec3 c) {
    float t = c.x - c.z;
    return vec3(t + c.y, c.x + c.z, t - c.y);
}

// `h` moved towards the box's centre along the line between them until it lies in the box
// [lo, hi] (a clip, not a per-channel clamp: the colour keeps its hue).
vec3 clip_to_box(vec3 h, vec3 lo, vec3 hi) {
    vec3 centre = 0.5 * (lo + hi);
    vec3 d = h - centre;
    vec3 r = abs(d) / max(0.5 * (hi - lo), vec3(1e-6));
    float k = max(r.x, max(r.y, r.z));
    return k > 1.0 ? centre + d / k : h;
}

// The display tangent a lens-distorted output shows direction `t` at: the radial polynomial
// r(1 + k1 r² + k2 r⁴) inverted by Newton's method (monotone over a lens's field). It starts
// from the display radius of `near` (this pixel's own place, whose direction lies a frame's
// motion from `t`): two steps from there land closer than four from `t`'s own radius did.
vec2 distorted(vec2 t, vec2 near) {
    float target = length(t);
    if (target < 1e-6) {
        return t;
    }
    float r = length(near);
    for (int i = 0; i < 2; i++) {
        float r2 = r * r;
        float f = r * (1.0 + r2 * (c.screen.z + c.screen.w * r2)) - target;
        float slope = 1.0 + r2 * (3.0 * c.screen.z + 5.0 * c.screen.w * r2);
        r -= f / slope;
    }
    return t * (r / target);
}

// Whether the frame before's periphery saw, where direction `t` seen at `distance` (the sky:
// infinitely far) lay in it (`uv`, its rendered field's; `w`, its distance there), the same
// surface: a depth within 10 % (the disocclusion test; the history keeps no depth of its own,
// so the frame before's periphery depth is kept instead). `moved`: the point moved since the
// frame before (by a tenth of a periphery texel or more: motion, not rounding).
// `under_fovea`: the history there holds what the fovea showed, so where the frame before's
// periphery has no depth (its hole) there is nothing to test.
bool seen_before(uint eye, vec2 uv, float w, bool sky, bool moved, bool under_fovea) {
    if (c.clip.y < 0.5) {
        return true; // HistoryClip::Off: the history is not held to anything
    }
    // Where the point has not moved, any of the 2×2 texels around it will do: the jitter
    // moved the samples by less than a texel, and across an edge or a slanted surface their
    // depths differ, so one texel would drop good history at every edge. Where it moved, an
    // edge may have uncovered it: only the texel it lay in counts.
    ivec2 size = textureSize(previous_depth, 0).xy;
    vec2 at = uv * vec2(size) + c.clip.zw;
    ivec2 base = moved ? ivec2(floor(at)) : ivec2(floor(at - 0.5));
    // The distances within 10 % of `w` as an interval of depth values, found once: each tap
    // then compares its depth with no division (depth falls as distance grows).
    vec2 depths = c.depth.y / (vec2(1.1, 0.9) * w) - c.depth.x;
    for (int k = 0; k < (moved ? 1 : 4); k++) {
        ivec2 texel = clamp(base + ivec2(k & 1, k >> 1), ivec2(0), size - 1);
        float d = texelFetch(previous_depth, ivec3(texel, eye), 0).r;
        if (d <= 0.0 && (sky || under_fovea)) {
            return true;
        }
        if (sky || d <= 0.0) {
            continue;
        }
        if (d >= depths.x && d <= depths.y) {
            return true;
        }
    }
    return false;
}

// Where, in the previous frame's output pixels (continuous, centres at .5), direction `t`
// (at `here` in this frame's rendered field) seen at `distance` (the sky: infinitely far)
// lay; z < 0 when behind that frame's eye or when that frame saw another surface there.
// `moved`: whether the point moved on screen since then (the head's motion). `display`: this
// pixel's place on the display (LENS).
vec3 previous_pixel(uint eye, vec2 here, vec2 t, vec2 display, float distance, bool sky,
                    out bool moved) {
    moved = false;
    vec4 seen = sky ? vec4(t, -1.0, 0.0) : vec4(t * distance, -distance, 1.0);
    vec4 clip = c.previous_from_view[eye] * seen;
    vec2 uv = clip.xy / clip.w * 0.5 + 0.5;
    if (clip.w <= 0.0) {
        NOTE_OUTCOME(OUTCOME_OFF_SCREEN);
        return vec3(0.0, 0.0, -1.0);
    }
    vec2 at = uv;
    if (LENS) {
        vec4 p = c.periphery[eye];
        vec4 d = c.display[eye];
        vec2 tp = vec2(-p.x + uv.x * (p.x + p.y), p.z - uv.y * (p.z + p.w));
        vec2 td = distorted(tp, display);
        at = vec2((td.x + d.x) / (d.x + d.y), (d.z - td.y) / (d.z + d.w));
    }
    at *= c.screen.xy;
    ivec2 nearest = clamp(ivec2(floor(at)), ivec2(0), ivec2(c.screen.xy) - 1);
    float kind = history_texel(nearest, eye).a;
    // A luma history cannot say that it holds what the fovea showed: where it holds anything
    // and the frame before's periphery has no depth (its hole, or the sky), it is trusted as
    // the colour history trusts the fovea's (the clip's box still holds it where it moved).
    bool under_fovea = LUMA_HISTORY ? kind > 0.5 : abs(kind - FROM_FOVEA) < 0.1;
    vec2 motion = (uv - here) * vec2(textureSize(previous_depth, 0).xy); // periphery texels
    moved = dot(motion, motion) >= 0.01;
#ifdef COUNT_FRAGMENTS
    // Where the frame before's view saw this direction: a failed test there is a disocclusion.
    bool in_view = all(greaterThanEqual(uv, vec2(0.0))) && all(lessThanEqual(uv, vec2(1.0)));
#endif
    if (!seen_before(eye, uv, clip.w, sky, moved, under_fovea)) {
        NOTE_OUTCOME(in_view ? OUTCOME_DISOCCLUDED : OUTCOME_OFF_SCREEN);
        return vec3(0.0, 0.0, -1.0);
    }
    NOTE_OUTCOME(!in_view ? OUTCOME_OFF_SCREEN : (under_fovea ? OUTCOME_FROM_FOVEA : OUTCOME_KEPT));
    return vec3(at, clip.w);
}

// The history at `at` (previous output pixels), bilinear over the taps that hold something;
// w: the weight found (0: nothing usable). `mover`: a tap used holds where an instance that
// moves lay.
vec4 history_at(uint eye, vec2 at, out bool mover) {
    mover = false;
    vec2 pos = at - 0.5;
    ivec2 base = ivec2(floor(pos));
    vec2 frac = pos - floor(pos);
    vec3 sum = vec3(0.0);
    float weight = 0.0;
    for (int k = 0; k < 4; k++) {
        ivec2 o = ivec2(k & 1, k >> 1);
        ivec2 tap = base + o;
        if (any(lessThan(tap, ivec2(0))) || any(greaterThanEqual(tap, ivec2(c.screen.xy)))) {
            continue;
        }
        vec4 h = history_texel(tap, eye);
        if (h.a < 0.5 * MOVER) {
            continue;
        }
        mover = mover || abs(h.a - MOVER) < 0.1;
        vec2 w2 = mix(1.0 - frac, frac, vec2(o));
        sum += w2.x * w2.y * h.rgb * h.rgb;
        weight += w2.x * w2.y;
    }
    return vec4(weight > 0.0 ? sum / weight : vec3(0.0), weight);
}

// Catmull-Rom's weights for the taps at -1, 0, 1 and 2 texels from the one below `f`.
vec4 catmull_rom(float f) {
    float f2 = f * f;
    float f3 = f2 * f;
    return vec4(-0.5 * f3 + f2 - 0.5 * f, 1.5 * f3 - 2.5 * f2 + 1.0, -1.5 * f3 + 2.0 * f2 + 0.5 * f,
                0.5 * f3 - 0.5 * f2);
}

// The history at `at` resampled with Catmull-Rom over its 4×4 taps (Karis 2014: a bilinear
// resample every frame blurs a history whose points all move, as on a walk), held within the
// range of the 2×2 taps around `at` so its negative lobes cannot ring. `bilinear` where a tap
// holds nothing or lies past the edge: a sharper kernel there would mix what was never seen.
vec3 history_sharp(uint eye, vec2 at, vec3 bilinear) {
    vec2 pos = at - 0.5;
    ivec2 base = ivec2(floor(pos)) - 1;
    if (any(lessThan(base, ivec2(0))) || any(greaterThan(base + 3, ivec2(c.screen.xy) - 1))) {
        return bilinear;
    }
    vec4 wx = catmull_rom(pos.x - floor(pos.x));
    vec4 wy = catmull_rom(pos.y - floor(pos.y));
    vec3 sum = vec3(0.0);
    vec3 lo = vec3(1e30);
    vec3 hi = vec3(-1e30);
    for (int y = 0; y < 4; y++) {
        for (int x = 0; x < 4; x++) {
            vec4 h = history_texel(base + ivec2(x, y), eye);
            if (h.a < 0.5 * MOVER) {
                return bilinear;
            }
            vec3 linear = h.rgb * h.rgb;
            sum += wx[x] * wy[y] * linear;
            if ((x == 1 || x == 2) && (y == 1 || y == 2)) {
                lo = min(lo, linear);
                hi = max(hi, linear);
            }
        }
    }
    return clamp(sum, lo, hi);
}

// The periphery around `texel` (Salvi's variance clipping, in YCoCg): `lo`, `hi`, the
// neighbourhood's mean ± c.clip.x standard deviations, within its range; `mover`, an instance
// that moves lies in it; and, from the same reads, the weighted new sample's sum (`weighted`,
// `mass`: new_sample below).
struct Neighbourhood {
    vec3 lo;
    vec3 hi;
    bool mover;
    vec3 weighted;
    float mass;
};

// The neighbourhood's box where `box` is wanted, its weighted new sample for the pixel whose
// centre lies at `centre` where `weigh` is. Read only where either is: a loop that runs no texel
// where neither is, which a GPU and lavapipe both skip when no pixel of a group wants it
// (lavapipe runs both sides of an `if` under a mask, but ends a loop that no pixel runs). The
// weighted sample takes the 3×3 even when the box takes the cross: the box then counts only the
// cross's texels.
Neighbourhood neighbourhood(uint eye, ivec2 texel, ivec2 size, vec2 centre, bool box,
                            bool weigh) {
    Neighbourhood n = Neighbourhood(vec3(1e30), vec3(-1e30), false, vec3(0.0), 0.0);
    vec2 screen_per_texel = c.screen.xy / vec2(size);
    vec3 sum = vec3(0.0);
    vec3 squares = vec3(0.0);
    bool cross_only = CROSS_NEIGHBOURHOOD && !weigh;
    int texels = cross_only ? 5 : 9;
    for (int k = 0; k < (box || weigh ? texels : 0); k++) {
        // The cross: the texel, then its four edge neighbours (−x, +x, −y, +y); the square: row
        // by row. Computed, not read from a constant array: lavapipe indexes such an array
        // through memory, which made the five-texel cross slower than the nine-texel square.
        ivec2 offset = cross_only
            ? (k == 0 ? ivec2(0) : (k < 3 ? ivec2(2 * k - 3, 0) : ivec2(0, 2 * k - 7)))
            : ivec2(k % 3 - 1, k / 3 - 1);
        ivec2 at = texel + offset;
        vec4 fetched = texelFetch(images, ivec3(clamp(at, ivec2(0), size - 1), eye), 0);
        // A texel past the image's edge was never rendered: it adds no weight.
        if (weigh && all(greaterThanEqual(at, ivec2(0))) && all(lessThan(at, size))) {
            vec2 off = (vec2(at) + 0.5 - centre) * screen_per_texel;
            float w = exp(-2.0 * dot(off, off));
            n.weighted += w * fetched.rgb;
            n.mass += w;
        }
        if (CROSS_NEIGHBOURHOOD && offset.x != 0 && offset.y != 0) {
            continue;
        }
        n.mover = n.mover || fetched.a < MOVER_ALPHA;
        vec3 s = to_ycocg(fetched.rgb);
        sum += s;
        squares += s * s;
        n.lo = min(n.lo, s);
        n.hi = max(n.hi, s);
    }
    float count = CROSS_NEIGHBOURHOOD ? 5.0 : 9.0;
    vec3 mean = sum / count;
    vec3 spread = c.clip.x * sqrt(max(squares / count - mean * mean, vec3(0.0)));
    n.lo = max(n.lo, mean - spread);
    n.hi = min(n.hi, mean + spread);
    return n;
}

// This frame's periphery for the pixel whose centre lies at `centre` (in this frame's jittered
// texels, whose centres lie at n + 0.5), `texel` the nearest: that texel, weighted by exp(−2d²),
// d its distance from the centre in screen pixels; where WEIGHTED_NEW_SAMPLE weighed the 3×3
// texels around it so (`n`: where the point moved, from the box's own reads), their weighted
// mean (a texel past the 3×3 lies over 1.5 texels away, where the weight is 1 % or less at the
// screen's density). `mass`: the weights' sum.
vec3 new_sample(uint eye, ivec2 texel, ivec2 size, vec2 centre, Neighbourhood n,
                out float mass) {
    // Far below the screen's density every weight can round to 0: the nearest texel then.
    if (n.mass > 0.0) {
        mass = n.mass;
        return n.weighted / n.mass;
    }
    vec2 off = (vec2(texel) + 0.5 - centre) * (c.screen.xy / vec2(size));
    mass = exp(-2.0 * dot(off, off));
    return texelFetch(images, ivec3(texel, eye), 0).rgb;
}

// This frame's periphery of eye `eye` at `uv`, bilinearly at the pixel's centre (the jitter
// undone).
vec3 unjittered_periphery(uint eye, vec2 uv) {
    vec2 size = vec2(textureSize(images, 0).xy);
    return texture(images, vec3((uv * size + c.jitter.xy) / size, float(eye))).rgb;
}

// The accumulated periphery of eye `eye` at `uv` (the rendered field's) in direction `t`,
// shown at `display` (display tangents, LENS); `next` is what the history keeps of this pixel.
vec3 accumulate(uint eye, vec2 uv, vec2 t, vec2 display, out vec4 next) {
    vec4 p = c.periphery[eye];
    vec4 f = c.fovea[eye];
    vec2 fovea_centre = vec2((f.y - f.x) * 0.5, (f.z - f.w) * 0.5);
    vec2 px_per_tangent = c.screen.xy / vec2(p.x + p.y, p.z + p.w);
    ivec2 size = textureSize(images, 0).xy;
    vec2 q = uv * vec2(size);
    vec2 j = c.jitter.xy;
    vec3 bilinear = unjittered_periphery(eye, uv);
    // Inside the periphery's hole nothing was rendered: the output keeps what the fovea shows.
    if (length((t - fovea_centre) * px_per_tangent) < c.depth.z) {
        NOTE_OUTCOME(OUTCOME_HOLE);
        next = NOTHING;
        return bilinear;
    }
    ivec2 texel = clamp(ivec2(floor(q + j)), ivec2(0), size - 1);
    vec3 result = bilinear;
    float d = texelFetch(periphery_depth, ivec3(texel, eye), 0).r;
    bool sky = d <= 0.0;
    float distance = sky ? 0.0 : c.depth.y / (d + c.depth.x);
    bool moved;
    vec3 at = previous_pixel(eye, uv, t, display, distance, sky, moved);
    // Whether the history is clipped here: HistoryClip::Moved clips only where the head's
    // motion moved the point (clip.y = 2), or where an instance that moves lies or lay (the
    // reprojection follows the head alone); elsewhere the depth test alone holds it. With
    // instances that move the box is built everywhere (they are found in it); without, only
    // where it clips. The weighted new sample only where the point moved: there the box's
    // reads are made anyway, and where nothing moved the still blend's small weight hides
    // which texel is nearest.
    bool clip_on = c.clip.x >= 0.0;
    bool weigh = WEIGHTED_NEW_SAMPLE && moved;
    Neighbourhood n = neighbourhood(eye, texel, size, q + j,
                                    MARK_MOVING || (clip_on && (c.clip.y < 1.5 || moved)), weigh);
    bool mover = MARK_MOVING && n.mover; // an instance that moves lies in the neighbourhood
    bool clipped = clip_on && (c.clip.y < 1.5 || moved || mover);
    if (c.jitter.w >= 0.5) {
        NOTE_OUTCOME(OUTCOME_RESET);
    } else if (at.z > 0.0) {
        bool mover_before;
        vec4 h = history_at(eye, at.xy, mover_before);
        // Only a frame whose scene marks instances that move writes MOVER into the history, and
        // then (MARK_MOVING) the box was built everywhere: clipping switched on here has one.
        clipped = clipped || (clip_on && mover_before);
        if (HISTORY_CATMULL_ROM && moved && h.w > 0.99) {
            h.rgb = history_sharp(eye, at.xy, h.rgb);
        }
        if (LUMA_HISTORY) {
            // Its luma (grey: every channel the same), this frame's periphery's chroma.
            h.rgb = from_ycocg(vec3(h.r, to_ycocg(bilinear).yz));
        }
#ifdef COUNT_FRAGMENTS
        if (h.w <= 0.01) {
            NOTE_OUTCOME(history_outcome == OUTCOME_OFF_SCREEN ? OUTCOME_OFF_SCREEN : OUTCOME_EMPTY);
        } else {
            // Taps past the edge of the frame before's view can still hold something: used.
            NOTE_OUTCOME(history_outcome == OUTCOME_OFF_SCREEN ? OUTCOME_KEPT : history_outcome);
            vec3 y = to_ycocg(h.rgb);
            if (history_outcome == OUTCOME_KEPT && clipped && clip_to_box(y, n.lo, n.hi) != y) {
                NOTE_OUTCOME(OUTCOME_CLIPPED);
            }
        }
#endif
        if (h.w > 0.01) {
            vec3 kept = clipped ? from_ycocg(clip_to_box(to_ycocg(h.rgb), n.lo, n.hi)) : h.rgb;
            float mass;
            vec3 fresh = new_sample(eye, texel, size, q + j, n, mass);
            // Where nothing moved the history needs no quick correction: the still weight.
            float settled = moved || mover || mover_before ? c.jitter.z : c.still.x;
            float trust = max(settled, c.depth.w) * min(mass, 1.0);
            result = mix(max(kept, vec3(0.0)), fresh, trust);
        }
    }
    next = to_history(result, mover ? MOVER : 1.0);
    return result;
}

// How much of the accumulated periphery the pixel in direction `t` shows: 1 within the reach
// (TemporalConfig::within_deg), 0 beyond it, smooth across its edge. The cosine of its angle
// from the fovea's centre `gaze` (both tangents of the eye looking down −z) against c.still.y
// (the reach's) and c.still.z (where the fade starts); accumulating everywhere, both lie below −1.
float reach_weight(vec2 t, vec2 gaze) {
    float cos_angle = (dot(t, gaze) + 1.0) * inversesqrt((dot(t, t) + 1.0) * (dot(gaze, gaze) + 1.0));
    return smoothstep(c.still.y, c.still.z, cos_angle);
}

// The periphery accumulated out to the reach and each frame's own beyond it (the jitter undone):
// a pixel beyond reads no history, does none of the accumulation's work and keeps nothing, so
// one the reach later covers starts from its frame's periphery, as one the frame before did not
// see. A GPU skips the work where a whole group of pixels lies beyond the reach; lavapipe runs
// it under a mask all the same (as it does in a loop of one pass, or after a `discard`: measured,
// the pass costs as much as accumulating everywhere; docs/notebook/2026-12-03-accumulation-only-near-the-gaze.md).
vec3 accumulate_within_reach(uint eye, vec2 uv, vec2 t, vec2 display, vec2 gaze, out vec4 next) {
    if (!REACH) {
        return accumulate(eye, uv, t, display, next);
    }
    float reach = reach_weight(t, gaze);
    vec3 result = vec3(0.0);
    next = NOTHING;
    if (reach > 0.0) {
        result = accumulate(eye, uv, t, display, next);
    }
    if (reach < 1.0) {
        if (reach <= 0.0) {
            NOTE_OUTCOME(OUTCOME_BEYOND);
        }
        result = mix(unjittered_periphery(eye, uv), result, reach);
    }
    return result;
}
