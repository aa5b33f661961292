// Radial density masking (Preißner 2020 §4.4.2, after Vlachos, GDC 2016): in the periphery, 2x2
// pixel quads are skipped with a density that falls with the distance from the lens centre —
// none inside INNER, every other quad (a checkerboard) out to OUTER, three quads in four beyond.
// Distances are in units of the lens ellipse's radii (1 = the lens edge). The plan fixes every
// parameter, so they are specialisation constants.
layout(constant_id = 10) const float VIEW_WIDTH = 1.0;
layout(constant_id = 11) const float VIEW_HEIGHT = 1.0;
layout(constant_id = 12) const float INNER = 0.5;
layout(constant_id = 13) const float OUTER = 0.8;
// Each eye's lens ellipse in NDC: centre x, y; radius x, y.
layout(constant_id = 14) const float LEFT_CX = 0.0;
layout(constant_id = 15) const float LEFT_CY = 0.0;
layout(constant_id = 16) const float LEFT_RX = 1.0;
layout(constant_id = 17) const float LEFT_RY = 1.0;
layout(constant_id = 18) const float RIGHT_CX = 0.0;
layout(constant_id = 19) const float RIGHT_CY = 0.0;
layout(constant_id = 20) const float RIGHT_RX = 1.0;
layout(constant_id = 21) const float RIGHT_RY = 1.0;

// Whether the quad holding pixel `p` of eye `eye` is skipped.
bool quad_skipped(ivec2 quad, uint eye) {
    vec4 lens = eye == 0u ? vec4(LEFT_CX, LEFT_CY, LEFT_RX, LEFT_RY)
                          : vec4(RIGHT_CX, RIGHT_CY, RIGHT_RX, RIGHT_RY);
    vec2 centre = (vec2(quad * 2) + 1.0) / vec2(VIEW_WIDTH, VIEW_HEIGHT) * 2.0 - 1.0;
    float r = length((centre - lens.xy) / lens.zw);
    if (r < INNER) {
        return false;
    }
    if (r < OUTER) {
        return ((quad.x + quad.y) & 1) == 1;
    }
    return (quad.x & 1) != 0 || (quad.y & 1) != 0;
}
