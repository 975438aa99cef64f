// The layers of the glTF material extensions (shaders/common/brdf_layers.glsl) judged in white
// furnaces: a flat quad, tilted by theta about the x axis, fills an orthographic view under a
// uniform sky of radiance 1 with no lights. Every pixel then shows the directional albedo
// E(cos theta) of its material, which the path tracer estimates from independent batches (the
// --spp-shard k/N sample sets): the z of the batch mean is tested against a closed form computed
// here by quadrature from the lobe's own formulas, or against the bound 1 where the model only
// promises not to create energy. Each closed-form case also shows its power (the closed form
// scaled by 1 -+ 1 % fails), and the rasterizer's split-sum version of each layer is held to the
// tracer within a stated tolerance.
#include <gtest/gtest.h>

#include <glm/gtc/constants.hpp>

#include <algorithm>
#include <cmath>
#include <cstdio>
#include <functional>
#include <string>
#include <vector>

#include "../tools/sheen_albedo.hpp"
#include "gl_fixture.hpp"
#include "gltf_builder.hpp"
#include "image/image.hpp"
#include "render/still.hpp"
#include "rt/ray_tracer.hpp"
#include "scene/gltf_loader.hpp"

namespace candela {
namespace material_layers_test {
namespace fs = std::filesystem;
using nlohmann::json;

constexpr double kPi = glm::pi<double>();
constexpr int kBatches = 16;
constexpr int kSize = 16;  // pixels per side

// ---- closed forms (the lobes of brdf.glsl / brdf_layers.glsl, integrated in double) ----------

double brdf_alpha(double roughness) { return std::max(roughness * roughness, 1e-3); }

// Albedo of an anisotropic GGX lobe with F = 1 seen from v = (vx, vy, vz) in its (t, b, n) frame,
// over half vectors h (l = reflect(-v, h), dw_l = 4 v.h dw_h), midpoint rule in (cos theta_h, phi).
double ggx_albedo(glm::dvec3 v, double ax, double ay, int n = 1024) {
    auto lambda = [&](const glm::dvec3& w) { return std::sqrt(ax * ax * w.x * w.x + ay * ay * w.y * w.y + w.z * w.z); };
    double sum = 0.0;
    for (int i = 0; i < n; ++i) {
        // cos theta_h = 1 - u^2 concentrates samples near the normal (dcos = 2u du).
        const double u = (i + 0.5) / n, ch = 1.0 - u * u, sh = std::sqrt(std::max(0.0, 1.0 - ch * ch));
        for (int j = 0; j < n; ++j) {
            const double phi = 2.0 * kPi * (j + 0.5) / n;
            const glm::dvec3 h(sh * std::cos(phi), sh * std::sin(phi), ch);
            const double vh = glm::dot(v, h);
            if (vh <= 0.0) continue;
            const glm::dvec3 l = 2.0 * vh * h - v;
            if (l.z <= 0.0) continue;
            const glm::dvec3 s(h.x / ax, h.y / ay, h.z);
            const double d2 = glm::dot(s, s);
            const double D = 1.0 / (kPi * ax * ay * d2 * d2);
            const double V = 0.5 / (l.z * lambda(v) + v.z * lambda(l));
            sum += D * V * l.z * 4.0 * vh * (2.0 * u) * (1.0 / n) * (2.0 * kPi / n);
        }
    }
    return sum;
}
double coat_fresnel(double cos_v) { return 0.04 + 0.96 * std::pow(1.0 - cos_v, 5.0); }

// ---- scenes -----------------------------------------------------------------------------------

// A quad of material `m` tilted by theta (radians) about x, seen along -z by an orthographic
// camera whose view it fills, under a uniform sky of radiance 1.
Scene furnace(const std::string& name, const json& m, double theta) {
    test::GltfBuilder b;
    b.json()["materials"] = {m};
    // Stretched along the tilt so that it still fills the view at grazing angles.
    const double stretch = std::max(1.0, 0.2 / std::cos(theta));
    b.add_node({{"mesh", b.add_quad_mesh(0)}, {"rotation", {std::sin(-theta / 2), 0, 0, std::cos(-theta / 2)}}, {"scale", {1.0, stretch, 1.0}}});
    b.json()["scenes"][0]["extras"]["environment_radiance"] = {1, 1, 1};
    b.json()["cameras"] = {{{"type", "orthographic"}, {"orthographic", {{"xmag", 0.1}, {"ymag", 0.1}, {"znear", 0.01}, {"zfar", 100}}}}};
    b.add_node({{"camera", 0}, {"translation", {0, 0, 5}}});
    return load_gltf(b.write(test::test_dir("layers_" + name), name));
}

json material(glm::vec3 base, float metallic, float roughness, float specular, json extensions) {
    json m = {{"pbrMetallicRoughness", {{"baseColorFactor", {base.r, base.g, base.b, 1}}, {"metallicFactor", metallic},
                                        {"roughnessFactor", roughness}}}};
    extensions["KHR_materials_specular"] = {{"specularFactor", specular}};
    m["extensions"] = extensions;
    return m;
}
// A white Lambert base (no specular lobe) under the extensions given.
json white_lambert(json extensions) { return material(glm::vec3(1.0f), 0.0f, 1.0f, 0.0f, std::move(extensions)); }

struct Estimate {
    glm::dvec3 mean{0.0}, se{0.0};  // of the image mean, from the batch means
};

class MaterialLayersTest : public test::GlContextTest {
protected:
    Estimate trace(const Scene& scene, int spp_per_batch = 256) {
        rt::Options o;
        o.mode = rt::Mode::path;
        o.spp = spp_per_batch * kBatches;
        GpuScene gpu(scene);
        rt::RayTracer tracer(shaders_, scene, gpu, o);
        const Camera camera = scene.select_camera("", 1.0f);
        std::vector<glm::dvec3> means;
        for (int k = 0; k < kBatches; ++k) {
            tracer.set_shard(k, kBatches);
            const rt::Result r = tracer.render(camera, kSize, kSize);
            EXPECT_EQ(r.nonfinite_samples, 0u);
            EXPECT_EQ(count_nonfinite(r.image), 0u);
            glm::dvec3 m(0.0);
            for (int y = 0; y < kSize; ++y)
                for (int x = 0; x < kSize; ++x) m += glm::dvec3(r.image.at(x, y)[0], r.image.at(x, y)[1], r.image.at(x, y)[2]);
            means.push_back(m / static_cast<double>(kSize * kSize));
        }
        Estimate e;
        for (const glm::dvec3& m : means) e.mean += m / static_cast<double>(kBatches);
        glm::dvec3 var(0.0);
        for (const glm::dvec3& m : means) var += (m - e.mean) * (m - e.mean) / static_cast<double>(kBatches - 1);
        e.se = glm::sqrt(var / static_cast<double>(kBatches)) + 1e-7;  // + the closed form's own rounding
        return e;
    }
    glm::dvec3 raster(const Scene& scene, const char* effects = "none", const std::vector<std::string>& knobs = {}) {
        StillOptions so;
        so.width = so.height = kSize;
        so.settings.path = RenderPath::forward;
        apply_effects(so.settings, effects);
        apply_knobs(so.settings, knobs);
        const StillResult r = render_still(scene, shaders_, so);
        EXPECT_EQ(count_nonfinite(r.radiance), 0u);
        glm::dvec3 m(0.0);
        for (int y = 0; y < kSize; ++y)
            for (int x = 0; x < kSize; ++x) m += glm::dvec3(r.radiance.at(x, y)[0], r.radiance.at(x, y)[1], r.radiance.at(x, y)[2]);
        return m / static_cast<double>(kSize * kSize);
    }
    static double z(const Estimate& e, double expected, int c = 0) { return (e.mean[c] - expected) / e.se[c]; }
    // The estimate agrees with the closed form (|z| < 4), and a closed form 1 % off either way
    // would have failed: the batches resolve a bias of 1 %.
    static void expect_closed_form(const Estimate& e, double expected, const std::string& what) {
        std::printf("%s: traced %.5f +- %.5f, closed form %.5f, z %+.2f\n", what.c_str(), e.mean.x, e.se.x, expected, z(e, expected));
        EXPECT_LT(std::fabs(z(e, expected)), 4.0) << what;
        EXPECT_GE(std::fabs(z(e, expected * 1.01)), 4.0) << what << ": a 1 % bias would go unseen";
        EXPECT_GE(std::fabs(z(e, expected * 0.99)), 4.0) << what << ": a 1 % bias would go unseen";
    }
    // Energy is not created: every channel's albedo is at most 1 (z of the mean against 1 below 4).
    static void expect_at_most_one(const Estimate& e, const std::string& what) {
        std::printf("%s: traced %.5f %.5f %.5f (se %.5f)\n", what.c_str(), e.mean.x, e.mean.y, e.mean.z, e.se.x);
        for (int c = 0; c < 3; ++c) EXPECT_LT(z(e, 1.0, c), 4.0) << what << " channel " << c << ": albedo " << e.mean[c] << " > 1";
    }
    ShaderLibrary shaders_{fs::path(CANDELA_SOURCE_DIR) / "shaders"};
};

// A thin white glass wall (KHR_materials_transmission 1, no volume) under a uniform sky reflects
// F of the sky in front and passes 1 - F of the sky behind: 1 at every angle when smooth (the
// tracer's dielectric takes F(v.h) and 1 - F(v.h) about each microfacet); a rough wall loses what
// its single-scattering lobe shadows (the tracer: 0.97 at normal view, 0.87 at 80 degrees at
// roughness 0.4). The raster's ambient term splits the lobe's albedo A + B into f0 A + f90 B
// reflected and the rest transmitted. Weighting the transmitted light by the diffuse lobe's
// Fresnel instead (about 1 - f0 at any angle) made a grazing view 1.3 and the rough wall 1.0.
TEST_P(MaterialLayersTest, ThinGlassUnderAUniformSkyAddsUpToTheSky) {
    for (const float roughness : {0.0f, 0.4f})
        for (const double deg : {0.0, 60.0, 80.0}) {
            const json m = material(glm::vec3(1.0f), 0.0f, roughness, 1.0f, {{"KHR_materials_transmission", {{"transmissionFactor", 1.0}}}});
            const Scene scene = furnace("thin_glass", m, glm::radians(deg));
            const std::string what = "thin glass, roughness " + std::to_string(roughness) + ", " + std::to_string(static_cast<int>(deg)) + " deg";
            const Estimate t = trace(scene, 64);
            expect_at_most_one(t, what);
            if (roughness == 0.0f) EXPECT_LT(std::fabs(z(t, 1.0)), 4.0) << what << ": a smooth wall passes what it does not reflect";
            const glm::dvec3 r = raster(scene, "reflections");
            std::printf("%s: raster %.4f, traced %.4f +- %.4f\n", what.c_str(), r.x, t.mean.x, t.se.x);
            EXPECT_LT(r.x, 1.002) << what << ": the raster creates light";
            EXPECT_NEAR(r.x, t.mean.x, 0.02) << what;
        }
}

// A smooth coat over a white Lambert base reflects exactly 1 (Fc of the coat's mirror lobe plus
// 1 - Fc of the base) at every angle; a rough coat 1 - Fc + Fc E_ggx. Dropping the base's
// attenuation by 1 - Fc gives 1 + Fc, which fails both.
TEST_P(MaterialLayersTest, ClearcoatOverWhiteLambertIsOneWhenSmoothAndItsClosedFormWhenRough) {
    for (const double deg : {0.0, 60.0, 80.0}) {
        const double theta = glm::radians(deg), mu = std::cos(theta);
        {
            const Scene s = furnace("coat_smooth", white_lambert({{"KHR_materials_clearcoat", {{"clearcoatFactor", 1.0}}}}), theta);
            expect_closed_form(trace(s), 1.0, "smooth coat at " + std::to_string(int(deg)) + " deg");
            if (deg < 70.0) EXPECT_NEAR(raster(s).x, 1.0, 0.03) << "raster, smooth coat at " << deg << " deg";
        }
        {
            const double a = brdf_alpha(0.5);
            const double expected = 1.0 - coat_fresnel(mu) + coat_fresnel(mu) * ggx_albedo({0.0, std::sin(theta), mu}, a, a);
            const Scene s = furnace("coat_rough",
                                    white_lambert({{"KHR_materials_clearcoat", {{"clearcoatFactor", 1.0}, {"clearcoatRoughnessFactor", 0.5}}}}),
                                    theta);
            const Estimate e = trace(s);
            expect_closed_form(e, expected, "rough coat at " + std::to_string(int(deg)) + " deg");
            expect_at_most_one(e, "rough coat");
            if (deg < 70.0) EXPECT_NEAR(raster(s).x, expected, 0.03) << "raster, rough coat at " << deg << " deg";
        }
    }
}

// The sheen lobe alone (black base, no specular) reflects its own albedo, integrated here from
// the lobe's formula (tests/tools/sheen_albedo.hpp) at grid points of the shaders' table; over a
// white Lambert base the albedo scaling keeps the stack at most 1, at grazing views too.
TEST_P(MaterialLayersTest, SheenReflectsItsAlbedoAndKeepsTheStackWithinOne) {
    const double r = 15.0 / 31.0;  // a row of the table: its value is the integral itself
    // The smoothest sheen at a grazing view, where the fitted lobe's albedo exceeds 1 (1.54 at cos
    // 1/31) and the lobe is normalised.
    for (const double mu : {1.0 / 31.0, 2.0 / 31.0})
        expect_at_most_one(trace(furnace("sheen_grazing",
                                         white_lambert({{"KHR_materials_sheen", {{"sheenColorFactor", {1, 1, 1}}, {"sheenRoughnessFactor", 0.0}}}}),
                                         std::acos(mu))),
                           "smoothest sheen over white Lambert, cos " + std::to_string(mu));
    for (const double mu : {1.0, 20.0 / 31.0, 8.0 / 31.0}) {
        const double theta = std::acos(mu);
        const json sheen = {{"KHR_materials_sheen", {{"sheenColorFactor", {1, 1, 1}}, {"sheenRoughnessFactor", r}}}};
        const Scene alone = furnace("sheen_alone", material(glm::vec3(0.0f), 0.0f, 1.0f, 0.0f, sheen), theta);
        const double expected = std::min(sheen::albedo(mu, r), 1.0);
        const Estimate e = trace(alone);
        expect_closed_form(e, expected, "sheen alone at cos " + std::to_string(mu));
        if (mu > 0.5) EXPECT_NEAR(raster(alone).x, expected, 0.03) << "raster, sheen alone at cos " << mu;
        for (const double rough : {0.0, r, 1.0})
            expect_at_most_one(trace(furnace("sheen_white",
                                             white_lambert({{"KHR_materials_sheen", {{"sheenColorFactor", {1, 1, 1}}, {"sheenRoughnessFactor", rough}}}}),
                                             theta)),
                               "sheen over white Lambert, roughness " + std::to_string(rough) + ", cos " + std::to_string(mu));
    }
}

// Where the GI probes run they carry the sky's diffuse light instead of the ambient term, and the
// layers must take their share of it as they do of the ambient term: the sheen alone reflects its
// albedo, and a smooth coat over white Lambert stays 1 (the coat passes 1 - Fc of the probes'
// light). Shading the probes' light with the base lobes alone gave the sheen 0 and the coat 1 + Fc
// (1.09 at 60 degrees); on SheenChair, the GI-lit velvet lost its sheen. (The forward path: the
// deferred path's G-buffer holds the base only, as docs/materials.md says.)
TEST_P(MaterialLayersTest, LayersTakeTheirShareOfTheGiProbesLight) {
    const std::vector<std::string> gi_on = {"gi.threshold=0"};
    const double r = 15.0 / 31.0, mu = 20.0 / 31.0;
    const json sheen = {{"KHR_materials_sheen", {{"sheenColorFactor", {1, 1, 1}}, {"sheenRoughnessFactor", r}}}};
    const Scene alone = furnace("sheen_alone_gi", material(glm::vec3(0.0f), 0.0f, 1.0f, 0.0f, sheen), std::acos(mu));
    const double expected = std::min(sheen::albedo(mu, r), 1.0);
    const double without = raster(alone).x, with = raster(alone, "gi", gi_on).x;
    std::printf("sheen alone %.4f without GI, %.4f with (albedo %.4f)\n", without, with, expected);
    EXPECT_NEAR(with, expected, 0.03) << "sheen alone under the GI probes";
    const Scene coat = furnace("coat_smooth_gi", white_lambert({{"KHR_materials_clearcoat", {{"clearcoatFactor", 1.0}}}}), glm::radians(60.0));
    const double coat_with = raster(coat, "gi", gi_on).x;
    std::printf("smooth coat at 60 deg %.4f with GI\n", coat_with);
    EXPECT_NEAR(coat_with, 1.0, 0.03) << "smooth coat over white Lambert under the GI probes";
}

// White metal (F = 1): the anisotropic lobe's albedo, with the direction of anisotropy across the
// view (rotation 0: the quad's tangent, +x) and along it (rotation pi/2); the two differ, so a lost
// direction or rotation fails one of them. Strength 0 is the isotropic lobe.
TEST_P(MaterialLayersTest, AnisotropicMetalReflectsTheAnisotropicGgxAlbedo) {
    const double theta = glm::radians(60.0), mu = std::cos(theta), st = std::sin(theta);
    const double roughness = 0.4, strength = 0.8, a = brdf_alpha(roughness);
    const double at = a + (1.0 - a) * strength * strength;  // mix(alpha, 1, strength^2) along t
    const double across = ggx_albedo({0.0, st, mu}, at, a), along = ggx_albedo({st, 0.0, mu}, at, a);
    std::printf("anisotropic albedo: across %.5f, along %.5f, isotropic %.5f\n", across, along, ggx_albedo({0.0, st, mu}, a, a));
    ASSERT_GT(std::fabs(across - along), 0.02);  // the case can tell the directions apart
    for (const double rotation : {0.0, kPi / 2}) {
        const json m = material(glm::vec3(1.0f), 1.0f, static_cast<float>(roughness), 1.0f,
                                {{"KHR_materials_anisotropy", {{"anisotropyStrength", strength}, {"anisotropyRotation", rotation}}}});
        const Scene s = furnace("aniso", m, theta);
        const double expected = rotation == 0.0 ? across : along;
        expect_closed_form(trace(s), expected, "anisotropic metal, rotation " + std::to_string(rotation));
    }
}

// A thin film never creates energy (white Lambert dielectric and white metal under a 400 nm
// film), and it tints: on a black dielectric, whose light is all specular, a 400 nm film moves
// the colour of the reflection far from the film-less one (0 nm).
TEST_P(MaterialLayersTest, IridescenceTintsWithoutCreatingEnergy) {
    for (const float metallic : {0.0f, 1.0f}) {
        const json m = material(glm::vec3(1.0f), metallic, 0.3f, 1.0f,
                                {{"KHR_materials_iridescence", {{"iridescenceFactor", 1.0}, {"iridescenceThicknessMaximum", 400.0}}}});
        expect_at_most_one(trace(furnace("iridescence", m, glm::radians(30.0))), "iridescence over white, metallic " + std::to_string(metallic));
    }
    glm::dvec3 film[2];
    for (int k = 0; k < 2; ++k) {
        const json m = material(glm::vec3(0.0f), 0.0f, 0.3f, 1.0f,
                                {{"KHR_materials_iridescence", {{"iridescenceFactor", 1.0}, {"iridescenceThicknessMaximum", k ? 400.0 : 0.0}}}});
        film[k] = trace(furnace("iridescence_black", m, glm::radians(30.0))).mean;
        std::printf("black dielectric, film %d nm: %.5f %.5f %.5f\n", k ? 400 : 0, film[k].x, film[k].y, film[k].z);
    }
    const glm::dvec3 ratio = film[1] / film[0];
    EXPECT_GT(std::max({ratio.x, ratio.y, ratio.z}) - std::min({ratio.x, ratio.y, ratio.z}), 0.2) << "a 400 nm film must tint the reflection";
}

// Unlit: every ray that meets the surface sees its base colour, whatever the light; the raster
// draws the same colour.
TEST_P(MaterialLayersTest, UnlitShowsItsBaseColourExactly) {
    const glm::vec3 c(0.2f, 0.5f, 0.8f);
    json m = {{"pbrMetallicRoughness", {{"baseColorFactor", {c.r, c.g, c.b, 1}}}}, {"extensions", {{"KHR_materials_unlit", json::object()}}}};
    const Scene s = furnace("unlit", m, glm::radians(40.0));
    const Estimate e = trace(s, 2);
    const glm::dvec3 r = raster(s);
    for (int ch = 0; ch < 3; ++ch) {
        EXPECT_NEAR(e.mean[ch], c[ch], 1e-5) << "traced channel " << ch;
        EXPECT_NEAR(r[ch], c[ch], 2e-3) << "raster channel " << ch;
    }
}

INSTANTIATE_TEST_SUITE_P(Backends, MaterialLayersTest, ::testing::Values(Backend::egl), test::backend_name);

}  // namespace material_layers_test
}  // namespace candela
