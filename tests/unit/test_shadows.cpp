// Shadow maps judged against the ray tracer's exact visibility (`debug.view=visibility` against
// `--raytrace visibility`): no acne at any light elevation, bounded peter-panning, no seams
// between the faces of a point light's cube map, the same visibility at any scene scale, and the
// deferred path equal to the forward one.
#include <gtest/gtest.h>

#include <algorithm>
#include <cmath>
#include <fstream>

#include <glm/gtc/matrix_transform.hpp>
#include <glm/gtx/quaternion.hpp>

#include "gltf_builder.hpp"
#include "reference_fixture.hpp"
#include "render/still.hpp"
#include "scene/generate.hpp"
#include "scene/gltf_loader.hpp"

namespace candela {
namespace {
namespace fs = std::filesystem;
using nlohmann::json;

json lambert(glm::vec3 c) {
    return {{"pbrMetallicRoughness", {{"baseColorFactor", {c.r, c.g, c.b, 1}}, {"metallicFactor", 0}, {"roughnessFactor", 1}}}};
}

// An axis-aligned unit cube [-0.5, 0.5]^3 with outward normals.
int add_box_mesh(test::GltfBuilder& b, int material) {
    std::vector<glm::vec3> p, n;
    std::vector<uint32_t> idx;
    for (int axis = 0; axis < 3; ++axis)
        for (int sign = -1; sign <= 1; sign += 2) {
            glm::vec3 nn(0.0f);
            nn[axis] = static_cast<float>(sign);
            const glm::vec3 u = axis == 0 ? glm::vec3(0, 1, 0) : axis == 1 ? glm::vec3(0, 0, 1) : glm::vec3(1, 0, 0);
            const glm::vec3 v = glm::cross(nn, u);
            const uint32_t base = static_cast<uint32_t>(p.size());
            for (int k = 0; k < 4; ++k) {
                const float a = (k == 1 || k == 2) ? 0.5f : -0.5f, c = k >= 2 ? 0.5f : -0.5f;
                p.push_back(nn * 0.5f + u * a + v * c);
                n.push_back(nn);
            }
            idx.insert(idx.end(), {base, base + 1, base + 2, base, base + 2, base + 3});
        }
    return b.add_mesh({{"POSITION", b.add_positions(p)}, {"NORMAL", b.add_vec3(n)}}, b.add_indices(idx), material);
}

json quat_json(const glm::quat& q) { return {q.x, q.y, q.z, q.w}; }

// Rotation that turns a node's -Z (where lights and cameras look) towards `dir`.
glm::quat look_along(glm::vec3 dir) { return glm::rotation(glm::vec3(0, 0, -1), glm::normalize(dir)); }

void add_floor(test::GltfBuilder& b, float half) {
    b.add_node({{"mesh", b.add_quad_mesh(0)}, {"rotation", {-0.70710678, 0, 0, 0.70710678}}, {"scale", {half, half, half}}});
}

void add_light(test::GltfBuilder& b, const std::string& type, glm::vec3 pos, glm::vec3 dir) {
    b.json()["extensions"]["KHR_lights_punctual"]["lights"] = {{{"type", type}, {"intensity", 5.0}}};
    b.add_node({{"translation", {pos.x, pos.y, pos.z}},
                {"rotation", quat_json(look_along(dir))},
                {"extensions", {{"KHR_lights_punctual", {{"light", 0}}}}}});
}

struct Visibility {
    ImageF image;
    ShadowViews views;
};

class ShadowTest : public test::ReferenceTest {
protected:
    // Light 0's visibility buffer and the frame's shadow views.
    Visibility visibility(const Scene& scene, int w, int h, std::vector<std::string> knobs = {}) {
        knobs.insert(knobs.begin(), "debug.view=visibility");
        ImageF img = raster(scene, w, h, settings("", knobs));
        return {std::move(img), last_views_};
    }
    ImageF traced_visibility(const Scene& scene, int w, int h) {
        rt::Options o;
        o.mode = rt::Mode::visibility;
        o.spp = 1;
        o.jitter = 0;  // pixel centres, where the rasterizer samples: the shadow's error alone
        return traced(scene, w, h, o).image;
    }
};

// Of the pixels the ray tracer finds lit, the fraction the raster also finds lit.
double lit_agreement(const ImageF& raster, const ImageF& reference, int* lit_count = nullptr) {
    int lit = 0, agree = 0;
    for (int y = 0; y < raster.height; ++y)
        for (int x = 0; x < raster.width; ++x)
            if (reference.at(x, y)[0] > 0.5f) {
                ++lit;
                agree += raster.at(x, y)[0] > 0.5f;
            }
    if (lit_count) *lit_count = lit;
    return lit ? static_cast<double>(agree) / lit : 0.0;
}

double mismatch_fraction(const ImageF& a, const ImageF& b) {
    int differ = 0;
    for (int y = 0; y < a.height; ++y)
        for (int x = 0; x < a.width; ++x) differ += (a.at(x, y)[0] > 0.5f) != (b.at(x, y)[0] > 0.5f);
    return static_cast<double>(differ) / (a.width * a.height);
}

TEST_P(ShadowTest, NoAcneAtAnyDirectionalElevation) {
    for (float elevation : {5.0f, 30.0f, 60.0f, 85.0f}) {
        SCOPED_TRACE("elevation " + std::to_string(elevation));
        test::GltfBuilder b;
        b.json()["materials"] = {lambert(glm::vec3(0.8f))};
        add_floor(b, 10.0f);
        b.add_node({{"mesh", add_box_mesh(b, 0)}, {"translation", {0, 0.5, 0}}});
        const float e = glm::radians(elevation);
        add_light(b, "directional", glm::vec3(0, 5, 0), glm::vec3(0.6f * std::cos(e), -std::sin(e), -0.8f * std::cos(e)));
        b.json()["cameras"] = {{{"type", "perspective"}, {"perspective", {{"yfov", 0.9}, {"znear", 0.05}}}}};
        b.add_node({{"camera", 0}, {"translation", {0, 3, 8}}, {"rotation", quat_json(look_along(glm::vec3(0, -3, -8)))}});
        const Scene scene = load_gltf(b.write(test::test_dir("acne"), "acne"));
        const ImageF reference = traced_visibility(scene, 128, 96);
        const std::vector<std::pair<std::string, std::vector<std::string>>> variants = {
            {"hard", {"shadows.filter=hard"}},
            {"pcf", {"shadows.filter=pcf"}},
            {"pcss", {"shadows.filter=pcss"}},
            {"pcss cascades", {"shadows.filter=pcss", "shadows.cascades=3"}},
        };
        for (const auto& [name, knobs] : variants) {
            const char* filter = name.c_str();
            SCOPED_TRACE(filter);
            const Visibility v = visibility(scene, 128, 96, knobs);
            if (knobs.size() == 2) {
                ASSERT_EQ(v.views.views.size(), 3u);
                // Nearer cascades cover less: finer texels.
                EXPECT_LT(v.views.texel_world[0], v.views.texel_world[2]);
            }
            int lit = 0;
            const double agreement = lit_agreement(v.image, reference, &lit);
            EXPECT_GT(lit, 128 * 96 / 4);  // the floor is mostly lit
            EXPECT_GE(agreement, 0.995) << "lit pixels " << lit;
            std::printf("elevation %g %s: lit %d agreement %.5f mismatch %.5f\n", elevation, filter, lit, agreement,
                        mismatch_fraction(v.image, reference));
            // And the shadow is there: the raster does not pass by lighting everything.
            EXPECT_LE(lit_agreement(reference, v.image), 1.0);
            EXPECT_LT(mismatch_fraction(v.image, reference), 0.02);
        }
        // The comparison can see acne: without the biases the same setup has plenty.
        const Visibility unbiased = visibility(scene, 128, 96, {"shadows.filter=hard", "shadows.normal_bias=0", "shadows.depth_bias=0",
                                                            "shadows.slope_bias=0", "shadows.receiver_slope_bias=0"});
        std::printf("elevation %g without bias: agreement %.5f\n", elevation, lit_agreement(unbiased.image, reference));
        EXPECT_LT(lit_agreement(unbiased.image, reference), 0.95);
    }
}

TEST(CascadeSplits, BlendLogarithmicAndUniform) {
    const auto uniform = cascade_splits(1.0f, 100.0f, 4, 0.0f);
    const auto logarithmic = cascade_splits(1.0f, 100.0f, 4, 1.0f);
    ASSERT_EQ(uniform.size(), 5u);
    EXPECT_FLOAT_EQ(uniform[0], 1.0f);
    EXPECT_FLOAT_EQ(uniform[4], 100.0f);
    EXPECT_NEAR(uniform[2], 50.5f, 1e-4f);
    EXPECT_NEAR(logarithmic[2], 10.0f, 1e-4f);  // sqrt(1 * 100)
    const auto mixed = cascade_splits(1.0f, 100.0f, 4, 0.5f);
    for (size_t i = 1; i < 4; ++i) {
        EXPECT_GT(mixed[i], mixed[i - 1]);
        EXPECT_NEAR(mixed[i], 0.5f * (uniform[i] + logarithmic[i]), 1e-3f);
    }
}

TEST_P(ShadowTest, PeterPanningIsBoundedInTexels) {
    // A unit box on the floor, a directional light at 45 degrees travelling +X: the shadow starts
    // at the box's +X side (x = 0.5). Seen from straight above, the gap between the base and the
    // raster shadow, beyond the reference's, must stay within 1.5 shadow texels.
    test::GltfBuilder b;
    b.json()["materials"] = {lambert(glm::vec3(0.8f))};
    add_floor(b, 4.0f);
    b.add_node({{"mesh", add_box_mesh(b, 0)}, {"translation", {0, 0.5, 0}}});
    add_light(b, "directional", glm::vec3(0, 5, 0), glm::vec3(1, -1, 0));
    const float half = 0.6f, cx = 0.9f;
    b.json()["cameras"] = {{{"type", "orthographic"}, {"orthographic", {{"xmag", half}, {"ymag", half}, {"znear", 0.01}, {"zfar", 10}}}}};
    b.add_node({{"camera", 0}, {"translation", {cx, 5, 0}}, {"rotation", {-0.70710678, 0, 0, 0.70710678}}});
    const Scene scene = load_gltf(b.write(test::test_dir("peterpan"), "peterpan"));
    const int n = 240;
    const float pixel = 2.0f * half / n;
    const ImageF reference = traced_visibility(scene, n, n);
    for (const char* filter : {"hard", "pcf", "pcss"}) {
        SCOPED_TRACE(filter);
        const Visibility v = visibility(scene, n, n, {"shadows.resolution=256", std::string("shadows.filter=") + filter});
        ASSERT_FALSE(v.views.texel_world.empty());
        const float texel = v.views.texel_world[0];
        ASSERT_GT(texel, pixel);  // the image resolves the shadow map's texels
        double worst = 0.0;
        int rows = 0;
        for (int y = n / 2 - 20; y < n / 2 + 20; ++y) {  // rows through the box's middle (|z| < 0.1)
            auto first_shadowed = [&](const ImageF& img) {
                for (int x = 0; x < n; ++x) {
                    const float wx = cx - half + (static_cast<float>(x) + 0.5f) * pixel;
                    if (wx > 0.5f + pixel && img.at(x, y)[0] < 0.5f) return wx;
                }
                return 1e9f;
            };
            const float raster_start = first_shadowed(v.image), reference_start = first_shadowed(reference);
            ASSERT_LT(reference_start, 0.6f);  // the reference shadow touches the box
            worst = std::max(worst, static_cast<double>(raster_start - reference_start));
            ++rows;
        }
        EXPECT_EQ(rows, 40);
        EXPECT_LE(worst / texel, 1.5) << "gap " << worst << " world units, texel " << texel;
        std::printf("peter-panning %s: gap %.3f texels (texel %g, pixel %g)\n", filter, worst / texel, texel, pixel);
    }
}

TEST_P(ShadowTest, PointLightCubeHasNoSeams) {
    // A point light 1 above a floor with posts around it: the cube faces meet along |x| = 1,
    // |z| = 1 and |x| = |z| on the floor. Along those lines the raster agrees with the ray tracer
    // as well as anywhere else. With a budget of 4 layers the six faces do not fit at full
    // resolution: they become half-size tiles, four to a layer, side by side in the atlas, and
    // a filter tap that read a neighbouring tile would show at the borders.
    test::GltfBuilder b;
    b.json()["materials"] = {lambert(glm::vec3(0.8f))};
    add_floor(b, 3.0f);
    const int box = add_box_mesh(b, 0);
    for (const glm::vec2 post : {glm::vec2(0.7f, 0.7f), glm::vec2(-0.9f, 0.3f), glm::vec2(0.2f, -0.95f), glm::vec2(-0.6f, -0.6f)})
        b.add_node({{"mesh", box}, {"translation", {post.x, 0.25, post.y}}, {"scale", {0.15, 0.5, 0.15}}});
    add_light(b, "point", glm::vec3(0, 1, 0), glm::vec3(0, -1, 0));
    b.json()["cameras"] = {{{"type", "orthographic"}, {"orthographic", {{"xmag", 3}, {"ymag", 3}, {"znear", 0.01}, {"zfar", 10}}}}};
    b.add_node({{"camera", 0}, {"translation", {0, 5, 0}}, {"rotation", {-0.70710678, 0, 0, 0.70710678}}});
    const Scene scene = load_gltf(b.write(test::test_dir("cube"), "cube"));
    const int n = 200;
    const ImageF reference = traced_visibility(scene, n, n);
    for (const int budget_mb : {512, 16}) {
        SCOPED_TRACE("shadows.budget_mb=" + std::to_string(budget_mb));
        const Visibility v = visibility(scene, n, n, {"shadows.resolution=1024", "shadows.budget_mb=" + std::to_string(budget_mb)});
        ASSERT_EQ(v.views.views.size(), 6u);
        EXPECT_EQ(v.views.views[0].tile_texels, budget_mb == 16 ? 512.0f : 1024.0f);
        EXPECT_EQ(count_nonfinite(v.image), 0u);
        int border = 0, border_differ = 0, other = 0, other_differ = 0;
        for (int y = 0; y < n; ++y)
            for (int x = 0; x < n; ++x) {
                // Pixel to floor point; image top is -Z.
                const float wx = -3.0f + 6.0f * (static_cast<float>(x) + 0.5f) / n, wz = -3.0f + 6.0f * (static_cast<float>(y) + 0.5f) / n;
                const glm::vec3 d = glm::abs(glm::vec3(wx, -1.0f, wz));
                const float major = std::max({d.x, d.y, d.z});
                const float second = d.x + d.y + d.z - major - std::min({d.x, d.y, d.z});
                const bool near_border = major - second < 0.03f * major;
                const bool differ = (v.image.at(x, y)[0] > 0.5f) != (reference.at(x, y)[0] > 0.5f);
                (near_border ? border : other) += 1;
                (near_border ? border_differ : other_differ) += differ;
            }
        ASSERT_GT(border, 500);
        const double border_rate = static_cast<double>(border_differ) / border;
        const double other_rate = static_cast<double>(other_differ) / other;
        EXPECT_LT(border_rate, 0.01) << border_differ << " of " << border << " border pixels differ";
        EXPECT_LT(other_rate, 0.01);
        std::printf("cube seams, %.0f-texel faces: border %d pixels, %.5f differ; elsewhere %.5f\n", v.views.views[0].tile_texels, border,
                    border_rate, other_rate);
    }
}

// shadow_test.gltf under a root node scaled by `s` (the camera too: the same picture).
Scene scaled_shadow_test(float s) {
    const fs::path src = fs::path(CANDELA_SOURCE_DIR) / "samples" / "scenes";
    json j = json::parse(std::ifstream(src / "shadow_test.gltf"));
    const fs::path dir = test::test_dir("scaled_" + std::to_string(s));
    fs::copy_file(src / "shadow_test.bin", dir / "shadow_test.bin");
    json roots = j["scenes"][0]["nodes"];
    j["nodes"].push_back({{"name", "scale"}, {"scale", {s, s, s}}, {"children", roots}});
    j["scenes"][0]["nodes"] = {j["nodes"].size() - 1};
    std::ofstream(dir / "shadow_test.gltf") << j.dump();
    return load_gltf(dir / "shadow_test.gltf");
}

TEST_P(ShadowTest, VisibilityIsTheSameAtAnyScale) {
    const ImageF unit = visibility(scaled_shadow_test(1.0f), 160, 120).image;
    for (float s : {0.01f, 100.0f}) {
        SCOPED_TRACE(s);
        const ImageF scaled = visibility(scaled_shadow_test(s), 160, 120).image;
        EXPECT_LT(mismatch_fraction(scaled, unit), 0.002);
        std::printf("scale %g: mismatch %.5f\n", s, mismatch_fraction(scaled, unit));
    }
}

// shadows.cache: a renderer that keeps its shadow views across frames redraws only the views that
// changed, and its image is the image of a renderer that draws every view afresh. A point light's
// cube does not follow the camera; a directional light's cascades do.
TEST_P(ShadowTest, CachedViewsGiveTheImageOfFreshOnes) {
    for (const char* name : {"cornell_point", "shadow_test"}) {
        SCOPED_TRACE(name);
        const Scene scene = load_gltf(fs::path(CANDELA_SOURCE_DIR) / "samples" / "scenes" / (std::string(name) + ".gltf"));
        const int w = 96, h = 72;
        const Camera first = scene.select_camera("", static_cast<float>(w) / h);
        Camera moved = first;
        moved.world = glm::translate(glm::mat4(1.0f), glm::vec3(0.15f, 0.05f, 0.1f)) * first.world;
        GpuScene gpu(scene);
        Renderer cached(lib_, scene, gpu, settings("shadows", {}));
        cached.render(first, w, h);
        const auto* shadows = cached.effect_runtime<ShadowsRuntime>();
        const int views = static_cast<int>(shadows->views().views.size());
        ASSERT_GT(views, 0);
        EXPECT_EQ(shadows->layers_drawn(), views);
        cached.render(first, w, h);
        EXPECT_EQ(shadows->layers_drawn(), 0) << "the same view again: every layer is still valid";
        cached.render(moved, w, h);
        const int redrawn = shadows->layers_drawn();
        if (std::string(name) == "cornell_point") EXPECT_EQ(redrawn, 0) << "a point light's cube does not follow the camera";
        else EXPECT_GT(redrawn, 0) << "a directional light's cascade follows the camera";
        const ImageF kept = cached.read_radiance();
        GpuScene fresh_gpu(scene);
        Renderer fresh(lib_, scene, fresh_gpu, settings("shadows", {"shadows.cache=0"}));
        fresh.render(moved, w, h);
        const ImageF reference = fresh.read_radiance();
        EXPECT_EQ(count_nonfinite(kept), 0u);
        ASSERT_EQ(kept.pixels.size(), reference.pixels.size());
        size_t differ = 0;
        for (size_t i = 0; i < kept.pixels.size(); ++i) differ += kept.pixels[i] != reference.pixels[i];
        EXPECT_EQ(differ, 0u);
        std::printf("%s: %d views, %d redrawn after the camera moved, %zu values differ from a fresh render\n", name, views,
                    redrawn, differ);
    }
}

// The shadow budget: 64 shadowed point lights (384 views) in 128, 32 and 16 MiB of 512-texel
// layers (1 MiB each). The atlas stays within the budget, lower-priority lights get
// smaller tiles and then none, the frame and `info` say so, and the shadows it keeps are closer
// to the full shadows than no shadows for those lights are.
TEST_P(ShadowTest, ManyShadowedLightsShareTheBudget) {
    const Scene scene = make_many_lights_scene(64, true);
    const int w = 96, h = 54;
    const Camera camera = scene.select_camera("", static_cast<float>(w) / h);
    auto frame = [&](const std::vector<std::string>& knobs, ShadowAtlas* atlas, std::string* text) {
        GpuScene gpu(scene);
        Renderer r(lib_, scene, gpu, settings("shadows", knobs));
        r.render(camera, w, h);
        if (atlas) *atlas = gpu.shadow_atlas();
        if (text) *text = r.features().shadow_budget;
        ImageF img = r.read_radiance();
        EXPECT_EQ(count_nonfinite(img), 0u);
        if (atlas) EXPECT_EQ(r.effect_runtime<ShadowsRuntime>()->views().views.size(), atlas->tiles.size());
        return img;
    };
    const std::vector<std::string> base{"shadows.max_lights=4096", "shadows.resolution=512"};
    auto with = [&](int budget_mb) {
        std::vector<std::string> k = base;
        k.push_back("shadows.budget_mb=" + std::to_string(budget_mb));
        return k;
    };
    auto difference = [](const ImageF& a, const ImageF& b) {
        double sum = 0.0;
        for (size_t i = 0; i < a.pixels.size(); ++i) sum += std::abs(a.pixels[i] - b.pixels[i]);
        return sum / static_cast<double>(a.pixels.size());
    };
    ShadowAtlas atlas;
    std::string text;
    const ImageF full = frame(with(1024), &atlas, &text);
    EXPECT_EQ(atlas.requested, 64);
    EXPECT_EQ(atlas.reduced, 0);
    EXPECT_EQ(atlas.layers, 384);
    const ImageF none = frame({"shadows.max_lights=0"}, nullptr, nullptr);
    const double off = difference(none, full);
    int last_shadowed = 65;
    for (const int budget_mb : {128, 32, 16}) {
        SCOPED_TRACE(budget_mb);
        const ImageF img = frame(with(budget_mb), &atlas, &text);
        EXPECT_LE(atlas.layers, budget_mb);
        EXPECT_GT(atlas.reduced, 0);
        EXPECT_EQ(text.find("unshadowed") != std::string::npos, atlas.unshadowed > 0) << text;
        const int shadowed = atlas.requested - atlas.unshadowed;
        EXPECT_LE(shadowed, last_shadowed);
        last_shadowed = shadowed;
        const double d = difference(img, full);
        EXPECT_LT(d, off) << "the budget's shadows are closer to the full ones than none";
        std::printf("budget %d MiB: %s; mean |difference| from full shadows %.5f (no shadows %.5f)\n", budget_mb, text.c_str(), d, off);
    }
    EXPECT_GT(atlas.unshadowed, 0) << "16 layers cannot hold 64 cubes of 128-texel faces";
}

INSTANTIATE_TEST_SUITE_P(Backends, ShadowTest, ::testing::Values(Backend::egl), test::backend_name);

}  // namespace
}  // namespace candela
