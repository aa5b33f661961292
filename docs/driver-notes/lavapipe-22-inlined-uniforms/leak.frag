#version 450
// One fragment shader, built once per candidate (glslc -D): what bounds its loop over four
// "lights", and what else it does. leak.c draws a full-view triangle with it every frame.
layout(location = 0) out vec4 color;

layout(set = 0, binding = 0) uniform Lights {
    vec4 lights[4];
    uvec4 count;
} u;
layout(std430, set = 0, binding = 1) readonly buffer Counts {
    uvec4 count;
} s;
layout(push_constant) uniform Push {
    uvec4 count;
} p;
layout(constant_id = 0) const uint COUNT = 4;
#ifdef TEXTURES
layout(set = 0, binding = 2) uniform sampler2DArray tex;
#endif

// A light's specular and diffuse share (GGX, Schlick): enough arithmetic for lavapipe to look
// for uniforms to inline (it skips shaders of 100 SSA values or fewer).
vec3 light(vec3 n, vec4 l) {
    vec3 v = vec3(0.0, 0.0, 1.0);
    vec3 h = normalize(v + normalize(l.xyz));
    float nl = max(dot(n, normalize(l.xyz)), 0.0);
    float nh = max(dot(n, h), 0.0);
    float a2 = pow(0.5 + 0.4 * l.w, 4.0);
    float d = nh * nh * (a2 - 1.0) + 1.0;
    float fresnel = 0.04 + 0.96 * pow(1.0 - max(dot(v, h), 0.0), 5.0);
    return l.rgb * nl * (0.3 + fresnel * a2 / (3.14159265 * d * d));
}

void main() {
#if defined(UNIFORM_LOOP)
    uint n = u.count.x;
#elif defined(PUSH_LOOP)
    uint n = p.count.x;
#elif defined(STORAGE_LOOP)
    uint n = s.count.x;
#else
    uint n = COUNT;
#endif
    vec3 c = vec3(0.0);
    vec3 normal = normalize(vec3(gl_FragCoord.xy / 64.0 - 0.5, 1.0));
    for (uint i = 0u; i < n; i++) {
        c += light(normal, u.lights[i]);
    }
#ifdef UNIFORM_IF
    if (u.count.y > 2u) {
        c *= 0.5;
    }
#endif
#ifdef TEXTURES
    vec2 uv = gl_FragCoord.xy / 64.0;
    c += textureGrad(tex, vec3(uv, 1.0), vec2(0.01, 0.0), vec2(0.0, 0.01)).rgb;
#endif
    color = vec4(c, 1.0);
}
