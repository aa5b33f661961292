// FLIP (Andersson et al. 2020, "FLIP: A Difference Evaluator for Alternating Images", LDR) on the
// GPU, and the eccentricity-aware FLIP built on it: the declarations and colour maths the
// compute passes share (`judge/flip.rs` records them). Images are YCxCz (Y', Cx, Cz) in a
// pyramid of tent-filtered halvings; each ppd level filters at the pyramid level the judge picked.
// The coarser levels extend past the image by their filters' reach, filled with the image's
// edge as the full-resolution filters see it (clamped), so the edge weighs the same there.

layout(local_size_x = 8, local_size_y = 8) in;

layout(push_constant) uniform Params {
    ivec2 full;        // the judged images' size (reduce: the source level's, padding included)
    ivec2 size;        // the size of the level this dispatch works at (reduce: the destination's)
    int src;           // the level's reference image in the pyramid (vec4s); the test follows it
                       // (reduce: the source level's)
    int dst;           // reduce: where the level's reference image goes
    int spatialRadius; // the colour (CSF) filter's radius in level pixels
    int featureRadius; // the edge and point filters' radius in level pixels
    int spatialTaps;   // where the colour filter's taps start in `taps`
    int featureTaps;   // where the feature filters' taps start
    int level;         // the ppd level (ppd × 2^level) being judged
    float scale;       // judged pixels per level texel (2^pyramid level)
    float cmax;        // the largest colour difference (green against blue), to the power 0.7
    int pad;           // texels the level extends past the judged image on each side
    ivec2 origin;      // the first texel (or pixel) of the region this dispatch covers
    ivec2 rowsOrigin;  // the resampled rows: the first judged pixel's column, the first texel row
    ivec2 rowsSize;    // how many columns and texel rows they hold
    int srcPad;        // reduce: texels the source level extends past the image on each side
    int bins;          // histogram: bins over (0, 1], besides the one for exact zeros
    ivec4 reference;   // gather: the reference's output, as `output_texels.glsl` describes it
    ivec4 test;        // gather: the test's
} pc;

// Both images as 8-bit sRGB RGBA: the reference's pixels, then the test's (uploaded, or
// gathered from the renderers' outputs).
layout(std430, set = 0, binding = 0) buffer Inputs { uint rgba[]; } inputs;
// Every pyramid level: its reference image, then its test image, row after row.
layout(std430, set = 0, binding = 1) buffer Pyramid { vec4 texel[]; } pyramid;
// The horizontal pass's sums, four per level pixel: colour (Y, Cx, Cz's two Gaussians) of the
// reference and the test, then features (d/dx, d²/dx², Gaussian) of each. On a coarse level,
// once the fields are filtered, the fields resampled along rows to the judged pixels' columns.
layout(std430, set = 0, binding = 2) buffer Intermediate { vec4 v[]; } mid;
// The filtered fields, four per level pixel: colour (Y, Cx, Cz) of the reference and the test,
// then features (dx, dy, ddx, ddy) of each.
layout(std430, set = 0, binding = 3) buffer Fields { vec4 v[]; } fields;
// Filter taps: colour (Y, Cx, Cz first Gaussian, Cz second), feature (G, G', G'', 0).
layout(std430, set = 0, binding = 4) readonly buffer Taps { vec4 t[]; } taps;
// Each judged pixel's position among the ppd levels (log2 of its acuity scale), −1: not judged.
layout(std430, set = 0, binding = 5) readonly buffer Positions { float t[]; } positions;
// Each judged pixel's FLIP at the display's ppd and its eccentricity-aware FLIP.
layout(std430, set = 0, binding = 6) buffer Maps { vec2 v[]; } maps;
// Each judged pixel's region (0 fovea, 1 band, 2 periphery, 3 hidden), a byte each.
layout(std430, set = 0, binding = 7) readonly buffer Labels { uint l[]; } labels;
// The histograms: the plain FLIP's, then the eccentricity-aware FLIP's per region, each
// `bins` + 1 counts (exact zeros first).
layout(std430, set = 0, binding = 8) buffer Counts { uint c[]; } counts;
// Both renderers' outputs as copied (the gather pass's input): the reference's, then the test's.
layout(std430, set = 0, binding = 9) readonly buffer Frames { uint w[]; } frames;

const vec3 ILLUMINANT = vec3(0.950428545, 1.0, 1.088900371);

float srgbToLinear(float c) {
    return c <= 0.04045 ? c / 12.92 : pow((c + 0.055) / 1.055, 2.4);
}

// Linear sRGB to XYZ (D65), and back; as columns.
const mat3 RGB_TO_XYZ = mat3(
    10135552.0 / 24577794.0, 2613072.0 / 12288897.0, 1425312.0 / 73733382.0,
    8788810.0 / 24577794.0, 8788810.0 / 12288897.0, 8788810.0 / 73733382.0,
    4435075.0 / 24577794.0, 887015.0 / 12288897.0, 70074185.0 / 73733382.0);
const mat3 XYZ_TO_RGB = mat3(
    3.241003275, -0.969224334, 0.055639423,
    -1.537398934, 1.875930071, -0.204011202,
    -0.498615861, 0.041554224, 1.057148933);

vec3 srgbToYCxCz(vec4 srgb) {
    vec3 linear = vec3(srgbToLinear(srgb.r), srgbToLinear(srgb.g), srgbToLinear(srgb.b));
    vec3 xyz = (RGB_TO_XYZ * linear) / ILLUMINANT;
    return vec3(116.0 * xyz.y - 16.0, 500.0 * (xyz.x - xyz.y), 200.0 * (xyz.y - xyz.z));
}

float labCurve(float t) {
    const float delta = 6.0 / 29.0;
    return t > delta * delta * delta ? pow(t, 1.0 / 3.0) : t / (3.0 * delta * delta) + 4.0 / 29.0;
}

// A filtered YCxCz colour as FLIP compares it: clamped to the displayable range in linear RGB,
// then CIELAB with the Hunt adjustment (chroma scaled by lightness).
vec3 huntLab(vec3 ycxcz) {
    float y = (ycxcz.x + 16.0) / 116.0;
    vec3 xyz = vec3(y + ycxcz.y / 500.0, y, y - ycxcz.z / 200.0) * ILLUMINANT;
    vec3 rgb = clamp(XYZ_TO_RGB * xyz, 0.0, 1.0);
    vec3 n = (RGB_TO_XYZ * rgb) / ILLUMINANT;
    vec3 f = vec3(labCurve(n.x), labCurve(n.y), labCurve(n.z));
    float l = 116.0 * f.y - 16.0;
    return vec3(l, 0.01 * l * 500.0 * (f.x - f.y), 0.01 * l * 200.0 * (f.y - f.z));
}

// FLIP's error from the filtered colours and features of the reference and the test.
float flipError(vec3 colourRef, vec3 colourTest, vec4 featRef, vec4 featTest) {
    vec3 a = huntLab(colourRef);
    vec3 b = huntLab(colourTest);
    // HyAB: city-block in lightness, Euclidean in chroma; then FLIP's compression and remap.
    float colour = pow(abs(a.x - b.x) + length(a.yz - b.yz), 0.7);
    const float pc_ = 0.4;
    const float pt = 0.95;
    float knee = pc_ * pc.cmax;
    colour = colour < knee ? colour * pt / knee
                           : pt + (colour - knee) / (pc.cmax - knee) * (1.0 - pt);
    float edge = abs(length(featRef.xy) - length(featTest.xy));
    float point = abs(length(featRef.zw) - length(featTest.zw));
    float feature = pow(max(edge, point) / sqrt(2.0), 0.5);
    float exponent = 1.0 - feature;
    if (colour <= 0.0) {
        return exponent == 0.0 ? 1.0 : 0.0;
    }
    return pow(colour, exponent);
}

// Catmull-Rom weights of the four texels around a sample at fraction f past the second.
vec4 catmullRom(float f) {
    float f2 = f * f;
    float f3 = f2 * f;
    return vec4(-0.5 * f3 + f2 - 0.5 * f, 1.5 * f3 - 2.5 * f2 + 1.0,
                -1.5 * f3 + 2.0 * f2 + 0.5 * f, 0.5 * f3 - 0.5 * f2);
}

// Where judged pixel `p` lies on the level's texel grid.
vec2 levelCoordinate(vec2 p) {
    return (p + 0.5) / pc.scale + float(pc.pad) - 0.5;
}

// Whether judged pixel `p` takes a share of ppd level `pc.level`, and its weight: a hat in log
// ppd around the pixel's own level. Level 0 writes the plain FLIP for every judged pixel (and
// NaN in both maps for a pixel the lens hides).
bool takesShare(ivec2 p, out float weight) {
    int i = p.y * pc.full.x + p.x;
    float t = positions.t[i];
    weight = 0.0;
    if (t < 0.0) {
        if (pc.level == 0) {
            maps.v[i] = vec2(uintBitsToFloat(0x7fc00000u));
        }
        return false;
    }
    weight = max(0.0, 1.0 - abs(t - float(pc.level)));
    return pc.level == 0 || weight > 0.0;
}

// Adds pixel `p`'s share of level `pc.level`'s error `e`: level 0 writes the plain FLIP and
// starts the eccentricity-aware sum, every other level adds to it.
void addError(ivec2 p, float weight, float e) {
    int i = p.y * pc.full.x + p.x;
    if (pc.level == 0) {
        maps.v[i] = vec2(e, weight * e);
    } else {
        maps.v[i].y += weight * e;
    }
}
