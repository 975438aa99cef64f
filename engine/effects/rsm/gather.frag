#version 450 core
// RSM indirect light (Dachsbacher & Stamminger 2005): each pixel gathers rsm.samples texels of
// every light's reflective shadow map around its own projection into it, in the paper's polar
// pattern (denser near the centre: r = radius * xi1). Each texel is a small Lambertian emitter of
// flux phi: irradiance phi / pi * cos_p * cos_x / d^2. The weights are the pattern's exact
// inverse density (2 pi radius^2 xi1 texels), so the sum estimates all texels within the radius.
// Output: the one-bounce irradiance E at the pixel (rgb) and its view depth (a); the lighting
// upsamples it geometry-aware and adds albedo / pi * E. Nothing
// tests visibility between the texel and the pixel: RSM's known missing occlusion.
#include "common/scene_data.glsl"
#include "lighting/gbuffer.glsl"
#include "effects/rsm/rsm_data.h"

layout(binding = RSM_DEPTH_UNIT) uniform sampler2D t_depth;    // full resolution, reversed-Z
layout(binding = RSM_NORMALS_UNIT) uniform sampler2D t_normals;  // xy: octahedral normal
layout(binding = RSM_POSITION_UNIT) uniform sampler2DArray t_rsm_position;
layout(binding = RSM_NORMAL_UNIT) uniform sampler2DArray t_rsm_normal;
layout(binding = RSM_FLUX_UNIT) uniform sampler2DArray t_rsm_flux;

layout(std430, binding = RSM_VIEWS_BINDING) readonly buffer RsmViews { RsmView rsm_views[]; };  // per layer
layout(location = 0) uniform int u_lights;       // RSM lights: rsm_views[first layer of each]
layout(location = 1) uniform ivec4 u_rsm;        // x resolution, y samples, z downscale
layout(location = 2) uniform float u_radius;     // sampling radius, fraction of the map width
layout(location = 3) uniform int u_light_first[8];

layout(location = 0) out vec4 out_irradiance;

float gather_noise(vec2 pixel) { return fract(52.9829189 * fract(dot(pixel, vec2(0.06711056, 0.00583715)))); }

// Uniform numbers per pixel independent of gather_noise (an integer hash, "lowbias32" by
// C. Wellons): the cube gather's layer rotation. Interleaved gradient noise is linear in the
// pixel, so a rotation drawn from it would correlate with the sequence shift (which layer a
// sample takes with where it lands in it), which biased the sum by up to 20 %.
uint hash32(uint x) {
    x ^= x >> 16;
    x *= 0x7feb352du;
    x ^= x >> 15;
    x *= 0x846ca68bu;
    x ^= x >> 16;
    return x;
}
vec3 pixel_random(uvec2 pixel) {
    uint h = hash32(pixel.x ^ hash32(pixel.y + 0x9e3779b9u));
    uint h2 = hash32(h), h3 = hash32(h2);
    return vec3(uvec3(h, h2, h3) >> 8) / 16777216.0;
}

void main() {
    ivec2 size = textureSize(t_depth, 0);
    ivec2 full = min(ivec2(gl_FragCoord.xy) * u_rsm.z, size - 1);
    float depth = texelFetch(t_depth, full, 0).r;
    if (depth <= 0.0) {
        out_irradiance = vec4(0.0, 0.0, 0.0, -6.0e4);  // no surface: (almost) never blended into one
        return;
    }
    vec4 pw = frame.inv_view_proj * vec4((vec2(full) + 0.5) / vec2(size) * 2.0 - 1.0, depth, 1.0);
    vec3 p = pw.xyz / pw.w;
    vec3 n = oct_decode(texelFetch(t_normals, full, 0).xy);
    float res = float(u_rsm.x);
    int samples = u_rsm.y;
    float phi0 = 6.28318531 * gather_noise(gl_FragCoord.xy);
    vec3 E = vec3(0.0);
    for (int li = 0; li < u_lights; ++li) {
        int first = u_light_first[li];
        RsmView v0 = rsm_views[first];
        // One view (directional, spot): the paper's pattern around the pixel's projection. Cube
        // faces (a point light; an area light: the faces of its pieces that it emits into): the
        // bounce light comes from every face, so the samples are spread uniformly over all the
        // light's layers, weighted layers res^2 / n.
        int count = int(v0.layer_count);
        bool cube = v0.face_half_width > 0.0;
        vec2 centre = vec2(0.5);
        if (!cube) {
            vec4 c = rsm_views[first].view_proj * vec4(p, 1.0);
            if (c.w <= 0.0) continue;
            centre = c.xy / c.w * 0.5 + 0.5;
        }
        float weight = cube ? float(count) * res * res / float(samples) : 2.0 * PI * u_radius * u_radius * res * res / float(samples);
        // Sample i takes layer i % count: with at least as many samples as layers each layer
        // gets n_k of them and weight res^2 / n_k (stratified, exact). With fewer, a random
        // (per-pixel hash) rotation picks which layers; every layer is still reached over
        // pixels, with weight count res^2 / n.
        int per_layer = samples / count, extra = samples % count;
        int rotate = 0;
        if (cube && per_layer == 0) rotate = min(int(pixel_random(uvec2(gl_FragCoord.xy)).x * float(count)), count - 1);
        for (int i = 0; i < samples; ++i) {
            vec2 uv;
            float w = weight;
            int layer = first;
            if (cube) {
                // Each layer walks an R2 sequence (index i / count), shifted per pixel and per piece
                // (six faces each): the faces of two pieces that look the same way do not sample the
                // same texels. Not per face: an offset per face lined the samples up with the pixel
                // shift and gave fireflies (bench accuracy: 64 samples worse than 16 on cornell_point).
                int k = (i + rotate) % count;
                layer = first + k;
                if (per_layer > 0) w = res * res / float(per_layer + (k < extra ? 1 : 0));
                float j = float(i / count);
                uv = fract(vec2(0.5 + j * 0.7548776662, 0.5 + j * 0.5698402910) + vec2(phi0 * 0.15915494, gather_noise(gl_FragCoord.yx)) +
                           float(k / 6) * vec2(0.4142135624, 0.7320508076));
                // The guard band belongs to the neighbouring face: counting it here too would
                // add its light twice. (Same weight: the estimate sums the faces' 90-degree parts.)
                if (any(greaterThan(abs(uv * 2.0 - 1.0), vec2(1.0 / v0.face_half_width)))) continue;
            } else {
                // Stratified polar pattern: xi1 from the sample index, xi2 a golden-angle spiral.
                float xi1 = (float(i) + 0.5) / float(samples);
                float angle = float(i) * 2.39996323 + phi0;
                uv = centre + u_radius * xi1 * vec2(cos(angle), sin(angle));
                w *= xi1;
            }
            if (any(lessThan(uv, vec2(0.0))) || any(greaterThan(uv, vec2(1.0)))) continue;
            vec3 tc = vec3(uv, float(layer));
            vec4 xp = textureLod(t_rsm_position, tc, 0.0);
            if (xp.w <= 0.0) continue;
            vec4 flux = textureLod(t_rsm_flux, tc, 0.0);
            vec3 np = textureLod(t_rsm_normal, tc, 0.0).xyz;
            vec3 d = p - xp.xyz;
            // Below the texel's own footprint the point-emitter model breaks down: bound 1/d^2.
            float d2 = max(dot(d, d), flux.a * flux.a);
            float cos_p = max(dot(np, d), 0.0);
            float cos_x = max(dot(n, -d), 0.0);
            E += flux.rgb * (INV_PI * cos_p * cos_x / (d2 * d2)) * w;
        }
    }
    out_irradiance = vec4(E, (frame.view * vec4(p, 1.0)).z);  // a: view depth, for the upsampling
}
