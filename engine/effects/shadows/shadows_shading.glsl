// Shadow-map lookups shared by the forward and deferred lighting (included by
// shaders/lighting/shading.glsl through the registry: hook light_visibility; shadow_views.hpp
// builds the views). All maps are square tiles of the layers of one depth array (the shadow
// atlas: a full-resolution view fills a layer, a smaller one shares it), reversed-Z (1 near the
// light, 0 far):
// directional lights have one orthographic view per cascade, spot lights one perspective view,
// point lights and area-light pieces six 90-degree views (+X, -X, +Y, -Y, +Z, -Z).
// Biases are in shadow-map texels converted to world units at the receiver, so they hold at any
// scene scale: a normal offset (receiver moved along its normal) and a depth bias (reference moved
// towards the light); the caster side adds slope-scaled polygon offset.

#include "effects/shadows/shadows_data.h"

layout(std430, binding = SHADOW_VIEWS_BINDING) readonly buffer ShadowViews { ShadowView shadow_views[]; };
layout(binding = SHADOW_UNIT) uniform sampler2DArrayShadow t_shadow;  // GEQUAL compare, linear: 2x2 PCF
layout(binding = SHADOW_DEPTH_UNIT) uniform sampler2DArray t_shadow_depth;  // raw depths for the blocker search

const int SHADOW_OFF = 0, SHADOW_HARD = 1, SHADOW_PCF = 2, SHADOW_PCSS = 3;

// Which of a light's views covers p.
int shadow_view_index(LightData light, vec3 p) {
    int first = int(light.first_shadow_view);
    int count = int(light.shadow_view_count);
    if (count == 6) {
        vec3 d = p - light.position;
        vec3 a = abs(d);
        if (a.x >= a.y && a.x >= a.z) return first + (d.x >= 0.0 ? 0 : 1);
        if (a.y >= a.z) return first + (d.y >= 0.0 ? 2 : 3);
        return first + (d.z >= 0.0 ? 4 : 5);
    }
    if (count > 1) {  // cascades, by view depth
        float depth = -(frame.view * vec4(p, 1.0)).z;
        for (int c = 0; c < count - 1; ++c)
            if (depth <= shadow_views[first + c].cascade_end) return first + c;
        return first + count - 1;
    }
    return first;
}

// Interleaved gradient noise (Jimenez 2014): a per-pixel rotation of the tap pattern.
float shadow_noise(vec2 pixel) { return fract(52.9829189 * fract(dot(pixel, vec2(0.06711056, 0.00583715)))); }

// The PCSS taps lie on a Vogel (golden angle) disk: tap i of n at radius sqrt((i + 0.5) / n) and
// angle i * 2.39996323 + phi, phi a per-pixel rotation.

// Distance from the light plane (ortho) or point (perspective) of a stored depth.
float shadow_linear_depth(ShadowView sv, float d) {
    return sv.kind < 0.5 ? (1.0 - d) * sv.depth_range : sv.depth_range / max(d, 1e-30);
}

// Fraction of the light reaching p (1 lit, 0 shadowed). n: the shading normal, l: towards the light.
float shadows_light_visibility(LightData light, vec3 p, vec3 n, vec3 l, vec2 pixel) {
    // SHADOW_FILTER_MODE: the mode as a constant (the forward program's variant, pass_env.cpp),
    // so only its code is compiled; llvmpipe would run the other modes' code masked.
#ifdef SHADOW_FILTER_MODE
    const int mode = SHADOW_FILTER_MODE;
#else
    int mode = shadows.filter_mode;
#endif
    if (mode == SHADOW_OFF || light.shadow_view_count < 0.5) return 1.0;
    ShadowView sv = shadow_views[shadow_view_index(light, p)];
    bool ortho = sv.kind < 0.5;
    vec4 c0 = sv.view_proj * vec4(p, 1.0);
    float texel_world = ortho ? sv.texel_size : sv.texel_size * max(c0.w, 0.0);
    // Normal offset: more where the light grazes the surface.
    float NdotL = saturate(dot(n, l));
    vec3 q = p + n * (shadows.normal_bias * texel_world * (1.0 - NdotL * NdotL));
    vec4 c = sv.view_proj * vec4(q, 1.0);
    if (c.w <= 0.0) return 1.0;
    vec3 ndc = c.xyz / c.w;
    vec2 uv = ndc.xy * 0.5 + 0.5;
    if (any(lessThan(uv, vec2(0.0))) || any(greaterThan(uv, vec2(1.0)))) return 1.0;
    // Depth bias towards the light, converted to the map's depth units at this distance. A filter
    // tap r texels away compares against a receiver that, if the surface is tilted against the
    // light, lies deeper by r * tan(theta) texels: the bias grows with the kernel's radius so that
    // wide kernels do not shadow the receiver with itself.
    float tan_theta = min(sqrt(max(1.0 - NdotL * NdotL, 0.0)) / max(NdotL, 0.1), 10.0);
    float depth_per_world = ortho ? 1.0 / sv.depth_range : sv.depth_range / (c.w * c.w);
    float ref0 = ndc.z + shadows.depth_bias * texel_world * depth_per_world;
    float slope_per_texel = shadows.receiver_slope_bias * tan_theta * texel_world * depth_per_world;
    if (ref0 >= 1.0) return 1.0;  // nearer to the light than anything in the map
    float layer = sv.layer;
    float res = shadows.resolution;
    vec2 texel_uv = vec2(1.0 / res);
    // Into the atlas: taps stay half a texel inside the tile, so that the 2x2 filter never reads
    // a neighbouring tile (at full resolution this is what clamping to the layer's edge gives).
    vec2 tile_lo = vec2(sv.tile_u, sv.tile_v);
    vec2 tap_lo = tile_lo + 0.5 * texel_uv, tap_hi = tile_lo + vec2(sv.tile_scale) - 0.5 * texel_uv;
    uv = tile_lo + uv * sv.tile_scale;

    if (mode == SHADOW_HARD) return texture(t_shadow, vec4(clamp(uv, tap_lo, tap_hi), layer, ref0 + slope_per_texel));
    if (mode == SHADOW_PCF) {
        // size x size taps one texel apart, centred (half-texel offsets for an even size).
        int size = shadows.pcf_size;
        float h = 0.5 * float(size - 1);
        float ref = ref0 + slope_per_texel * (h + 1.0);
        float sum = 0.0;
        for (int y = 0; y < size; ++y)
            for (int x = 0; x < size; ++x) sum += texture(t_shadow, vec4(clamp(uv + (vec2(x, y) - h) * texel_uv, tap_lo, tap_hi), layer, ref));
        return sum / float(size * size);
    }
    // PCSS (Fernando 2005): blocker search, penumbra estimate, variable-size PCF.
    float light_size = sv.light_size;
    float max_radius = shadows.max_radius;
    float z_receiver = shadow_linear_depth(sv, ndc.z);
    float phi = 2.0 * PI * shadow_noise(pixel);
    float search_texels;
    if (ortho) {
        search_texels = 0.5 * light_size * z_receiver / texel_world;
    } else {
        float near = sv.depth_range;
        search_texels = 0.5 * light_size * (z_receiver - near) / (z_receiver * near) / sv.texel_size;
    }
    search_texels = clamp(search_texels, 1.0, max_radius);
    int blocker_taps = shadows.blocker_taps;
    float blocker_sum = 0.0;
    int blockers = 0;
    float ref = ref0 + slope_per_texel * (search_texels + 1.0);
    // The Vogel disk's angles step by the golden angle: each tap's direction is the last one
    // turned by it (vogel_disk without a sine and cosine per tap).
    const vec2 golden_turn = vec2(cos(2.39996323), sin(2.39996323));
    vec2 dir = vec2(cos(phi), sin(phi));
    for (int i = 0; i < blocker_taps; ++i) {
        vec2 o = sqrt((float(i) + 0.5) / float(blocker_taps)) * dir * search_texels * texel_uv;
        dir = vec2(dir.x * golden_turn.x - dir.y * golden_turn.y, dir.y * golden_turn.x + dir.x * golden_turn.y);
        float d = textureLod(t_shadow_depth, vec3(clamp(uv + o, tap_lo, tap_hi), layer), 0.0).r;
        if (d > ref) {
            blocker_sum += shadow_linear_depth(sv, d);
            ++blockers;
        }
    }
    if (blockers == 0) return 1.0;
    float z_blocker = blocker_sum / float(blockers);
    float penumbra_world = ortho ? (z_receiver - z_blocker) * light_size
                                 : light_size * (z_receiver - z_blocker) / max(z_blocker, 1e-30);
    float radius = clamp(0.5 * penumbra_world / texel_world, 1.0, max_radius);
    ref = ref0 + slope_per_texel * (radius + 1.0);
    int taps = shadows.pcss_taps;
    float sum = 0.0;
    dir = vec2(cos(phi), sin(phi));
    for (int i = 0; i < taps; ++i) {
        vec2 o = sqrt((float(i) + 0.5) / float(taps)) * dir * radius * texel_uv;
        dir = vec2(dir.x * golden_turn.x - dir.y * golden_turn.y, dir.y * golden_turn.x + dir.x * golden_turn.y);
        sum += texture(t_shadow, vec4(clamp(uv + o, tap_lo, tap_hi), layer, ref));
    }
    return sum / float(taps);
}
