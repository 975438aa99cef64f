// Random numbers and direction sampling, shared by the ray tracer and raster effects.
// C++ twins: engine/rt/sampling.hpp (tested there for normalisation and pdf agreement).
#include "math.glsl"

// PCG hash (O'Neill 2014; the hash form of Jarzynski & Olano 2020): a stateless mix of 32 bits.
uint pcg_hash(uint v) {
    uint state = v * 747796405u + 2891336453u;
    uint word = ((state >> ((state >> 28u) + 4u)) ^ state) * 277803737u;
    return (word >> 22u) ^ word;
}

// A stream of uniform numbers in [0, 1): seeded by (seed, pixel, sample) so that any sample of
// any pixel can be recomputed alone (deterministic images, shards that merge exactly).
struct Rng { uint state; };
Rng rng_init(uint seed, uint pixel, uint sample_index) {
    Rng r;
    r.state = pcg_hash(seed ^ pcg_hash(pixel ^ pcg_hash(sample_index + 0x9e3779b9u)));
    return r;
}
float rng_next(inout Rng r) {
    r.state = pcg_hash(r.state);
    return float(r.state >> 8) * (1.0 / 16777216.0);
}

// Orthonormal basis around n (Duff et al. 2017, "Building an Orthonormal Basis, Revisited").
void onb(vec3 n, out vec3 t, out vec3 b) {
    float s = n.z >= 0.0 ? 1.0 : -1.0;
    float a = -1.0 / (s + n.z);
    float c = n.x * n.y * a;
    t = vec3(1.0 + s * n.x * n.x * a, s * c, -s * n.x);
    b = vec3(c, s + n.y * n.y * a, -n.y);
}
vec3 to_world(vec3 local, vec3 n) {
    vec3 t, b;
    onb(n, t, b);
    return local.x * t + local.y * b + local.z * n;
}

// Cosine-weighted hemisphere around +Z (Malley's method); pdf = cos(theta) / pi.
vec3 sample_cosine_hemisphere(vec2 u) {
    float r = sqrt(u.x);
    float phi = 2.0 * PI * u.y;
    return vec3(r * cos(phi), r * sin(phi), sqrt(max(0.0, 1.0 - u.x)));
}
float pdf_cosine_hemisphere(float cos_theta) { return max(cos_theta, 0.0) * INV_PI; }

// Visible GGX normals around +Z (Heitz 2018, "Sampling the GGX Distribution of Visible Normals").
// v_local: direction to the viewer in the local frame (z = normal). Returns the half vector.
// Anisotropic: a.x along the local x axis, a.y along y.
vec3 sample_ggx_vndf_aniso(vec3 v_local, vec2 a, vec2 u) {
    vec3 vh = normalize(vec3(a.x * v_local.x, a.y * v_local.y, v_local.z));
    float lensq = vh.x * vh.x + vh.y * vh.y;
    vec3 t1 = lensq > 0.0 ? vec3(-vh.y, vh.x, 0.0) * inversesqrt(lensq) : vec3(1.0, 0.0, 0.0);
    vec3 t2 = cross(vh, t1);
    float r = sqrt(u.x);
    float phi = 2.0 * PI * u.y;
    float p1 = r * cos(phi);
    float p2 = r * sin(phi);
    float s = 0.5 * (1.0 + vh.z);
    p2 = (1.0 - s) * sqrt(max(0.0, 1.0 - p1 * p1)) + s * p2;
    vec3 nh = p1 * t1 + p2 * t2 + sqrt(max(0.0, 1.0 - p1 * p1 - p2 * p2)) * vh;
    return normalize(vec3(a.x * nh.x, a.y * nh.y, max(1e-6, nh.z)));
}
vec3 sample_ggx_vndf(vec3 v_local, float alpha, vec2 u) { return sample_ggx_vndf_aniso(v_local, vec2(alpha), u); }

// Smith G1 for GGX.
float smith_g1_ggx(float NdotV, float alpha) {
    float a2 = alpha * alpha;
    return 2.0 * NdotV / (NdotV + sqrt(a2 + (1.0 - a2) * NdotV * NdotV));
}

// pdf (solid angle) of the reflected direction l = reflect(-v, h) with h from sample_ggx_vndf.
float pdf_ggx_vndf_reflection(float NdotV, float NdotH, float alpha) {
    if (NdotV <= 0.0) return 0.0;
    float a2 = alpha * alpha;
    float d = NdotH * NdotH * (a2 - 1.0) + 1.0;
    float D = a2 / (PI * d * d);
    return smith_g1_ggx(NdotV, alpha) * D / (4.0 * NdotV);
}
