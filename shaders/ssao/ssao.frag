#version 450 core
// Screen-space ambient occlusion that converges to the ray tracer's `ao` mode: from each pixel,
// ssao.samples cosine-distributed directions around the normal (a Vogel disk lifted to the
// hemisphere by Malley's method, rotated per pixel by a 4x4 noise texture), each marched in
// ssao.steps steps out to ao.radius. A direction is occluded when a step lands behind the depth
// buffer's surface, closer than ao.radius in depth (the thickness the screen cannot know).
// Output: the unoccluded fraction, as `--raytrace ao` computes it with rays.
#include "../common/scene_data.glsl"
#include "../lighting/gbuffer.glsl"

layout(binding = 0) uniform sampler2D t_depth;    // full resolution, reversed-Z
layout(binding = 1) uniform sampler2D t_normals;  // xy: octahedral normal
layout(binding = 2) uniform sampler2D t_noise;    // 4x4: rg rotation (cos, sin), b step jitter

layout(location = 0) out vec4 out_ao;

vec3 world_at(vec2 uv, float depth) {
    vec4 p = frame.inv_view_proj * vec4(uv * 2.0 - 1.0, depth, 1.0);
    return p.xyz / p.w;
}

void main() {
    // This pixel's full-resolution sample (the AO target may be at half resolution).
    ivec2 full = ivec2(gl_FragCoord.xy * float(frame.ssao_mode.z));
    ivec2 size = textureSize(t_depth, 0);
    full = min(full, size - 1);
    float depth = texelFetch(t_depth, full, 0).r;
    if (depth <= 0.0) {  // no geometry: nothing to occlude
        out_ao = vec4(1.0);
        return;
    }
    vec2 uv = (vec2(full) + 0.5) / vec2(size);
    vec3 p = world_at(uv, depth);
    vec3 n = oct_decode(texelFetch(t_normals, full, 0).xy);
    float radius = frame.ssao_params.x;
    float bias = frame.ssao_params.y * radius;
    int samples = int(frame.ssao_params.z);
    int steps = int(frame.ssao_params.w);
    vec4 noise = texelFetch(t_noise, full & 3, 0);
    vec3 t = normalize(abs(n.x) > 0.5 ? cross(n, vec3(0, 1, 0)) : cross(n, vec3(1, 0, 0)));
    vec3 b = cross(n, t);
    vec3 origin = p + n * bias;
    int occluded = 0;
    for (int i = 0; i < samples; ++i) {
        // Vogel disk point, rotated by the pixel's noise, lifted to a cosine-weighted direction.
        float r = sqrt((float(i) + 0.5) / float(samples));
        float theta = float(i) * 2.39996323;
        vec2 d2 = r * vec2(cos(theta), sin(theta));
        d2 = vec2(d2.x * noise.r - d2.y * noise.g, d2.x * noise.g + d2.y * noise.r);
        vec3 dir = d2.x * t + d2.y * b + sqrt(max(0.0, 1.0 - dot(d2, d2))) * n;
        for (int k = 0; k < steps; ++k) {
            float dist = radius * (float(k) + noise.b) / float(steps);
            vec3 s = origin + dir * dist;
            vec4 c = frame.view_proj * vec4(s, 1.0);
            if (c.w <= 0.0) break;
            vec2 suv = c.xy / c.w * 0.5 + 0.5;
            if (any(lessThan(suv, vec2(0.0))) || any(greaterThan(suv, vec2(1.0)))) break;
            // The nearest depth sample (filtering depth across a silhouette would invent surfaces).
            ivec2 sp = min(ivec2(suv * vec2(size)), size - 1);
            float scene_depth = texelFetch(t_depth, sp, 0).r;
            if (scene_depth <= 0.0) continue;
            vec3 q = world_at((vec2(sp) + 0.5) / vec2(size), scene_depth);
            // View-space depths (negative forward): q in front of s, by less than the radius.
            float zs = (frame.view * vec4(s, 1.0)).z;
            float zq = (frame.view * vec4(q, 1.0)).z;
            if (zq > zs + bias && zq - zs < radius) {
                ++occluded;
                break;
            }
        }
    }
    out_ao = vec4(1.0 - float(occluded) / float(max(samples, 1)));
}
