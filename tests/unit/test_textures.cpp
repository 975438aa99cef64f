// Raster textures on every path: mip selection must not depend on how a surface is cut
// into triangles, for every texture slot, texcoord set and KHR_texture_transform, and the
// raster's texel lookups must agree with the ray tracer's.
//
// The bug these guard against: the texcoord set and the transform were read per fragment from
// the materials SSBO, which llvmpipe does not load for helper invocations, so the quads along
// every triangle edge selected the smallest mip (2x2 speckle). A quad cut into 2048 triangles has
// such edges across the whole image; the same quad as two triangles has one diagonal.
#include <gtest/gtest.h>

#include <algorithm>
#include <cmath>
#include <cstdio>
#include <ostream>
#include <string>
#include <vector>

#include "gl_fixture.hpp"
#include "gltf_builder.hpp"
#include "image/image.hpp"
#include "render/gpu_scene.hpp"
#include "render/still.hpp"
#include "rt/ray_tracer.hpp"
#include "scene/gltf_loader.hpp"

namespace candela {
namespace {
namespace fs = std::filesystem;
using nlohmann::json;

constexpr double kPi = 3.14159265358979;
// The golden tolerance (docs/testing.md): 2/255 per channel on at most 0.1 % of pixels.
constexpr double kTolerance = 2.0 / 255.0;
constexpr double kMaxFailing = 0.001;
// Raster against tracer, linear radiance of an emissive texture in [0,1]: both bilinearly filter
// the same sRGB-decoded RGBA8 texels. GPUs may quantise bilinear weights to 8 bits (1/256 of a
// texel step); llvmpipe gives identical values (measured max difference 0).
constexpr double kLinearBound = 0.005;

ShaderLibrary shader_lib() { return ShaderLibrary(ShaderLibrary::default_root()); }  // CANDELA_SHADER_DIR when set

std::uint8_t byte(double v) { return static_cast<std::uint8_t>(std::clamp(std::lround(v), 0L, 255L)); }

// 256x256 with detail at every scale: a red wave of 32 texels, a green wave of 48 x 64 texels and
// a one-texel blue checker. Its 1x1 mip is about (0.5, 0.5, 0.5): wherever the wrong (smallest)
// mip is read, the waves vanish.
void write_detail_texture(const fs::path& path) {
    const int n = 256;
    std::vector<unsigned char> rgba(static_cast<size_t>(n * n * 4), 255);
    for (int y = 0; y < n; ++y)
        for (int x = 0; x < n; ++x) {
            unsigned char* p = &rgba[static_cast<size_t>((y * n + x) * 4)];
            p[0] = byte(128 + 127 * std::sin(2 * kPi * x / 32.0));
            p[1] = byte(128 + 127 * std::sin(2 * kPi * y / 48.0) * std::cos(2 * kPi * x / 64.0));
            p[2] = (x + y) % 2 ? 230 : 20;
        }
    write_display_rgba8(path, rgba, n, n);
}

// A normal map of the same size: gentle waves plus a one-texel ripple, z up.
void write_normal_texture(const fs::path& path) {
    const int n = 256;
    std::vector<unsigned char> rgba(static_cast<size_t>(n * n * 4), 255);
    for (int y = 0; y < n; ++y)
        for (int x = 0; x < n; ++x) {
            unsigned char* p = &rgba[static_cast<size_t>((y * n + x) * 4)];
            p[0] = byte(128 + 60 * std::sin(2 * kPi * x / 40.0) + ((x + y) % 2 ? 25 : -25));
            p[1] = byte(128 + 60 * std::cos(2 * kPi * y / 24.0));
            p[2] = 255;
        }
    write_display_rgba8(path, rgba, n, n);
}

// The quad [-1,1]^2 in the XY plane facing +Z as cells x cells squares of two triangles each;
// TEXCOORD_0 spans [0,1]^2, TEXCOORD_1 [0,2] x [0,1] (mirrored in u).
int add_grid_quad(test::GltfBuilder& b, int cells, int material) {
    std::vector<glm::vec3> p, n;
    std::vector<glm::vec2> uv0, uv1;
    std::vector<glm::vec4> t;
    std::vector<std::uint32_t> idx;
    for (int j = 0; j <= cells; ++j)
        for (int i = 0; i <= cells; ++i) {
            const float u = static_cast<float>(i) / static_cast<float>(cells), v = static_cast<float>(j) / static_cast<float>(cells);
            p.emplace_back(-1.0f + 2.0f * u, 1.0f - 2.0f * v, 0.0f);
            n.emplace_back(0.0f, 0.0f, 1.0f);
            t.emplace_back(1.0f, 0.0f, 0.0f, 1.0f);
            uv0.emplace_back(u, v);
            uv1.emplace_back(2.0f * (1.0f - u), v);
        }
    const auto at = [&](int i, int j) { return static_cast<std::uint32_t>(j * (cells + 1) + i); };
    for (int j = 0; j < cells; ++j)
        for (int i = 0; i < cells; ++i)
            idx.insert(idx.end(), {at(i, j + 1), at(i + 1, j + 1), at(i + 1, j), at(i, j + 1), at(i + 1, j), at(i, j)});
    const int tangents = b.add_accessor(b.add_view(t.data(), t.size() * 16), 5126, t.size(), "VEC4");
    return b.add_mesh({{"POSITION", b.add_positions(p)},
                       {"NORMAL", b.add_vec3(n)},
                       {"TANGENT", tangents},
                       {"TEXCOORD_0", b.add_vec2(uv0)},
                       {"TEXCOORD_1", b.add_vec2(uv1)}},
                      b.add_indices(idx), material);
}

json texture_ref(int texture, int texcoord, const json& transform) {
    json t = {{"index", texture}, {"texCoord", texcoord}};
    if (!transform.is_null()) t["extensions"]["KHR_texture_transform"] = transform;
    return t;
}

// Materials of the grid test.
enum class GridMaterial {
    emissive,            // emission = detail texture, nothing else: the texture as it is
    emissive_transform,  // the same through an offset + rotation + scale on TEXCOORD_1
    all_slots,           // base colour, metallic-roughness, normal, occlusion and emission textured,
                         // on both texcoord sets with different transforms, in a constant environment
};
const char* to_string(GridMaterial m) {
    return m == GridMaterial::emissive ? "emissive" : m == GridMaterial::emissive_transform ? "emissive_transform" : "all_slots";
}

// A scene: the quad (cells x cells) with `material`, seen orthographically so that it fills the
// view. No punctual light; all_slots has a constant environment of radiance 1.
fs::path write_grid_scene(const fs::path& dir, GridMaterial material, int cells) {
    test::GltfBuilder b;
    b.json()["images"] = {{{"uri", "detail.png"}}, {{"uri", "normal.png"}}};
    // Trilinear, repeating: the transforms below reach outside [0,1].
    b.json()["samplers"] = {{{"magFilter", 9729}, {"minFilter", 9987}, {"wrapS", 10497}, {"wrapT", 10497}}};
    b.json()["textures"] = {{{"source", 0}, {"sampler", 0}}, {{"source", 1}, {"sampler", 0}}};
    b.json()["extensionsUsed"] = {"KHR_texture_transform", "KHR_materials_specular"};
    json m = {{"pbrMetallicRoughness", {{"baseColorFactor", {0, 0, 0, 1}}, {"metallicFactor", 0}, {"roughnessFactor", 1}}},
              {"extensions", {{"KHR_materials_specular", {{"specularFactor", 0}}}}}};
    const json rotated = {{"offset", {0.1, -0.2}}, {"rotation", 0.4}, {"scale", {1.6, 1.3}}};
    if (material == GridMaterial::emissive) {
        m["emissiveFactor"] = {1, 1, 1};
        m["emissiveTexture"] = texture_ref(0, 0, nullptr);
    } else if (material == GridMaterial::emissive_transform) {
        m["emissiveFactor"] = {1, 1, 1};
        m["emissiveTexture"] = texture_ref(0, 1, rotated);
    } else {
        m = {{"pbrMetallicRoughness",
              {{"baseColorFactor", {1, 1, 1, 1}},
               {"baseColorTexture", texture_ref(0, 0, rotated)},
               {"metallicFactor", 0.8},
               {"roughnessFactor", 1},
               {"metallicRoughnessTexture", texture_ref(0, 1, json{{"offset", {0.3, 0.1}}, {"scale", {0.7, 1.4}}})}}},
             {"normalTexture", texture_ref(1, 0, json{{"rotation", -0.7}, {"scale", {1.2, 1.2}}})},
             {"occlusionTexture", texture_ref(0, 1, nullptr)},
             {"emissiveFactor", {0.2, 0.2, 0.2}},
             {"emissiveTexture", texture_ref(0, 0, json{{"offset", {0.5, 0.5}}, {"rotation", 1.1}})}};
        b.json()["extras"]["environment_radiance"] = {1, 1, 1};
    }
    b.json()["materials"] = {m};
    b.add_node({{"mesh", add_grid_quad(b, cells, 0)}});
    b.json()["cameras"] = {{{"type", "orthographic"}, {"orthographic", {{"xmag", 1}, {"ymag", 1}, {"znear", 0.01}, {"zfar", 100}}}}};
    b.add_node({{"camera", 0}, {"translation", {0, 0, 5}}});
    return b.write(dir, std::string(to_string(material)) + "_" + std::to_string(cells));
}

struct GridCase {
    Backend backend;
    std::string path;  // forward | deferred
    GridMaterial material;
};
void PrintTo(const GridCase& c, std::ostream* os) { *os << to_string(c.backend) << " " << c.path << " " << to_string(c.material); }
std::string grid_case_name(const ::testing::TestParamInfo<GridCase>& info) {
    return to_string(info.param.backend) + std::string("_") + info.param.path + "_" + to_string(info.param.material);
}

Backend grid_backend(const GridCase& c) { return c.backend; }
class TexturedGridTest : public test::GlContextTestOf<GridCase, grid_backend> {};

// Linear radiance of `scene_path` at n x n on the case's path (no SSAO: it would differ by mesh
// only through its own noise, and is not what this test is about).
ImageF render_grid(const fs::path& scene_path, const std::string& path, int n) {
    const Scene scene = load_gltf(scene_path);
    StillOptions so;
    so.width = so.height = n;
    apply_knob(so.settings, "render.path=" + path);
    so.settings.set_on("ssao", false);
    ImageF image = render_still(scene, shader_lib(), so).radiance;
    EXPECT_EQ(count_nonfinite(image), 0u);
    return image;
}

// Standard deviation of one channel's display value: a flat (or black) image has none.
double channel_stddev(const ImageF& display, int c) {
    double sum = 0, sum2 = 0;
    const double count = static_cast<double>(display.width) * display.height;
    for (int y = 0; y < display.height; ++y)
        for (int x = 0; x < display.width; ++x) {
            const double v = display.at(x, y)[c];
            sum += v, sum2 += v * v;
        }
    const double mean = sum / count;
    return std::sqrt(std::max(0.0, sum2 / count - mean * mean));
}

TEST_P(TexturedGridTest, ManySmallTrianglesRenderLikeTwo) {
    // 256 texels over 96 pixels (more with the transforms): minified, so the mip level matters.
    const GridCase c = GetParam();
    const std::string stem = std::string(to_string(c.backend)) + "_" + c.path + "_" + to_string(c.material);
    const auto dir = test::test_dir("textures_grid_" + stem);
    write_detail_texture(dir / "detail.png");
    write_normal_texture(dir / "normal.png");
    const int n = 96;
    const ImageF two = to_display(render_grid(write_grid_scene(dir, c.material, 1), c.path, n), 0.0f);
    const ImageF many = to_display(render_grid(write_grid_scene(dir, c.material, 32), c.path, n), 0.0f);
    write_display_image(dir / (stem + "_2.png"), two);
    write_display_image(dir / (stem + "_2048.png"), many);
    const CompareResult r = compare(many, two, kTolerance);
    std::printf("%s: 2048 against 2 triangles: %zu of %d pixels beyond 2/255 (%.3f %%), max %.4f, rmse %.5f; images in %s\n",
                stem.c_str(), r.failing_pixels, n * n, 100.0 * r.failing_fraction, r.max_abs, r.rmse, dir.c_str());
    EXPECT_EQ(r.nonfinite, 0u);
    EXPECT_LE(r.failing_fraction, kMaxFailing);
    // The texture is visible: the red and green waves vary across the image (a black or flat
    // image, or one that shows only the 1x1 mip, fails here). The one-texel blue checker is
    // filtered away at this minification.
    for (int ch = 0; ch < 2; ++ch) EXPECT_GT(channel_stddev(two, ch), 0.05) << "channel " << ch;
}

INSTANTIATE_TEST_SUITE_P(
    Paths, TexturedGridTest,
    ::testing::Values(GridCase{Backend::egl, "forward", GridMaterial::emissive}, GridCase{Backend::egl, "deferred", GridMaterial::emissive},
                      GridCase{Backend::egl, "forward", GridMaterial::emissive_transform},
                      GridCase{Backend::egl, "deferred", GridMaterial::emissive_transform},
                      GridCase{Backend::egl, "forward", GridMaterial::all_slots}, GridCase{Backend::egl, "deferred", GridMaterial::all_slots},
                      GridCase{Backend::osmesa, "forward", GridMaterial::emissive},
                      GridCase{Backend::osmesa, "deferred", GridMaterial::emissive},
                      GridCase{Backend::osmesa, "forward", GridMaterial::emissive_transform},
                      GridCase{Backend::osmesa, "deferred", GridMaterial::emissive_transform},
                      GridCase{Backend::osmesa, "forward", GridMaterial::all_slots},
                      GridCase{Backend::osmesa, "deferred", GridMaterial::all_slots}),
    grid_case_name);


// 32x32 texels of saturated and mid-tone colours (sRGB-encoded: decoding before filtering
// matters), a different colour in every texel.
void write_coarse_texture(const fs::path& path) {
    const int n = 32;
    std::vector<unsigned char> rgba(static_cast<size_t>(n * n * 4), 255);
    for (int y = 0; y < n; ++y)
        for (int x = 0; x < n; ++x) {
            unsigned char* p = &rgba[static_cast<size_t>((y * n + x) * 4)];
            p[0] = byte(255.0 * x / (n - 1));
            p[1] = byte(255.0 * y / (n - 1));
            p[2] = (x * 7 + y * 13) % 5 * 60;
        }
    write_display_rgba8(path, rgba, n, n);
}

class TextureTracerTest : public test::GlContextTest {};

TEST_P(TextureTracerTest, RasterTexelsAgreeWithTheTracer) {
    // An emissive quad (emission = sRGB texture, base colour black, no light) magnified 4 times or
    // more, so that both read level 0 with bilinear filtering: the raster (forward and deferred)
    // and the tracer's camera rays (whitted, no jitter: emission returned at the first hit) must
    // return the same radiance per pixel, with the identity and with a KHR_texture_transform.
    const auto dir = test::test_dir("textures_tracer");
    write_coarse_texture(dir / "coarse.png");
    const int n = 128;
    for (const bool transformed : {false, true}) {
        test::GltfBuilder b;
        b.json()["images"] = {{{"uri", "coarse.png"}}};
        b.json()["samplers"] = {{{"magFilter", 9729}, {"minFilter", 9987}, {"wrapS", 10497}, {"wrapT", 10497}}};
        b.json()["textures"] = {{{"source", 0}, {"sampler", 0}}};
        const json transform = transformed ? json{{"offset", {0.2, 0.1}}, {"rotation", 0.5}, {"scale", {0.6, 0.5}}} : json();
        b.json()["materials"] = {{{"pbrMetallicRoughness", {{"baseColorFactor", {0, 0, 0, 1}}, {"metallicFactor", 0}}},
                                  {"extensions", {{"KHR_materials_specular", {{"specularFactor", 0}}}}},
                                  {"emissiveFactor", {1, 1, 1}},
                                  {"emissiveTexture", texture_ref(0, 0, transform)}}};
        b.add_node({{"mesh", add_grid_quad(b, 8, 0)}});
        b.json()["cameras"] = {{{"type", "orthographic"}, {"orthographic", {{"xmag", 1}, {"ymag", 1}, {"znear", 0.01}, {"zfar", 100}}}}};
        b.add_node({{"camera", 0}, {"translation", {0, 0, 5}}});
        const Scene scene = load_gltf(b.write(dir, transformed ? "transformed" : "identity"));
        rt::Options o;
        o.mode = rt::Mode::whitted;
        o.jitter = 0;
        o.spp = 1;
        GpuScene gpu(scene);
        const rt::Result traced = rt::RayTracer(shader_lib(), scene, gpu, o).render(scene.select_camera("", 1.0f), n, n);
        EXPECT_EQ(traced.nonfinite_samples, 0u);
        EXPECT_EQ(count_nonfinite(traced.image), 0u);
        const ImageF traced_display = to_display(traced.image, 0.0f);
        write_display_image(dir / (std::string(transformed ? "transformed" : "identity") + "_traced.png"), traced_display);
        for (const std::string path : {"forward", "deferred"}) {
            const ImageF raster = render_grid(dir / (std::string(transformed ? "transformed" : "identity") + ".gltf"), path, n);
            const ImageF raster_display = to_display(raster, 0.0f);
            const std::string stem = std::string(transformed ? "transformed_" : "identity_") + path;
            write_display_image(dir / (stem + ".png"), raster_display);
            const CompareResult linear = compare(raster, traced.image, kTolerance);
            const CompareResult display = compare(raster_display, traced_display, kTolerance);
            std::printf("%s %s: raster against tracer: linear max %.5f rmse %.6f; display: %zu of %d pixels beyond 2/255, max %.4f\n",
                        to_string(GetParam()), stem.c_str(), linear.max_abs, linear.rmse, display.failing_pixels, n * n,
                        display.max_abs);
            EXPECT_EQ(display.failing_pixels, 0u);
            EXPECT_LT(linear.max_abs, kLinearBound);
            for (int ch = 0; ch < 3; ++ch) EXPECT_GT(channel_stddev(traced_display, ch), 0.05) << "channel " << ch;
        }
    }
}

INSTANTIATE_TEST_SUITE_P(Backends, TextureTracerTest, ::testing::Values(Backend::egl, Backend::osmesa), test::backend_name);

}  // namespace
}  // namespace candela
