#pragma once
// Internal to the glTF loader (gltf_loader*.cpp): the Loader that builds a Scene from a parsed
// tinygltf::Model, and the small helpers its parts share. The Loader's members are defined by
// concern, one file each:
//   gltf_loader.cpp            the build order (Loader::build), the file and its container, the entry points
//   gltf_loader_materials.cpp  image decoding, textures, materials
//   gltf_loader_meshes.cpp     accessor reads, meshes, primitives, skin attributes, morph targets
//   gltf_loader_nodes.cpp      nodes, cameras, lights, the environment
//   gltf_loader_animation.cpp  skins, animations, the deformation setup and its rest pose check
// Not part of the engine's interface: include only from the loader's files.
#include <tiny_gltf.h>

#include <algorithm>
#include <cmath>
#include <filesystem>
#include <limits>
#include <map>
#include <string>
#include <vector>

#include <glm/glm.hpp>

#include "core/error.hpp"
#include "core/log.hpp"
#include "scene/scene.hpp"

namespace candela::gltf_loading {

namespace fs = std::filesystem;
using tinygltf::Value;

constexpr int kMaxImageSide = 16384;

std::string trim(std::string s);
// "meshes[3]"
std::string idx(const char* array, size_t i);
// A number as a person would write it in a message: 2.2e+98, 4, 0.5.
std::string num(double v);
// A member of a JSON object (extensions) as a number, or `fallback` when absent or not a number.
double number(const Value& object, const char* key, double fallback);

template <int N>
glm::vec<N, float> vec(const Value& object, const char* key, glm::vec<N, float> fallback) {
    if (!object.IsObject() || !object.Has(key)) return fallback;
    const Value& v = object.Get(key);
    if (!v.IsArray() || v.ArrayLen() != N) return fallback;
    glm::vec<N, float> out;
    for (int i = 0; i < N; ++i) {
        if (!v.Get(i).IsNumber()) return fallback;
        out[i] = static_cast<float>(v.Get(i).GetNumberAsDouble());
    }
    return out;
}

// An extension's object in `map`, or null when absent or not an object.
const Value* extension(const tinygltf::ExtensionMap& map, const char* name);

// Embedded or external images, decoded with stb_image after tinygltf has parsed the file: its
// callback only keeps each image's bytes, and decode_images() decodes them on every core
// (FlightHelmet's fifteen 2048x2048 PNGs were most of its load time, one after another). Never
// fails the load: an undecodable image stays empty and gets the fallback texture later.
struct ImageDecodeLog {
    struct Entry {
        std::vector<unsigned char> bytes;  // as read (PNG, JPEG)
        int width = 0, height = 0;
        std::vector<unsigned char> rgba8;  // decoded
        std::string problem;               // why not
    };
    std::map<int, Entry> images;  // by glTF image index
    std::map<int, std::string> problems;
};


// tinygltf's image loader callback: keeps the bytes for decode_images.
bool keep_image_bytes(tinygltf::Image*, const int image_index, std::string*, std::string*, int, int, const unsigned char* bytes, int size,
                      void* user);
void decode_images(ImageDecodeLog& log);

class Loader {
public:
    Loader(const fs::path& path, const tinygltf::Model& model, ImageDecodeLog& images, const std::vector<bool>& unavailable)
        : file_(path.string()), dir_(path.parent_path()), m_(model), image_log_(images), unavailable_(unavailable) {}

    Scene build();

private:
    [[noreturn]] void fail(const std::string& json_path, const std::string& what) const {
        throw bad_input(file_ + ": " + json_path + ": " + what);
    }
    void warn(const std::string& json_path, const std::string& what) const {
        log::warn(file_ + ": " + json_path + ": " + what);
    }
    // A JSON number as a float: one that does not fit (|v| > FLT_MAX) is bad input.
    float f32(const std::string& json_path, double v) const {
        if (!std::isfinite(v) || std::fabs(v) > static_cast<double>(std::numeric_limits<float>::max()))
            fail(json_path, num(v) + " does not fit a 32-bit float");
        return static_cast<float>(v);
    }
    // A factor with a valid range (glTF's, or Candela's limit where glTF has none, so that sums
    // and products in float stay finite): values outside are clamped with a warning.
    float factor(const std::string& json_path, double v, float lo, float hi) const {
        const float f = f32(json_path, v);
        if (f >= lo && f <= hi) return f;
        warn(json_path, num(f) + " is outside [" + num(lo) + ", " + num(hi) + "]; clamped");
        return std::clamp(f, lo, hi);
    }
    template <int N>
    glm::vec<N, float> factors(const std::string& json_path, const std::vector<double>& v, float lo, float hi) const {
        glm::vec<N, float> out;
        for (int i = 0; i < N; ++i) out[i] = factor(json_path + "[" + std::to_string(i) + "]", v[static_cast<size_t>(i)], lo, hi);
        return out;
    }
    // The same for an object's member (extensions), with a fallback when absent or not a number.
    float factor(const std::string& json_path, const Value& object, const char* key, double fallback, float lo, float hi) const {
        return factor(json_path + "." + key, number(object, key, fallback), lo, hi);
    }
    template <int N>
    glm::vec<N, float> factors(const std::string& json_path, const Value& object, const char* key, glm::vec<N, float> fallback,
                               float lo, float hi) const {
        if (!object.IsObject() || !object.Has(key)) return fallback;
        const Value& v = object.Get(key);
        if (!v.IsArray() || v.ArrayLen() != N) return fallback;
        std::vector<double> d;
        for (int i = 0; i < N; ++i) {
            if (!v.Get(i).IsNumber()) return fallback;
            d.push_back(v.Get(i).GetNumberAsDouble());
        }
        return factors<N>(json_path + "." + key, d, lo, hi);
    }

    // Reads an accessor as float vectors (normalized integers mapped to [0,1] / [-1,1]).
    std::vector<glm::vec4> read_accessor(int accessor, const std::string& path, int want_components_max) const;
    // The same, flattened: `*components` floats per element (at most `want_components_max`, e.g. 16 for MAT4).
    std::vector<float> read_floats(int accessor, const std::string& path, int want_components_max, int* components) const;
    std::vector<uint32_t> read_indices(int accessor, const std::string& path, size_t vertex_count) const;
    // Byte range check of a (bufferView, offset, element size, stride, count) read.
    const unsigned char* view_data(int view, size_t offset, size_t elem, size_t stride, size_t count,
                                   const std::string& path) const;

    void build_images(Scene& scene);
    Material build_material(size_t i, Scene& scene);
    TextureRef texture_ref(const Value& ext, const char* key, const std::string& path, const char* scale_key) const;
    void convert_specular_glossiness(Material& mat, const Value& e, const std::string& path, Scene& scene);
    TextureRef texture_ref(const tinygltf::TextureInfo& info, const std::string& path, double scale) const;
    TextureRef texture_ref(int index, int texcoord, const tinygltf::ExtensionMap& ext, const std::string& path,
                           double scale) const;
    Mesh build_mesh(size_t i, Scene& scene);
    void read_skin_attributes(const tinygltf::Primitive& p, const std::string& path, Primitive& prim) const;
    void read_morph_targets(const tinygltf::Primitive& p, const std::string& path, Primitive& prim) const;
    void build_nodes(Scene& scene);
    void build_instances(Scene& scene);  // EXT_mesh_gpu_instancing (gltf_loader_nodes.cpp)
    // A scene far from the file's origin moved next to it in double (gltf_loader_nodes.cpp).
    void rebase_far_scene(Scene& scene);
    void hoist_transform_roots(Scene& scene, const std::vector<bool>& joint);
    void build_skins(Scene& scene);
    void build_animations(Scene& scene);
    void build_deformation(Scene& scene);
    void check_posed(const Scene& scene) const;
    void build_environment(Scene& scene);
    // The JSON path of scene.meshes[mesh].primitives[prim] in the file (meshes duplicated for
    // several deformed instances and skipped primitives shift the indices).
    std::string primitive_path(size_t mesh, size_t prim) const {
        const size_t src = mesh < mesh_source_.size() ? mesh_source_[mesh] : mesh;
        const size_t sp = src < primitive_source_.size() && prim < primitive_source_[src].size() ? primitive_source_[src][prim] : prim;
        return idx("meshes", src) + "." + idx("primitives", sp);
    }

    std::string file_;
    fs::path dir_;
    const tinygltf::Model& m_;
    ImageDecodeLog& image_log_;
    const std::vector<bool>& unavailable_;  // buffers with a stand-in for data the file does not provide
    std::vector<std::vector<size_t>> primitive_source_;  // [file mesh][built primitive] -> the file's primitive index
    std::vector<size_t> mesh_source_;                    // [scene mesh] -> the file's mesh (copies for deformed instances)
    std::vector<bool> own_weights_;                      // [node]: the node has its own `weights`
    // [file node]: its local transform and translation as the file's numbers, in double.
    std::vector<glm::dmat4> dlocal_;
    std::vector<glm::dvec3> dtranslation_;

    // Whether an accessor's data lies in such a buffer (the validation warned about it).
    bool unavailable(int accessor) const {
        if (accessor < 0 || static_cast<size_t>(accessor) >= m_.accessors.size()) return false;
        const tinygltf::Accessor& a = m_.accessors[static_cast<size_t>(accessor)];
        for (int view : {a.bufferView, a.sparse.isSparse ? a.sparse.indices.bufferView : -1, a.sparse.isSparse ? a.sparse.values.bufferView : -1}) {
            if (view < 0 || static_cast<size_t>(view) >= m_.bufferViews.size()) continue;
            const int b = m_.bufferViews[static_cast<size_t>(view)].buffer;
            if (b >= 0 && static_cast<size_t>(b) < unavailable_.size() && unavailable_[static_cast<size_t>(b)]) return true;
        }
        return false;
    }
};

}  // namespace candela::gltf_loading
