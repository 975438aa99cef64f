#pragma once
// C++ twins of shaders/rt/intersect.glsl, line for line, so the hard cases can be unit-tested on
// the CPU and the GLSL versions cross-checked against them through a compute shader.
#include <algorithm>
#include <cmath>
#include <cstdint>
#include <cstring>

#include <glm/glm.hpp>

namespace candela::rt {

struct Ray {
    glm::vec3 origin;
    glm::vec3 dir;
};

struct WatertightRay {
    glm::vec3 origin;
    glm::ivec3 k;
    glm::vec3 shear;
};

inline WatertightRay watertight_setup(const Ray& ray) {
    WatertightRay w;
    const glm::vec3 ad = glm::abs(ray.dir);
    const int kz = ad.x > ad.y ? (ad.x > ad.z ? 0 : 2) : (ad.y > ad.z ? 1 : 2);
    int kx = kz == 2 ? 0 : kz + 1;
    int ky = kx == 2 ? 0 : kx + 1;
    if (ray.dir[kz] < 0.0f) std::swap(kx, ky);
    w.k = glm::ivec3(kx, ky, kz);
    w.shear = glm::vec3(ray.dir[kx] / ray.dir[kz], ray.dir[ky] / ray.dir[kz], 1.0f / ray.dir[kz]);
    w.origin = ray.origin;
    return w;
}

// Woop, Benthin & Wald 2013. Returns t in (0, tmax) or -1.
inline float intersect_triangle(const WatertightRay& w, const glm::vec3& p0, const glm::vec3& p1, const glm::vec3& p2,
                                float tmax, glm::vec2& bary) {
    bary = glm::vec2(0.0f);
    const glm::vec3 A = p0 - w.origin, B = p1 - w.origin, C = p2 - w.origin;
    const float Ax = A[w.k.x] - w.shear.x * A[w.k.z], Ay = A[w.k.y] - w.shear.y * A[w.k.z];
    const float Bx = B[w.k.x] - w.shear.x * B[w.k.z], By = B[w.k.y] - w.shear.y * B[w.k.z];
    const float Cx = C[w.k.x] - w.shear.x * C[w.k.z], Cy = C[w.k.y] - w.shear.y * C[w.k.z];
    float U = Cx * By - Cy * Bx;
    float V = Ax * Cy - Ay * Cx;
    float W = Bx * Ay - By * Ax;
    if (U == 0.0f || V == 0.0f || W == 0.0f) {
        U = static_cast<float>(static_cast<double>(Cx) * By - static_cast<double>(Cy) * Bx);
        V = static_cast<float>(static_cast<double>(Ax) * Cy - static_cast<double>(Ay) * Cx);
        W = static_cast<float>(static_cast<double>(Bx) * Ay - static_cast<double>(By) * Ax);
    }
    if ((U < 0.0f || V < 0.0f || W < 0.0f) && (U > 0.0f || V > 0.0f || W > 0.0f)) return -1.0f;
    const float det = U + V + W;
    if (det == 0.0f) return -1.0f;
    const float Az = w.shear.z * A[w.k.z], Bz = w.shear.z * B[w.k.z], Cz = w.shear.z * C[w.k.z];
    const float T = U * Az + V * Bz + W * Cz;
    if (det < 0.0f ? (T >= 0.0f || T < tmax * det) : (T <= 0.0f || T > tmax * det)) return -1.0f;
    const float inv = 1.0f / det;
    bary = glm::vec2(V * inv, W * inv);
    return T * inv;
}

// Haines et al., Ray Tracing Gems ch. 7.
inline float intersect_sphere(const Ray& ray, const glm::vec3& center, float radius, float tmin, float tmax) {
    const float len = glm::length(ray.dir);
    const glm::vec3 d = ray.dir / len;
    const glm::vec3 f = ray.origin - center;
    const float b = -glm::dot(f, d);
    const glm::vec3 closest = f + b * d;
    const float disc = radius * radius - glm::dot(closest, closest);
    if (disc < 0.0f) return -1.0f;
    const float c = glm::dot(f, f) - radius * radius;
    const float q = b + (b >= 0.0f ? 1.0f : -1.0f) * std::sqrt(disc);
    float t0 = q != 0.0f ? c / q : 0.0f;
    float t1 = q;
    if (t0 > t1) std::swap(t0, t1);
    if (t0 > tmin * len && t0 < tmax * len) return t0 / len;
    if (t1 > tmin * len && t1 < tmax * len) return t1 / len;
    return -1.0f;
}

// The smallest offset for a scene whose bounding box has this diagonal: 2^-19 of it (1/65536
// for a scene of about 8 units, Wächter & Binder's constant). A hit's error against a triangle
// grows with the distances in the scene, not with the hit's own coordinates: a floor at y = 0
// in a scene 6000 units wide needs more than 1/65536 (hard case ScaleInvariance).
inline float ray_offset_for_extent(float diagonal) { return std::max(diagonal, 1e-30f) * (1.0f / 524288.0f); }

// Wächter & Binder, Ray Tracing Gems ch. 6: each coordinate moves along n by 16 ulps of itself
// (their 256 put a scene 10^4 from the origin 0.25 units off its surfaces: light leaked at
// contacts) or by `min_offset` (a distance), whichever is farther.
inline glm::vec3 offset_ray(const glm::vec3& p, const glm::vec3& n, float min_offset) {
    constexpr float int_scale = 16.0f;
    glm::vec3 out;
    for (int i = 0; i < 3; ++i) {
        const int of = static_cast<int>(int_scale * n[i]);
        std::int32_t bits;
        std::memcpy(&bits, &p[i], 4);
        bits += p[i] < 0.0f ? -of : of;
        float pi;
        std::memcpy(&pi, &bits, 4);
        const float pf = p[i] + min_offset * n[i];
        out[i] = std::fabs(pi - p[i]) > std::fabs(pf - p[i]) ? pi : pf;
    }
    return out;
}

}  // namespace candela::rt
