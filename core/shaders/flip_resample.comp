#version 450
// The first half of the Catmull-Rom resampling of a coarse level's fields at the judged pixels:
// along rows, to each judged pixel's column, for every texel row the pixels' columns need. The
// combine pass finishes it along columns: 4 reads per field and pixel there and 4 per field and
// resampled texel here, instead of the 16 per field and pixel of the 4×4 texels at once.
#include "flip_common.glsl"

void main() {
    ivec2 g = ivec2(gl_GlobalInvocationID.xy);
    if (any(greaterThanEqual(g, pc.rowsSize))) {
        return;
    }
    int row = clamp(pc.rowsOrigin.y + g.y, 0, pc.size.y - 1);
    float u = levelCoordinate(vec2(float(pc.rowsOrigin.x + g.x), 0.0)).x;
    int q = int(floor(u));
    vec4 w = catmullRom(u - float(q));
    int out_ = 4 * (g.y * pc.rowsSize.x + g.x);
    for (int k = 0; k < 4; k++) {
        vec4 sum = vec4(0.0);
        for (int i = 0; i < 4; i++) {
            int x = clamp(q + i - 1, 0, pc.size.x - 1);
            sum += w[i] * fields.v[4 * (row * pc.size.x + x) + k];
        }
        mid.v[out_ + k] = sum;
    }
}
