// Lit materials: PBR metallic-roughness (GGX distribution, Smith-Schlick visibility, Schlick
// Fresnel) with base colour, normal and occlusion-roughness-metallic textures — one layer of
// each array per material, full mip chains, trilinear or anisotropic — lit by the sun, up to
// four point lights and a hemispherical sky. Only lit scenes' pipelines include it.

// The periphery's specular prefilter: a view rendered coarser than the screen widens each
// highlight by the spread of the normals its coarser footprint averages beyond the screen's
// pixels' (`prefiltered_roughness`). Off, none of it is compiled.
layout(constant_id = 41) const bool PERIPHERY_PREFILTER = false;

// The scene's point lights (`FramePlan::point_lights`), fixed when the pipeline is compiled. Not
// a count in `Lighting`: a loop bounded by a uniform buffer's value makes lavapipe before Mesa 25
// inline the value and compile the shader anew each time a descriptor set is bound, and it
// never frees those shaders (about 2.6 MB a lit pass; docs/driver-notes).
layout(constant_id = 43) const uint POINT_LIGHTS = 0;

layout(set = 0, binding = 5) uniform sampler2DArray base_color_tex;
layout(set = 0, binding = 6) uniform sampler2DArray normal_tex;
layout(set = 0, binding = 7) uniform sampler2DArray orm_tex;

struct Material {
    vec4 base_color; // rgb factor
    vec4 params;     // metallic, roughness, world-space repeats per metre (0: mesh UVs),
                     // alpha cutoff over the alpha factor (alpha-masked builds only)
};
layout(std430, set = 0, binding = 8) readonly buffer Materials {
    Material materials[];
};

layout(std140, set = 0, binding = 9) uniform Lighting {
    vec4 sun_color;      // rgb
    vec4 sky_color;      // rgb, from above
    vec4 ground_color;   // rgb, from below
    vec4 point_pos[4];   // xyz, w: range
    vec4 point_color[4]; // rgb; the first POINT_LIGHTS are the scene's
} lighting;

const float PI = 3.14159265359;

// The surface's texture coordinates, their change per pixel in x and y, and its tangent frame
// (columns T, B, N). World mapping textures each face along its dominant axis, its frame
// axis-aligned, and its texture gradients are analytic: the pixel's footprint on the surface's
// plane from the view's ray and per-pixel ray steps (`dp_ray`), with no screen-space
// derivative — lavapipe's derivatives are garbage along triangle edges (the coarsest mip shows
// as a bright seam). Mesh UVs take gradients from screen-space derivatives, and their frame
// from the vertex tangent (`tangent.w`: the bitangent's sign; 0: none) or, without one, from
// derivatives too.
mat3 surface_frame(vec3 n, vec4 tangent, vec3 world, vec2 mesh_uv, float repeats, vec3 ray,
                   float depth, vec3 ray_dx, vec3 ray_dy, out vec2 uv, out vec2 duv_dx,
                   out vec2 duv_dy) {
    if (repeats > 0.0) {
        vec3 a = abs(n);
        vec3 s = sign(n);
        vec3 t;
        vec3 b;
        if (a.x >= a.y && a.x >= a.z) {
            uv = vec2(-s.x * world.z, -world.y);
            t = vec3(0.0, 0.0, -s.x);
            b = vec3(0.0, -1.0, 0.0);
        } else if (a.y >= a.z) {
            uv = vec2(world.x, s.y * world.z);
            t = vec3(1.0, 0.0, 0.0);
            b = vec3(0.0, 0.0, s.y);
        } else {
            uv = vec2(s.z * world.x, -world.y);
            t = vec3(s.z, 0.0, 0.0);
            b = vec3(0.0, -1.0, 0.0);
        }
        uv *= repeats;
        float facing = dot(n, ray);
        facing = sign(facing) * max(abs(facing), 1e-3);
        vec3 dp_dx = depth * (ray_dx - dot(n, ray_dx) / facing * ray);
        vec3 dp_dy = depth * (ray_dy - dot(n, ray_dy) / facing * ray);
        duv_dx = repeats * vec2(dot(dp_dx, t), dot(dp_dx, b));
        duv_dy = repeats * vec2(dot(dp_dy, t), dot(dp_dy, b));
        return mat3(t, b, n);
    }
    uv = mesh_uv;
    duv_dx = dFdx(uv);
    duv_dy = dFdy(uv);
    if (tangent.w != 0.0) {
        vec3 t = tangent.xyz - n * dot(n, tangent.xyz);
        t *= inversesqrt(max(dot(t, t), 1e-20));
        return mat3(t, cross(n, t) * sign(tangent.w), n);
    }
    vec3 dp1 = dFdx(world);
    vec3 dp2 = dFdy(world);
    vec2 duv1 = dFdx(uv);
    vec2 duv2 = dFdy(uv);
    vec3 dp2perp = cross(dp2, n);
    vec3 dp1perp = cross(n, dp1);
    vec3 t = dp2perp * duv1.x + dp1perp * duv2.x;
    vec3 b = dp2perp * duv1.y + dp1perp * duv2.y;
    float scale = inversesqrt(max(max(dot(t, t), dot(b, b)), 1e-20));
    return mat3(t * scale, b * scale, n);
}

// Specular anti-aliasing (Toksvig 2005, "Mipmapping Normal Maps"): a minified normal map
// averages normals that point apart, and one point-sampled highlight then stands for a footprint
// whose highlights do not line up — it flickers as the footprint moves. The normal map's alpha
// keeps the length of the mean normal under the texel (`scene::textures`); 1 − len over len is
// the variance of the normals' slopes, and a GGX lobe of roughness α has a slope variance of
// about α² / 2, so the two add as α² + 2σ² (Toksvig's widened Blinn-Phong exponent, 1/s' = 1/s
// + σ², in α's terms).
float widened_roughness(float roughness, float mean_normal_length) {
    float len = max(mean_normal_length, 1.0 / 255.0);
    float variance = (1.0 - len) / len;
    float alpha2 = min(roughness * roughness * roughness * roughness + 2.0 * variance, 1.0);
    return sqrt(sqrt(alpha2));
}

// A pixel of a view `coarser` times the screen's pixel (per axis) should show what the
// screen's pixels under it show, averaged: the mean of highlights lit by the screen's normals,
// not one highlight lit by their mean. The normals the screen's footprint averages are already
// in the screen's look, so only the spread between them widens the lobe: the mean normal's
// length at the view's footprint over its length at the screen's (each texel's children about
// equally long). At the screen's density the two fetches agree and nothing changes.
float prefiltered_roughness(float roughness, float view_length, vec3 uvw, vec2 gx, vec2 gy,
                            float coarser) {
    float screen_length = textureGrad(normal_tex, uvw, gx / coarser, gy / coarser).a;
    return widened_roughness(roughness, min(view_length / max(screen_length, 1.0 / 255.0), 1.0));
}

// One light's contribution: radiance `light` arriving from direction `l`.
vec3 brdf(vec3 n, vec3 v, vec3 l, vec3 light, vec3 albedo, float metallic, float roughness) {
    float nl = max(dot(n, l), 0.0);
    if (nl <= 0.0) {
        return vec3(0.0);
    }
    vec3 h = normalize(v + l);
    float nv = max(dot(n, v), 1e-4);
    float nh = max(dot(n, h), 0.0);
    float vh = max(dot(v, h), 0.0);
    float alpha = roughness * roughness;
    float a2 = alpha * alpha;
    float d = nh * nh * (a2 - 1.0) + 1.0;
    float distribution = a2 / (PI * d * d);
    float k = (roughness + 1.0) * (roughness + 1.0) / 8.0;
    float visibility = 0.25 / ((nv * (1.0 - k) + k) * (nl * (1.0 - k) + k));
    vec3 f0 = mix(vec3(0.04), albedo, metallic);
    vec3 fresnel = f0 + (1.0 - f0) * pow(1.0 - vh, 5.0);
    vec3 diffuse = (1.0 - fresnel) * (1.0 - metallic) * albedo / PI;
    return (diffuse + fresnel * distribution * visibility) * light * nl;
}

// `eye`: the view's eye; `depth`: the fragment's view depth; `ray_dx`, `ray_dy`: how the view
// ray at unit depth moves per pixel (world space); `coarser`: how many of the screen's pixels
// (per axis) the view's texture footprint spans. Alpha: the base colour texture's.
vec4 shade_lit(vec3 n, vec4 tangent, vec3 world, vec2 mesh_uv, uint material, vec3 tint,
               vec3 eye, float depth, vec3 ray_dx, vec3 ray_dy, float coarser, vec3 sun_dir) {
    Material m = materials[material];
    float layer = float(material);
    vec2 uv;
    vec2 gx;
    vec2 gy;
    vec3 ray = (world - eye) / depth;
    mat3 frame = surface_frame(n, tangent, world, mesh_uv, m.params.z, ray, depth, ray_dx,
                               ray_dy, uv, gx, gy);
    vec4 base = textureGrad(base_color_tex, vec3(uv, layer), gx, gy);
    vec3 albedo = base.rgb * m.base_color.rgb * tint;
    vec3 orm = textureGrad(orm_tex, vec3(uv, layer), gx, gy).rgb;
    vec4 normal_texel = textureGrad(normal_tex, vec3(uv, layer), gx, gy);
    vec3 bump = normal_texel.xyz * 2.0 - 1.0;
    vec3 normal = normalize(frame * bump);
    float roughness = clamp(orm.g * m.params.y, 0.04, 1.0);
    if (PERIPHERY_PREFILTER && coarser > 1.0) {
        roughness = prefiltered_roughness(roughness, normal_texel.a, vec3(uv, layer), gx, gy,
                                          coarser);
    }
    float metallic = clamp(orm.b * m.params.x, 0.0, 1.0);
    vec3 v = normalize(eye - world);

    vec3 color = brdf(normal, v, -sun_dir, lighting.sun_color.rgb, albedo, metallic, roughness);
    for (uint i = 0u; i < POINT_LIGHTS; i++) {
        vec3 to_light = lighting.point_pos[i].xyz - world;
        float dist2 = max(dot(to_light, to_light), 1e-4);
        float range = lighting.point_pos[i].w;
        // Inverse square, windowed to reach zero at the light's range.
        float window = clamp(1.0 - dist2 * dist2 / (range * range * range * range), 0.0, 1.0);
        vec3 radiance = lighting.point_color[i].rgb * window * window / dist2;
        color += brdf(normal, v, to_light * inversesqrt(dist2), radiance, albedo, metallic,
                      roughness);
    }
    vec3 sky = mix(lighting.ground_color.rgb, lighting.sky_color.rgb, 0.5 + 0.5 * normal.y);
    color += sky * albedo * (1.0 - 0.7 * metallic) * orm.r;
    // A gentle shoulder instead of hard clipping at 1.
    return vec4(color / (1.0 + 0.15 * max(max(color.r, color.g), color.b)), base.a);
}
