// Loader: compressed and instanced glTF geometry. KHR_draco_mesh_compression and
// EXT_meshopt_compression decode to the geometry of the uncompressed model; EXT_mesh_gpu_instancing
// places every instance where the file says; KHR_texture_basisu falls back to the PNG/JPEG source
// or is refused with advice; KHR_xmp loads silently. Bad extension data (wrong members, corrupt,
// truncated or bit-flipped streams) is bad input naming the JSON path, never a crash.
#include <gtest/gtest.h>

#include <cstring>
#include <fstream>
#include <set>
#include <sstream>

#include <glm/gtc/matrix_transform.hpp>
#include <glm/gtc/quaternion.hpp>
#include <nlohmann/json.hpp>

#include "core/error.hpp"
#include "core/log.hpp"
#include "scene/gltf_validate_internal.hpp"
#include "rt/rt_geometry.hpp"
#include "scene/gltf_loader.hpp"

#ifndef CANDELA_SOURCE_DIR
#error "CANDELA_SOURCE_DIR must be defined by the build"
#endif

namespace candela {
namespace {

namespace fs = std::filesystem;
using json = nlohmann::json;

const fs::path kModelDir = fs::path(CANDELA_SOURCE_DIR) / "tests" / "data" / "models";

std::string file_bytes(const fs::path& p) {
    std::ifstream in(p, std::ios::binary);
    std::ostringstream s;
    s << in.rdbuf();
    return s.str();
}

// A .glb split into its JSON and BIN chunks, and put back together.
struct Glb {
    json doc;
    std::string bin;
};
Glb read_glb(const fs::path& p) {
    const std::string b = file_bytes(p);
    uint32_t json_len = 0, bin_len = 0;
    std::memcpy(&json_len, b.data() + 12, 4);
    std::memcpy(&bin_len, b.data() + 20 + json_len, 4);
    return {json::parse(b.substr(20, json_len)), b.substr(28 + json_len, bin_len)};
}
std::string write_glb(const Glb& g) {
    std::string j = g.doc.dump();
    j.append((4 - j.size() % 4) % 4, ' ');
    std::string bin = g.bin;
    bin.append((4 - bin.size() % 4) % 4, '\0');
    std::string out = "glTF";
    auto u32 = [&](uint32_t v) { out.append(reinterpret_cast<const char*>(&v), 4); };
    u32(2);
    u32(static_cast<uint32_t>(12 + 8 + j.size() + 8 + bin.size()));
    u32(static_cast<uint32_t>(j.size()));
    out += "JSON";
    out += j;
    u32(static_cast<uint32_t>(bin.size()));
    out.append("BIN\0", 4);
    out += bin;
    return out;
}

// Box-Draco as a self-contained .gltf (its Box.bin as a data URI), for changing either part.
json draco_box(const std::string& bin) {
    json d = json::parse(file_bytes(kModelDir / "Box-Draco" / "Box.gltf"));
    d["buffers"][0]["uri"] = "data:application/octet-stream;base64," + gltf::validation::base64_encode(bin);
    d["buffers"][0]["byteLength"] = bin.size();
    return d;
}
const std::string& draco_bin() {
    static const std::string b = file_bytes(kModelDir / "Box-Draco" / "Box.bin");
    return b;
}

// Loads `bytes` as if it were `as`; returns "" or the bad_input message. Any other exception
// (or a crash) fails the test.
std::string load_message(const fs::path& as, const std::string& bytes, Scene* out = nullptr) {
    try {
        Scene s = load_gltf_from_memory(as, bytes);
        if (out) *out = std::move(s);
        return {};
    } catch (const Error& e) {
        EXPECT_EQ(e.code(), ExitCode::bad_input) << e.what();
        return e.what();
    }
}

// Every triangle as its three world-space corners (a rotation of them brought to a fixed order).
std::vector<std::array<glm::vec3, 3>> world_triangles(const Scene& scene) {
    std::vector<std::array<glm::vec3, 3>> out;
    for (const Node& node : scene.nodes) {
        if (node.mesh < 0) continue;
        for (const Primitive& p : scene.meshes[static_cast<size_t>(node.mesh)].primitives)
            for (size_t t = 0; t + 2 < p.indices.size(); t += 3) {
                std::array<glm::vec3, 3> tri;
                for (int k = 0; k < 3; ++k) tri[static_cast<size_t>(k)] = glm::vec3(node.world * glm::vec4(p.vertices[p.indices[t + static_cast<size_t>(k)]].position, 1.0f));
                out.push_back(tri);
            }
    }
    return out;
}

bool same_triangle(const std::array<glm::vec3, 3>& a, const std::array<glm::vec3, 3>& b, float tol) {
    for (int r = 0; r < 3; ++r) {  // the same winding, any starting corner
        bool all = true;
        for (int k = 0; k < 3 && all; ++k)
            all = glm::all(glm::lessThanEqual(glm::abs(a[static_cast<size_t>(k)] - b[static_cast<size_t>((k + r) % 3)]), glm::vec3(tol)));
        if (all) return true;
    }
    return false;
}

// Box-Draco is the Khronos "Box" compressed; BoxTextured is the same box (with texture
// coordinates), uncompressed. Draco quantised the positions (11 bits over the box: ~0.0005).
TEST(DracoCompression, BoxDecodesToTheUncompressedBox) {
    const int before = log::warning_count();
    const Scene draco = load_gltf(kModelDir / "Box-Draco" / "Box.gltf");
    EXPECT_EQ(log::warning_count(), before) << "a valid Draco file loads without warnings";
    EXPECT_TRUE(draco.ignored.empty());
    const Scene plain = load_gltf(kModelDir / "BoxTextured" / "BoxTextured.gltf");
    const auto a = world_triangles(draco), b = world_triangles(plain);
    ASSERT_EQ(a.size(), 12u);
    ASSERT_EQ(b.size(), 12u);
    std::vector<bool> used(b.size(), false);
    for (size_t i = 0; i < a.size(); ++i) {
        bool found = false;
        for (size_t j = 0; j < b.size() && !found; ++j)
            if (!used[j] && same_triangle(a[i], b[j], 2e-3f)) used[j] = found = true;
        EXPECT_TRUE(found) << "decoded triangle " << i << " is not a triangle of the uncompressed box";
    }
    // The normals: unit, along the face normal of the triangle (so the winding is right too).
    const Primitive& p = draco.meshes.at(0).primitives.at(0);
    ASSERT_EQ(p.vertices.size(), 24u);
    for (size_t t = 0; t < p.indices.size(); t += 3) {
        const glm::vec3 v0 = p.vertices[p.indices[t]].position, v1 = p.vertices[p.indices[t + 1]].position,
                        v2 = p.vertices[p.indices[t + 2]].position;
        const glm::vec3 face = glm::normalize(glm::cross(v1 - v0, v2 - v0));
        for (int k = 0; k < 3; ++k) EXPECT_GT(glm::dot(face, p.vertices[p.indices[t + static_cast<size_t>(k)]].normal), 0.99f);
    }
    // The accessor's min/max (+-0.5004885 in mesh space) are Draco's quantisation grid: the decoded
    // box lies within them, less than a grid step (1/1023 of the extent) inside.
    const Bounds bounds = p.bounds;
    for (int c = 0; c < 3; ++c) {
        EXPECT_GE(bounds.min[c], -0.5004885f);
        EXPECT_LE(bounds.max[c], 0.5004885f);
        EXPECT_NEAR(bounds.min[c], -0.5004885f, 1e-3f);
        EXPECT_NEAR(bounds.max[c], 0.5004885f, 1e-3f);
    }
}

// Morph targets stay uncompressed beside the Draco-compressed base attributes.
TEST(DracoCompression, MorphTargetsStayUncompressed) {
    const int before = log::warning_count();
    const Scene s = load_gltf(kModelDir / "MorphPrimitivesTest-Draco" / "MorphPrimitivesTest.gltf");
    EXPECT_EQ(log::warning_count(), before);
    size_t morphed = 0;
    for (const Mesh& m : s.meshes)
        for (const Primitive& p : m.primitives) {
            EXPECT_GT(p.triangle_count(), 0u);
            for (const MorphTarget& t : p.targets) {
                ++morphed;
                EXPECT_EQ(t.position.size(), p.rest.size());
            }
        }
    EXPECT_GT(morphed, 0u);
}

TEST(DracoCompression, BadExtensionNamesTheJsonPath) {
    const fs::path as = kModelDir / "Box-Draco" / "edited.gltf";
    const std::string ext = "meshes[0].primitives[0].extensions.KHR_draco_mesh_compression";
    {
        json d = draco_box(draco_bin());
        d["meshes"][0]["primitives"][0]["extensions"]["KHR_draco_mesh_compression"].erase("bufferView");
        const std::string m = load_message(as, d.dump());
        EXPECT_NE(m.find(ext + ": 'bufferView' is required"), std::string::npos) << m;
    }
    {
        json d = draco_box(draco_bin());
        d["meshes"][0]["primitives"][0]["extensions"]["KHR_draco_mesh_compression"]["attributes"]["POSITION"] = 7;
        const std::string m = load_message(as, d.dump());
        EXPECT_NE(m.find(ext + ".attributes.POSITION: the Draco mesh has no attribute with id 7"), std::string::npos) << m;
    }
    {
        json d = draco_box(draco_bin());
        d["accessors"][2]["count"] = 23;  // POSITION; NORMAL keeps 24 (so the primitive check names that first)
        d["accessors"][1]["count"] = 23;
        const std::string m = load_message(as, d.dump());
        EXPECT_NE(m.find(ext + ".attributes."), std::string::npos) << m;
        EXPECT_NE(m.find("has count 23 but the Draco mesh has 24 points"), std::string::npos) << m;
    }
    {
        json d = draco_box(draco_bin());
        d["accessors"][0]["count"] = 33;
        const std::string m = load_message(as, d.dump());
        EXPECT_NE(m.find("meshes[0].primitives[0].indices: accessor 0 has count 33 but the Draco mesh"), std::string::npos) << m;
    }
    {
        json d = draco_box(draco_bin());
        d["meshes"][0]["primitives"][0]["extensions"]["KHR_draco_mesh_compression"]["attributes"]["TEXCOORD_0"] = 0;
        const std::string m = load_message(as, d.dump());
        EXPECT_NE(m.find(ext + ".attributes.TEXCOORD_0: the primitive has no TEXCOORD_0 attribute"), std::string::npos) << m;
    }
}

// Truncated and bit-flipped streams: an error naming the extension, or (a flip the decoder
// cannot notice) a scene; never a crash or another kind of failure. Run under ASan/UBSan too.
TEST(DracoCompression, CorruptStreamsAreBadInputNotCrashes) {
    const fs::path as = kModelDir / "Box-Draco" / "edited.gltf";
    const std::string ext = "meshes[0].primitives[0].extensions.KHR_draco_mesh_compression";
    const std::string& bin = draco_bin();
    const size_t stream = 118;  // bufferViews[0].byteLength
    int truncated_errors = 0;
    for (size_t len = 1; len < stream; ++len) {
        json d = draco_box(bin);
        d["bufferViews"][0]["byteLength"] = len;
        const std::string m = load_message(as, d.dump());
        truncated_errors += !m.empty();
        if (!m.empty()) EXPECT_NE(m.find(ext), std::string::npos) << len << ": " << m;
    }
    EXPECT_EQ(truncated_errors, static_cast<int>(stream) - 1) << "every truncated stream is refused";
    int flip_errors = 0, flips = 0;
    for (size_t byte = 0; byte < stream; ++byte)
        for (int bit = 0; bit < 8; bit += 3) {
            std::string bad = bin;
            bad[byte] = static_cast<char>(bad[byte] ^ (1 << bit));
            const std::string m = load_message(as, draco_box(bad).dump());
            ++flips;
            flip_errors += !m.empty();
        }
    std::printf("bit flips: %d of %d refused\n", flip_errors, flips);
    EXPECT_GT(flip_errors, 0);
    // Not a Draco stream at all.
    const std::string m = load_message(as, draco_box(std::string(120, 'x')).dump());
    EXPECT_NE(m.find(ext + ": not a Draco stream"), std::string::npos) << m;
}

// gltfpack's meshopt-compressed, quantised Box: a closed box in [-0.5, 0.5]^3 (the node's scale
// and translation undo the quantisation; the accessors' min/max are 0 and 16383).
TEST(MeshoptCompression, BoxDecodesToAClosedBoxWithinItsBounds) {
    const int before = log::warning_count();
    const Scene s = load_gltf(kModelDir / "BoxMeshopt" / "BoxMeshopt.glb");
    EXPECT_EQ(log::warning_count(), before);
    const auto tris = world_triangles(s);
    ASSERT_EQ(tris.size(), 12u);
    const Bounds b = s.world_bounds();
    for (int c = 0; c < 3; ++c) {
        EXPECT_NEAR(b.min[c], -0.5f, 1e-3f);
        EXPECT_NEAR(b.max[c], 0.5f, 1e-3f);
    }
    // Closed: with corners welded by position, every edge belongs to exactly two triangles, once
    // in each direction (consistent winding).
    auto key = [](glm::vec3 p) { return glm::ivec3(glm::round(p * 1000.0f)); };
    std::map<std::pair<std::array<int, 3>, std::array<int, 3>>, int> edges;
    for (const auto& t : tris)
        for (int k = 0; k < 3; ++k) {
            const glm::ivec3 a = key(t[static_cast<size_t>(k)]), c = key(t[static_cast<size_t>((k + 1) % 3)]);
            ++edges[{{a.x, a.y, a.z}, {c.x, c.y, c.z}}];
        }
    for (const auto& [e, n] : edges) {
        EXPECT_EQ(n, 1);
        EXPECT_EQ(edges.count({e.second, e.first}), 1u) << "an open or inconsistently wound edge";
    }
    // Octahedral-free normals from normalized BYTE: unit, along the face normals.
    const Primitive& p = s.meshes.at(0).primitives.at(0);
    for (size_t t = 0; t < p.indices.size(); t += 3) {
        const glm::vec3 v0 = p.vertices[p.indices[t]].position, v1 = p.vertices[p.indices[t + 1]].position,
                        v2 = p.vertices[p.indices[t + 2]].position;
        const glm::vec3 face = glm::normalize(glm::cross(v1 - v0, v2 - v0));
        for (int k = 0; k < 3; ++k) EXPECT_GT(glm::dot(face, p.vertices[p.indices[t + static_cast<size_t>(k)]].normal), 0.99f);
    }
}

TEST(MeshoptCompression, BadExtensionNamesTheJsonPath) {
    const fs::path as = kModelDir / "BoxMeshopt" / "edited.glb";
    const std::string ext = "bufferViews[1].extensions.EXT_meshopt_compression";
    auto edited = [&](const std::function<void(Glb&)>& change) {
        Glb g = read_glb(kModelDir / "BoxMeshopt" / "BoxMeshopt.glb");
        change(g);
        return load_message(as, write_glb(g));
    };
    std::string m = edited([](Glb& g) { g.doc["bufferViews"][1]["extensions"]["EXT_meshopt_compression"]["mode"] = "STRIPS"; });
    EXPECT_NE(m.find(ext + ".mode: 'STRIPS' is not ATTRIBUTES, TRIANGLES or INDICES"), std::string::npos) << m;
    m = edited([](Glb& g) { g.doc["bufferViews"][0]["extensions"]["EXT_meshopt_compression"]["filter"] = "QUATERNION"; });
    EXPECT_NE(m.find("bufferViews[0].extensions.EXT_meshopt_compression.byteStride: 4 is not 8 (filter QUATERNION)"), std::string::npos) << m;
    m = edited([](Glb& g) { g.doc["bufferViews"][1]["extensions"]["EXT_meshopt_compression"]["filter"] = "SPHERICAL"; });
    EXPECT_NE(m.find(ext + ".filter: 'SPHERICAL' is not"), std::string::npos) << m;
    m = edited([](Glb& g) { g.doc["bufferViews"][1]["extensions"]["EXT_meshopt_compression"]["byteStride"] = 6; });
    EXPECT_NE(m.find(ext + ".byteStride: 6 is not a multiple of 4 (mode ATTRIBUTES)"), std::string::npos) << m;
    m = edited([](Glb& g) { g.doc["bufferViews"][1]["extensions"]["EXT_meshopt_compression"]["count"] = 23; });
    EXPECT_NE(m.find(ext + ".count: count 23 x byteStride 8 = 184 bytes, but the bufferView's byteLength is 192"), std::string::npos) << m;
    m = edited([](Glb& g) { g.doc["bufferViews"][2]["extensions"]["EXT_meshopt_compression"]["count"] = 35; });
    EXPECT_NE(m.find("bufferViews[2].extensions.EXT_meshopt_compression.count: 35 is not a multiple of 3 (mode TRIANGLES)"), std::string::npos) << m;
    m = edited([](Glb& g) { g.doc["bufferViews"][1]["extensions"]["EXT_meshopt_compression"]["byteLength"] = 400; });
    EXPECT_NE(m.find(ext + ".byteLength: byteOffset 72 + byteLength 400 exceeds buffers[0].byteLength 228"), std::string::npos) << m;
    // A plain view of the fallback buffer has no data: warned and not drawn, not a crash.
    m = edited([](Glb& g) { g.doc["bufferViews"][1].erase("extensions"); });
    EXPECT_EQ(m, "");
}

TEST(MeshoptCompression, CorruptStreamsAreBadInputNotCrashes) {
    const fs::path as = kModelDir / "BoxMeshopt" / "edited.glb";
    const Glb original = read_glb(kModelDir / "BoxMeshopt" / "BoxMeshopt.glb");
    int errors = 0, runs = 0;
    // Truncated: each compressed view's byteLength cut short.
    for (int view = 0; view < 3; ++view) {
        const int64_t len = original.doc["bufferViews"][view]["extensions"]["EXT_meshopt_compression"]["byteLength"];
        for (int64_t cut = 1; cut < len; ++cut) {
            Glb g = original;
            g.doc["bufferViews"][view]["extensions"]["EXT_meshopt_compression"]["byteLength"] = cut;
            const std::string m = load_message(as, write_glb(g));
            EXPECT_NE(m, "") << "view " << view << " cut to " << cut << " bytes loaded";
            EXPECT_NE(m.find("bufferViews[" + std::to_string(view) + "].extensions.EXT_meshopt_compression: the compressed data is corrupt"),
                      std::string::npos) << m;
        }
    }
    // Bit flips in the compressed bytes (the first 225 of the BIN chunk).
    for (size_t byte = 0; byte < 225; ++byte)
        for (int bit = 0; bit < 8; bit += 2) {
            Glb g = original;
            g.bin[byte] = static_cast<char>(g.bin[byte] ^ (1 << bit));
            errors += !load_message(as, write_glb(g)).empty();
            ++runs;
        }
    std::printf("bit flips: %d of %d refused\n", errors, runs);
    EXPECT_GT(errors, 0);
}

// SimpleInstancing: one box mesh on one node with 125 instances (TRANSLATION, ROTATION, SCALE).
TEST(GpuInstancing, EveryInstanceIsPlacedAsTheFileSays) {
    const int before = log::warning_count();
    const Scene s = load_gltf(kModelDir / "SimpleInstancing" / "SimpleInstancing.glb");
    EXPECT_EQ(log::warning_count(), before);
    EXPECT_TRUE(s.ignored.empty());
    ASSERT_EQ(s.meshes.size(), 1u) << "the instances share the mesh";
    // The expected transforms, read from the file here independently of the loader.
    const Glb g = read_glb(kModelDir / "SimpleInstancing" / "SimpleInstancing.glb");
    auto floats = [&](int accessor) {
        const json& a = g.doc["accessors"][accessor];
        const json& v = g.doc["bufferViews"][a["bufferView"].get<int>()];
        const size_t n = a["count"].get<size_t>() * (a["type"] == "VEC4" ? 4 : 3);
        std::vector<float> out(n);
        std::memcpy(out.data(), g.bin.data() + v.value("byteOffset", 0) + a.value("byteOffset", 0), n * 4);
        return out;
    };
    const json& attrs = g.doc["nodes"][0]["extensions"]["EXT_mesh_gpu_instancing"]["attributes"];
    const std::vector<float> t = floats(attrs["TRANSLATION"]), r = floats(attrs["ROTATION"]), sc = floats(attrs["SCALE"]);
    ASSERT_EQ(t.size(), 125u * 3);
    std::vector<const Node*> drawn;
    for (const Node& n : s.nodes)
        if (n.mesh >= 0) drawn.push_back(&n);
    ASSERT_EQ(drawn.size(), 125u);
    EXPECT_EQ(s.triangle_count(), 125u * 12);
    for (size_t k = 0; k < 125; ++k) {
        const glm::quat q(r[k * 4 + 3], r[k * 4], r[k * 4 + 1], r[k * 4 + 2]);
        const glm::mat4 expect = glm::translate(glm::mat4(1.0f), glm::vec3(t[k * 3], t[k * 3 + 1], t[k * 3 + 2])) * glm::mat4_cast(glm::normalize(q)) *
                                 glm::scale(glm::mat4(1.0f), glm::vec3(sc[k * 3], sc[k * 3 + 1], sc[k * 3 + 2]));
        const glm::mat4& got = drawn[k]->world;
        for (int c = 0; c < 4; ++c)
            for (int row = 0; row < 4; ++row) EXPECT_NEAR(got[c][row], expect[c][row], 1e-5f) << "instance " << k;
    }
    // The scene spans the instances: translations 0..10, boxes up to 2 units.
    const Bounds b = s.world_bounds();
    EXPECT_GT(b.max.x - b.min.x, 10.0f);
    // The tracer's geometry holds every instance's triangles, in world space where the raster
    // draws them (the instances are flattened into its one BVH).
    const rt::RtGeometry geometry = rt::build_rt_geometry(s, 0);
    ASSERT_EQ(geometry.triangles.size(), 125u * 12);
    const auto world = world_triangles(s);
    for (size_t i = 0; i < world.size(); i += 37) {
        bool found = false;
        for (size_t j = 0; j < geometry.triangles.size() && !found; ++j)
            found = same_triangle(world[i], {glm::vec3(geometry.triangles[j].p0), glm::vec3(geometry.triangles[j].p1), glm::vec3(geometry.triangles[j].p2)}, 1e-4f);
        EXPECT_TRUE(found) << "world triangle " << i << " is not in the tracer's geometry";
    }
}

TEST(GpuInstancing, BadAttributesNameTheJsonPath) {
    const fs::path as = kModelDir / "SimpleInstancing" / "edited.glb";
    const std::string ext = "nodes[0].extensions.EXT_mesh_gpu_instancing.attributes.";
    auto edited = [&](const std::function<void(Glb&)>& change) {
        Glb g = read_glb(kModelDir / "SimpleInstancing" / "SimpleInstancing.glb");
        change(g);
        return load_message(as, write_glb(g));
    };
    std::string m = edited([](Glb& g) { g.doc["accessors"][5]["count"] = 124; });
    // (JSON members in name order: ROTATION is the first one read.)
    EXPECT_NE(m.find(ext + "SCALE: accessor 5 has 124 elements, ROTATION has 125 (one per instance)"), std::string::npos) << m;
    m = edited([](Glb& g) { g.doc["nodes"][0]["extensions"]["EXT_mesh_gpu_instancing"]["attributes"]["ROTATION"] = 3; });
    EXPECT_NE(m.find(ext + "ROTATION: accessor 3 is FLOAT VEC3; ROTATION must be VEC4"), std::string::npos) << m;
    m = edited([](Glb& g) { g.doc["nodes"][0]["extensions"]["EXT_mesh_gpu_instancing"]["attributes"]["SCALE"] = 99; });
    EXPECT_NE(m.find(ext + "SCALE: accessor 99 does not exist"), std::string::npos) << m;
    m = edited([](Glb& g) { g.doc["nodes"][0]["extensions"]["EXT_mesh_gpu_instancing"].erase("attributes"); });
    EXPECT_NE(m.find("nodes[0].extensions.EXT_mesh_gpu_instancing: needs a non-empty 'attributes' object"), std::string::npos) << m;
}

// BoxTextured with its texture marked as KTX2/Basis Universal.
json basisu_box(bool with_source, bool required) {
    json d = json::parse(file_bytes(kModelDir / "BoxTextured" / "BoxTextured.gltf"));
    d["images"].push_back({{"uri", "CesiumLogoFlat.ktx2"}, {"mimeType", "image/ktx2"}});
    json& tex = d["textures"][0];
    tex["extensions"]["KHR_texture_basisu"] = {{"source", d["images"].size() - 1}};
    if (!with_source) tex.erase("source");
    d["extensionsUsed"].push_back("KHR_texture_basisu");
    if (required) d["extensionsRequired"] = json::array({"KHR_texture_basisu"});
    return d;
}

TEST(TextureBasisu, FallbackSourceIsUsedAndWithoutOneARequiredFileIsRefused) {
    const fs::path as = kModelDir / "BoxTextured" / "edited.gltf";
    Scene s;
    const int before = log::warning_count();
    EXPECT_EQ(load_message(as, basisu_box(true, false).dump(), &s), "");
    EXPECT_TRUE(s.ignored.empty());
    ASSERT_FALSE(s.materials.empty());
    const int image = s.materials[0].base_color_texture.image;
    ASSERT_GE(image, 0);
    EXPECT_EQ(s.images[static_cast<size_t>(image)].width, 211) << "the PNG fallback is drawn, not the checker";
    EXPECT_EQ(log::warning_count(), before) << "the KTX2 image nothing draws is not reported as unreadable";
    const std::string m = load_message(as, basisu_box(false, true).dump());
    EXPECT_NE(m.find("textures[0].extensions.KHR_texture_basisu: KTX2/Basis Universal textures are not supported"), std::string::npos) << m;
    EXPECT_NE(m.find("re-exporting the file with PNG or JPEG textures works"), std::string::npos) << m;
    // A `source` that is the KTX2 image itself is no fallback.
    json ktx2_source = basisu_box(true, true);
    ktx2_source["textures"][0]["source"] = ktx2_source["textures"][0]["extensions"]["KHR_texture_basisu"]["source"];
    EXPECT_NE(load_message(as, ktx2_source.dump()).find("textures[0].extensions.KHR_texture_basisu: KTX2/Basis Universal"), std::string::npos);
}

TEST(Xmp, MetadataLoadsWithoutWarnings) {
    json d = json::parse(file_bytes(kModelDir / "BoxTextured" / "BoxTextured.gltf"));
    d["extensionsUsed"] = json::array({"KHR_xmp_json_ld", "KHR_xmp"});
    d["extensions"]["KHR_xmp_json_ld"] = {{"packets", json::array({{{"@context", {{"dc", "http://purl.org/dc/elements/1.1/"}}}, {"dc:title", "Box"}}})}};
    d["asset"]["extensions"]["KHR_xmp_json_ld"] = {{"packet", 0}};
    d["extensions"]["KHR_xmp"] = d["extensions"]["KHR_xmp_json_ld"];
    d["asset"]["extensions"]["KHR_xmp"] = {{"packet", 0}};
    const int before = log::warning_count();
    Scene s;
    EXPECT_EQ(load_message(kModelDir / "BoxTextured" / "edited.gltf", d.dump(), &s), "");
    EXPECT_EQ(log::warning_count(), before);
    EXPECT_TRUE(s.ignored.empty());
}

}  // namespace
}  // namespace candela
