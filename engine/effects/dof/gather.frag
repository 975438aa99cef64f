#version 450 core
// Depth of field, pass 4: scatter-as-gather with separate near and far fields, composited into
// the HDR target (docs/effects/dof.md).
//
// Every pixel q of the sharp image spreads its radiance evenly over its blur circle (radius r_q,
// the signed CoC of pass 1). A pixel p gathers the circles that cover it, from samples on a
// golden-angle (Vogel) spiral: equal-area rings, the first sample at p itself, the spiral turned
// per pixel by interleaved gradient noise. A sample's weight is its coverage of p divided by K(r),
// the number of spiral samples within radius r of the centre, so that a uniform region of blur
// radius r sums to exactly 1 whatever the footprint R.
// - FAR field (behind the focus plane, CoC >= 0), gathered over p's own radius: a sample spreads
//   with min(r_q, r_p). In the far field the CoC grows with depth, so a sample in front of p is
//   sharper (its own radius) and one behind p is cut to p's radius: a blurred background never
//   bleeds over a sharper surface in front of it. Normalized: the far colour.
// - NEAR field (in front of the focus plane), gathered over the largest near CoC within reach
//   (the dilated tiles): a sample spreads with its own radius over anything behind it. The sum
//   of the weights is the near field's coverage alpha; it is blended OVER the far colour (for a
//   pixel that is itself in the near field, over the pixels behind it within its own blur circle:
//   what the lens sees past the near object's edge).
#include "effects/dof/dof_data.h"

layout(binding = DOF_IN_UNIT) uniform sampler2D t_color;  // rgb radiance, a signed CoC radius (pixels)
layout(binding = DOF_IN2_UNIT) uniform sampler2D t_near;   // r: near-field reach of the pixel's tile (pixels)

layout(location = 0) out vec4 out_radiance;

const float kGoldenAngle = 2.39996323;
const float kMinRadius = 0.5;  // a sharp pixel covers itself

// The part of the pixel at distance `dist` that a blur circle of radius r covers (1-pixel ramp).
float cover(float dist, float r) { return clamp(r - dist + 0.5, 0.0, 1.0); }

// K(r): spiral samples within radius r of the centre on a spiral of n samples over radius R.
// Sample i > 0 lies at R sqrt((i + 0.5) / n); sample 0 at the centre.
float count_within(float r, float R, int n) {
    float k = floor(float(n) * (r * r) / (R * R) - 0.5) + 1.0;
    return clamp(k, 1.0, float(n));
}

vec2 spiral(int i, float R, int n, float turn) {
    if (i == 0) return vec2(0.0);
    float rho = R * sqrt((float(i) + 0.5) / float(n));
    float a = float(i) * kGoldenAngle + turn;
    return rho * vec2(cos(a), sin(a));
}

// Jimenez 2014, "Next Generation Post Processing in Call of Duty: Advanced Warfare".
float interleaved_gradient_noise(vec2 p) { return fract(52.9829189 * fract(dot(p, vec2(0.06711056, 0.00583715)))); }

void main() {
    ivec2 pixel = ivec2(gl_FragCoord.xy);
    ivec2 last = textureSize(t_color, 0) - 1;
    vec4 centre = texelFetch(t_color, pixel, 0);
    float s0 = centre.a, r0 = abs(s0);
    float reach = texelFetch(t_near, pixel / max(dof.tile, 1), 0).r;
    int n = max(dof.samples, 1);
    if (r0 < kMinRadius && reach < kMinRadius) {
        out_radiance = vec4(centre.rgb, 1.0);
        return;
    }
    float turn = 6.28318531 * interleaved_gradient_noise(gl_FragCoord.xy);

    // Far field: p's own blur circle.
    vec3 far = centre.rgb;
    if (s0 >= kMinRadius) {
        vec3 sum = vec3(0.0);
        float weight = 0.0;
        for (int i = 0; i < n; ++i) {
            vec2 off = spiral(i, r0, n, turn);
            vec4 q = texelFetch(t_color, clamp(ivec2(floor(gl_FragCoord.xy + off)), ivec2(0), last), 0);
            if (q.a < 0.0) continue;  // the near field's
            float r = max(min(q.a, s0), kMinRadius);
            float w = cover(length(off), r) / count_within(r, r0, n);
            sum += w * q.rgb;
            weight += w;
        }
        if (weight > 0.0) far = sum / weight;
    }

    // Near field: every near blur circle that can reach p, in layers by CoC (a continuous surface
    // changes it gradually, an occlusion edge in a jump): the circles of points clearly in front of
    // p (CoC larger by more than `band`) composited OVER those of p's own layer, OVER what lies
    // behind p. A sharp subject just in front of the focus plane is covered by a nearer object's
    // blur rather than averaged with it, and a near object's blur thins out over what is behind
    // it on both sides of its silhouette.
    vec3 front = vec3(0.0), own = vec3(0.0), behind = vec3(0.0);
    float front_weight = 0.0, own_weight = 0.0, behind_count = 0.0;
    float band = max(1.0, 0.25 * r0);
    if (reach >= kMinRadius) {
        for (int i = 0; i < n; ++i) {
            vec2 off = spiral(i, reach, n, turn);
            vec4 q = texelFetch(t_color, clamp(ivec2(floor(gl_FragCoord.xy + off)), ivec2(0), last), 0);
            bool near_sample = q.a < 0.0;
            if (near_sample && (s0 >= 0.0 || q.a <= s0 + band)) {
                float r = max(-q.a, kMinRadius);
                float w = cover(length(off), r) / count_within(r, reach, n);
                if (s0 >= 0.0 || q.a < s0 - band) {
                    front += w * q.rgb;
                    front_weight += w;
                } else {
                    own += w * q.rgb;
                    own_weight += w;
                }
            } else {
                // What p's own blur circle can see past its edge.
                float w = cover(length(off), max(r0, kMinRadius)) + 1e-3;
                behind += w * q.rgb;
                behind_count += w;
            }
        }
    }
    float front_alpha = min(front_weight, 1.0), own_alpha = min(own_weight, 1.0);
    vec3 near = (front_weight > 0.0 ? front / front_weight : vec3(0.0)) * front_alpha +
                (own_weight > 0.0 ? own / own_weight : vec3(0.0)) * own_alpha * (1.0 - front_alpha);
    float alpha = front_alpha + own_alpha * (1.0 - front_alpha);
    // What the near field leaves uncovered: the far field; for a pixel in the near field, the
    // pixels behind it within its own blur circle (what the lens sees past a near edge), else its own
    // layer.
    vec3 background = s0 >= 0.0           ? far
                      : behind_count > 0.0 ? behind / behind_count
                      : own_weight > 0.0   ? own / own_weight
                                           : centre.rgb;
    vec3 result = near + (1.0 - alpha) * background;
    if (any(isnan(result)) || any(isinf(result))) result = centre.rgb;
    out_radiance = vec4(result, 1.0);
}
