#version 450 core
// Motion blur, pass 4: the reconstruction filter of McGuire, Hennessy, Bukowski and Osman 2012,
// "A Reconstruction Filter for Plausible Motion Blur" (I3D; its Listing 1), into the HDR target.
//
// Every pixel Y of the sharp image spreads its colour along its own motion (half vector V[Y]).
// A pixel X gathers `samples` taps along the dominant velocity of its neighbourhood (NeighborMax
// vN), spaced evenly over [-vN, +vN] and jittered per pixel. A tap Y contributes by
// - f * cone(Y, X, V[Y]): Y is in front of X (soft depth comparison f) and its blur reaches X;
// - b * cone(X, Y, V[X]): Y is behind X and X's own blur uncovers it;
// - 2 * cylinder(Y, X, V[Y]) * cylinder(X, Y, V[X]): both blurred over each other (the same
//   moving surface).
// The centre tap (X itself) weighs 1 / |V[X]|; the other taps' weights are scaled by 16 / (n + 1)
// (the paper's at its 15 taps, whatever the count). The result is the weighted mean.
#include "common/scene_data.glsl"
#include "effects/motion_blur/motion_blur_data.h"

layout(binding = MOTION_BLUR_COLOR_UNIT) uniform sampler2D t_color;     // the sharp radiance (rgb)
layout(binding = MOTION_BLUR_VELOCITY_UNIT) uniform sampler2D t_velocity;  // rg: half vector V in pixels
layout(binding = MOTION_BLUR_DEPTH_UNIT) uniform sampler2D t_depth;     // the velocity pass's depth (reversed-Z)
layout(binding = MOTION_BLUR_NEIGHBOR_UNIT) uniform sampler2D t_neighbor;  // rg: NeighborMax per tile

layout(location = 0) out vec4 out_radiance;

const float kMinRadius = 0.5;  // a pixel covers itself: |V| is at least half a pixel

// Distance along the view axis (positive); the far plane and the sky are 1e30.
float view_depth(ivec2 p) {
    float d = texelFetch(t_depth, p, 0).r;
    vec4 k = frame.depth_to_view;
    float num = k.x * d + k.y, den = k.z * d + k.w;
    float z = abs(den) > 1e-30 ? -num / den : 1e30;
    return (z > 0.0 && z < 1e30) ? z : 1e30;
}

// 1 where a is in front of b, 0 where it is behind by more than the soft extent (a fraction of
// the nearer depth), linear between.
float soft_depth_compare(float a, float b) {
    float extent = max(motion_blur.soft_z * min(a, b), 1e-6);
    return clamp(1.0 - (a - b) / extent, 0.0, 1.0);
}

float cone(float dist, float v) { return clamp(1.0 - dist / v, 0.0, 1.0); }
float cylinder(float dist, float v) { return 1.0 - smoothstep(0.95 * v, 1.05 * v, dist); }

// White noise per pixel (PCG hash, Jarzynski & Olano 2020): the taps' jitter. Interleaved gradient
// noise, whose values run in ramps along x, beat with stripes that move along x into visible bands.
float pixel_noise(ivec2 p) {
    uint v = uint(p.x) * 1973u + uint(p.y) * 9277u + 26699u;
    v = v * 747796405u + 2891336453u;
    v = ((v >> ((v >> 28u) + 4u)) ^ v) * 277803737u;
    v = (v >> 22u) ^ v;
    return float(v) * (1.0 / 4294967296.0);
}

void main() {
    ivec2 X = ivec2(gl_FragCoord.xy);
    ivec2 last = textureSize(t_color, 0) - 1;
    vec3 cx = texelFetch(t_color, X, 0).rgb;
    vec2 vn = texelFetch(t_neighbor, X / max(motion_blur.tile, 1), 0).xy;
    float vn_len = length(vn);
    if (vn_len <= kMinRadius + 0.01) {  // nothing near moves by more than half a pixel
        out_radiance = vec4(cx, 1.0);
        return;
    }
    float vx = max(length(texelFetch(t_velocity, X, 0).xy), kMinRadius);
    float zx = view_depth(X);
    float weight = 1.0 / vx;
    vec3 sum = cx * weight;
    float j = pixel_noise(X) - 0.5;  // in [-0.5, 0.5)
    int n = max(motion_blur.samples, 1);
    int centre = (n - 1) / 2;
    // The paper weighs each tap on its own and the centre once, so its blur would widen with the
    // tap count (RMSE 0.0154 at 15 taps, 0.0170 at 31 on generated:motion at 320 x 240): the taps'
    // weights are scaled to sum as the paper's 15 do (0.0154, 0.0153), so more taps only cut noise.
    float tap_scale = 16.0 / float(n + 1);
    for (int i = 0; i < n; ++i) {
        if (i == centre) continue;  // X itself, weighted above
        float t = mix(-1.0, 1.0, (float(i) + j + 1.0) / float(n + 1));
        ivec2 Y = clamp(ivec2(floor(gl_FragCoord.xy + vn * t)), ivec2(0), last);
        float dist = length(vec2(Y - X));
        float vy = max(length(texelFetch(t_velocity, Y, 0).xy), kMinRadius);
        float zy = view_depth(Y);
        float f = soft_depth_compare(zy, zx);  // Y in front of X
        float b = soft_depth_compare(zx, zy);  // Y behind X
        float a = (f * cone(dist, vy) + b * cone(dist, vx) + 2.0 * cylinder(dist, vy) * cylinder(dist, vx)) * tap_scale;
        weight += a;
        sum += a * texelFetch(t_color, Y, 0).rgb;
    }
    out_radiance = vec4(sum / weight, 1.0);
}
