#pragma once
// C++ twins of shaders/common/sampling.glsl (tested for normalisation and pdf agreement).
#include <cmath>
#include <cstdint>

#include <glm/glm.hpp>

namespace candela::rt {

constexpr float kPi = 3.14159265358979323846f;

inline std::uint32_t pcg_hash(std::uint32_t v) {
    const std::uint32_t state = v * 747796405u + 2891336453u;
    const std::uint32_t word = ((state >> ((state >> 28u) + 4u)) ^ state) * 277803737u;
    return (word >> 22u) ^ word;
}

inline void onb(const glm::vec3& n, glm::vec3& t, glm::vec3& b) {
    const float s = n.z >= 0.0f ? 1.0f : -1.0f;
    const float a = -1.0f / (s + n.z);
    const float c = n.x * n.y * a;
    t = glm::vec3(1.0f + s * n.x * n.x * a, s * c, -s * n.x);
    b = glm::vec3(c, s + n.y * n.y * a, -n.y);
}

inline glm::vec3 sample_cosine_hemisphere(glm::vec2 u) {
    const float r = std::sqrt(u.x);
    const float phi = 2.0f * kPi * u.y;
    return {r * std::cos(phi), r * std::sin(phi), std::sqrt(std::max(0.0f, 1.0f - u.x))};
}
inline float pdf_cosine_hemisphere(float cos_theta) { return std::max(cos_theta, 0.0f) / kPi; }

inline glm::vec3 sample_ggx_vndf(const glm::vec3& v_local, float alpha, glm::vec2 u) {
    const glm::vec3 vh = glm::normalize(glm::vec3(alpha * v_local.x, alpha * v_local.y, v_local.z));
    const float lensq = vh.x * vh.x + vh.y * vh.y;
    const glm::vec3 t1 = lensq > 0.0f ? glm::vec3(-vh.y, vh.x, 0.0f) / std::sqrt(lensq) : glm::vec3(1, 0, 0);
    const glm::vec3 t2 = glm::cross(vh, t1);
    const float r = std::sqrt(u.x);
    const float phi = 2.0f * kPi * u.y;
    const float p1 = r * std::cos(phi);
    float p2 = r * std::sin(phi);
    const float s = 0.5f * (1.0f + vh.z);
    p2 = (1.0f - s) * std::sqrt(std::max(0.0f, 1.0f - p1 * p1)) + s * p2;
    const glm::vec3 nh = p1 * t1 + p2 * t2 + std::sqrt(std::max(0.0f, 1.0f - p1 * p1 - p2 * p2)) * vh;
    return glm::normalize(glm::vec3(alpha * nh.x, alpha * nh.y, std::max(1e-6f, nh.z)));
}

inline float smith_g1_ggx(float NdotV, float alpha) {
    const float a2 = alpha * alpha;
    return 2.0f * NdotV / (NdotV + std::sqrt(a2 + (1.0f - a2) * NdotV * NdotV));
}

inline float pdf_ggx_vndf_reflection(float NdotV, float NdotH, float alpha) {
    if (NdotV <= 0.0f) return 0.0f;
    const float a2 = alpha * alpha;
    const float d = NdotH * NdotH * (a2 - 1.0f) + 1.0f;
    const float D = a2 / (kPi * d * d);
    return smith_g1_ggx(NdotV, alpha) * D / (4.0f * NdotV);
}

}  // namespace candela::rt
