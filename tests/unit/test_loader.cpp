// Loader: sample scenes, broken files (message names file and JSON path), geometry rules.
#include <gtest/gtest.h>

#include <fstream>

#include <glm/gtc/matrix_transform.hpp>

#include "core/error.hpp"
#include "core/log.hpp"
#include "gltf_builder.hpp"
#include "scene/features.hpp"
#include "scene/gltf_loader.hpp"

#ifndef CANDELA_SOURCE_DIR
#error "CANDELA_SOURCE_DIR must be defined by the build"
#endif

namespace candela {
namespace {

using test::GltfBuilder;
namespace fs = std::filesystem;

const fs::path kScenes = fs::path(CANDELA_SOURCE_DIR) / "samples" / "scenes";
const fs::path kBroken = fs::path(CANDELA_SOURCE_DIR) / "tests" / "data" / "broken";

// Loads and returns the bad_input message; fails the test if it loads or fails otherwise.
std::string load_error(const fs::path& path) {
    try {
        load_gltf(path);
    } catch (const Error& e) {
        EXPECT_EQ(e.code(), ExitCode::bad_input) << e.what();
        return e.what();
    }
    ADD_FAILURE() << path << " loaded but should not";
    return {};
}

TEST(SampleScenes, AllLoadWithoutWarnings) {
    for (const char* name : {"cornell_box", "cornell_point", "spheres", "shadow_test", "transparency", "reflections"}) {
        SCOPED_TRACE(name);
        const int before = log::warning_count();
        const Scene scene = load_gltf(kScenes / (std::string(name) + ".gltf"));
        EXPECT_EQ(log::warning_count(), before);
        EXPECT_GT(scene.triangle_count(), 10u);
        EXPECT_FALSE(scene.world_bounds().empty());
        EXPECT_EQ(scene.cameras.size(), 1u);
    }
}

TEST(SampleScenes, ContentMatchesTheirDescription) {
    const Scene point = load_gltf(kScenes / "cornell_point.gltf");
    ASSERT_EQ(point.placed_lights().size(), 1u);
    EXPECT_EQ(point.placed_lights()[0].light->type, LightType::point);

    const Scene box = load_gltf(kScenes / "cornell_box.gltf");
    EXPECT_TRUE(analyze_features(box).emissive_area_lights.needed);
    EXPECT_FALSE(analyze_features(box).transparency.needed);

    const Scene spheres = load_gltf(kScenes / "spheres.gltf");
    int analytic = 0;
    for (const Node& n : spheres.nodes) analytic += n.sphere_radius.has_value();
    EXPECT_EQ(analytic, 25);

    const Scene transparency = load_gltf(kScenes / "transparency.gltf");
    const SceneFeatures f = analyze_features(transparency);
    EXPECT_TRUE(f.transparency.needed);
    bool masked_textured = false;
    for (const Material& m : transparency.materials)
        if (m.alpha_mode == AlphaMode::mask && m.base_color_texture.present())
            masked_textured = transparency.images[static_cast<size_t>(m.base_color_texture.image)].valid;
    EXPECT_TRUE(masked_textured);

    const Scene reflections = load_gltf(kScenes / "reflections.gltf");
    EXPECT_TRUE(analyze_features(reflections).reflections.needed);
    EXPECT_TRUE(analyze_features(reflections).transmission.needed);
}

struct BrokenCase {
    const char* file;
    const char* expected;  // a fragment of the message after the file name
};

class BrokenFiles : public ::testing::TestWithParam<BrokenCase> {};

TEST_P(BrokenFiles, ExitTwoWithFileAndJsonPath) {
    const std::string message = load_error(kBroken / GetParam().file);
    EXPECT_NE(message.find(GetParam().file), std::string::npos) << message;
    EXPECT_NE(message.find(GetParam().expected), std::string::npos) << message;
}

INSTANTIATE_TEST_SUITE_P(
    Loader, BrokenFiles,
    ::testing::Values(
        BrokenCase{"truncated_buffer.gltf", "buffers[0]: 'truncated_buffer.bin' has 30 bytes but byteLength is 48"},
        BrokenCase{"index_out_of_range.gltf", "meshes[0].primitives[0].indices: index 4096 out of range (accessor has 3 vertices)"},
        BrokenCase{"accessor_past_view.gltf", "meshes[0].primitives[0].attributes.POSITION (accessors[0]): accessor reads past the end of bufferView 0"},
        BrokenCase{"bad_json.gltf", "invalid JSON: parse error at line 7"},
        BrokenCase{"bad_mesh_reference.gltf", "nodes[0].mesh: mesh 7 does not exist"},
        BrokenCase{"node_cycle.gltf", "scenes[0].nodes: node 0 is a root and also a child"}));

// Material 0's base colour texture is the visible (magenta) fallback image.
void expect_fallback_base_color(const Scene& scene) {
    const TextureRef& ref = scene.materials.at(0).base_color_texture;
    ASSERT_TRUE(ref.present());
    const Image& img = scene.images.at(static_cast<size_t>(ref.image));
    EXPECT_TRUE(img.valid);
    EXPECT_EQ(img.name, "fallback");
    ASSERT_GE(img.rgba8.size(), 2u);
    EXPECT_EQ(img.rgba8[0], 255);  // magenta
    EXPECT_EQ(img.rgba8[1], 0);
}

TEST(Loader, MissingTextureWarnsAndUsesVisibleFallback) {
    const int before = log::warning_count();
    const Scene scene = load_gltf(kBroken / "missing_texture.gltf");
    EXPECT_GT(log::warning_count(), before);
    EXPECT_EQ(scene.sanitized.missing_textures, 1);
    expect_fallback_base_color(scene);
}

// Bad texture files: truncated, not an image, a header that claims 65536x65536 or
// 0x0, an unsupported format. Each is a warning naming the image and the fallback texture.
TEST(Loader, BadTextureFilesFallBackWithAWarning) {
    const fs::path dir = test::test_dir("bad_textures");
    std::string png;
    {
        std::ifstream in(fs::path(CANDELA_SOURCE_DIR) / "samples" / "scenes" / "fence.png", std::ios::binary);
        png.assign(std::istreambuf_iterator<char>(in), {});
    }
    ASSERT_GT(png.size(), 60u);
    // An IHDR chunk with the given size (CRC not checked by the decoder before the size).
    auto header = [&](std::uint32_t w, std::uint32_t h) {
        std::string s = png.substr(0, 33);
        for (int i = 0; i < 4; ++i) {
            s[16 + i] = static_cast<char>((w >> (24 - 8 * i)) & 0xff);
            s[20 + i] = static_cast<char>((h >> (24 - 8 * i)) & 0xff);
        }
        return s + png.substr(33);
    };
    const std::vector<std::pair<std::string, std::string>> files = {
        {"truncated.png", png.substr(0, png.size() / 2)}, {"garbage.png", "not an image at all"},
        {"huge.png", header(65536, 65536)}, {"empty.png", header(0, 0)}, {"image.bmp", std::string("BM") + std::string(60, '\0')}};
    for (const auto& [name, bytes] : files) {
        SCOPED_TRACE(name);
        std::ofstream(dir / name, std::ios::binary) << bytes;
        test::GltfBuilder b;
        b.json()["images"] = {{{"uri", name}}};
        b.json()["textures"] = {{{"source", 0}}};
        b.json()["materials"] = {{{"pbrMetallicRoughness", {{"baseColorTexture", {{"index", 0}}}}}}};
        b.add_node({{"mesh", b.add_quad_mesh(0)}});
        const int before = log::warning_count();
        const Scene scene = load_gltf(b.write(dir, "scene_" + name));
        EXPECT_EQ(log::warning_count(), before + 1);
        EXPECT_EQ(scene.sanitized.missing_textures, 1);
        expect_fallback_base_color(scene);
    }
}

TEST(Loader, NotAFileOrNotGltf) {
    EXPECT_NE(load_error("/nonexistent/scene.gltf").find("no such file"), std::string::npos);
    const fs::path dir = test::test_dir("garbage");
    std::ofstream(dir / "empty.gltf");
    EXPECT_NE(load_error(dir / "empty.gltf").find("empty.gltf"), std::string::npos);
    std::ofstream(dir / "array.gltf") << "[1, 2, 3]";
    EXPECT_NE(load_error(dir / "array.gltf").find("not a JSON object"), std::string::npos);
    std::ofstream(dir / "garbage.glb") << "glTF\x02\0\0\0garbage";
    load_error(dir / "garbage.glb");
    load_error(dir);  // a directory
}

TEST(Loader, HugeAccessorCountIsRejectedNotAllocated) {
    GltfBuilder b;
    const int mesh = b.add_quad_mesh();
    b.json()["accessors"][0]["count"] = 4000000000ull;
    b.add_node({{"mesh", mesh}});
    const std::string msg = load_error(b.write(test::test_dir("huge"), "huge"));
    EXPECT_NE(msg.find("accessors[0]"), std::string::npos) << msg;
}

TEST(Loader, ByteStrideSmallerThanElementIsRejected) {
    GltfBuilder b;
    const int mesh = b.add_quad_mesh();
    b.json()["bufferViews"][0]["byteStride"] = 4;
    b.add_node({{"mesh", mesh}});
    const std::string msg = load_error(b.write(test::test_dir("stride"), "stride"));
    EXPECT_NE(msg.find("byteStride 4"), std::string::npos) << msg;
}

TEST(Loader, FactorsOutsideTheirRangeAreClampedWithAWarning) {
    GltfBuilder b;
    b.json()["materials"] = {{{"pbrMetallicRoughness", {{"baseColorFactor", {2.0, 0.5, -1.0, 1.0}}, {"roughnessFactor", 7.0}}},
                              {"extensions", {{"KHR_materials_ior", {{"ior", 40.0}}}}}}};
    b.json()["extensionsUsed"] = {"KHR_materials_ior"};  // undeclared, it would be a fifth warning
    b.add_node({{"mesh", b.add_quad_mesh(0)}});
    const int before = log::warning_count();
    const Scene scene = load_gltf(b.write(test::test_dir("clamp"), "clamp"));
    EXPECT_EQ(log::warning_count(), before + 4);  // two colour channels, roughness, IOR
    const Material& m = scene.materials.at(0);
    EXPECT_EQ(m.base_color, glm::vec4(1.0f, 0.5f, 0.0f, 1.0f));
    EXPECT_EQ(m.roughness, 1.0f);
    EXPECT_EQ(m.ior, 10.0f);
}

TEST(Loader, WorldTransformOverflowIsRejected) {
    // Each node's own scale fits a float; their product along the hierarchy does not.
    GltfBuilder b;
    const int leaf = b.add_node({{"mesh", b.add_quad_mesh()}, {"scale", {1e30, 1e30, 1e30}}}, false);
    b.add_node({{"children", {leaf}}, {"scale", {1e30, 1e30, 1e30}}});
    const std::string msg = load_error(b.write(test::test_dir("overflow"), "overflow"));
    EXPECT_NE(msg.find("world transform overflows"), std::string::npos) << msg;
}

TEST(Transforms, HierarchyComposesTrsAndMatrix) {
    GltfBuilder b;
    const int mesh = b.add_quad_mesh();
    // Parent: translate (10, 0, 0). Child: rotate 90 degrees about Y, scale 2, as TRS.
    const int child = b.add_node({{"mesh", mesh}, {"rotation", {0.0, 0.70710678, 0.0, 0.70710678}}, {"scale", {2, 2, 2}}}, false);
    b.add_node({{"children", {child}}, {"matrix", {1, 0, 0, 0, 0, 1, 0, 0, 0, 0, 1, 0, 10, 0, 0, 1}}});
    const Scene scene = load_gltf(b.write(test::test_dir("hier"), "hier"));
    const glm::vec3 p = glm::vec3(scene.nodes[static_cast<size_t>(child)].world * glm::vec4(1, 0, 0, 1));
    // (1,0,0) scaled to (2,0,0), rotated +90 about Y to (0,0,-2), translated to (10,0,-2).
    EXPECT_NEAR(p.x, 10.0f, 1e-5f);
    EXPECT_NEAR(p.y, 0.0f, 1e-5f);
    EXPECT_NEAR(p.z, -2.0f, 1e-5f);
}

TEST(Transforms, NegativeDeterminantFlipsWinding) {
    GltfBuilder b;
    const int mesh = b.add_quad_mesh();
    b.add_node({{"mesh", mesh}, {"translation", {-3, 0, 0}}});
    b.add_node({{"mesh", mesh}, {"translation", {3, 0, 0}}, {"scale", {-1, 1, 1}}});
    const Scene scene = load_gltf(b.write(test::test_dir("mirror"), "mirror"));
    int mirrored = 0;
    for (const WorldTriangle& t : scene.world_triangles()) {
        const glm::vec3 geometric = glm::cross(t.p[1] - t.p[0], t.p[2] - t.p[0]);
        // Counter-clockwise seen from the front: the geometric normal agrees with the shading one.
        EXPECT_GT(glm::dot(geometric, t.n[0]), 0.0f);
        mirrored += scene.nodes[static_cast<size_t>(t.node)].mirrored();
    }
    EXPECT_EQ(mirrored, 2);
}

TEST(Transforms, NormalsUseInverseTranspose) {
    GltfBuilder b;
    // A plane tilted 45 degrees (normal (0, 1, 1)/sqrt2), then scaled non-uniformly.
    const std::vector<glm::vec3> p = {{0, 0, 0}, {1, 0, 0}, {0, 1, -1}};
    const glm::vec3 n = glm::normalize(glm::vec3(0, 1, 1));
    const int mesh = b.add_mesh({{"POSITION", b.add_positions(p)}, {"NORMAL", b.add_vec3({n, n, n})}});
    b.add_node({{"mesh", mesh}, {"scale", {1, 4, 0.5}}});
    const Scene scene = load_gltf(b.write(test::test_dir("invt"), "invt"));
    const auto tris = scene.world_triangles();
    ASSERT_EQ(tris.size(), 1u);
    const WorldTriangle& t = tris[0];
    EXPECT_NEAR(glm::dot(t.n[0], t.p[1] - t.p[0]), 0.0f, 1e-5f);
    EXPECT_NEAR(glm::dot(t.n[0], t.p[2] - t.p[0]), 0.0f, 1e-5f);
    EXPECT_NEAR(glm::length(t.n[0]), 1.0f, 1e-5f);
}

TEST(Geometry, MissingNormalsAreGeneratedFlat) {
    GltfBuilder b;
    b.add_node({{"mesh", b.add_quad_mesh(-1, false)}});
    const Scene scene = load_gltf(b.write(test::test_dir("flat"), "flat"));
    EXPECT_EQ(scene.sanitized.generated_normals, 1);
    for (const Vertex& v : scene.meshes[0].primitives[0].vertices) {
        EXPECT_NEAR(v.normal.z, 1.0f, 1e-6f);
    }
    EXPECT_EQ(scene.meshes[0].primitives[0].vertices.size(), 6u);  // unshared per face
}

TEST(Geometry, SparseAccessorOverridesValues) {
    GltfBuilder b;
    const std::vector<glm::vec3> p = {{0, 0, 0}, {1, 0, 0}, {0, 1, 0}};
    const int pos = b.add_positions(p);
    const uint16_t sparse_index = 2;
    const glm::vec3 sparse_value(0, 5, 0);
    const int iv = b.add_view(&sparse_index, 2);
    const int vv = b.add_view(&sparse_value, 12);
    b.json()["accessors"][static_cast<size_t>(pos)]["sparse"] = {
        {"count", 1}, {"indices", {{"bufferView", iv}, {"componentType", 5123}}}, {"values", {{"bufferView", vv}}}};
    b.json()["accessors"][static_cast<size_t>(pos)]["max"] = {1, 5, 0};
    b.add_node({{"mesh", b.add_mesh({{"POSITION", pos}})}});
    const Scene scene = load_gltf(b.write(test::test_dir("sparse"), "sparse"));
    bool found = false;
    for (const Vertex& v : scene.meshes[0].primitives[0].vertices) found |= v.position.y == 5.0f;
    EXPECT_TRUE(found);
}

TEST(Geometry, NormalizedIntegerTexcoords) {
    GltfBuilder b;
    const std::vector<glm::vec3> p = {{0, 0, 0}, {1, 0, 0}, {0, 1, 0}};
    const uint16_t uv[6] = {0, 0, 65535, 0, 0, 32768};
    const int uva = b.add_accessor(b.add_view(uv, sizeof uv), 5123, 3, "VEC2", true);
    b.add_node({{"mesh", b.add_mesh({{"POSITION", b.add_positions(p)}, {"TEXCOORD_0", uva}})}});
    const Scene scene = load_gltf(b.write(test::test_dir("norm"), "norm"));
    // Flat-normal generation unshares vertices but keeps their order within each triangle.
    const auto& v = scene.meshes[0].primitives[0].vertices;
    EXPECT_FLOAT_EQ(v[1].uv0.x, 1.0f);
    EXPECT_NEAR(v[2].uv0.y, 32768.0f / 65535.0f, 1e-6f);
}

TEST(Geometry, NonTrianglePrimitivesAreSkippedWithWarning) {
    GltfBuilder b;
    const std::vector<glm::vec3> p = {{0, 0, 0}, {1, 0, 0}};
    const int lines = b.add_mesh({{"POSITION", b.add_positions(p)}}, -1, -1, 1);
    b.add_node({{"mesh", lines}});
    const int before = log::warning_count();
    const Scene scene = load_gltf(b.write(test::test_dir("lines"), "lines"));
    EXPECT_EQ(scene.sanitized.skipped_primitives, 1);
    EXPECT_GT(log::warning_count(), before);
    EXPECT_EQ(scene.triangle_count(), 0u);
}

TEST(Materials, ExtensionsAndTextureTransform) {
    GltfBuilder b;
    const unsigned char png_stub = 0;
    (void)png_stub;
    b.json()["images"] = {{{"uri", "missing.png"}}};
    b.json()["textures"] = {{{"source", 0}}};
    b.json()["materials"] = {{{"name", "m"},
                              {"emissiveFactor", {1, 0.5, 0}},
                              {"pbrMetallicRoughness",
                               {{"baseColorTexture",
                                 {{"index", 0},
                                  {"extensions",
                                   {{"KHR_texture_transform", {{"offset", {0.5, 0}}, {"scale", {2, 2}}, {"rotation", 0.0}}}}}}}}},
                              {"extensions",
                               {{"KHR_materials_emissive_strength", {{"emissiveStrength", 10}}},
                                {"KHR_materials_specular", {{"specularFactor", 0}}},
                                {"KHR_materials_ior", {{"ior", 1.33}}},
                                {"KHR_materials_transmission", {{"transmissionFactor", 0.75}}},
                                {"KHR_materials_volume", {{"thicknessFactor", 0.2}}}}}}};
    b.add_node({{"mesh", b.add_quad_mesh(0)}});
    const Scene scene = load_gltf(b.write(test::test_dir("ext"), "ext"));
    const Material& m = scene.materials.at(0);
    EXPECT_FLOAT_EQ(m.emission().x, 10.0f);
    EXPECT_FLOAT_EQ(m.emission().y, 5.0f);
    EXPECT_FLOAT_EQ(m.specular_factor, 0.0f);
    EXPECT_FLOAT_EQ(m.ior, 1.33f);
    EXPECT_FLOAT_EQ(m.transmission, 0.75f);
    EXPECT_FLOAT_EQ(m.thickness, 0.2f);
    const glm::vec3 uv = m.base_color_texture.transform * glm::vec3(1, 1, 1);
    EXPECT_NEAR(uv.x, 2.5f, 1e-6f);
    EXPECT_NEAR(uv.y, 2.0f, 1e-6f);
    // Rotation by +90 degrees maps u to -v (the extension's matrix).
    b.json()["materials"][0]["pbrMetallicRoughness"]["baseColorTexture"]["extensions"]["KHR_texture_transform"] = {
        {"rotation", 1.5707963}};
    const Scene rotated = load_gltf(b.write(test::test_dir("ext2"), "ext2"));
    const glm::vec3 r = rotated.materials.at(0).base_color_texture.transform * glm::vec3(1, 0, 1);
    EXPECT_NEAR(r.x, 0.0f, 1e-6f);
    EXPECT_NEAR(r.y, -1.0f, 1e-6f);
}

TEST(Lights, PunctualLightsAreParsedAndPlaced) {
    GltfBuilder b;
    b.json()["extensionsUsed"] = {"KHR_lights_punctual"};
    b.json()["extensions"]["KHR_lights_punctual"]["lights"] = {
        {{"type", "spot"}, {"intensity", 40}, {"range", 10}, {"spot", {{"innerConeAngle", 0.3}, {"outerConeAngle", 0.5}}}},
        {{"type", "directional"}, {"color", {1, 0.5, 0.25}}, {"intensity", 2}}};
    // Rotated -90 degrees about X: the node's -Z axis points down (-Y).
    b.add_node({{"translation", {0, 5, 0}}, {"rotation", {-0.70710678, 0, 0, 0.70710678}},
                {"extensions", {{"KHR_lights_punctual", {{"light", 0}}}}}});
    b.add_node({{"extensions", {{"KHR_lights_punctual", {{"light", 1}}}}}});
    b.add_node({{"mesh", b.add_quad_mesh()}});
    const Scene scene = load_gltf(b.write(test::test_dir("lights"), "lights"));
    const auto placed = scene.placed_lights();
    ASSERT_EQ(placed.size(), 2u);
    EXPECT_EQ(placed[0].light->type, LightType::spot);
    EXPECT_NEAR(placed[0].direction.y, -1.0f, 1e-5f);
    EXPECT_NEAR(placed[0].position.y, 5.0f, 1e-5f);
    EXPECT_FLOAT_EQ(placed[0].light->outer_cone, 0.5f);
    EXPECT_FLOAT_EQ(placed[0].light->range, 10.0f);
    EXPECT_FLOAT_EQ(placed[1].light->color.y, 0.5f);
    EXPECT_NEAR(placed[1].direction.z, -1.0f, 1e-5f);
    // A node naming a light that does not exist is bad input.
    b.json()["nodes"][1]["extensions"]["KHR_lights_punctual"]["light"] = 5;
    const std::string msg = load_error(b.write(test::test_dir("lights2"), "lights2"));
    EXPECT_NE(msg.find("nodes[1].extensions.KHR_lights_punctual.light"), std::string::npos) << msg;
}

TEST(Cameras, SelectionByIndexAndNameAndFraming) {
    GltfBuilder b;
    b.json()["cameras"] = {{{"type", "perspective"}, {"name", "front"}, {"perspective", {{"yfov", 0.7}, {"znear", 0.1}}}},
                           {{"type", "orthographic"}, {"name", "top"},
                            {"orthographic", {{"xmag", 2}, {"ymag", 2}, {"znear", 0.1}, {"zfar", 100}}}}};
    b.add_node({{"camera", 0}, {"translation", {0, 0, 5}}});
    b.add_node({{"camera", 1}, {"translation", {0, 5, 0}}});
    b.add_node({{"mesh", b.add_quad_mesh()}});
    const Scene scene = load_gltf(b.write(test::test_dir("cams"), "cams"));
    EXPECT_EQ(scene.select_camera("", 1.0f).name, "front");
    EXPECT_TRUE(scene.select_camera("1", 1.0f).orthographic);
    EXPECT_TRUE(scene.select_camera("top", 1.0f).orthographic);
    EXPECT_THROW(scene.select_camera("nope", 1.0f), Error);
    EXPECT_THROW(scene.select_camera("7", 1.0f), Error);
}

TEST(Cameras, ReversedZProjection) {
    Camera c;
    c.yfov = 1.0f;
    c.znear = 0.1f;
    const glm::mat4 p = projection_matrix(c, 1.0f);
    auto depth = [&](float z) {
        const glm::vec4 clip = p * glm::vec4(0, 0, z, 1);
        return clip.z / clip.w;
    };
    EXPECT_NEAR(depth(-0.1f), 1.0f, 1e-6f);   // near plane -> 1
    EXPECT_LT(depth(-1e6f), 1e-6f);           // infinity -> 0
    EXPECT_GT(depth(-1000.0f), depth(-1000.001f));  // still ordered far away
    const Camera framing = framing_camera(Bounds{glm::vec3(-1), glm::vec3(1)});
    const glm::vec3 eye(framing.world[3]);
    EXPECT_GT(glm::length(eye), 1.7f);  // outside the bounds' sphere
}

TEST(Environment, SceneExtras) {
    GltfBuilder b;
    b.json()["scenes"][0]["extras"] = {{"environment_radiance", {0.1, 0.2, 0.3}}, {"environment_intensity", 2.0}};
    b.add_node({{"mesh", b.add_quad_mesh()}});
    const Scene scene = load_gltf(b.write(test::test_dir("env"), "env"));
    EXPECT_FLOAT_EQ(scene.environment.radiance.z, 0.3f);
    EXPECT_FLOAT_EQ(scene.environment.intensity, 2.0f);
    EXPECT_TRUE(scene.environment.present());
}

}  // namespace
}  // namespace candela

namespace candela {
namespace {

// Packs a .gltf + .bin written by GltfBuilder into one GLB (glTF 2.0 binary container).
std::filesystem::path to_glb(const std::filesystem::path& gltf_path) {
    nlohmann::json j = nlohmann::json::parse(std::ifstream(gltf_path));
    std::ifstream bin_in(gltf_path.parent_path() / j["buffers"][0]["uri"].get<std::string>(), std::ios::binary);
    std::string bin((std::istreambuf_iterator<char>(bin_in)), std::istreambuf_iterator<char>());
    j["buffers"][0].erase("uri");
    std::string text = j.dump();
    while (text.size() % 4) text += ' ';
    while (bin.size() % 4) bin += '\0';
    auto u32 = [](std::string& s, uint32_t v) { s.append(reinterpret_cast<const char*>(&v), 4); };
    std::string glb = "glTF";
    u32(glb, 2);
    u32(glb, static_cast<uint32_t>(12 + 8 + text.size() + 8 + bin.size()));
    u32(glb, static_cast<uint32_t>(text.size()));
    u32(glb, 0x4E4F534A);  // JSON
    glb += text;
    u32(glb, static_cast<uint32_t>(bin.size()));
    u32(glb, 0x004E4942);  // BIN
    glb += bin;
    auto out = gltf_path;
    out.replace_extension(".glb");
    std::ofstream(out, std::ios::binary) << glb;
    return out;
}

TEST(Loader, BinaryGlbLoadsLikeGltf) {
    test::GltfBuilder b;
    b.add_node({{"mesh", b.add_quad_mesh()}});
    const auto gltf = b.write(test::test_dir("glb"), "quad");
    const Scene a = load_gltf(gltf);
    const Scene g = load_gltf(to_glb(gltf));
    EXPECT_EQ(g.triangle_count(), 2u);
    EXPECT_EQ(g.meshes[0].primitives[0].vertices.size(), a.meshes[0].primitives[0].vertices.size());
    // A GLB cut short is bad input, not a crash.
    std::ifstream in(to_glb(gltf), std::ios::binary);
    std::string bytes((std::istreambuf_iterator<char>(in)), std::istreambuf_iterator<char>());
    const auto cut = gltf.parent_path() / "cut.glb";
    std::ofstream(cut, std::ios::binary) << bytes.substr(0, bytes.size() - 20);
    EXPECT_THROW(load_gltf(cut), Error);
}

// An honest loader: every glTF feature Candela ignores is named once per kind, in Scene::ignored and as
// one warning naming the file and the JSON path of its first occurrence.
const fs::path kModels = fs::path(CANDELA_SOURCE_DIR) / "tests" / "data" / "models";

struct Loaded {
    Scene scene;
    int warnings;
    std::string err;
};
Loaded load_capturing(const fs::path& file) {
    const log::Level saved = log::level();
    log::set_level(log::Level::warn);
    testing::internal::CaptureStderr();
    const int before = log::warning_count();
    Loaded out;
    try {
        out.scene = load_gltf(file);
    } catch (...) {
        out.err = testing::internal::GetCapturedStderr();
        log::set_level(saved);
        throw;
    }
    out.warnings = log::warning_count() - before;
    out.err = testing::internal::GetCapturedStderr();
    log::set_level(saved);
    return out;
}

// Skins, animations and morph targets are implemented: not among the ignored features.
TEST(Loader, SkinAndAnimationsAreNotIgnored) {
    const Loaded fox = load_capturing(kModels / "Fox" / "Fox.glb");
    EXPECT_TRUE(fox.scene.ignored.empty());
    EXPECT_EQ(fox.warnings, 0) << fox.err;
    EXPECT_EQ(fox.scene.skins.size(), 1u);
    EXPECT_EQ(fox.scene.animations.size(), 3u);
    EXPECT_GT(fox.scene.triangle_count(), 100u);
}

TEST(Loader, IgnoredExtensionIsNamedWithTheObjectsUsingIt) {
    test::GltfBuilder b;
    b.json()["materials"] = {{{"extensions", {{"KHR_materials_diffuse_transmission", {{"diffuseTransmissionFactor", 0.5}}}}}},
                             {{"extensions", {{"KHR_materials_diffuse_transmission", {{"diffuseTransmissionFactor", 0.2}}}}}}};
    b.add_node({{"mesh", b.add_quad_mesh(0)}});
    b.add_node({{"mesh", b.add_quad_mesh(1)}});
    const Loaded l = load_capturing(b.write(test::test_dir("ignored_extension"), "ignored"));
    EXPECT_EQ(l.scene.ignored, (std::vector<std::string>{"KHR_materials_diffuse_transmission on 2 materials"}));
    EXPECT_EQ(l.warnings, 1) << l.err;
    EXPECT_NE(l.err.find("ignored.gltf: materials[0].extensions.KHR_materials_diffuse_transmission: KHR_materials_diffuse_transmission on 2 materials"),
              std::string::npos) << l.err;
}

// The material extensions' layers load with their textures, and nothing of them is ignored.
TEST(Loader, ClearcoatLoadsWithItsTextures) {
    const Loaded cc = load_capturing(kModels / "ClearCoatTest" / "ClearCoatTest.gltf");
    EXPECT_TRUE(cc.scene.ignored.empty());
    EXPECT_EQ(cc.warnings, 0) << cc.err;
    int coated = 0, coat_normal_maps = 0;
    for (const Material& m : cc.scene.materials) {
        coated += m.clearcoat > 0.0f;
        coat_normal_maps += m.ext_textures[Material::ext_clearcoat_normal].present();
    }
    EXPECT_EQ(coated, 6);
    EXPECT_EQ(coat_normal_maps, 2);
}

TEST(Loader, MorphTargetsAreNotIgnored) {
    const Loaded cube = load_capturing(kModels / "AnimatedMorphCube" / "AnimatedMorphCube.glb");
    EXPECT_TRUE(cube.scene.ignored.empty());
    EXPECT_EQ(cube.warnings, 0) << cube.err;
    EXPECT_EQ(cube.scene.meshes[0].primitives[0].targets.size(), 2u);
}

// The test models and the sample scenes warn about nothing but the features they use that
// Candela ignores (the validation adds no noise on good files), and RiggedFigure about its skin
// weights, which do not sum to 1 (normalised; test_loader_animation.cpp).
TEST(Loader, ModelsWarnOnlyAboutIgnoredFeatures) {
    std::vector<fs::path> files;
    for (const auto& e : fs::recursive_directory_iterator(kModels))
        if (e.path().extension() == ".gltf" || e.path().extension() == ".glb") files.push_back(e.path());
    for (const auto& e : fs::directory_iterator(kScenes))
        if (e.path().extension() == ".gltf") files.push_back(e.path());
    ASSERT_GE(files.size(), 20u);
    for (const fs::path& f : files) {
        SCOPED_TRACE(f.string());
        const Loaded l = load_capturing(f);
        const int weights = f.filename() == "RiggedFigure.glb" ? 1 : 0;
        EXPECT_EQ(l.warnings, static_cast<int>(l.scene.ignored.size()) + weights) << l.err;
    }
}

TEST(Loader, UnimplementedRequiredExtensionIsRejected) {
    EXPECT_NE(load_error(kBroken / "required_extension.gltf").find("required_extension.gltf: extensionsRequired: 'KHR_materials_diffuse_transmission' is not supported"),
              std::string::npos);
}

TEST(Loader, TexCoordAboveOneIsAnIgnoredFeature) {
    test::GltfBuilder b;
    b.add_node({{"mesh", b.add_quad_mesh()}});
    auto gltf = b.write(test::test_dir("texcoord2"), "quad");
    nlohmann::json doc = nlohmann::json::parse(std::ifstream(gltf));
    doc["images"] = {{{"uri", "does_not_matter.png"}}};
    doc["textures"] = {{{"source", 0}}};
    doc["materials"] = {{{"pbrMetallicRoughness", {{"baseColorTexture", {{"index", 0}, {"texCoord", 2}}}}}}};
    doc["meshes"][0]["primitives"][0]["material"] = 0;
    std::ofstream(gltf) << doc.dump();
    const Loaded l = load_capturing(gltf);
    EXPECT_EQ(l.scene.ignored, (std::vector<std::string>{"texture coordinate sets above 1 on 1 texture reference"}));
    EXPECT_NE(l.err.find("materials[0].pbrMetallicRoughness.baseColorTexture: texture coordinate sets above 1"), std::string::npos) << l.err;
    EXPECT_EQ(l.scene.materials[0].base_color_texture.texcoord, 0);
}

}  // namespace
}  // namespace candela
