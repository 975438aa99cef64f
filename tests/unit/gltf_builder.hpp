#pragma once
// Builds small glTF files for tests: JSON through nlohmann, one binary buffer written next to it.
#include <unistd.h>

#include <algorithm>
#include <cstring>
#include <filesystem>
#include <fstream>
#include <string>
#include <vector>

#include <glm/glm.hpp>
#include <nlohmann/json.hpp>

namespace candela::test {

class GltfBuilder {
public:
    GltfBuilder() {
        json_ = {{"asset", {{"version", "2.0"}}}, {"scene", 0}, {"scenes", {{{"nodes", nlohmann::json::array()}}}}};
    }
    nlohmann::json& json() { return json_; }

    // Appends raw bytes (4-byte aligned) as a new buffer view; returns its index.
    int add_view(const void* data, size_t bytes, int stride = 0) {
        while (bin_.size() % 4) bin_.push_back(0);
        nlohmann::json view = {{"buffer", 0}, {"byteOffset", bin_.size()}, {"byteLength", bytes}};
        if (stride) view["byteStride"] = stride;
        const auto* p = static_cast<const unsigned char*>(data);
        bin_.insert(bin_.end(), p, p + bytes);
        json_["bufferViews"].push_back(view);
        return static_cast<int>(json_["bufferViews"].size()) - 1;
    }
    int add_accessor(int view, int component_type, size_t count, const std::string& type, bool normalized = false) {
        nlohmann::json a = {{"bufferView", view}, {"componentType", component_type}, {"count", count}, {"type", type}};
        if (normalized) a["normalized"] = true;
        json_["accessors"].push_back(a);
        return static_cast<int>(json_["accessors"].size()) - 1;
    }
    int add_positions(const std::vector<glm::vec3>& p) {
        const int a = add_accessor(add_view(p.data(), p.size() * 12), 5126, p.size(), "VEC3");
        glm::vec3 lo(1e30f), hi(-1e30f);
        for (const auto& v : p) lo = glm::min(lo, v), hi = glm::max(hi, v);
        json_["accessors"][static_cast<size_t>(a)]["min"] = {lo.x, lo.y, lo.z};
        json_["accessors"][static_cast<size_t>(a)]["max"] = {hi.x, hi.y, hi.z};
        return a;
    }
    int add_vec3(const std::vector<glm::vec3>& v) { return add_accessor(add_view(v.data(), v.size() * 12), 5126, v.size(), "VEC3"); }
    int add_vec2(const std::vector<glm::vec2>& v) { return add_accessor(add_view(v.data(), v.size() * 8), 5126, v.size(), "VEC2"); }
    int add_indices(const std::vector<uint32_t>& i) { return add_accessor(add_view(i.data(), i.size() * 4), 5125, i.size(), "SCALAR"); }
    // A mesh with one primitive; attributes given as name -> accessor. Returns the mesh index.
    int add_mesh(const nlohmann::json& attributes, int indices = -1, int material = -1, int mode = -1) {
        nlohmann::json prim = {{"attributes", attributes}};
        if (indices >= 0) prim["indices"] = indices;
        if (material >= 0) prim["material"] = material;
        if (mode >= 0) prim["mode"] = mode;
        json_["meshes"].push_back({{"primitives", {prim}}});
        return static_cast<int>(json_["meshes"].size()) - 1;
    }
    int add_node(nlohmann::json node, bool root = true) {
        json_["nodes"].push_back(std::move(node));
        const int i = static_cast<int>(json_["nodes"].size()) - 1;
        if (root) json_["scenes"][0]["nodes"].push_back(i);
        return i;
    }
    // A unit quad in the XY plane facing +Z (two triangles), positions/normals/uvs.
    int add_quad_mesh(int material = -1, bool with_normals = true) {
        const std::vector<glm::vec3> p = {{-1, -1, 0}, {1, -1, 0}, {1, 1, 0}, {-1, 1, 0}};
        const std::vector<glm::vec3> n(4, glm::vec3(0, 0, 1));
        const std::vector<glm::vec2> uv = {{0, 1}, {1, 1}, {1, 0}, {0, 0}};
        nlohmann::json attrs = {{"POSITION", add_positions(p)}, {"TEXCOORD_0", add_vec2(uv)}};
        if (with_normals) attrs["NORMAL"] = add_vec3(n);
        return add_mesh(attrs, add_indices({0, 1, 2, 0, 2, 3}), material);
    }

    // Writes DIR/NAME.gltf and DIR/NAME.bin; returns the .gltf path.
    std::filesystem::path write(const std::filesystem::path& dir, const std::string& name) {
        std::filesystem::create_directories(dir);
        if (!bin_.empty()) json_["buffers"] = {{{"uri", name + ".bin"}, {"byteLength", bin_.size()}}};
        std::ofstream(dir / (name + ".bin"), std::ios::binary).write(reinterpret_cast<const char*>(bin_.data()),
                                                                      static_cast<std::streamsize>(bin_.size()));
        declare_extensions(json_);  // glTF requires every extension in use to be in extensionsUsed
        const auto path = dir / (name + ".gltf");
        std::ofstream(path) << json_.dump(1);
        return path;
    }

private:
    void declare_extensions(const nlohmann::json& root) {
        std::vector<std::string> names;
        auto collect = [&](auto&& self, const nlohmann::json& v) -> void {
            if (v.is_object() && v.contains("extensions") && v["extensions"].is_object())
                for (const auto& [ext, _] : v["extensions"].items()) names.push_back(ext);
            if (v.is_structured())
                for (const auto& child : v) self(self, child);
        };
        collect(collect, root);
        for (const std::string& ext : names) {
            auto& used = json_["extensionsUsed"];
            if (std::find(used.begin(), used.end(), ext) == used.end()) used.push_back(ext);
        }
    }
    nlohmann::json json_;
    std::vector<unsigned char> bin_;
};

// This process's scratch root under the system temp directory, removed when the process exits
// (a test that crashes leaves it behind for inspection).
inline const std::filesystem::path& test_root(const std::string& prefix = "candela_test_") {
    struct Root {
        std::filesystem::path path;
        ~Root() {
            std::error_code ec;
            std::filesystem::remove_all(path, ec);
        }
    };
    static Root root{std::filesystem::temp_directory_path() / (prefix + std::to_string(::getpid()))};
    return root.path;
}

// A fresh directory under this process's scratch root.
inline std::filesystem::path test_dir(const std::string& name) {
    const auto dir = test_root() / name;
    std::filesystem::remove_all(dir);
    std::filesystem::create_directories(dir);
    return dir;
}

}  // namespace candela::test
