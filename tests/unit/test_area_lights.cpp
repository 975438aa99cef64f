// Area lights in the raster path: emissive triangles shaded as polygon lights by
// linearly transformed cosines, judged against the ray tracer's `direct` mode (exact), and the
// energy bound: no passive surface is brighter than the brightest emitter it reflects.
#include <gtest/gtest.h>

#include <glm/gtx/quaternion.hpp>

#include <algorithm>
#include <cmath>

#include "effects/area_lights/area_lights.hpp"
#include "gltf_builder.hpp"
#include "reference_fixture.hpp"
#include "scene/gltf_loader.hpp"
#include "shapes.hpp"

namespace candela {
namespace {
namespace fs = std::filesystem;
using nlohmann::json;

json quat(glm::vec3 dir) {
    const glm::quat q = glm::rotation(glm::vec3(0, 0, -1), glm::normalize(dir));
    return {q.x, q.y, q.z, q.w};
}

json material(glm::vec3 base, float metallic, float roughness) {
    return {{"pbrMetallicRoughness", {{"baseColorFactor", {base.r, base.g, base.b, 1}}, {"metallicFactor", metallic}, {"roughnessFactor", roughness}}}};
}

// A black, one-sided emitter of radiance Le (it reflects nothing: its pixels are exactly Le).
json emitter(float Le) {
    json m = {{"pbrMetallicRoughness", {{"baseColorFactor", {0, 0, 0, 1}}, {"metallicFactor", 0}}}, {"emissiveFactor", {1, 1, 1}}};
    m["extensions"] = json::object();
    m["extensions"]["KHR_materials_emissive_strength"] = {{"emissiveStrength", Le}};
    m["extensions"]["KHR_materials_specular"] = {{"specularFactor", 0}};
    return m;
}

// A 0.6 x 0.6 quad light 1.2 above a 4 x 4 floor, facing down, seen from above at 40-60 degrees
// from the normal (NdotV 0.55 to 0.85) so that the floor shows the light's reflection. Grazing
// views are where the LTC fit is weakest (test_ltc.cpp measures the fit itself).
// (`half`, `height`: the light's half side and height, for other tests.)
Scene floor_under_quad(const std::string& name, glm::vec3 base, float metallic, float roughness, float Le, float half = 0.3f,
                       float height = 1.2f) {
    test::GltfBuilder b;
    b.json()["materials"] = {material(base, metallic, roughness), emitter(Le)};
    const int quad0 = b.add_quad_mesh(0), quad1 = b.add_quad_mesh(1);
    b.add_node({{"mesh", quad0}, {"rotation", {-0.70710678, 0, 0, 0.70710678}}, {"scale", {2, 2, 2}}});  // floor facing +Y
    b.add_node({{"mesh", quad1}, {"translation", {0, height, -0.3}}, {"rotation", {0.70710678, 0, 0, 0.70710678}}, {"scale", {half, half, 1}}});  // facing -Y
    b.json()["cameras"] = {{{"type", "perspective"}, {"perspective", {{"yfov", 0.8}, {"znear", 0.05}}}}};
    b.add_node({{"camera", 0}, {"translation", {0, 2.4, 1.6}}, {"rotation", quat(glm::vec3(0, -2.4, -2.0))}});
    return load_gltf(b.write(test::test_dir(name), name));
}

class AreaLightTest : public test::ReferenceTest {
protected:
    ImageF direct(const Scene& scene, int n, int spp) {
        rt::Options o;
        o.mode = rt::Mode::direct;
        o.spp = spp;
        o.jitter = 0;  // pixel centres, where the rasterizer samples
        return traced(scene, n, n, o).image;
    }
    // Per-pixel relative error where the reference holds at least `share` of its brightest
    // pixel: the 95th percentile and the maximum; and the relative error of the image sum.
    struct Errors {
        double p95 = 0.0, max = 0.0, sum = 0.0;
    };
    static Errors relative_errors(const ImageF& raster, const ImageF& ref, double share) {
        double peak = 0.0, sum_a = 0.0, sum_r = 0.0;
        for (size_t i = 0; i < ref.pixels.size(); i += 4) {
            peak = std::max(peak, static_cast<double>(ref.pixels[i + 1]));
            sum_a += raster.pixels[i + 1];
            sum_r += ref.pixels[i + 1];
        }
        std::vector<double> e;
        for (size_t i = 0; i < ref.pixels.size(); i += 4)
            if (ref.pixels[i + 1] > share * peak) e.push_back(std::fabs(raster.pixels[i + 1] - ref.pixels[i + 1]) / ref.pixels[i + 1]);
        std::sort(e.begin(), e.end());
        Errors out;
        if (!e.empty()) out = {e[static_cast<size_t>(0.95 * static_cast<double>(e.size() - 1))], e.back(), 0.0};
        out.sum = sum_r > 0.0 ? std::fabs(sum_a - sum_r) / sum_r : 0.0;
        return out;
    }
    static double max_radiance(const ImageF& img) {
        double m = 0.0;
        for (size_t i = 0; i < img.pixels.size(); i += 4) m = std::max({m, static_cast<double>(img.pixels[i]), static_cast<double>(img.pixels[i + 1]), static_cast<double>(img.pixels[i + 2])});
        return m;
    }
};

// Unshadowed polygon light on a smooth and a rough floor, metal (the specular LTC alone) and
// dielectric (diffuse and specular): the raster agrees with the tracer per pixel.
// Two coplanar triangles of one emitter with the same radiance are integrated as one convex quad
// (the quad light test below then checks the quad's shading against the tracer); a folded pair
// stays two triangles.
TEST_P(AreaLightTest, CoplanarTrianglePairsBecomeOneQuad) {
    {
        const Scene scene = floor_under_quad("merge_quad", glm::vec3(0.5f), 0.0f, 1.0f, 4.0f);
        GpuScene gpu(scene);
        const std::vector<PolygonLightGpu> polys = polygon_lights(scene, gpu, 4);
        ASSERT_EQ(polys.size(), 1u);
        EXPECT_EQ(polys[0].corners, 4.0f);
        // The quad's area (two triangles fanned from p0) is the light's 0.6 x 0.6.
        const PolygonLightGpu& q = polys[0];
        const float area = 0.5f * glm::length(glm::cross(q.p1 - q.p0, q.p2 - q.p0)) + 0.5f * glm::length(glm::cross(q.p2 - q.p0, q.p3 - q.p0));
        EXPECT_NEAR(area, 0.36f, 1e-5f);
        // Convex, wound one way: every corner turns the same way as the first.
        const glm::vec3 c[4] = {q.p0, q.p1, q.p2, q.p3};
        const glm::vec3 n = glm::cross(c[1] - c[0], c[2] - c[1]);
        for (int k = 0; k < 4; ++k) EXPECT_GT(glm::dot(glm::cross(c[(k + 1) % 4] - c[k], c[(k + 2) % 4] - c[(k + 1) % 4]), n), 0.0f);
    }
    {
        test::GltfBuilder b;
        b.json()["materials"] = {emitter(2.0f)};
        const std::vector<glm::vec3> p = {{0, 0, 0}, {1, 0, 0}, {1, 1, 0}, {0, 1, 0.5f}};  // the fourth corner lifted
        b.add_node({{"mesh", b.add_mesh({{"POSITION", b.add_positions(p)}}, b.add_indices({0, 1, 2, 0, 2, 3}), 0)}});
        const Scene scene = load_gltf(b.write(test::test_dir("merge_folded"), "merge_folded"));
        GpuScene gpu(scene);
        const std::vector<PolygonLightGpu> polys = polygon_lights(scene, gpu, 4);
        ASSERT_EQ(polys.size(), 2u);
        for (const PolygonLightGpu& t : polys) EXPECT_EQ(t.corners, 3.0f);
    }
}

TEST_P(AreaLightTest, QuadLightOnSmoothAndRoughFloorsMatchesTheTracer) {
    struct Case {
        const char* name;
        glm::vec3 base;
        float metallic, roughness;
        double p95_bound, max_bound, sum_bound;  // over pixels with >= 10 % of the peak; the image sum
    };
    // Bounds: the measured values (printed below) rounded up. What remains is the LTC fit's own
    // error (test_ltc.cpp) where the residual fades out (cells that hold a sharp lobe), the
    // residual's 3x3-cell quadrature elsewhere, and, for dielectrics, the Fresnel weight of the
    // diffuse lobe taken at one direction.
    const Case cases[] = {
        // measured (LTC and its residual): p95 0.064 max 0.120 sum 0.0004 / 0.172 0.322 0.0087 /
        // 0.034 0.089 0.0014 / 0.037 0.202 0.0002. The LTC alone: 0.103 0.206 0.027 / 0.185 0.334
        // 0.0002 / 0.033 0.076 0.011 / 0.037 0.202 0.0096; the 4 pieces: p95 0.074 / 2.31 / 0.035 /
        // 0.111, max up to 6.1.
        {"rough metal", glm::vec3(0.9f), 1.0f, 0.5f, 0.08, 0.16, 0.01},
        {"smooth metal", glm::vec3(0.9f), 1.0f, 0.15f, 0.20, 0.36, 0.012},
        {"rough dielectric", glm::vec3(0.6f), 0.0f, 0.5f, 0.05, 0.10, 0.005},
        {"smooth dielectric", glm::vec3(0.6f), 0.0f, 0.15f, 0.05, 0.22, 0.005},
    };
    const int n = 64;
    for (const Case& c : cases) {
        SCOPED_TRACE(c.name);
        const Scene scene = floor_under_quad("ltc_floor", c.base, c.metallic, c.roughness, 5.0f);
        const ImageF ref = direct(scene, n, 256);
        const Errors ltc = relative_errors(raster(scene, n, n, settings("none", {"arealight.method=ltc"})), ref, 0.1);
        const Errors pieces = relative_errors(raster(scene, n, n, settings("none", {"arealight.method=pieces"})), ref, 0.1);
        std::printf("%s: LTC relative error p95 %.4f max %.4f sum %.4f; 4 pieces p95 %.4f max %.4f sum %.4f\n", c.name, ltc.p95, ltc.max,
                    ltc.sum, pieces.p95, pieces.max, pieces.sum);
        EXPECT_LT(ltc.p95, c.p95_bound);
        EXPECT_LT(ltc.max, c.max_bound);
        EXPECT_LT(ltc.sum, c.sum_bound);
    }
}

// Where a clamped cosine cannot take GGX's shape, the specular the fitted lobe misses is measured
// on the pieces (arealight.residual): a large light seen only in the tail of a smooth metal wall's
// lobe (the view's mirror direction points away from it; GGX's f cos stays finite towards the
// horizon while the fit's cosine goes to 0), and a small light towards the viewer over a rough
// metal floor seen at a grazing angle (the fit's worst entries, test_ltc.cpp).
TEST_P(AreaLightTest, LightInTheLobesTailOrTowardsAGrazingViewMatchesTheTracer) {
    struct Case {
        const char* name;
        float roughness;
        glm::vec3 light_at, light_scale, camera, target;
        double sum_bound, p95_bound;  // with the residual (relative errors, pixels >= 10 % of the peak)
        double off_at_least;          // without it the image sum misses by more than this
    };
    const Case cases[] = {
        // measured with the residual: sum 0.0032 p95 0.059 / sum 0.030 p95 0.119; without it:
        // sum 0.241 p95 0.41 / sum 0.280 p95 1.25.
        {"tail of a smooth metal wall", 0.16f, {0, 5, 2.5}, {2, 1.5, 1}, {0, 1.5, 5}, {0, 0, 0}, 0.01, 0.08, 0.15},
        {"light towards a grazing view", 0.3f, {0, 1.5, 0.5}, {0.5, 0.25, 1}, {0, 0.6, 3.5}, {0, 0, 0}, 0.05, 0.16, 0.15},
    };
    const int n = 64;
    for (size_t k = 0; k < std::size(cases); ++k) {
        const Case& c = cases[k];
        SCOPED_TRACE(c.name);
        test::GltfBuilder b;
        b.json()["materials"] = {material(glm::vec3(0.9f), 1.0f, c.roughness), emitter(20.0f)};
        // Case 0: a wall facing +Z; case 1: a floor facing +Y. The light faces -Y.
        json surface = {{"mesh", b.add_quad_mesh(0)}, {"scale", {2, 2, 2}}};
        if (k == 1) surface["rotation"] = {-0.70710678, 0, 0, 0.70710678};
        b.add_node(surface);
        b.add_node({{"mesh", b.add_quad_mesh(1)}, {"translation", {c.light_at.x, c.light_at.y, c.light_at.z}},
                    {"rotation", {0.70710678, 0, 0, 0.70710678}}, {"scale", {c.light_scale.x, c.light_scale.y, c.light_scale.z}}});
        b.json()["cameras"] = {{{"type", "perspective"}, {"perspective", {{"yfov", 0.8}, {"znear", 0.05}}}}};
        b.add_node({{"camera", 0}, {"translation", {c.camera.x, c.camera.y, c.camera.z}}, {"rotation", quat(c.target - c.camera)}});
        const Scene scene = load_gltf(b.write(test::test_dir("ltc_residual"), "ltc_residual" + std::to_string(k)));
        const ImageF ref = direct(scene, n, 256);
        const Errors on = relative_errors(raster(scene, n, n, settings("none", {})), ref, 0.1);
        const Errors off = relative_errors(raster(scene, n, n, settings("none", {"arealight.residual=0"})), ref, 0.1);
        std::printf("%s: with the residual p95 %.4f max %.4f sum %.4f; without p95 %.4f max %.4f sum %.4f\n", c.name, on.p95, on.max, on.sum,
                    off.p95, off.max, off.sum);
        EXPECT_LT(on.sum, c.sum_bound);
        EXPECT_LT(on.p95, c.p95_bound);
        EXPECT_GT(off.sum, c.off_at_least) << "the fitted lobe alone is right here: this case no longer shows what the residual is for";
    }
}

// The reflection of a quad light in a smooth metal sphere has at most the light's radiance: the old
// pieces, point lights with a finite lobe, made highlights several times brighter than the light.
TEST_P(AreaLightTest, MirrorSphereReflectsTheLightsRadianceNotMore) {
    const float Le = 17.0f;
    test::GltfBuilder b;
    // Roughness 0.1: a highlight wide enough for the pixel centres to find it (roughness 0 is in
    // the energy test below).
    b.json()["materials"] = {material(glm::vec3(1.0f), 1.0f, 0.1f), emitter(Le)};
    b.add_node({{"mesh", test::add_closed_sphere(b, 0)}, {"scale", {0.5, 0.5, 0.5}}});
    b.add_node({{"mesh", b.add_quad_mesh(1)}, {"translation", {0, 1.0, 0}}, {"rotation", {0.70710678, 0, 0, 0.70710678}}, {"scale", {0.3, 0.3, 1}}});
    b.json()["cameras"] = {{{"type", "perspective"}, {"perspective", {{"yfov", 0.5}, {"znear", 0.05}}}}};
    b.add_node({{"camera", 0}, {"translation", {0, 0.3, 2.5}}, {"rotation", quat(glm::vec3(0, -0.3, -2.5))}});
    const Scene scene = load_gltf(b.write(test::test_dir("mirror_sphere"), "mirror_sphere"));
    const int n = 96;
    const ImageF ltc = raster(scene, n, n, settings("none", {}));
    const ImageF pieces = raster(scene, n, n, settings("none", {"arealight.method=pieces"}));
    const double ltc_max = max_radiance(ltc), pieces_max = max_radiance(pieces);
    std::printf("mirror sphere under a light of radiance %.1f: brightest pixel %.2f (LTC), %.2f (4 pieces)\n", Le, ltc_max, pieces_max);
    EXPECT_LE(ltc_max, Le * 1.001);
    EXPECT_GT(ltc_max, Le * 0.8) << "the light's reflection is missing";
    EXPECT_GT(pieces_max, Le) << "the pieces' overshoot is gone: this test no longer shows what it guards against";
}

// Energy: with only area lights (punctual lights and the environment removed), no pixel of a
// passive surface exceeds the largest emitted radiance, for any roughness (0 included) and
// metalness, on the sample scenes with emitters and on the floor scene above.
TEST_P(AreaLightTest, NoPassiveSurfaceIsBrighterThanTheBrightestEmitter) {
    std::vector<Scene> scenes;
    scenes.push_back(load_gltf(fs::path(CANDELA_SOURCE_DIR) / "samples" / "scenes" / "cornell_box.gltf"));
    scenes.push_back(floor_under_quad("energy_floor", glm::vec3(1.0f), 1.0f, 0.0f, 9.0f));
    int checked = 0;
    for (Scene& base : scenes) {
        double le_max = 0.0;
        for (const Material& m : base.materials) le_max = std::max({le_max, static_cast<double>(m.emission().r), static_cast<double>(m.emission().g), static_cast<double>(m.emission().b)});
        ASSERT_GT(le_max, 0.0);
        for (float roughness : {0.0f, 0.05f, 0.3f, 1.0f})
            for (float metallic : {0.0f, 1.0f}) {
                Scene s = base;
                s.lights.clear();
                for (Node& node : s.nodes) node.light = -1;
                s.environment = Scene{}.environment;
                for (Material& m : s.materials) {
                    if (m.is_emissive()) {  // black emitters: their pixels are exactly their radiance
                        m.base_color = glm::vec4(0.0f, 0.0f, 0.0f, 1.0f);
                        m.specular_factor = 0.0f;
                        m.metallic = 0.0f;
                        continue;
                    }
                    m.base_color = glm::vec4(1.0f);
                    m.base_color_texture = TextureRef{};
                    m.metallic_roughness_texture = TextureRef{};
                    m.roughness = roughness;
                    m.metallic = metallic;
                }
                const ImageF img = raster(s, 96, 96, settings("shadows", {}));
                const double peak = max_radiance(img);
                EXPECT_LE(peak, le_max * 1.001) << "roughness " << roughness << " metallic " << metallic;
                ++checked;
            }
    }
    EXPECT_EQ(checked, 16);
}

// Block means (b x b pixels): the reference's noise averages out, the raster's bias stays.
ImageF block_means(const ImageF& img, int b) {
    ImageF out(img.width / b, img.height / b, 4);
    for (int y = 0; y < out.height; ++y)
        for (int x = 0; x < out.width; ++x) {
            float* o = out.at(x, y);
            for (int j = 0; j < b; ++j)
                for (int i = 0; i < b; ++i)
                    for (int c = 0; c < 3; ++c) o[c] += img.at(x * b + i, y * b + j)[c] / static_cast<float>(b * b);
            o[3] = 1.0f;
        }
    return out;
}

// cornell_box's direct light is closer to the tracer with LTC than with the 4 pieces: per pixel
// (RMSE, where the reference's noise weighs in) and on 8 x 8 block means (the bias alone).
TEST_P(AreaLightTest, CornellBoxDirectLightIsCloserToTheTracerThanThePieces) {
    const Scene scene = load_gltf(fs::path(CANDELA_SOURCE_DIR) / "samples" / "scenes" / "cornell_box.gltf");
    const int n = 96;
    const ImageF ref = direct(scene, n, 64);
    const ImageF ltc_img = raster(scene, n, n, settings("shadows", {}));
    const ImageF pieces_img = raster(scene, n, n, settings("shadows", {"arealight.method=pieces"}));
    const CompareResult ltc = compare(ltc_img, ref, 2.0 / 255.0), pieces = compare(pieces_img, ref, 2.0 / 255.0);
    const CompareResult ltc_blocks = compare(block_means(ltc_img, 8), block_means(ref, 8), 2.0 / 255.0);
    const CompareResult pieces_blocks = compare(block_means(pieces_img, 8), block_means(ref, 8), 2.0 / 255.0);
    std::printf("cornell_box vs --raytrace direct (64 spp): RMSE %.5f rel. MSE %.6f, 8x8 blocks RMSE %.5f (LTC); RMSE %.5f rel. MSE %.6f, "
                "blocks RMSE %.5f (4 pieces)\n",
                ltc.rmse, ltc.relative_mse, ltc_blocks.rmse, pieces.rmse, pieces.relative_mse, pieces_blocks.rmse);
    EXPECT_LT(ltc_blocks.rmse, pieces_blocks.rmse);
    EXPECT_LT(ltc.rmse, pieces.rmse * 1.02);  // no worse per pixel (the reference's noise dominates there)
}

// arealight.far_field: a 0.1 m square light 1.5 m above the floor is under 1/20 of a radian
// wide from every floor point, so where the lobe is wide (roughness 0.5) it is shaded as a
// point emitter; the image stays within the point's bound (the irradiance of a disk of angular
// radius t is the point's times 1 / (1 + t^2): 0.25 % here) of the LTC's and as close to the
// tracer. On a smooth metal (a lobe narrower than 4 t) the LTC still shades it: the same image
// bit for bit.
TEST_P(AreaLightTest, SmallFarLightsShadeAsPointsWithinTheirBound) {
    struct Case {
        const char* name;
        glm::vec3 base;
        float metallic, roughness;
        bool far;  // the far field applies
    };
    const Case cases[] = {{"rough dielectric", glm::vec3(0.6f), 0.0f, 0.5f, true},
                          {"rough metal", glm::vec3(0.9f), 1.0f, 0.5f, true},
                          {"smooth metal", glm::vec3(0.9f), 1.0f, 0.15f, false}};
    const int n = 64;
    for (const Case& c : cases) {
        SCOPED_TRACE(c.name);
        const Scene scene = floor_under_quad("far_field", c.base, c.metallic, c.roughness, 400.0f, 0.05f, 1.5f);
        const ImageF point = raster(scene, n, n, settings("none", {"arealight.far_field=8"}));
        const ImageF ltc = raster(scene, n, n, settings("none", {"arealight.far_field=0"}));
        const ImageF ref = direct(scene, n, 256);
        EXPECT_EQ(count_nonfinite(point), 0u);
        EXPECT_EQ(count_nonfinite(ltc), 0u);
        size_t differ = 0;
        for (size_t i = 0; i < point.pixels.size(); ++i) differ += point.pixels[i] != ltc.pixels[i];
        const Errors against_ltc = relative_errors(point, ltc, 0.1);
        const Errors point_ref = relative_errors(point, ref, 0.1), ltc_ref = relative_errors(ltc, ref, 0.1);
        std::printf("%s: %zu values differ; point vs LTC p95 %.5f max %.5f sum %.5f; vs tracer point p95 %.4f sum %.4f, LTC p95 %.4f "
                    "sum %.4f\n",
                    c.name, differ, against_ltc.p95, against_ltc.max, against_ltc.sum, point_ref.p95, point_ref.sum, ltc_ref.p95,
                    ltc_ref.sum);
        if (!c.far) {
            EXPECT_EQ(differ, 0u);
            continue;
        }
        EXPECT_GT(differ, 0u) << "the far field shaded nothing";
        EXPECT_LT(against_ltc.sum, 0.01);
        EXPECT_LT(against_ltc.p95, 0.03);
        EXPECT_LT(point_ref.p95, ltc_ref.p95 + 0.01);
        EXPECT_LT(point_ref.sum, ltc_ref.sum + 0.01);
    }
}

INSTANTIATE_TEST_SUITE_P(Backends, AreaLightTest, ::testing::Values(Backend::egl), test::backend_name);

}  // namespace
}  // namespace candela
