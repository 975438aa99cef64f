#version 450 core
// Screen-space ambient occlusion that converges to the ray tracer's `ao` mode: from each pixel,
// ssao.samples cosine-distributed directions around the normal (a Vogel disk lifted to the
// hemisphere by Malley's method, rotated per pixel by a 4x4 noise texture), each marched in
// ssao.steps steps out to ao.radius. A direction is occluded when a step lands behind the depth
// buffer's surface, closer than ao.radius in depth (the thickness the screen cannot know).
// Output: r the unoccluded fraction, as `--raytrace ao` computes it with rays; g the pixel's view
// depth, for the blur. All in view space: one projection per step, no matrix inverse.
#include "common/scene_data.glsl"
#include "lighting/gbuffer.glsl"
#include "effects/ssao/ssao_data.h"

layout(binding = SSAO_DEPTH_UNIT) uniform sampler2D t_depth;    // full resolution, reversed-Z
layout(binding = SSAO_NORMALS_UNIT) uniform sampler2D t_normals;  // xy: octahedral normal (world)
layout(binding = SSAO_NOISE_UNIT) uniform sampler2D t_noise;    // 4x4: rg rotation (cos, sin), b step jitter

layout(location = 0) out vec4 out_ao;

float view_z(float d) { return (frame.depth_to_view.x * d + frame.depth_to_view.y) / (frame.depth_to_view.z * d + frame.depth_to_view.w); }

// The view depth at which the view ray through s (view space) meets the tangent plane of the
// surface the depth buffer holds at `texel` (depth `d`): its centre's position and its normal.
// Perspective rays start at the eye, orthographic ones run along -z.
float tangent_plane_z(ivec2 texel, float d, vec3 s, vec2 fsize) {
    vec4 pw = frame.inv_view_proj * vec4((vec2(texel) + 0.5) / fsize * 2.0 - 1.0, d, 1.0);
    vec3 c = (frame.view * vec4(pw.xyz / pw.w, 1.0)).xyz;
    vec3 n = mat3(frame.view) * oct_decode(texelFetch(t_normals, texel, 0).xy);
    bool orthographic = frame.proj[3][3] == 1.0;
    if (orthographic) return abs(n.z) > 1e-6 ? s.z + dot(n, c - s) / n.z : view_z(d);
    float ns = dot(n, s);
    return abs(ns) > 1e-12 * length(s) ? s.z * dot(n, c) / ns : view_z(d);
}

void main() {
    // This pixel's full-resolution sample (the AO target may be at half resolution).
    ivec2 size = textureSize(t_depth, 0);
    ivec2 full = min(ivec2(gl_FragCoord.xy) * ssao.downscale, size - 1);
    float depth = texelFetch(t_depth, full, 0).r;
    if (depth <= 0.0) {  // no geometry: nothing to occlude
        out_ao = vec4(1.0, -1e30, 0.0, 0.0);
        return;
    }
    vec4 pw = frame.inv_view_proj * vec4((vec2(full) + 0.5) / vec2(size) * 2.0 - 1.0, depth, 1.0);
    vec3 p = (frame.view * vec4(pw.xyz / pw.w, 1.0)).xyz;
    vec3 n = normalize(mat3(frame.view) * oct_decode(texelFetch(t_normals, full, 0).xy));
    float radius = ssao.radius;
    float bias = ssao.bias * radius;
    int samples = ssao.samples;
    int steps = ssao.steps;
    vec4 noise = texelFetch(t_noise, ivec2(gl_FragCoord.xy) & 3, 0);  // per AO pixel: all 16 rotations
    vec3 t = normalize(abs(n.x) > 0.5 ? cross(n, vec3(0, 1, 0)) : cross(n, vec3(1, 0, 0)));
    vec3 b = cross(n, t);
    vec3 origin = p + n * bias;
    vec2 fsize = vec2(size);
    int occluded = 0;
    // Vogel disk points (radius sqrt((i + 0.5) / n), angle i times the golden angle): each
    // direction is the last one turned by the golden angle, without a sine and cosine per sample.
    const vec2 golden_turn = vec2(cos(2.39996323), sin(2.39996323));
    vec2 turn = vec2(1.0, 0.0);
    for (int i = 0; i < samples; ++i) {
        // The disk point, rotated by the pixel's noise, lifted to a cosine-weighted direction.
        float r = sqrt((float(i) + 0.5) / float(samples));
        vec2 d2 = r * turn;
        turn = vec2(turn.x * golden_turn.x - turn.y * golden_turn.y, turn.y * golden_turn.x + turn.x * golden_turn.y);
        d2 = vec2(d2.x * noise.r - d2.y * noise.g, d2.x * noise.g + d2.y * noise.r);
        vec3 dir = d2.x * t + d2.y * b + sqrt(max(0.0, 1.0 - dot(d2, d2))) * n;
        for (int k = 0; k < steps; ++k) {
            vec3 s = origin + dir * (radius * (float(k) + noise.b) / float(steps));
            vec4 c = frame.proj * vec4(s, 1.0);
            if (c.w <= 0.0) break;
            vec2 suv = c.xy / c.w * 0.5 + 0.5;
            if (any(lessThan(suv, vec2(0.0))) || any(greaterThan(suv, vec2(1.0)))) break;
            // The nearest depth sample (filtering depth across a silhouette would invent surfaces).
            ivec2 texel = min(ivec2(suv * fsize), size - 1);
            float scene_depth = texelFetch(t_depth, texel, 0).r;
            if (scene_depth <= 0.0) continue;
            float zq = view_z(scene_depth);
            // View-space depths (negative forward): the surface in front of s, by less than the radius.
            if (zq > s.z + bias && zq - s.z < radius) {
                // The texel holds its surface at its centre; s projects up to half a texel away,
                // where a surface inclined to the view lies nearer or farther. Compared with the
                // centre's depth, a plane shadowed itself by that difference, the more the coarser
                // the buffer against the radius and the more grazing the view (a floor seen at 6
                // degrees: AO 0.90 at 64x48). So the depth compared is that of the texel's own
                // tangent plane (its centre and normal) on the view ray through s.
                zq = tangent_plane_z(texel, scene_depth, s, fsize);
                if (zq > s.z + bias && zq - s.z < radius) {
                    ++occluded;
                    break;
                }
            }
        }
    }
    out_ao = vec4(1.0 - float(occluded) / float(max(samples, 1)), p.z, 0.0, 0.0);
}
