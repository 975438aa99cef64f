// Environment reflection maps judged against closed forms and the ray tracer: the split-sum LUT
// against an independent quadrature, a mirror sphere in a constant environment (exactly the
// environment's colour through every lookup path), and reflections.gltf's mirror sphere against
// `--raytrace whitted` with max depth 1 (static > dynamic > box-projected error).
#include <gtest/gtest.h>

#include <cmath>

#include <glm/gtc/matrix_transform.hpp>

#include "core/error.hpp"
#include "gltf_builder.hpp"
#include "image/image.hpp"
#include "reference_fixture.hpp"
#include "render/environment.hpp"
#include "effects/reflections/reflections.hpp"
#include "scene/gltf_loader.hpp"

namespace candela {
namespace {
namespace fs = std::filesystem;
using nlohmann::json;

constexpr double kPi = 3.14159265358979323846;

// The specular lobe's (A, B) by midpoint quadrature over the hemisphere of l (uniform in cos
// theta and phi): an estimator independent of the shader's GGX importance sampling.
glm::dvec2 lut_quadrature(double NdotV, double roughness) {
    const double alpha = std::max(roughness * roughness, 1e-3), a2 = alpha * alpha;
    const glm::dvec3 v(std::sqrt(1.0 - NdotV * NdotV), 0.0, NdotV);
    const int nt = 1024, np = 1024;
    glm::dvec2 sum(0.0);
    for (int i = 0; i < nt; ++i) {
        const double ct = (i + 0.5) / nt, st = std::sqrt(1.0 - ct * ct);
        for (int j = 0; j < np; ++j) {
            const double phi = 2.0 * kPi * (j + 0.5) / np;
            const glm::dvec3 l(st * std::cos(phi), st * std::sin(phi), ct);
            const glm::dvec3 h = glm::normalize(l + v);
            const double NdotH = h.z, VdotH = glm::dot(v, h), NdotL = ct;
            const double d = NdotH * NdotH * (a2 - 1.0) + 1.0;
            const double D = a2 / (kPi * d * d);
            const double gv = NdotL * std::sqrt(NdotV * NdotV * (1.0 - a2) + a2);
            const double gl = NdotV * std::sqrt(NdotL * NdotL * (1.0 - a2) + a2);
            const double V = 0.5 / (gv + gl);
            const double fc = std::pow(1.0 - VdotH, 5.0);
            const double f = D * V * NdotL;  // d omega = d(cos theta) d phi
            sum += glm::dvec2((1.0 - fc) * f, fc * f);
        }
    }
    return sum * (2.0 * kPi / (static_cast<double>(nt) * np));
}

// A UV sphere of radius 1 (positions = normals).
int add_sphere_mesh(test::GltfBuilder& b, int material) {
    std::vector<glm::vec3> p;
    std::vector<uint32_t> idx;
    const int rings = 48, segments = 96;
    for (int r = 0; r <= rings; ++r)
        for (int s = 0; s <= segments; ++s) {
            const double t = kPi * r / rings, ph = 2.0 * kPi * s / segments;
            p.emplace_back(std::sin(t) * std::cos(ph), std::cos(t), -std::sin(t) * std::sin(ph));
        }
    for (int r = 0; r < rings; ++r)
        for (int s = 0; s < segments; ++s) {
            const uint32_t a = static_cast<uint32_t>(r * (segments + 1) + s), c = a + segments + 1;
            idx.insert(idx.end(), {a, c, a + 1, a + 1, c, c + 1});
        }
    return b.add_mesh({{"POSITION", b.add_positions(p)}, {"NORMAL", b.add_vec3(p)}}, b.add_indices(idx), material);
}

const glm::vec3 kEnv(0.3f, 0.5f, 0.7f);

// An equirect map of kEnv, or (`gradient`) of a colour that changes with direction,
// 0.2 + 0.3 (d + 1), so that a lookup in a wrong direction shows.
void write_environment_map(const fs::path& path, bool gradient) {
    ImageF img(256, 128, 4);
    for (int y = 0; y < img.height; ++y)
        for (int x = 0; x < img.width; ++x) {
            // The inverse of direction_to_equirect (shaders/common/math.glsl).
            const double theta = kPi * (y + 0.5) / img.height, phi = 2.0 * kPi * ((x + 0.5) / img.width - 0.5);
            const glm::vec3 d(std::sin(theta) * std::sin(phi), std::cos(theta), -std::sin(theta) * std::cos(phi));
            const glm::vec3 c = gradient ? 0.2f + 0.3f * (d + 1.0f) : kEnv;
            for (int ch = 0; ch < 3; ++ch) img.at(x, y)[ch] = c[ch];
            img.at(x, y)[3] = 1.0f;
        }
    write_image(path, img);
}

// A perfect mirror (white metal, roughness 0) in a constant environment, seen head-on; with
// `map`, an equirect map of the constant, or (`gradient`) of a colour that changes with
// direction, so that a wrongly oriented cube face shows.
Scene mirror_sphere_scene(const std::string& map, bool gradient = false) {
    test::GltfBuilder b;
    b.json()["materials"] = {{{"pbrMetallicRoughness", {{"baseColorFactor", {1, 1, 1, 1}}, {"metallicFactor", 1}, {"roughnessFactor", 0}}}}};
    b.add_node({{"mesh", add_sphere_mesh(b, 0)}, {"extras", {{"sphere", {{"radius", 1.0}}}}}});
    b.json()["scenes"][0]["extras"]["environment_radiance"] = {kEnv.r, kEnv.g, kEnv.b};
    const fs::path dir = test::test_dir("mirror_env");
    if (!map.empty()) {
        write_environment_map(dir / map, gradient);
        b.json()["scenes"][0]["extras"]["environment_map"] = map;
    }
    b.json()["cameras"] = {{{"type", "perspective"}, {"perspective", {{"yfov", 0.5}, {"znear", 0.05}}}}};
    b.add_node({{"camera", 0}, {"translation", {0, 0, 4}}});
    return load_gltf(b.write(dir, "mirror"));
}

class ReflectionsTest : public test::ReferenceTest {};

// `whitted` with one ray through each pixel's centre (as the raster samples), to max_depth.
rt::Options whitted_at_centres(int max_depth) {
    rt::Options o;
    o.mode = rt::Mode::whitted;
    o.max_depth = max_depth;
    o.spp = 1;
    o.jitter = 0;
    return o;
}

TEST_P(ReflectionsTest, BrdfLutMatchesAnIndependentQuadrature) {
    ImageBasedLighting ibl(lib_);
    const int n = ImageBasedLighting::kLutSize;
    std::vector<float> lut(static_cast<size_t>(n * n * 2));
    glGetTextureImage(ibl.brdf_lut().id(), 0, GL_RG, GL_FLOAT, static_cast<GLsizei>(lut.size() * sizeof(float)), lut.data());
    auto at = [&](int i, int j) { return glm::vec2(lut[static_cast<size_t>((j * n + i) * 2)], lut[static_cast<size_t>((j * n + i) * 2 + 1)]); };
    for (float x : lut) ASSERT_TRUE(std::isfinite(x));
    // Roughness 0: a mirror's lobe reflects everything (A + B = 1) away from grazing angles.
    for (int i = n / 8; i < n; ++i) EXPECT_NEAR(at(i, 0).x + at(i, 0).y, 1.0f, 2e-3f) << "NdotV " << float(i) / float(n - 1);
    // Rough rows against the quadrature (which resolves lobes of alpha >= 0.06 well).
    for (int j : {n / 4, n / 2, 3 * n / 4, n - 1})
        for (int i : {n / 8, n / 2, n - 1}) {
            const glm::dvec2 q = lut_quadrature(static_cast<double>(i) / (n - 1), static_cast<double>(j) / (n - 1));
            EXPECT_NEAR(at(i, j).x, q.x, 0.01) << "A at NdotV " << i << "/" << n - 1 << ", roughness " << j << "/" << n - 1;
            EXPECT_NEAR(at(i, j).y, q.y, 0.01) << "B at NdotV " << i << "/" << n - 1 << ", roughness " << j << "/" << n - 1;
        }
    // Energy of the lobe falls with roughness (single scattering loses the multiply-scattered part).
    EXPECT_GT(at(n / 2, 0).x + at(n / 2, 0).y, at(n / 2, n - 1).x + at(n / 2, n - 1).y + 0.1f);
}

// Every lookup path reproduces a constant environment exactly on a perfect mirror: the constant
// itself, the equirect map through the prefiltered cube, and a probe that sees only the sky.
TEST_P(ReflectionsTest, MirrorSphereInConstantEnvironmentIsTheEnvironment) {
    const int w = 64;
    struct Case {
        const char* name;
        std::string map;
        std::string effects;
    };
    for (const Case& c : {Case{"constant", "", "none"}, Case{"constant + probe", "", "reflections"},
                          Case{"map cube", "env.exr", "none"}, Case{"map + probe", "env.exr", "reflections"}}) {
        const Scene scene = mirror_sphere_scene(c.map);
        const ImageF img = raster(scene, w, w, settings(c.effects, {}));
        // The sphere covers the centre: 1 / tan(0.25) / 4 = 1.02 of the half height; use the
        // inner 60 % of its disc (away from grazing angles and silhouette pixels).
        double worst = 0.0;
        int pixels = 0;
        for (int y = 0; y < w; ++y)
            for (int x = 0; x < w; ++x) {
                const double dx = (x + 0.5) / w * 2.0 - 1.0, dy = (y + 0.5) / w * 2.0 - 1.0;
                if (dx * dx + dy * dy > 0.36) continue;
                for (int ch = 0; ch < 3; ++ch)
                    worst = std::max(worst, static_cast<double>(std::abs(img.at(x, y)[ch] - kEnv[ch]) / kEnv[ch]));
                ++pixels;
            }
        EXPECT_GT(pixels, 1000);
        EXPECT_LT(worst, 2e-3) << c.name << ": largest relative difference from the environment";
    }
}

double rmse_over(const ImageF& a, const ImageF& b, const std::vector<std::pair<int, int>>& pixels);

// A map whose colour follows the direction: the static cube (and a probe that sees only the sky)
// must show on the mirror what the tracer's mirror reflection shows. A face turned or flipped
// would put colours of other directions there.
TEST_P(ReflectionsTest, MirrorSphereReflectsAMapWhereTheTracerDoes) {
    const Scene scene = mirror_sphere_scene("gradient.exr", true);
    const int w = 64;
    const ImageF reference = traced(scene, w, w, whitted_at_centres(1)).image;
    std::vector<std::pair<int, int>> inner;
    for (int y = 0; y < w; ++y)
        for (int x = 0; x < w; ++x) {
            const double dx = (x + 0.5) / w * 2.0 - 1.0, dy = (y + 0.5) / w * 2.0 - 1.0;
            if (dx * dx + dy * dy <= 0.64) inner.emplace_back(x, y);
        }
    for (const char* effects : {"none", "reflections"}) {
        const double e = rmse_over(raster(scene, w, w, settings(effects, {})), reference, inner);
        std::printf("mirror in a direction-coloured map, --effects %s: RMSE %.5f vs whitted\n", effects, e);
        // The colours span 0.2..0.8; resampling the map into 128-texel faces costs ~1e-3.
        EXPECT_LT(e, 0.01) << effects;
    }
}

// Pixels of a sphere (centre, radius) in the scene's first camera at w x h.
std::vector<std::pair<int, int>> sphere_pixels(const Scene& scene, int w, int h, glm::vec3 centre, float radius) {
    const Camera cam = scene.select_camera("", static_cast<float>(w) / static_cast<float>(h));
    const glm::mat4 inv = glm::inverse(projection_matrix(cam, static_cast<float>(w) / static_cast<float>(h)) * glm::inverse(cam.world));
    const glm::vec3 eye(cam.world[3]);
    std::vector<std::pair<int, int>> out;
    for (int y = 0; y < h; ++y)
        for (int x = 0; x < w; ++x) {
            const glm::vec4 ndc((x + 0.5f) / w * 2.0f - 1.0f, 1.0f - (y + 0.5f) / h * 2.0f, 0.5f, 1.0f);
            const glm::vec4 p = inv * ndc;
            const glm::vec3 d = glm::normalize(glm::vec3(p) / p.w - eye);
            const glm::vec3 oc = eye - centre;
            const float b = glm::dot(oc, d), c = glm::dot(oc, oc) - radius * radius;
            if (b * b - c > 0.0f) out.emplace_back(x, y);
        }
    return out;
}

// RMSE of radiance clamped to 1: the point light's highlight on a mirror (the same BRDF in both,
// thousands in radiance over a pixel or two) would otherwise be all the error there is.
double rmse_over(const ImageF& a, const ImageF& b, const std::vector<std::pair<int, int>>& pixels) {
    double sum = 0.0;
    for (auto [x, y] : pixels)
        for (int c = 0; c < 3; ++c) {
            const double d = std::min(a.at(x, y)[c], 1.0f) - std::min(b.at(x, y)[c], 1.0f);
            sum += d * d;
        }
    return std::sqrt(sum / (3.0 * static_cast<double>(pixels.size())));
}

fs::path sample(const char* name) { return fs::path(CANDELA_SOURCE_DIR) / "samples" / "scenes" / name; }

TEST_P(ReflectionsTest, ProbesOnReflectionsSceneApproachWhittedReference) {
    const Scene scene = load_gltf(sample("reflections.gltf"));
    const int w = 128;
    rt::Options o;
    o.mode = rt::Mode::whitted;
    o.max_depth = 1;
    o.spp = 1;
    o.jitter = 0;  // pixel centres, as the rasterizer samples
    const ImageF reference = traced(scene, w, w, o).image;
    // The mirror sphere (shrunk by 10 % to stay off its silhouette).
    const auto mirror = sphere_pixels(scene, w, w, glm::vec3(-0.8f, 0.55f, -0.7f), 0.55f * 0.9f);
    ASSERT_GT(mirror.size(), 500u);
    const double e_static = rmse_over(raster(scene, w, w, settings("shadows", {})), reference, mirror);
    const double e_infinite =
        rmse_over(raster(scene, w, w, settings("shadows,reflections", {"probe.placement=auto", "probe.parallax=off"})), reference, mirror);
    const double e_dynamic = rmse_over(raster(scene, w, w, settings("shadows,reflections", {"probe.placement=auto"})), reference, mirror);
    const double e_box = rmse_over(raster(scene, w, w, settings("shadows,reflections", {})), reference, mirror);
    std::printf("mirror sphere RMSE vs whitted depth 1: static %.4f, automatic probe with an infinitely distant lookup %.4f, "
                "marching its distance cube %.4f, the file's box-projected probe %.4f\n",
                e_static, e_infinite, e_dynamic, e_box);
    EXPECT_GT(e_static, e_infinite);
    // The automatic probe has no box: its distance cube finds the room's walls (and the other
    // objects, which a box does not know) where the reflected rays meet them.
    EXPECT_LT(e_dynamic, 0.75 * e_infinite);
    EXPECT_LT(e_dynamic, 0.05);
    EXPECT_LT(e_box, 0.05);  // box projection fits a mirror in a box room closely
    // Coarser probes blur the reflected room.
    std::vector<double> by_resolution;
    for (int res : {32, 64, 128, 256}) {
        by_resolution.push_back(rmse_over(raster(scene, w, w, settings("shadows,reflections", {"probe.resolution=" + std::to_string(res)})),
                                          reference, mirror));
        std::printf("  probe.resolution=%d: box-projected RMSE %.4f\n", res, by_resolution.back());
    }
    EXPECT_GT(by_resolution[0], by_resolution[2]);
}

TEST_P(ReflectionsTest, GlassRefractsTheRoomCloserThanAnOpaqueDielectric) {
    // Single-interface refraction against the exact two-interface path (whitted depth 2).
    const Scene scene = load_gltf(sample("reflections.gltf"));
    const int w = 128;
    const ImageF reference = traced(scene, w, w, whitted_at_centres(2)).image;
    const auto glass = sphere_pixels(scene, w, w, glm::vec3(0.55f, 0.4f, 0.35f), 0.4f * 0.9f);
    ASSERT_GT(glass.size(), 300u);
    const double e_opaque = rmse_over(raster(scene, w, w, settings("shadows", {})), reference, glass);
    const double e_refracted = rmse_over(raster(scene, w, w, settings("shadows,reflections", {})), reference, glass);
    std::printf("glass sphere RMSE vs whitted depth 2: opaque dielectric %.4f, single-interface refraction %.4f\n", e_opaque,
                e_refracted);
    EXPECT_LT(e_refracted, e_opaque);
}

// A solid glass cube of side 1 (ior 1.5, KHR_materials_volume thickness 1, optionally tinted by
// an attenuation colour and distance) turned `yaw` radians about Y, in the direction-coloured
// map, seen head-on from 4 m.
Scene glass_cube_scene(float yaw, glm::vec3 attenuation_color, float attenuation_distance) {
    test::GltfBuilder b;
    nlohmann::json volume = {{"thicknessFactor", 1.0}};
    if (attenuation_distance > 0.0f) {
        volume["attenuationColor"] = {attenuation_color.r, attenuation_color.g, attenuation_color.b};
        volume["attenuationDistance"] = attenuation_distance;
    }
    b.json()["materials"] = {{{"pbrMetallicRoughness", {{"baseColorFactor", {1, 1, 1, 1}}, {"metallicFactor", 0}, {"roughnessFactor", 0}}},
                              {"extensions", {{"KHR_materials_transmission", {{"transmissionFactor", 1.0}}},
                                              {"KHR_materials_volume", volume}}}}};
    b.json()["extensionsUsed"] = {"KHR_materials_transmission", "KHR_materials_volume"};
    std::vector<glm::vec3> p, n;
    std::vector<uint32_t> idx;
    for (int axis = 0; axis < 3; ++axis)
        for (const float side : {-1.0f, 1.0f}) {
            glm::vec3 normal(0.0f), u(0.0f), v(0.0f);
            normal[axis] = side;
            u[(axis + 1) % 3] = 1.0f;
            v[(axis + 2) % 3] = 1.0f;
            if (side < 0.0f) std::swap(u, v);  // counter-clockwise seen from outside
            const uint32_t first = static_cast<uint32_t>(p.size());
            for (const glm::vec2 c : {glm::vec2(-1, -1), glm::vec2(1, -1), glm::vec2(1, 1), glm::vec2(-1, 1)}) {
                p.push_back(0.5f * (normal + c.x * u + c.y * v));
                n.push_back(normal);
            }
            idx.insert(idx.end(), {first, first + 1, first + 2, first, first + 2, first + 3});
        }
    const int mesh = b.add_mesh({{"POSITION", b.add_positions(p)}, {"NORMAL", b.add_vec3(n)}}, b.add_indices(idx), 0);
    b.add_node({{"mesh", mesh}, {"rotation", {0.0, std::sin(0.5 * yaw), 0.0, std::cos(0.5 * yaw)}}});
    const fs::path dir = test::test_dir("glass_cube");
    write_environment_map(dir / "gradient.exr", true);
    b.json()["scenes"][0]["extras"]["environment_map"] = "gradient.exr";
    b.json()["scenes"][0]["extras"]["environment_radiance"] = {1.0, 1.0, 1.0};
    b.json()["cameras"] = {{{"type", "perspective"}, {"perspective", {{"yfov", 0.5}, {"znear", 0.05}}}}};
    b.add_node({{"camera", 0}, {"translation", {0, 0, 4}}});
    return load_gltf(b.write(dir, "glass_cube"));
}

// The pixels within `half` (in NDC) of the image's centre.
std::vector<std::pair<int, int>> central_pixels(int w, double half) {
    std::vector<std::pair<int, int>> out;
    for (int y = 0; y < w; ++y)
        for (int x = 0; x < w; ++x)
            if (std::abs((x + 0.5) / w * 2.0 - 1.0) < half && std::abs((y + 0.5) / w * 2.0 - 1.0) < half) out.emplace_back(x, y);
    return out;
}

// Through a solid of known shape (a box, a sphere) the raster follows the refracted ray to where
// it leaves and bends it a second time there: through a turned cube, whose faces are parallel, the
// map is seen where the tracer sees it, not where the first interface alone points.
TEST_P(ReflectionsTest, GlassCubeBendsTheViewTwice) {
    const Scene scene = glass_cube_scene(0.6f, glm::vec3(1.0f), 0.0f);
    const int w = 64;
    const ImageF reference = traced(scene, w, w, whitted_at_centres(6)).image;
    const auto inner = central_pixels(w, 0.3);
    const double e = rmse_over(raster(scene, w, w, settings("reflections", {})), reference, inner);
    std::printf("glass cube turned 0.6 rad in a direction-coloured map: RMSE %.5f vs whitted\n", e);
    // Measured 0.0299; with the first interface alone 0.0497.
    EXPECT_LT(e, 0.04);
}

// Beer-Lambert in the raster (KHR_materials_volume): straight through the cube face-on the path
// inside is 1, so what the tinted cube lets through over what the clear one does is
// attenuationColor^(1 / attenuationDistance). What both reflect is an opaque cube's image (one
// that absorbs everything within 1 cm), taken off both.
TEST_P(ReflectionsTest, GlassCubeAbsorbsAsBeerLambert) {
    const glm::vec3 colour(0.5f, 0.7f, 0.9f);
    const float distance = 0.5f;
    const int w = 64;
    const ImageF clear = raster(glass_cube_scene(0.0f, glm::vec3(1.0f), 0.0f), w, w, settings("reflections", {}));
    const ImageF tinted = raster(glass_cube_scene(0.0f, colour, distance), w, w, settings("reflections", {}));
    const ImageF opaque = raster(glass_cube_scene(0.0f, glm::vec3(0.5f), 0.01f), w, w, settings("reflections", {}));
    const auto centre = central_pixels(w, 0.08);
    ASSERT_GT(centre.size(), 4u);
    for (int c = 0; c < 3; ++c) {
        double a = 0.0, b = 0.0;
        for (auto [x, y] : centre) {
            a += tinted.at(x, y)[c] - opaque.at(x, y)[c];
            b += clear.at(x, y)[c] - opaque.at(x, y)[c];
        }
        ASSERT_GT(b, 0.0);
        const double expected = std::pow(colour[c], 1.0 / distance);
        std::printf("channel %d: transmitted, tinted / clear %.4f, Beer-Lambert %.4f\n", c, a / b, expected);
        EXPECT_NEAR(a / b, expected, 0.01) << c;
    }
}

// Two thin glass spheres that share one automatic probe (probe.budget 1: it sits between them, in
// neither), in front of a red patch (behind the left one) and a green patch (behind the right
// one) on a backdrop whose floor and wall are one mesh, so that its bounds hold the probe. A
// sphere's middle shows what lies behind it, as the tracer's straight paths through thin walls
// do. A probe that captured the spheres it serves showed the left sphere's own outside there,
// and one that left out every draw whose bounds hold it lost the backdrop with its patches
// (TransmissionTest's spheres looked opaque for both reasons).
TEST_P(ReflectionsTest, ThinGlassSharingAProbeShowsWhatIsBehindIt) {
    test::GltfBuilder b;
    b.json()["materials"] = {
        {{"name", "backdrop"}, {"pbrMetallicRoughness", {{"baseColorFactor", {0.7, 0.7, 0.7, 1}}, {"metallicFactor", 0}, {"roughnessFactor", 1}}}},
        {{"name", "red"}, {"pbrMetallicRoughness", {{"baseColorFactor", {0.9, 0.05, 0.05, 1}}, {"metallicFactor", 0}, {"roughnessFactor", 1}}}},
        {{"name", "green"}, {"pbrMetallicRoughness", {{"baseColorFactor", {0.05, 0.9, 0.05, 1}}, {"metallicFactor", 0}, {"roughnessFactor", 1}}}},
        {{"name", "glass"},
         {"pbrMetallicRoughness", {{"baseColorFactor", {1, 1, 1, 1}}, {"metallicFactor", 0}, {"roughnessFactor", 0}}},
         {"extensions", {{"KHR_materials_transmission", {{"transmissionFactor", 1.0}}}}}}};
    // Floor (y = -1, z from -3 to 3) and wall (z = -3, y from -1 to 4): one primitive.
    const std::vector<glm::vec3> bp = {{-4, -1, 3}, {4, -1, 3}, {4, -1, -3}, {-4, -1, -3}, {-4, -1, -3}, {4, -1, -3}, {4, 4, -3}, {-4, 4, -3}};
    const std::vector<glm::vec3> bn = {{0, 1, 0}, {0, 1, 0}, {0, 1, 0}, {0, 1, 0}, {0, 0, 1}, {0, 0, 1}, {0, 0, 1}, {0, 0, 1}};
    const int backdrop = b.add_mesh({{"POSITION", b.add_positions(bp)}, {"NORMAL", b.add_vec3(bn)}}, b.add_indices({0, 1, 2, 0, 2, 3, 4, 5, 6, 4, 6, 7}), 0);
    b.add_node({{"mesh", backdrop}, {"name", "backdrop"}});
    b.add_node({{"mesh", b.add_quad_mesh(1)}, {"name", "red"}, {"translation", {-0.8, 0.5, -2.99}}, {"scale", {0.8, 1.2, 1}}});
    b.add_node({{"mesh", b.add_quad_mesh(2)}, {"name", "green"}, {"translation", {0.8, 0.5, -2.99}}, {"scale", {0.8, 1.2, 1}}});
    const int sphere = add_sphere_mesh(b, 3);
    b.add_node({{"mesh", sphere}, {"name", "left"}, {"translation", {-0.8, 0.5, 0}}, {"scale", {0.5, 0.5, 0.5}}});
    b.add_node({{"mesh", sphere}, {"name", "right"}, {"translation", {0.8, 0.5, 0}}, {"scale", {0.5, 0.5, 0.5}}});
    b.json()["scenes"][0]["extras"]["environment_radiance"] = {0.6, 0.6, 0.6};
    b.json()["cameras"] = {{{"type", "perspective"}, {"perspective", {{"yfov", 0.6}, {"znear", 0.1}, {"zfar", 100}}}}};
    b.add_node({{"camera", 0}, {"translation", {0, 0.5, 4}}});
    const Scene scene = load_gltf(b.write(test::test_dir("thin_glass_shared_probe"), "thin_glass_shared_probe"));

    const int w = 96;
    GpuScene gpu(scene);
    Renderer r(lib_, scene, gpu, settings("reflections", {"probe.budget=1"}));
    r.render(scene.select_camera("", 1.0f), w, w);
    const ImageF img = r.read_radiance();
    EXPECT_EQ(count_nonfinite(img), 0u);
    const std::vector<ProbePlacement>& probes = r.effect_runtime<ReflectionsRuntime>()->placements();
    ASSERT_EQ(probes.size(), 1u);
    EXPECT_EQ(probes[0].excluded_draws.size(), 2u) << "the probe leaves out the two spheres it serves, and only them";

    const ImageF reference = traced(scene, w, w, whitted_at_centres(4)).image;
    const auto left = sphere_pixels(scene, w, w, glm::vec3(-0.8f, 0.5f, 0.0f), 0.5f * 0.6f);
    ASSERT_GT(left.size(), 50u);
    glm::dvec3 raster_mean(0.0), traced_mean(0.0);
    for (auto [x, y] : left)
        for (int c = 0; c < 3; ++c) raster_mean[c] += img.at(x, y)[c] / left.size(), traced_mean[c] += reference.at(x, y)[c] / left.size();
    std::printf("left sphere's middle: raster %.3f %.3f %.3f, whitted %.3f %.3f %.3f\n", raster_mean.x, raster_mean.y, raster_mean.z, traced_mean.x,
                traced_mean.y, traced_mean.z);
    EXPECT_GT(traced_mean.x, 3.0 * traced_mean.y) << "the tracer sees the red patch through the sphere";
    EXPECT_GT(raster_mean.x, 3.0 * raster_mean.y) << "the raster must see the red patch through the sphere too";
    EXPECT_LT(rmse_over(img, reference, left), 0.1);
}

TEST_P(ReflectionsTest, ProbePassRunsOnlyWhenCalledForAndWhenStale) {
    auto probes = [](const Renderer& r) -> const std::vector<ProbePlacement>& {
        return r.effect_runtime<ReflectionsRuntime>()->placements();
    };
    auto passes = [](const Renderer& r) {
        std::vector<std::string> names;
        for (const auto& p : r.last_frame().passes) names.push_back(p.name);
        return names;
    };
    auto has = [](const std::vector<std::string>& v, const char* n) { return std::find(v.begin(), v.end(), n) != v.end(); };
    {
        const Scene scene = load_gltf(sample("cornell_box.gltf"));
        GpuScene gpu(scene);
        Renderer r(lib_, scene, gpu, RenderSettings{});
        r.render(scene.select_camera("", 1.0f), 32, 32);
        EXPECT_FALSE(has(passes(r), "env_probe"));
        EXPECT_TRUE(probes(r).empty());
    }
    const Scene scene = load_gltf(sample("reflections.gltf"));
    GpuScene gpu(scene);
    Renderer r(lib_, scene, gpu, settings("reflections", {}));
    ASSERT_EQ(probes(r).size(), 2u);  // the two declared probes, with boxes
    EXPECT_TRUE(probes(r)[0].has_box);
    const Camera cam = scene.select_camera("", 1.0f);
    r.render(cam, 32, 32);
    EXPECT_TRUE(has(passes(r), "env_probe"));
    r.render(cam, 32, 32);
    EXPECT_FALSE(has(passes(r), "env_probe")) << "probe.update=once captures once";
    r.invalidate_captures();
    r.render(cam, 32, 32);
    EXPECT_TRUE(has(passes(r), "env_probe"));
    r.set_settings(settings("reflections", {"probe.update=every_frame", "probe.placement=auto", "render.path=deferred"}));
    EXPECT_EQ(probes(r).size(), 2u);  // one per reflective object
    EXPECT_FALSE(probes(r)[0].has_box);
    for (int i = 0; i < 2; ++i) {
        r.render(cam, 32, 32);
        EXPECT_TRUE(has(passes(r), "env_probe"));
        EXPECT_TRUE(has(passes(r), "transmissive"));
        EXPECT_EQ(count_nonfinite(r.read_radiance()), 0u);
    }
    // A probe never captures the object it sits in.
    for (const ProbePlacement& p : probes(r)) EXPECT_EQ(p.excluded_draws.size(), 1u) << p.origin;
}

// A capture kept while nothing moved (probe.update=once) gives the image a fresh renderer gives,
// bit for bit; moving a box the probes see captures again, and that frame too is a fresh
// renderer's; a pose that moves nothing keeps the capture.
TEST_P(ReflectionsTest, KeptCaptureGivesAFreshRenderersImage) {
    auto captured = [](const Renderer& r) {
        for (const auto& p : r.last_frame().passes)
            if (p.name == "env_probe") return true;
        return false;
    };
    Scene scene = load_gltf(sample("reflections.gltf"));
    const RenderSettings s = settings("reflections", {});
    const Camera cam = scene.select_camera("", 1.0f);
    const int w = 48;
    auto fresh = [&]() {
        GpuScene g(scene);
        Renderer f(lib_, scene, g, s);
        f.render(cam, w, w);
        EXPECT_TRUE(captured(f));
        ImageF img = f.read_radiance();
        EXPECT_EQ(count_nonfinite(img), 0u);
        return img;
    };
    GpuScene gpu(scene);
    Renderer r(lib_, scene, gpu, s);
    r.render(cam, w, w);
    ASSERT_TRUE(captured(r));
    r.render(cam, w, w);
    EXPECT_FALSE(captured(r)) << "nothing changed: the capture is kept";
    const ImageF kept = r.read_radiance();
    EXPECT_EQ(count_nonfinite(kept), 0u);
    EXPECT_EQ(kept.pixels, fresh().pixels) << "the kept capture gives a fresh renderer's image";

    // The same pose again moves nothing: no new pose, the capture stays.
    const std::uint64_t pose = gpu.pose_version();
    EXPECT_FALSE(gpu.update_pose());
    EXPECT_EQ(gpu.pose_version(), pose);
    r.render(cam, w, w);
    EXPECT_FALSE(captured(r));

    // The orange box, which both spheres show, moves: the probes capture again.
    int box = -1;
    for (size_t i = 0; i < scene.nodes.size(); ++i)
        if (scene.nodes[i].name == "orange_box") box = static_cast<int>(i);
    ASSERT_GE(box, 0);
    scene.nodes[static_cast<size_t>(box)].local = glm::translate(glm::mat4(1.0f), glm::vec3(0.3f, 0.0f, 0.2f)) * scene.nodes[static_cast<size_t>(box)].local;
    scene.update_world_transforms();
    EXPECT_TRUE(gpu.update_pose());
    r.render(cam, w, w);
    EXPECT_TRUE(captured(r)) << "a box the probes see moved";
    const ImageF moved = r.read_radiance();
    EXPECT_EQ(count_nonfinite(moved), 0u);
    EXPECT_NE(moved.pixels, kept.pixels);
    EXPECT_EQ(moved.pixels, fresh().pixels) << "after the move, a fresh renderer's image";
    r.render(cam, w, w);
    EXPECT_FALSE(captured(r));
    EXPECT_EQ(r.read_radiance().pixels, moved.pixels);
}

// A smooth metal sphere under a small emitter, and nothing else. The emitter's reflection is the
// area lights' work (LTC, with the emitter's shadow) and must not come a second time from the
// reflection probe, which sees the same emitter: the probe reflects what it captured less the
// area lights' emitters. With the emitter in the probe's reflection, the sphere was twice as
// bright as the tracer's (a random scene's image +137 %).
TEST_P(ReflectionsTest, ProbeReflectionLeavesTheEmittersToTheAreaLights) {
    test::GltfBuilder b;
    b.json()["materials"] = {
        {{"pbrMetallicRoughness", {{"baseColorFactor", {0.9, 0.9, 0.9, 1}}, {"metallicFactor", 1}, {"roughnessFactor", 0.15}}}},
        {{"pbrMetallicRoughness", {{"baseColorFactor", {0, 0, 0, 1}}}},
         {"emissiveFactor", {1.0, 0.9, 0.8}},
         {"extensions", {{"KHR_materials_emissive_strength", {{"emissiveStrength", 20.0}}}}}}};
    b.json()["extensionsUsed"] = {"KHR_materials_emissive_strength"};
    b.add_node({{"mesh", add_sphere_mesh(b, 0)}});
    // The unit quad turned to face down, above the sphere and towards the camera.
    b.add_node({{"mesh", b.add_quad_mesh(1)},
                {"translation", {0.0, 2.0, 1.2}},
                {"rotation", {0.70710678, 0.0, 0.0, 0.70710678}},
                {"scale", {0.3, 0.3, 0.3}}});
    b.json()["cameras"] = {{{"type", "perspective"}, {"perspective", {{"yfov", 0.6}, {"znear", 0.05}}}}};
    b.add_node({{"camera", 0}, {"translation", {0, 0, 4}}});
    const Scene scene = load_gltf(b.write(test::test_dir("probe_emitter"), "probe_emitter"));
    const int w = 48;
    const double with_probe = mean_luminance(raster(scene, w, w, settings("shadows,reflections", {})));
    const double without = mean_luminance(raster(scene, w, w, settings("shadows", {})));
    double se = 0.0;
    const double traced = path_mean_luminance(scene, w, w, 256, se);
    std::printf("mean luminance: probe %.5f, no probe %.5f, path %.5f +- %.5f\n", with_probe, without, traced, se);
    ASSERT_GT(without, 0.0);
    // The probe sees the emitter and black: what it adds to the reflection is nothing.
    EXPECT_NEAR(with_probe / without, 1.0, 0.03);
    EXPECT_NEAR(with_probe / traced, 1.0, 0.08 + 3.0 * se / traced);
}

INSTANTIATE_TEST_SUITE_P(Backends, ReflectionsTest, ::testing::Values(Backend::egl), test::backend_name);

TEST(ReflectionProbeLoading, BadProbeIsNamed) {
    for (const json& probe : {json{{"extent", {1, -1, 1}}}, json{{"position", {0, "x", 0}}}, json("box"),
                              json{{"position", {5, 0, 0}}, {"center", {0, 0, 0}}, {"extent", {1, 1, 1}}}}) {
        test::GltfBuilder b;
        b.add_node({{"name", "p"}, {"extras", {{"reflection_probe", probe}}}});
        const fs::path path = b.write(test::test_dir("bad_probe"), "bad");
        try {
            load_gltf(path);
            ADD_FAILURE() << "loaded " << probe.dump();
        } catch (const Error& e) {
            EXPECT_EQ(e.code(), ExitCode::bad_input);
            EXPECT_NE(std::string(e.what()).find("reflection_probe"), std::string::npos) << e.what();
            EXPECT_NE(std::string(e.what()).find("bad.gltf"), std::string::npos) << e.what();
        }
    }
}

}  // namespace
}  // namespace candela
