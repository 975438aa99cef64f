// Environment map importance sampling (path and direct modes, with HAS_ENV_MAP_SAMPLING):
// directions drawn by the map's luminance, combined with BRDF sampling by MIS.
#include "trace_common.glsl"
#ifdef HAS_ENV_MAP_SAMPLING
// env_dist: texel probabilities, row-conditional CDFs, marginal CDF (engine/rt/ray_tracer.hpp).
layout(std430, binding = RT_ENV_DISTRIBUTION_BINDING) readonly buffer EnvDistribution { float env_dist[]; };

// Solid-angle pdf of drawing `dir` from the environment distribution.
float env_pdf(vec3 dir) {
    int w = rt.env_width, h = rt.env_height;
    vec2 uv = direction_to_equirect(normalize(dir));
    int x = clamp(int(uv.x * float(w)), 0, w - 1);
    int y = clamp(int(uv.y * float(h)), 0, h - 1);
    float sin_theta = sin(PI * (float(y) + 0.5) / float(h));
    if (sin_theta <= 0.0) return 0.0;
    return env_dist[y * w + x] * float(w * h) / (2.0 * PI * PI * sin_theta);
}

vec3 sample_env(inout Rng rng, out float pdf) {
    int w = rt.env_width, h = rt.env_height;
    int n = w * h;
    float u = rng_next(rng);
    int lo = 0, hi = h - 1;
    while (lo < hi) {
        int mid = (lo + hi) / 2;
        if (env_dist[2 * n + mid] < u) lo = mid + 1; else hi = mid;
    }
    int y = lo;
    float u2 = rng_next(rng);
    lo = 0;
    hi = w - 1;
    while (lo < hi) {
        int mid = (lo + hi) / 2;
        if (env_dist[n + y * w + mid] < u2) lo = mid + 1; else hi = mid;
    }
    int x = lo;
    // Uniform within the texel; the pdf uses the texel-centre sin(theta), as env_pdf does.
    float phi = ((float(x) + rng_next(rng)) / float(w) - 0.5) * 2.0 * PI;
    float theta = (float(y) + rng_next(rng)) / float(h) * PI;
    vec3 dir = vec3(sin(theta) * sin(phi), cos(theta), -sin(theta) * cos(phi));
    float sin_c = sin(PI * (float(y) + 0.5) / float(h));
    pdf = sin_c > 0.0 ? env_dist[y * w + x] * float(n) / (2.0 * PI * PI * sin_c) : 0.0;
    return dir;
}
#endif
