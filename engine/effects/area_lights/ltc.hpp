#pragma once
// Linearly transformed cosines (Heitz, Dupuy, Hill & Neubelt 2016, "Real-Time Polygonal-Light
// Shading with Linearly Transformed Cosines"): the fit of Candela's own GGX specular lobe
// (shaders/common/brdf.glsl, F = 1) by a clamped cosine D_o(w) = max(0, w.z) / pi transformed by a
// 3x3 matrix M:
//     D(w) = D_o(M^-1 w / |M^-1 w|) * |det M^-1| / |M^-1 w|^3      (|w| = 1)
// The fitting tool (effects/area_lights/ltc_fit) writes ltc_table.inc from fit_table(); tests/unit/test_ltc.cpp
// checks the table against the BRDF.
//
// Frame of every fit: the normal is +Z and the view direction lies in the XZ plane on the +X side,
// v = (sin theta, 0, cos theta); the specular lobe then leans towards -X. A shader builds this
// frame as T1 = normalize(V - N * dot(N, V)), T2 = cross(N, T1), rows (T1, T2, N).
//
// Matrix layout: in this frame M^-1 has the form (math notation, row r, column c, acting on
// column vectors: (M^-1 w)_r = sum_c m_rc w_c)
//     M^-1 = [ m00  0   m02 ]
//            [  0  m11   0  ]
//            [ m20  0    1  ]
// normalised so that m22 = 1 (D is invariant to a scale of M). Fit::m_inv packs it as
// (m00, m02, m11, m20). In GLSL (column-major constructors) that is
//     mat3(vec3(m00, 0, m20), vec3(0, m11, 0), vec3(m02, 0, 1)).
//
// Table axes (kTableSize = N texels each, entry index j * N + i):
//   x (i): perceptual roughness r = i / (N - 1) (alpha = max(r^2, 1e-3) as brdf_alpha);
//   y (j): t = j / (N - 1) with t = u * (0.5 + 0.5 u), u = theta / (pi / 2), theta = acos(NdotV).
//          dt/dtheta grows from 0.5 at normal incidence to 1.5 at grazing, so the grazing third of
//          the angles, where the lobe changes fastest, gets about twice the texels per degree of
//          uniform spacing (rows step ~5.8 deg at theta = 0 and ~1.9 deg at 90 deg). The inverse,
//          used by the fit: u = sqrt(0.25 + 2 t) - 0.5.
//   table_coords() gives the texture coordinate of a (roughness, NdotV) at texel centres, so that
//   a bilinear lookup of an N x N texture interpolates the entries linearly in (r, t).
#include <glm/glm.hpp>

#include <cmath>
#include <vector>

namespace candela::ltc {

constexpr int kTableSize = 32;

// Texture coordinates in [0,1]^2 of (roughness, NdotV), at texel centres ((i + 0.5) / N).
inline glm::vec2 table_coords(float roughness, float NdotV) {
    const float u = std::acos(glm::clamp(NdotV, 0.0f, 1.0f)) * 0.63661977236758134f;  // theta / (pi/2)
    const glm::vec2 rt(glm::clamp(roughness, 0.0f, 1.0f), u * (0.5f + 0.5f * u));
    return (rt * float(kTableSize - 1) + 0.5f) / float(kTableSize);
}

// The (roughness, cos theta) of table entry (i, j): the inverse of table_coords at texel centres.
float table_roughness(int i);
float table_cos_theta(int j);

struct Fit {
    glm::vec4 m_inv;  // (m00, m02, m11, m20) of M^-1, m22 = 1 (see above)
    float norm;       // integral over the hemisphere of D * V * NdotL (directional albedo, F = 1)
    float fresnel;    // integral of D * V * NdotL * (1 - VdotH)^5: with Schlick's F the specular
                      // albedo is F0 * (norm - fresnel) + F90 * fresnel
    float error;      // residual of the fit: integral over the sphere of |f / norm - D_ltc|, the L1
                      // distance between the normalised lobe and the LTC (0 = exact, 2 = disjoint);
                      // half of it bounds the difference of their integrals over any region
};

// Fits one entry (roughness is perceptual, cos_theta = NdotV). initial_guess (may be null) seeds
// Nelder-Mead; the result is deterministic for a given guess.
Fit fit_entry(float roughness, float cos_theta, const Fit* initial_guess);

// The whole table, N * N entries, index j * N + i (each row seeded from its neighbour).
std::vector<Fit> fit_table();

// Value of the fitted distribution at direction w (normalised inside; integrates to 1 over the
// sphere), in the frame above.
float ltc_eval(const glm::vec4& m_inv, glm::vec3 w);

// Candela's specular lobe with F = 1, cosine included: D_GGX * V_SmithGGXCorrelated * NdotL
// (0 when NdotL <= 0 or NdotV <= 0), exactly as brdf.glsl evaluates it. v, l unit vectors in the
// frame above (normal +Z).
double brdf_cos(float roughness, glm::vec3 v, glm::vec3 l);

}  // namespace candela::ltc
