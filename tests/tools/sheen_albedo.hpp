// Directional albedo of the sheen lobe of shaders/common/brdf_layers.glsl (colour 1): the Charlie
// distribution and its height-correlated shadowing with the fitted Lambda (Estevez & Kulla 2017,
// "Production Friendly Microfacet Sheen BRDF", the fit's coefficients from their table), integrated over the hemisphere by the midpoint rule
// in (cos theta_l, phi). Used by sheen_albedo_table.cpp to write the table the shaders read, and
// by the unit test that checks that table against this integral.
#pragma once
#include <algorithm>
#include <cmath>

namespace candela::sheen {

// The smallest sheen roughness the BRDF uses (below, the Charlie lobe is too narrow to tabulate).
constexpr double kMinRoughness = 0.07;

inline double charlie_d(double alpha, double cos_h) {
    const double inv = 1.0 / alpha;
    const double sin2 = std::max(0.0, 1.0 - cos_h * cos_h);
    return (2.0 + inv) * std::pow(sin2, 0.5 * inv) / (2.0 * M_PI);
}
// Lambda(cos theta) of the Charlie distribution: exp of the fit L, mirrored above 45 degrees.
inline double charlie_fit(double x, double alpha) {
    const double t = (1.0 - alpha) * (1.0 - alpha);
    const double a = 21.5473 + (25.3245 - 21.5473) * t, b = 3.82987 + (3.32435 - 3.82987) * t,
                 c = 0.19823 + (0.16801 - 0.19823) * t, d = -1.97760 + (-1.27393 + 1.97760) * t,
                 e = -4.32054 + (-4.85967 + 4.32054) * t;
    return a / (1.0 + b * std::pow(x, c)) + d * x + e;
}
inline double charlie_lambda(double cos_t, double alpha) {
    return cos_t < 0.5 ? std::exp(charlie_fit(cos_t, alpha))
                       : std::exp(2.0 * charlie_fit(0.5, alpha) - charlie_fit(1.0 - cos_t, alpha));
}
// V = G2 / (4 n.l n.v), G2 = 1 / (1 + Lambda(v) + Lambda(l)).
inline double charlie_v(double nl, double nv, double alpha) {
    return 1.0 / ((1.0 + charlie_lambda(nv, alpha) + charlie_lambda(nl, alpha)) * 4.0 * nl * nv);
}

inline double albedo(double cos_v, double roughness, int n = 768) {
    const double r = std::max(roughness, kMinRoughness);
    const double alpha = r * r;
    cos_v = std::clamp(cos_v, 1e-4, 1.0);
    const double sv = std::sqrt(1.0 - cos_v * cos_v);
    double sum = 0.0;
    for (int i = 0; i < n; ++i) {
        const double cl = (i + 0.5) / n;
        const double sl = std::sqrt(1.0 - cl * cl);
        for (int j = 0; j < n; ++j) {
            const double phi = M_PI * (j + 0.5) / n;  // symmetric in phi: [0, pi] twice
            const double hx = sl * std::cos(phi) + sv, hy = sl * std::sin(phi), hz = cl + cos_v;
            const double ch = hz / std::sqrt(hx * hx + hy * hy + hz * hz);
            sum += charlie_d(alpha, ch) * charlie_v(cl, cos_v, alpha) * cl;
        }
    }
    return sum * (1.0 / n) * (M_PI / n) * 2.0;
}

}  // namespace candela::sheen
