#include "scene/gltf_loader.hpp"

#include <tiny_gltf.h>

#include <algorithm>
#include <atomic>
#include <cmath>
#include <limits>
#include <cstdio>
#include <cstring>
#include <fstream>
#include <functional>
#include <map>
#include <sstream>
#include <thread>

#include <glm/gtc/quaternion.hpp>
#include <glm/gtc/type_ptr.hpp>
#include <nlohmann/json.hpp>
#include <stb/stb_image.h>

#include "core/error.hpp"
#include "core/log.hpp"
#include "scene/animation.hpp"
#include "scene/gltf_validate.hpp"
#include "scene/mesh_utils.hpp"

namespace candela {
namespace {

namespace fs = std::filesystem;
using tinygltf::Value;

constexpr int kMaxImageSide = 16384;

std::string trim(std::string s) {
    while (!s.empty() && (s.back() == '\n' || s.back() == ' ' || s.back() == '\r')) s.pop_back();
    return s;
}

std::string idx(const char* array, size_t i) { return std::string(array) + "[" + std::to_string(i) + "]"; }

// A number as a person would write it in a message: 2.2e+98, 4, 0.5.
std::string num(double v) {
    char buf[32];
    std::snprintf(buf, sizeof buf, "%g", v);
    return buf;
}

double number(const Value& object, const char* key, double fallback) {
    if (!object.IsObject() || !object.Has(key)) return fallback;
    const Value& v = object.Get(key);
    return v.IsNumber() ? v.GetNumberAsDouble() : fallback;
}

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

const Value* extension(const tinygltf::ExtensionMap& map, const char* name) {
    auto it = map.find(name);
    return it == map.end() || !it->second.IsObject() ? nullptr : &it->second;
}

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

bool keep_image_bytes(tinygltf::Image*, const int image_index, std::string*, std::string*, int, int, const unsigned char* bytes, int size,
                      void* user) {
    auto* log = static_cast<ImageDecodeLog*>(user);
    log->images[image_index].bytes.assign(bytes, bytes + std::max(size, 0));
    return true;
}

// One image; `problem` empty on success. stb_image's failure reason is a global in some builds,
// so the message of a failed decode is taken again on the calling thread (decode_images).
void decode_one(ImageDecodeLog::Entry& e, bool with_reason) {
    const auto reason = [&](const char* fallback) {
        return std::string("cannot decode: ") + (with_reason && stbi_failure_reason() ? stbi_failure_reason() : fallback);
    };
    const int size = static_cast<int>(std::min<size_t>(e.bytes.size(), static_cast<size_t>(std::numeric_limits<int>::max())));
    int w = 0, h = 0, comp = 0;
    if (!stbi_info_from_memory(e.bytes.data(), size, &w, &h, &comp)) {
        e.problem = reason("unknown format");
        return;
    }
    if (w <= 0 || h <= 0 || w > kMaxImageSide || h > kMaxImageSide) {
        e.problem = "unsupported size " + std::to_string(w) + "x" + std::to_string(h);
        return;
    }
    unsigned char* pixels = stbi_load_from_memory(e.bytes.data(), size, &w, &h, &comp, 4);
    if (!pixels) {
        e.problem = reason("?");
        return;
    }
    e.width = w;
    e.height = h;
    e.rgba8.assign(pixels, pixels + static_cast<size_t>(w) * static_cast<size_t>(h) * 4);
    stbi_image_free(pixels);
}

void decode_images(ImageDecodeLog& log) {
    std::vector<ImageDecodeLog::Entry*> todo;
    for (auto& [index, e] : log.images) todo.push_back(&e);
    const size_t threads = std::min<size_t>(todo.size(), std::max(1u, std::thread::hardware_concurrency()));
    std::atomic<size_t> next{0};
    const auto work = [&] {
        for (size_t k; (k = next.fetch_add(1)) < todo.size();) decode_one(*todo[k], false);
    };
    std::vector<std::thread> pool;
    for (size_t t = 1; t < threads; ++t) pool.emplace_back(work);
    work();
    for (std::thread& t : pool) t.join();
    for (auto& [index, e] : log.images) {
        if (!e.problem.empty()) {
            e.problem.clear();
            decode_one(e, true);  // again, alone, for stb_image's reason
            if (!e.problem.empty()) log.problems[index] = e.problem;
        }
        e.bytes = {};
    }
}

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
    Material build_material(size_t i);
    TextureRef texture_ref(const tinygltf::TextureInfo& info, const std::string& path, double scale) const;
    TextureRef texture_ref(int index, int texcoord, const tinygltf::ExtensionMap& ext, const std::string& path,
                           double scale) const;
    Mesh build_mesh(size_t i, Scene& scene);
    void read_skin_attributes(const tinygltf::Primitive& p, const std::string& path, Primitive& prim) const;
    void read_morph_targets(const tinygltf::Primitive& p, const std::string& path, Primitive& prim) const;
    void build_nodes(Scene& scene);
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

const unsigned char* Loader::view_data(int view, size_t offset, size_t elem, size_t stride, size_t count,
                                       const std::string& path) const {
    if (view < 0 || static_cast<size_t>(view) >= m_.bufferViews.size())
        fail(path, "bufferView " + std::to_string(view) + " does not exist (the file has " +
                       std::to_string(m_.bufferViews.size()) + ")");
    const tinygltf::BufferView& bv = m_.bufferViews[static_cast<size_t>(view)];
    const std::string bv_path = idx("bufferViews", static_cast<size_t>(view));
    if (bv.buffer < 0 || static_cast<size_t>(bv.buffer) >= m_.buffers.size())
        fail(bv_path, "buffer " + std::to_string(bv.buffer) + " does not exist");
    const tinygltf::Buffer& buffer = m_.buffers[static_cast<size_t>(bv.buffer)];
    if (bv.byteOffset > buffer.data.size() || bv.byteLength > buffer.data.size() - bv.byteOffset)
        fail(bv_path, "byteOffset " + std::to_string(bv.byteOffset) + " + byteLength " +
                          std::to_string(bv.byteLength) + " exceeds buffer " + std::to_string(bv.buffer) +
                          " (" + std::to_string(buffer.data.size()) + " bytes)");
    if (count == 0) return buffer.data.data() + bv.byteOffset;
    // Overflow-safe: offset + (count-1)*stride + elem <= byteLength.
    const unsigned __int128 need =
        static_cast<unsigned __int128>(offset) + static_cast<unsigned __int128>(count - 1) * stride + elem;
    if (need > bv.byteLength)
        fail(path, "accessor reads past the end of bufferView " + std::to_string(view) + " (needs " +
                       std::to_string(static_cast<unsigned long long>(std::min<unsigned __int128>(need, ~0ull))) +
                       " bytes from offset " + std::to_string(offset) + ", view has " +
                       std::to_string(bv.byteLength) + ")");
    return buffer.data.data() + bv.byteOffset + offset;
}

float read_component(const unsigned char* p, int type, bool normalized) {
    switch (type) {
        case TINYGLTF_COMPONENT_TYPE_FLOAT: { float v; std::memcpy(&v, p, 4); return v; }
        case TINYGLTF_COMPONENT_TYPE_UNSIGNED_BYTE: return normalized ? *p / 255.0f : *p;
        case TINYGLTF_COMPONENT_TYPE_BYTE: {
            const auto v = static_cast<int8_t>(*p);
            return normalized ? std::max(v / 127.0f, -1.0f) : v;
        }
        case TINYGLTF_COMPONENT_TYPE_UNSIGNED_SHORT: { uint16_t v; std::memcpy(&v, p, 2); return normalized ? v / 65535.0f : v; }
        case TINYGLTF_COMPONENT_TYPE_SHORT: { int16_t v; std::memcpy(&v, p, 2); return normalized ? std::max(v / 32767.0f, -1.0f) : v; }
        case TINYGLTF_COMPONENT_TYPE_UNSIGNED_INT: { uint32_t v; std::memcpy(&v, p, 4); return static_cast<float>(v); }
        default: return 0.0f;
    }
}

std::vector<glm::vec4> Loader::read_accessor(int accessor, const std::string& path, int want_components_max) const {
    int nc = 0;
    const std::vector<float> flat = read_floats(accessor, path, std::min(want_components_max, 4), &nc);
    std::vector<glm::vec4> out(nc > 0 ? flat.size() / static_cast<size_t>(nc) : 0, glm::vec4(0.0f));
    for (size_t i = 0; i < out.size(); ++i)
        for (int c = 0; c < nc; ++c) out[i][c] = flat[i * static_cast<size_t>(nc) + static_cast<size_t>(c)];
    return out;
}

std::vector<float> Loader::read_floats(int accessor, const std::string& path, int want_components_max, int* components) const {
    if (accessor < 0 || static_cast<size_t>(accessor) >= m_.accessors.size())
        fail(path, "accessor " + std::to_string(accessor) + " does not exist (the file has " +
                       std::to_string(m_.accessors.size()) + ")");
    const tinygltf::Accessor& a = m_.accessors[static_cast<size_t>(accessor)];
    const std::string apath = path + " (accessors[" + std::to_string(accessor) + "])";
    const int csize = tinygltf::GetComponentSizeInBytes(static_cast<uint32_t>(a.componentType));
    const int ncomp = tinygltf::GetNumComponentsInType(static_cast<uint32_t>(a.type));
    if (csize <= 0 || ncomp <= 0) fail(apath, "invalid componentType or type");
    if (ncomp > want_components_max) fail(apath, "has " + std::to_string(ncomp) + " components, at most " +
                                                     std::to_string(want_components_max) + " expected");
    if ((a.type == TINYGLTF_TYPE_MAT2 || a.type == TINYGLTF_TYPE_MAT3) && csize < 4)
        fail(apath, "matrices of 8- or 16-bit components (padded columns) are not supported");
    constexpr size_t kMaxCount = size_t(1) << 28;
    if (a.count > kMaxCount || a.count * static_cast<size_t>(ncomp) > 4 * kMaxCount) fail(apath, "count " + std::to_string(a.count) + " is larger than supported");
    const size_t elem = static_cast<size_t>(csize * ncomp);
    const size_t nc = static_cast<size_t>(ncomp);
    *components = ncomp;
    std::vector<float> out(a.count * nc, 0.0f);
    auto read_block = [&](const unsigned char* base, size_t stride, size_t count, auto&& store) {
        float v[16];
        for (size_t i = 0; i < count; ++i) {
            for (int c = 0; c < ncomp; ++c)
                v[c] = read_component(base + i * stride + static_cast<size_t>(c * csize), a.componentType, a.normalized);
            store(i, v);
        }
    };
    if (a.bufferView >= 0) {
        size_t stride = elem;
        if (static_cast<size_t>(a.bufferView) < m_.bufferViews.size()) {
            const size_t s = m_.bufferViews[static_cast<size_t>(a.bufferView)].byteStride;
            if (s != 0) {
                if (s < elem) fail(apath, "bufferView byteStride " + std::to_string(s) + " is smaller than the element (" + std::to_string(elem) + " bytes)");
                stride = s;
            }
        }
        const unsigned char* base = view_data(a.bufferView, a.byteOffset, elem, stride, a.count, apath);
        read_block(base, stride, a.count, [&](size_t i, const float* v) { std::copy(v, v + nc, out.begin() + static_cast<std::ptrdiff_t>(i * nc)); });
    }
    if (a.sparse.isSparse) {
        const size_t n = static_cast<size_t>(std::max(a.sparse.count, 0));
        if (n > a.count) fail(apath + ".sparse", "count " + std::to_string(n) + " exceeds the accessor count");
        const int itype = a.sparse.indices.componentType;
        const int isize = tinygltf::GetComponentSizeInBytes(static_cast<uint32_t>(itype));
        if (isize <= 0 || itype == TINYGLTF_COMPONENT_TYPE_FLOAT) fail(apath + ".sparse.indices", "invalid componentType");
        const unsigned char* ib = view_data(a.sparse.indices.bufferView, static_cast<size_t>(std::max(a.sparse.indices.byteOffset, 0)),
                                            static_cast<size_t>(isize), static_cast<size_t>(isize), n, apath + ".sparse.indices");
        const unsigned char* vb = view_data(a.sparse.values.bufferView, static_cast<size_t>(std::max(a.sparse.values.byteOffset, 0)),
                                            elem, elem, n, apath + ".sparse.values");
        read_block(vb, elem, n, [&](size_t i, const float* v) {
            const auto target = static_cast<size_t>(read_component(ib + i * static_cast<size_t>(isize), itype, false));
            if (target >= a.count)
                fail(apath + ".sparse.indices", "index " + std::to_string(target) + " out of range (accessor has " +
                                                    std::to_string(a.count) + " elements)");
            std::copy(v, v + nc, out.begin() + static_cast<std::ptrdiff_t>(target * nc));
        });
    }
    return out;
}

std::vector<uint32_t> Loader::read_indices(int accessor, const std::string& path, size_t vertex_count) const {
    if (accessor >= 0 && static_cast<size_t>(accessor) < m_.accessors.size()) {
        const tinygltf::Accessor& a = m_.accessors[static_cast<size_t>(accessor)];
        if (a.componentType != TINYGLTF_COMPONENT_TYPE_UNSIGNED_BYTE &&
            a.componentType != TINYGLTF_COMPONENT_TYPE_UNSIGNED_SHORT &&
            a.componentType != TINYGLTF_COMPONENT_TYPE_UNSIGNED_INT)
            fail(path, "indices must be unsigned byte, short or int");
        if (a.type != TINYGLTF_TYPE_SCALAR) fail(path, "indices must be SCALAR");
    }
    // Read as raw integers: floats cannot hold every uint32 exactly.
    const std::vector<glm::vec4> raw = read_accessor(accessor, path, 1);
    const tinygltf::Accessor& a = m_.accessors[static_cast<size_t>(accessor)];
    std::vector<uint32_t> out(raw.size());
    if (a.componentType == TINYGLTF_COMPONENT_TYPE_UNSIGNED_INT && a.bufferView >= 0 && !a.sparse.isSparse) {
        const size_t stride = std::max<size_t>(4, m_.bufferViews[static_cast<size_t>(a.bufferView)].byteStride);
        const unsigned char* base = view_data(a.bufferView, a.byteOffset, 4, stride, a.count, path);
        for (size_t i = 0; i < out.size(); ++i) std::memcpy(&out[i], base + i * stride, 4);
    } else {
        for (size_t i = 0; i < out.size(); ++i) out[i] = static_cast<uint32_t>(raw[i].x);
    }
    for (uint32_t index : out)
        if (index >= vertex_count)
            fail(path, "index " + std::to_string(index) + " out of range (accessor has " +
                           std::to_string(vertex_count) + " vertices)");
    return out;
}

TextureRef Loader::texture_ref(int index, int texcoord, const tinygltf::ExtensionMap& ext, const std::string& path,
                               double scale) const {
    TextureRef ref;
    if (index < 0) return ref;
    if (static_cast<size_t>(index) >= m_.textures.size())
        fail(path + ".index", "texture " + std::to_string(index) + " does not exist (the file has " +
                                  std::to_string(m_.textures.size()) + ")");
    const tinygltf::Texture& tex = m_.textures[static_cast<size_t>(index)];
    const std::string tpath = idx("textures", static_cast<size_t>(index));
    if (tex.source < 0) {
        warn(tpath, "has no image source this loader understands; using the fallback texture");
        ref.image = -2;  // resolved to the fallback
    } else if (static_cast<size_t>(tex.source) >= m_.images.size()) {
        fail(tpath + ".source", "image " + std::to_string(tex.source) + " does not exist (the file has " +
                                    std::to_string(m_.images.size()) + ")");
    } else {
        ref.image = tex.source;
    }
    if (tex.sampler >= 0) {
        if (static_cast<size_t>(tex.sampler) >= m_.samplers.size())
            fail(tpath + ".sampler", "sampler " + std::to_string(tex.sampler) + " does not exist");
        const tinygltf::Sampler& s = m_.samplers[static_cast<size_t>(tex.sampler)];
        // Values outside glTF's lists were warned about by the validation; they keep the defaults
        // rather than reach OpenGL as invalid enums.
        auto one_of = [](int v, std::initializer_list<int> ok) { return std::find(ok.begin(), ok.end(), v) != ok.end(); };
        if (one_of(s.magFilter, {9728, 9729})) ref.sampler.mag_filter = s.magFilter;
        if (one_of(s.minFilter, {9728, 9729, 9984, 9985, 9986, 9987})) ref.sampler.min_filter = s.minFilter;
        if (one_of(s.wrapS, {33071, 33648, 10497})) ref.sampler.wrap_s = s.wrapS;
        if (one_of(s.wrapT, {33071, 33648, 10497})) ref.sampler.wrap_t = s.wrapT;
    }
    ref.texcoord = texcoord;
    ref.scale = static_cast<float>(scale);
    if (const Value* t = extension(ext, "KHR_texture_transform")) {
        // uv' = T * R * S * uv, with R = [[cos, sin], [-sin, cos]] (the extension's definition).
        const glm::vec2 offset = vec<2>(*t, "offset", glm::vec2(0.0f));
        const float r = static_cast<float>(number(*t, "rotation", 0.0));
        const glm::vec2 s = vec<2>(*t, "scale", glm::vec2(1.0f));
        const glm::mat3 T(1, 0, 0, 0, 1, 0, offset.x, offset.y, 1);  // column-major
        const glm::mat3 R(std::cos(r), -std::sin(r), 0, std::sin(r), std::cos(r), 0, 0, 0, 1);
        const glm::mat3 S(s.x, 0, 0, 0, s.y, 0, 0, 0, 1);
        ref.transform = T * R * S;
        ref.texcoord = static_cast<int>(number(*t, "texCoord", texcoord));
    }
    // Sets above 1 are named once among the ignored features (gltf::ignored_features).
    if (ref.texcoord < 0 || ref.texcoord > 1) ref.texcoord = 0;
    return ref;
}

TextureRef Loader::texture_ref(const tinygltf::TextureInfo& info, const std::string& path, double scale) const {
    return texture_ref(info.index, info.texCoord, info.extensions, path, scale);
}

Material Loader::build_material(size_t i) {
    const tinygltf::Material& src = m_.materials[i];
    const std::string path = idx("materials", i);
    Material mat;
    mat.name = src.name.empty() ? path : src.name;
    const auto& pbr = src.pbrMetallicRoughness;
    if (pbr.baseColorFactor.size() == 4)
        mat.base_color = factors<4>(path + ".pbrMetallicRoughness.baseColorFactor", pbr.baseColorFactor, 0.0f, 1.0f);
    mat.metallic = factor(path + ".pbrMetallicRoughness.metallicFactor", pbr.metallicFactor, 0.0f, 1.0f);
    mat.roughness = factor(path + ".pbrMetallicRoughness.roughnessFactor", pbr.roughnessFactor, 0.0f, 1.0f);
    // glTF caps emissiveFactor at 1 (KHR_materials_emissive_strength goes beyond); several
    // exporters and Candela's own generated scenes write more, which is accepted up to 1e6.
    if (src.emissiveFactor.size() == 3) mat.emissive = factors<3>(path + ".emissiveFactor", src.emissiveFactor, 0.0f, 1e6f);
    mat.base_color_texture = texture_ref(pbr.baseColorTexture, path + ".pbrMetallicRoughness.baseColorTexture", 1.0);
    mat.metallic_roughness_texture =
        texture_ref(pbr.metallicRoughnessTexture, path + ".pbrMetallicRoughness.metallicRoughnessTexture", 1.0);
    mat.normal_texture = texture_ref(src.normalTexture.index, src.normalTexture.texCoord, src.normalTexture.extensions,
                                     path + ".normalTexture", src.normalTexture.scale);
    mat.occlusion_texture = texture_ref(src.occlusionTexture.index, src.occlusionTexture.texCoord,
                                        src.occlusionTexture.extensions, path + ".occlusionTexture",
                                        src.occlusionTexture.strength);
    mat.emissive_texture = texture_ref(src.emissiveTexture, path + ".emissiveTexture", 1.0);
    if (src.alphaMode == "MASK") mat.alpha_mode = AlphaMode::mask;
    else if (src.alphaMode == "BLEND") mat.alpha_mode = AlphaMode::blend;
    else if (src.alphaMode != "OPAQUE") warn(path + ".alphaMode", "unknown mode '" + src.alphaMode + "'; using OPAQUE");
    mat.alpha_cutoff = factor(path + ".alphaCutoff", src.alphaCutoff, 0.0f, 1.0f);
    mat.double_sided = src.doubleSided;
    // Limits where glTF has none: emission up to 1e6 (the hard cases use 1e4), specular colour up
    // to 100, IOR up to 10 (diamond is 2.42), thickness and attenuation distance up to 1e30.
    const std::string ext = path + ".extensions.";
    if (const Value* e = extension(src.extensions, "KHR_materials_emissive_strength"))
        mat.emissive_strength = factor(ext + "KHR_materials_emissive_strength", *e, "emissiveStrength", 1.0, 0.0f, 1e6f);
    if (const Value* e = extension(src.extensions, "KHR_materials_specular")) {
        mat.specular_factor = factor(ext + "KHR_materials_specular", *e, "specularFactor", 1.0, 0.0f, 1.0f);
        mat.specular_color = factors<3>(ext + "KHR_materials_specular", *e, "specularColorFactor", glm::vec3(1.0f), 0.0f, 100.0f);
    }
    if (const Value* e = extension(src.extensions, "KHR_materials_ior")) {
        mat.ior = f32(ext + "KHR_materials_ior.ior", number(*e, "ior", 1.5));
        if (mat.ior < 1.0f && mat.ior != 0.0f) {
            warn(ext + "KHR_materials_ior.ior", "must be >= 1 (or 0); using 1.5");
            mat.ior = 1.5f;
        }
        mat.ior = factor(ext + "KHR_materials_ior.ior", mat.ior, 0.0f, 10.0f);
    }
    if (const Value* e = extension(src.extensions, "KHR_materials_transmission"))
        mat.transmission = factor(ext + "KHR_materials_transmission", *e, "transmissionFactor", 0.0, 0.0f, 1.0f);
    if (const Value* e = extension(src.extensions, "KHR_materials_volume")) {
        mat.thickness = factor(ext + "KHR_materials_volume", *e, "thicknessFactor", 0.0, 0.0f, 1e30f);
        mat.attenuation_color = factors<3>(ext + "KHR_materials_volume", *e, "attenuationColor", glm::vec3(1.0f), 0.0f, 1.0f);
        const Value& ad = e->IsObject() && e->Has("attenuationDistance") ? e->Get("attenuationDistance") : Value();
        if (ad.IsNumber()) mat.attenuation_distance = factor(ext + "KHR_materials_volume.attenuationDistance", ad.GetNumberAsDouble(), 1e-30f, 1e30f);
    }
    return mat;
}

void Loader::build_images(Scene& scene) {
    scene.images.resize(m_.images.size());
    for (size_t i = 0; i < m_.images.size(); ++i) {
        const tinygltf::Image& src = m_.images[i];
        Image& img = scene.images[i];
        img.name = src.name;
        img.uri = src.uri.rfind("data:", 0) == 0 ? "(embedded)" : src.uri;
        if (auto d = image_log_.images.find(static_cast<int>(i)); d != image_log_.images.end() && !d->second.rgba8.empty()) {
            img.width = d->second.width;
            img.height = d->second.height;
            img.rgba8 = std::move(d->second.rgba8);
            img.valid = true;
            continue;
        }
        auto it = image_log_.problems.find(static_cast<int>(i));
        std::string why = it != image_log_.problems.end() ? it->second
                          : !src.uri.empty() && src.uri.rfind("data:", 0) != 0
                              ? "cannot read '" + (dir_ / src.uri).string() + "'"
                              : "no image data";
        warn(idx("images", i) + (img.uri.empty() ? "" : " ('" + img.uri + "')"), why + "; using the fallback texture");
        ++scene.sanitized.missing_textures;
    }
}

Mesh Loader::build_mesh(size_t mi, Scene& scene) {
    const tinygltf::Mesh& src = m_.meshes[mi];
    if (primitive_source_.size() <= mi) primitive_source_.resize(mi + 1);
    Mesh mesh;
    mesh.name = src.name.empty() ? idx("meshes", mi) : src.name;
    for (size_t pi = 0; pi < src.primitives.size(); ++pi) {
        const tinygltf::Primitive& p = src.primitives[pi];
        const std::string path = idx("meshes", mi) + "." + idx("primitives", pi);
        const int mode = p.mode < 0 ? TINYGLTF_MODE_TRIANGLES : p.mode;
        if (mode != TINYGLTF_MODE_TRIANGLES) {
            warn(path + ".mode", "mode " + std::to_string(mode) + " is not triangles; primitive skipped");
            ++scene.sanitized.skipped_primitives;
            continue;
        }
        auto attr = [&](const std::string& name) {
            auto it = p.attributes.find(name);
            return it == p.attributes.end() ? -1 : it->second;
        };
        if (attr("POSITION") < 0) {  // valid glTF (e.g. for extensions), but nothing to draw
            warn(path + ".attributes", "has no POSITION; primitive skipped");
            ++scene.sanitized.skipped_primitives;
            continue;
        }
        bool missing_data = unavailable(p.indices);
        for (const auto& [name, a] : p.attributes) missing_data = missing_data || unavailable(a);
        for (const auto& target : p.targets)
            for (const auto& [name, a] : target) missing_data = missing_data || unavailable(a);
        if (missing_data) {  // warned by the validation
            ++scene.sanitized.skipped_primitives;
            continue;
        }
        const std::vector<glm::vec4> pos = read_accessor(attr("POSITION"), path + ".attributes.POSITION", 3);
        Primitive prim;
        prim.vertices.resize(pos.size());
        for (size_t v = 0; v < pos.size(); ++v) {
            glm::vec3 position(pos[v]);
            if (!std::isfinite(position.x) || !std::isfinite(position.y) || !std::isfinite(position.z)) {
                position = glm::vec3(0.0f);
                ++scene.sanitized.nonfinite_positions;
            }
            prim.vertices[v].position = position;
        }
        auto read_attr = [&](const char* name, int max_components, auto&& store) {
            const int a = attr(name);
            if (a < 0) return false;
            const auto values = read_accessor(a, path + ".attributes." + std::string(name), max_components);
            if (values.size() != pos.size())
                fail(path + ".attributes." + name, "has " + std::to_string(values.size()) + " elements, POSITION has " +
                                                       std::to_string(pos.size()));
            for (size_t v = 0; v < values.size(); ++v) store(prim.vertices[v], values[v]);
            return true;
        };
        const bool has_normals = read_attr("NORMAL", 3, [](Vertex& v, const glm::vec4& x) { v.normal = glm::vec3(x); });
        const bool has_tangents = read_attr("TANGENT", 4, [](Vertex& v, const glm::vec4& x) {
            v.tangent = glm::vec4(glm::vec3(x), x.w < 0.0f ? -1.0f : 1.0f);
        });
        read_attr("TEXCOORD_0", 2, [](Vertex& v, const glm::vec4& x) { v.uv0 = glm::vec2(x); });
        read_attr("TEXCOORD_1", 2, [](Vertex& v, const glm::vec4& x) { v.uv1 = glm::vec2(x); });
        if (attr("COLOR_0") >= 0) {
            const int ncomp = m_.accessors.size() > static_cast<size_t>(attr("COLOR_0"))
                                  ? tinygltf::GetNumComponentsInType(static_cast<uint32_t>(m_.accessors[static_cast<size_t>(attr("COLOR_0"))].type))
                                  : 4;
            read_attr("COLOR_0", 4, [ncomp](Vertex& v, const glm::vec4& x) { v.color = glm::vec4(glm::vec3(x), ncomp == 4 ? x.w : 1.0f); });
        }
        if (p.indices >= 0) {
            prim.indices = read_indices(p.indices, path + ".indices", pos.size());
        } else {
            prim.indices.resize(pos.size());
            for (size_t v = 0; v < pos.size(); ++v) prim.indices[v] = static_cast<uint32_t>(v);
        }
        if (prim.indices.size() % 3 != 0) {
            warn(path, std::to_string(prim.indices.size()) + " indices is not a multiple of 3; the last " +
                           std::to_string(prim.indices.size() % 3) + " ignored");
            prim.indices.resize(prim.indices.size() - prim.indices.size() % 3);
        }
        if (p.material >= 0 && static_cast<size_t>(p.material) >= m_.materials.size())
            fail(path + ".material", "material " + std::to_string(p.material) + " does not exist (the file has " +
                                         std::to_string(m_.materials.size()) + ")");
        prim.material = p.material;
        // Deformation data (skins, morph targets), per vertex like the attributes above; what the node it is
        // drawn by does not use (joints without a skin) is dropped in build_deformation.
        read_skin_attributes(p, path, prim);
        read_morph_targets(p, path, prim);
        // Deltas of an attribute the file does not give are not applied to the generated one.
        for (MorphTarget& t : prim.targets) {
            if (!has_normals) t.normal.clear();
            if (!has_tangents) t.tangent.clear();
        }
        if (!has_normals) {
            // Flat normals unshare the vertices: corner i becomes vertex i, so the per-vertex
            // deformation data follows its corner.
            const std::vector<uint32_t> corner = prim.indices;
            generate_flat_normals(prim);
            auto follow = [&](auto& values, size_t per_vertex) {
                if (values.empty()) return;
                std::remove_reference_t<decltype(values)> out(corner.size() * per_vertex);
                for (size_t i = 0; i < corner.size(); ++i)
                    for (size_t k = 0; k < per_vertex; ++k) out[i * per_vertex + k] = values[corner[i] * per_vertex + k];
                values = std::move(out);
            };
            follow(prim.joints, static_cast<size_t>(prim.influence_sets));
            follow(prim.weights, static_cast<size_t>(prim.influence_sets));
            for (MorphTarget& t : prim.targets) follow(t.position, 1), follow(t.tangent, 1);
            ++scene.sanitized.generated_normals;
        } else {
            scene.sanitized.bad_normals += repair_normals(prim);
        }
        const Material& mat = scene.material(prim.material);
        if (mat.normal_texture.present() && !has_tangents) {
            generate_tangents(prim, mat.normal_texture.texcoord);
            ++scene.sanitized.generated_tangents;
        }
        compute_bounds(prim);
        mesh.primitives.push_back(std::move(prim));
        primitive_source_[mi].push_back(pi);
    }
    // Morph targets: as many in every primitive, and as many default weights (glTF 3.7.2.2).
    const size_t targets = src.primitives.empty() ? 0 : src.primitives[0].targets.size();
    for (size_t pi = 1; pi < src.primitives.size(); ++pi)
        if (src.primitives[pi].targets.size() != targets)
            fail(idx("meshes", mi) + "." + idx("primitives", pi) + ".targets",
                 "has " + std::to_string(src.primitives[pi].targets.size()) + " morph targets, primitives[0] has " + std::to_string(targets));
    if (!src.weights.empty()) {
        const std::string wpath = idx("meshes", mi) + ".weights";
        if (src.weights.size() != targets)
            fail(wpath, "has " + std::to_string(src.weights.size()) + " weights for " + std::to_string(targets) + " morph targets");
        for (size_t k = 0; k < targets; ++k) mesh.weights.push_back(f32(wpath + "[" + std::to_string(k) + "]", src.weights[k]));
    } else {
        mesh.weights.assign(targets, 0.0f);
    }
    return mesh;
}

void Loader::read_skin_attributes(const tinygltf::Primitive& p, const std::string& path, Primitive& prim) const {
    const size_t nv = prim.vertices.size();
    auto attr = [&](const std::string& name) {
        auto it = p.attributes.find(name);
        return it == p.attributes.end() ? -1 : it->second;
    };
    // JOINTS_n/WEIGHTS_n for n = 0..k-1 (sets are numbered without gaps; the validation warns otherwise).
    int sets = 0;
    while (sets < 64 && attr("JOINTS_" + std::to_string(sets)) >= 0 && attr("WEIGHTS_" + std::to_string(sets)) >= 0) ++sets;
    if (sets == 0) return;
    const size_t k_sets = static_cast<size_t>(sets);
    prim.influence_sets = sets;
    prim.joints.assign(nv * k_sets, glm::u16vec4(0));
    prim.weights.assign(nv * k_sets, glm::vec4(0.0f));
    for (size_t k = 0; k < k_sets; ++k) {
        const std::string jname = "JOINTS_" + std::to_string(k), wname = "WEIGHTS_" + std::to_string(k);
        const std::string jpath = path + ".attributes." + jname, wpath = path + ".attributes." + wname;
        const int ja = attr(jname), wa = attr(wname);
        const std::vector<glm::vec4> j = read_accessor(ja, jpath, 4);
        const tinygltf::Accessor& jacc = m_.accessors[static_cast<size_t>(ja)];
        if (jacc.type != TINYGLTF_TYPE_VEC4 || jacc.normalized ||
            (jacc.componentType != TINYGLTF_COMPONENT_TYPE_UNSIGNED_BYTE && jacc.componentType != TINYGLTF_COMPONENT_TYPE_UNSIGNED_SHORT))
            fail(jpath, "accessor " + std::to_string(ja) + " must be VEC4 of UNSIGNED_BYTE or UNSIGNED_SHORT (not normalized)");
        const std::vector<glm::vec4> w = read_accessor(wa, wpath, 4);
        const tinygltf::Accessor& wacc = m_.accessors[static_cast<size_t>(wa)];
        const bool unorm = wacc.normalized && (wacc.componentType == TINYGLTF_COMPONENT_TYPE_UNSIGNED_BYTE ||
                                               wacc.componentType == TINYGLTF_COMPONENT_TYPE_UNSIGNED_SHORT);
        if (wacc.type != TINYGLTF_TYPE_VEC4 || !(wacc.componentType == TINYGLTF_COMPONENT_TYPE_FLOAT || unorm))
            fail(wpath, "accessor " + std::to_string(wa) + " must be VEC4 of FLOAT or normalized UNSIGNED_BYTE/UNSIGNED_SHORT");
        if (j.size() != nv) fail(jpath, "has " + std::to_string(j.size()) + " elements, POSITION has " + std::to_string(nv));
        if (w.size() != nv) fail(wpath, "has " + std::to_string(w.size()) + " elements, POSITION has " + std::to_string(nv));
        for (size_t v = 0; v < nv; ++v) {
            prim.joints[v * k_sets + k] = glm::u16vec4(j[v]);
            for (int c = 0; c < 4; ++c) {
                if (!std::isfinite(w[v][c])) fail(wpath, "vertex " + std::to_string(v) + ": weight " + num(w[v][c]) + " is not a finite number");
                prim.weights[v * k_sets + k][c] = std::max(w[v][c], 0.0f);  // negative: warned by the validation
            }
        }
    }
}

void Loader::read_morph_targets(const tinygltf::Primitive& p, const std::string& path, Primitive& prim) const {
    const size_t nv = prim.vertices.size();
    for (size_t ti = 0; ti < p.targets.size(); ++ti) {
        const std::string tpath = path + "." + idx("targets", ti);
        MorphTarget target;
        // TEXCOORD_n and COLOR_n targets are named among the ignored features; others were warned about.
        for (const auto& [name, out] : {std::pair<const char*, std::vector<glm::vec3>*>{"POSITION", &target.position},
                                        {"NORMAL", &target.normal}, {"TANGENT", &target.tangent}}) {
            auto it = p.targets[ti].find(name);
            if (it == p.targets[ti].end()) continue;
            const std::string apath = tpath + "." + name;
            const std::vector<glm::vec4> d = read_accessor(it->second, apath, 3);
            if (d.size() != nv) fail(apath, "has " + std::to_string(d.size()) + " elements, the primitive has " + std::to_string(nv) + " vertices");
            out->resize(nv);
            for (size_t v = 0; v < nv; ++v) {
                const glm::vec3 x(d[v]);
                if (!std::isfinite(x.x) || !std::isfinite(x.y) || !std::isfinite(x.z))
                    fail(apath, "element " + std::to_string(v) + " is not a finite number");
                (*out)[v] = x;
            }
        }
        prim.targets.push_back(std::move(target));
    }
}

void Loader::build_nodes(Scene& scene) {
    const size_t n = m_.nodes.size();
    scene.nodes.resize(n);
    for (size_t i = 0; i < n; ++i) {
        const tinygltf::Node& src = m_.nodes[i];
        Node& node = scene.nodes[i];
        const std::string path = idx("nodes", i);
        node.name = src.name.empty() ? path : src.name;
        if (src.matrix.size() == 16) {
            for (int k = 0; k < 16; ++k)
                glm::value_ptr(node.local)[k] = f32(path + ".matrix[" + std::to_string(k) + "]", src.matrix[static_cast<size_t>(k)]);
            node.has_matrix = true;  // not animatable (glTF 3.7.2.1): channels on it are dropped
        } else {
            glm::vec3 t(0.0f), s(1.0f);
            glm::quat r(1.0f, 0.0f, 0.0f, 0.0f);
            for (size_t k = 0; k < 3 && src.translation.size() == 3; ++k)
                t[static_cast<int>(k)] = f32(path + ".translation[" + std::to_string(k) + "]", src.translation[k]);
            for (size_t k = 0; k < 3 && src.scale.size() == 3; ++k)
                s[static_cast<int>(k)] = f32(path + ".scale[" + std::to_string(k) + "]", src.scale[k]);
            if (src.rotation.size() == 4) {
                r = glm::quat(static_cast<float>(src.rotation[3]), static_cast<float>(src.rotation[0]),
                              static_cast<float>(src.rotation[1]), static_cast<float>(src.rotation[2]));
                const float len = glm::length(r);
                r = len > 0.0f && std::isfinite(len) ? r / len : glm::quat(1, 0, 0, 0);
            }
            node.local = glm::translate(glm::mat4(1.0f), t) * glm::mat4_cast(r) * glm::scale(glm::mat4(1.0f), s);
            node.translation = t;
            node.rotation = r;
            node.scale = s;
        }
        for (int k = 0; k < 16; ++k)
            if (!std::isfinite(glm::value_ptr(node.local)[k])) fail(path, "transform has a non-finite value");
        if (src.mesh >= 0) {
            if (static_cast<size_t>(src.mesh) >= m_.meshes.size())
                fail(path + ".mesh", "mesh " + std::to_string(src.mesh) + " does not exist (the file has " +
                                         std::to_string(m_.meshes.size()) + ")");
            node.mesh = src.mesh;
        }
        if (src.skin >= 0) {
            if (static_cast<size_t>(src.skin) >= m_.skins.size())
                fail(path + ".skin", "skin " + std::to_string(src.skin) + " does not exist (the file has " + std::to_string(m_.skins.size()) + ")");
            node.skin = src.skin;
        }
        // Morph weights: the node's own, else its mesh's defaults (zeros when the file has none).
        own_weights_.resize(n, false);
        if (node.mesh >= 0) {
            const std::vector<float>& defaults = scene.meshes[static_cast<size_t>(node.mesh)].weights;
            node.rest_weights = defaults;
            if (!src.weights.empty()) {
                if (src.weights.size() != defaults.size())
                    fail(path + ".weights", "has " + std::to_string(src.weights.size()) + " weights, meshes[" + std::to_string(node.mesh) +
                                                "] has " + std::to_string(defaults.size()) + " morph targets");
                for (size_t k = 0; k < defaults.size(); ++k)
                    node.rest_weights[k] = f32(path + ".weights[" + std::to_string(k) + "]", src.weights[k]);
                own_weights_[i] = true;
            }
        }  // weights without a mesh: warned by the validation, nothing to morph
        node.weights = node.rest_weights;
        if (src.camera >= 0) {
            if (static_cast<size_t>(src.camera) >= m_.cameras.size())
                fail(path + ".camera", "camera " + std::to_string(src.camera) + " does not exist");
            node.camera = src.camera;
        }
        if (const Value* e = extension(src.extensions, "KHR_lights_punctual")) {
            const int light = static_cast<int>(number(*e, "light", -1));
            if (light < 0 || static_cast<size_t>(light) >= m_.lights.size())
                fail(path + ".extensions.KHR_lights_punctual.light", "light " + std::to_string(light) + " does not exist (the file has " +
                                                                         std::to_string(m_.lights.size()) + ")");
            node.light = light;
        }
        if (src.extras.IsObject() && src.extras.Has("sphere")) {
            const double r = number(src.extras.Get("sphere"), "radius", -1.0);
            if (!(r > 0.0) || !std::isfinite(r)) fail(path + ".extras.sphere.radius", "must be a positive number");
            node.sphere_radius = static_cast<float>(r);
        }
        if (src.extras.IsObject() && src.extras.Has("reflection_probe")) {
            const Value& e = src.extras.Get("reflection_probe");
            const std::string where = path + ".extras.reflection_probe";
            if (!e.IsObject()) fail(where, "must be an object {position, extent, center}");
            ReflectionProbe probe;
            const glm::vec3 bad(std::numeric_limits<float>::quiet_NaN());
            auto finite3 = [&](const char* key, glm::vec3 fallback) {
                const glm::vec3 v = vec<3>(e, key, bad);
                if (!e.Has(key)) return fallback;
                if (glm::any(glm::isnan(v)) || glm::any(glm::isinf(v))) fail(where + "." + key, "must be an array of 3 finite numbers");
                return v;
            };
            probe.position = finite3("position", glm::vec3(0.0f));
            probe.center = finite3("center", probe.position);
            if (e.Has("extent")) {
                probe.extent = finite3("extent", glm::vec3(0.0f));
                if (glm::any(glm::lessThanEqual(probe.extent, glm::vec3(0.0f))))
                    fail(where + ".extent", "half sizes must be positive");
                probe.has_extent = true;
                if (glm::any(glm::greaterThan(glm::abs(probe.position - probe.center), probe.extent)))
                    fail(where, "the position lies outside the box center +- extent");
            }
            node.reflection_probe = probe;
        }
        for (int c : src.children) {
            if (c < 0 || static_cast<size_t>(c) >= n) fail(path + ".children", "node " + std::to_string(c) + " does not exist");
            Node& child = scene.nodes[static_cast<size_t>(c)];
            if (child.parent >= 0 || static_cast<size_t>(c) == i)
                fail(path + ".children", "node " + std::to_string(c) + " has more than one parent (the hierarchy must be a tree)");
            child.parent = static_cast<int>(i);
            node.children.push_back(c);
        }
    }
    // Roots: the default scene's nodes, else every parentless node.
    if (!m_.scenes.empty()) {
        const size_t si = m_.defaultScene >= 0 && static_cast<size_t>(m_.defaultScene) < m_.scenes.size()
                              ? static_cast<size_t>(m_.defaultScene) : 0;
        for (int r : m_.scenes[si].nodes) {
            if (r < 0 || static_cast<size_t>(r) >= n) fail(idx("scenes", si) + ".nodes", "node " + std::to_string(r) + " does not exist");
            if (scene.nodes[static_cast<size_t>(r)].parent >= 0)
                fail(idx("scenes", si) + ".nodes", "node " + std::to_string(r) + " is a root and also a child");
            scene.roots.push_back(r);
        }
    } else {
        for (size_t i = 0; i < n; ++i)
            if (scene.nodes[i].parent < 0) scene.roots.push_back(static_cast<int>(i));
    }
    // With one parent per node and parentless roots, no cycle is reachable from a root.
    scene.update_world_transforms();
}

void Loader::build_skins(Scene& scene) {
    const size_t nodes = scene.nodes.size();
    for (size_t i = 0; i < m_.skins.size(); ++i) {
        const tinygltf::Skin& src = m_.skins[i];
        const std::string path = idx("skins", i);
        Skin skin;
        skin.name = src.name.empty() ? path : src.name;
        if (src.joints.empty()) fail(path + ".joints", "a skin needs at least one joint");
        for (size_t k = 0; k < src.joints.size(); ++k) {
            const int j = src.joints[k];
            if (j < 0 || static_cast<size_t>(j) >= nodes)
                fail(path + ".joints[" + std::to_string(k) + "]", "node " + std::to_string(j) + " does not exist (the file has " +
                                                                      std::to_string(nodes) + ")");
            skin.joints.push_back(j);
        }
        skin.inverse_bind.assign(skin.joints.size(), glm::mat4(1.0f));
        const int ibm = src.inverseBindMatrices;
        if (ibm >= 0 && unavailable(ibm)) {
            warn(path + ".inverseBindMatrices", "the data is not available; identity matrices used");
        } else if (ibm >= 0) {
            const std::string ipath = path + ".inverseBindMatrices";
            int nc = 0;
            const std::vector<float> m = read_floats(ibm, ipath, 16, &nc);
            const tinygltf::Accessor& a = m_.accessors[static_cast<size_t>(ibm)];
            if (a.type != TINYGLTF_TYPE_MAT4 || a.componentType != TINYGLTF_COMPONENT_TYPE_FLOAT)
                fail(ipath, "accessor " + std::to_string(ibm) + " must be FLOAT MAT4");
            const size_t count = m.size() / 16;
            if (count < skin.joints.size())
                fail(ipath, "accessor " + std::to_string(ibm) + " has " + std::to_string(count) + " matrices for " +
                                std::to_string(skin.joints.size()) + " joints");
            for (size_t k = 0; k < skin.joints.size(); ++k) {
                for (size_t c = 0; c < 16; ++c)
                    if (!std::isfinite(m[k * 16 + c])) fail(ipath, "matrix " + std::to_string(k) + " is not finite");
                skin.inverse_bind[k] = glm::make_mat4(m.data() + k * 16);
            }
        }
        if (src.skeleton >= 0 && static_cast<size_t>(src.skeleton) < nodes) skin.skeleton = src.skeleton;
        scene.skins.push_back(std::move(skin));
    }
}

void Loader::build_animations(Scene& scene) {
    for (size_t ai = 0; ai < m_.animations.size(); ++ai) {
        const tinygltf::Animation& src = m_.animations[ai];
        const std::string path = idx("animations", ai);
        Animation anim;
        anim.name = src.name.empty() ? path : src.name;
        // Samplers: the input times (finite, strictly increasing) here; the output when a channel
        // says how wide its elements are. Samplers the validation warned about stay empty.
        anim.samplers.resize(src.samplers.size());
        std::vector<bool> usable(src.samplers.size(), false);
        std::vector<std::vector<float>> outputs(src.samplers.size());
        std::vector<int> output_components(src.samplers.size(), 0);
        bool any_times = false;
        for (size_t si = 0; si < src.samplers.size(); ++si) {
            const tinygltf::AnimationSampler& s = src.samplers[si];
            const std::string spath = path + "." + idx("samplers", si);
            auto exists = [&](int a) { return a >= 0 && static_cast<size_t>(a) < m_.accessors.size() && !unavailable(a); };
            if (!exists(s.input) || !exists(s.output)) continue;  // warned by the validation
            AnimationSampler& out = anim.samplers[si];
            if (s.interpolation == "STEP") out.interpolation = Interpolation::step;
            else if (s.interpolation == "CUBICSPLINE") out.interpolation = Interpolation::cubic_spline;
            const std::string ipath = spath + ".input";
            const tinygltf::Accessor& in = m_.accessors[static_cast<size_t>(s.input)];
            if (in.type != TINYGLTF_TYPE_SCALAR || in.componentType != TINYGLTF_COMPONENT_TYPE_FLOAT)
                fail(ipath, "accessor " + std::to_string(s.input) + " must be FLOAT SCALAR (times in seconds)");
            // An accessor without data is all zeros: valid glTF, but no keyframe times to sample.
            if (in.bufferView < 0 && !in.sparse.isSparse && in.count > 1) {
                warn(ipath, "accessor " + std::to_string(s.input) + " has no data (all times 0); the sampler is ignored");
                continue;
            }
            int nc = 0;
            out.times = read_floats(s.input, ipath, 1, &nc);
            if (out.times.empty()) fail(ipath, "accessor " + std::to_string(s.input) + " has no keyframes");
            for (size_t k = 0; k < out.times.size(); ++k) {
                if (!std::isfinite(out.times[k]))
                    fail(ipath, "keyframe " + std::to_string(k) + ": time " + num(out.times[k]) + " is not a finite number");
                if (k > 0 && !(out.times[k] > out.times[k - 1]))
                    fail(ipath, "keyframe times are not strictly increasing (keyframe " + std::to_string(k) + ": " + num(out.times[k]) +
                                    " after " + num(out.times[k - 1]) + ")");
            }
            const std::string opath = spath + ".output";
            outputs[si] = read_floats(s.output, opath, 4, &output_components[si]);
            for (size_t k = 0; k < outputs[si].size(); ++k)
                if (!std::isfinite(outputs[si][k]))
                    fail(opath, "element " + std::to_string(k / static_cast<size_t>(output_components[si])) + " is not a finite number");
            out.width = output_components[si];
            usable[si] = true;
            anim.start = any_times ? std::min(anim.start, out.times.front()) : out.times.front();
            anim.end = any_times ? std::max(anim.end, out.times.back()) : out.times.back();
            any_times = true;
        }
        std::vector<int> width(src.samplers.size(), 0);  // fixed by the first channel using the sampler
        for (size_t ci = 0; ci < src.channels.size(); ++ci) {
            const tinygltf::AnimationChannel& c = src.channels[ci];
            const std::string cpath = path + "." + idx("channels", ci);
            AnimationChannel channel;
            if (c.target_path == "translation") channel.path = AnimationPath::translation;
            else if (c.target_path == "rotation") channel.path = AnimationPath::rotation;
            else if (c.target_path == "scale") channel.path = AnimationPath::scale;
            else if (c.target_path == "weights") channel.path = AnimationPath::weights;
            else continue;  // KHR_animation_pointer ("pointer"): an ignored feature; others warned by the validation
            if (c.target_node < 0 || static_cast<size_t>(c.target_node) >= scene.nodes.size()) continue;  // warned by the validation
            if (c.sampler < 0 || static_cast<size_t>(c.sampler) >= src.samplers.size() || !usable[static_cast<size_t>(c.sampler)]) continue;
            const Node& node = scene.nodes[static_cast<size_t>(c.target_node)];
            // glTF 3.11: a node given by `matrix` is not animated (the validation warns: the channel is dropped).
            if (node.has_matrix && channel.path != AnimationPath::weights) continue;
            const size_t si = static_cast<size_t>(c.sampler);
            const int nc = output_components[si];
            const int need_components = channel.path == AnimationPath::rotation ? 4 : channel.path == AnimationPath::weights ? 1 : 3;
            if (nc != need_components)
                fail(cpath + ".sampler", "output accessor " + std::to_string(src.samplers[si].output) + " has " + std::to_string(nc) +
                                             " components per element; path '" + c.target_path + "' needs " + std::to_string(need_components));
            int w = need_components;
            if (channel.path == AnimationPath::weights) {
                w = node.mesh >= 0 ? static_cast<int>(scene.meshes[static_cast<size_t>(node.mesh)].weights.size()) : 0;
                if (w == 0) continue;  // no morph targets to animate: warned by the validation
            }
            AnimationSampler& smp = anim.samplers[si];
            const size_t per_key = static_cast<size_t>(w) * (smp.interpolation == Interpolation::cubic_spline ? 3 : 1);
            const size_t expect = smp.times.size() * per_key;  // floats
            if (outputs[si].size() != expect) {
                const size_t elements = outputs[si].size() / static_cast<size_t>(nc);
                fail(path + "." + idx("samplers", si) + ".output",
                     "has " + std::to_string(elements) + " elements for " + std::to_string(smp.times.size()) + " keyframes; " +
                         std::to_string(expect / static_cast<size_t>(nc)) + " expected (" + std::to_string(smp.times.size()) + " keyframes" +
                         (smp.interpolation == Interpolation::cubic_spline ? " x 3 for CUBICSPLINE" : "") +
                         (channel.path == AnimationPath::weights ? " x " + std::to_string(w) + " morph targets of nodes[" +
                                                                       std::to_string(c.target_node) + "]" : "") +
                         ", as " + cpath + " uses it)");
            }
            if (width[si] != 0 && width[si] != w)
                fail(cpath + ".sampler", "sampler " + std::to_string(si) + " is used with " + std::to_string(width[si]) + " and " +
                                             std::to_string(w) + " values per keyframe");
            width[si] = w;
            smp.width = w;
            if (smp.values.empty()) smp.values = outputs[si];
            channel.sampler = c.sampler;
            channel.node = c.target_node;
            anim.channels.push_back(channel);
        }
        scene.animations.push_back(std::move(anim));
    }
}

void Loader::build_deformation(Scene& scene) {
    const size_t file_meshes = scene.meshes.size();
    mesh_source_.resize(file_meshes);
    for (size_t m = 0; m < file_meshes; ++m) mesh_source_[m] = m;
    std::vector<std::vector<size_t>> users(file_meshes);
    for (size_t i = 0; i < scene.nodes.size(); ++i)
        if (scene.nodes[i].mesh >= 0) users[static_cast<size_t>(scene.nodes[i].mesh)].push_back(i);
    std::vector<bool> weights_animated(scene.nodes.size(), false);
    for (const Animation& a : scene.animations)
        for (const AnimationChannel& c : a.channels)
            if (c.path == AnimationPath::weights) weights_animated[static_cast<size_t>(c.node)] = true;
    // A mesh that deforms differently per node (a skin, own or animated weights) gets one copy per
    // node, so that each deformed primitive belongs to exactly one node. Instances that all deform
    // alike (the mesh's default weights, no skin) keep sharing it.
    for (size_t m = 0; m < file_meshes; ++m) {
        if (users[m].size() < 2) continue;
        bool has_joints = false, has_targets = false;
        for (const Primitive& p : scene.meshes[m].primitives) has_joints |= p.skinned(), has_targets |= !p.targets.empty();
        bool individual = false;
        for (size_t u : users[m]) {
            const Node& node = scene.nodes[u];
            individual |= (has_joints && node.skin >= 0) || (has_targets && (own_weights_[u] || weights_animated[u]));
        }
        if (!individual) continue;
        for (size_t k = 1; k < users[m].size(); ++k) {
            Mesh copy = scene.meshes[m];
            scene.meshes.push_back(std::move(copy));
            mesh_source_.push_back(m);
            scene.nodes[users[m][k]].mesh = static_cast<int>(scene.meshes.size()) - 1;
        }
    }
    std::vector<int> owner(scene.meshes.size(), -1);
    for (size_t i = 0; i < scene.nodes.size(); ++i)
        if (const int m = scene.nodes[i].mesh; m >= 0 && owner[static_cast<size_t>(m)] < 0) owner[static_cast<size_t>(m)] = static_cast<int>(i);
    for (size_t mi = 0; mi < scene.meshes.size(); ++mi) {
        const int skin_index = owner[mi] >= 0 ? scene.nodes[static_cast<size_t>(owner[mi])].skin : -1;
        for (size_t pi = 0; pi < scene.meshes[mi].primitives.size(); ++pi) {
            Primitive& prim = scene.meshes[mi].primitives[pi];
            if (prim.skinned() && skin_index >= 0) {
                const Skin& skin = scene.skins[static_cast<size_t>(skin_index)];
                const size_t sets = static_cast<size_t>(prim.influence_sets);
                const size_t nv = prim.vertices.size();
                for (size_t v = 0; v < nv; ++v)
                    for (size_t k = 0; k < sets; ++k)
                        for (int c = 0; c < 4; ++c)
                            if (const unsigned j = prim.joints[v * sets + k][c]; j >= skin.joints.size())
                                fail(primitive_path(mi, pi) + ".attributes.JOINTS_" + std::to_string(k),
                                     "vertex " + std::to_string(v) + ": joint " + std::to_string(j) + " is out of range (skins[" +
                                         std::to_string(skin_index) + "] of nodes[" + std::to_string(owner[mi]) + "] has " +
                                         std::to_string(skin.joints.size()) + " joints)");
                // Each vertex's weights sum to 1 (all zero: the vertex stays in the node's space).
                size_t off = 0;
                float worst = 0.0f;
                for (size_t v = 0; v < nv; ++v) {
                    float sum = 0.0f;
                    for (size_t k = 0; k < sets; ++k) sum += glm::dot(prim.weights[v * sets + k], glm::vec4(1.0f));
                    if (!(sum > 0.0f)) continue;
                    if (std::fabs(sum - 1.0f) > 1e-3f) ++off, worst = std::max(worst, std::fabs(sum - 1.0f));
                    if (!std::isfinite(sum)) fail(primitive_path(mi, pi) + ".attributes.WEIGHTS_0", "vertex " + std::to_string(v) + ": the weights overflow");
                    for (size_t k = 0; k < sets; ++k) prim.weights[v * sets + k] /= sum;
                }
                if (off && mesh_source_[mi] == mi)  // once per primitive of the file, not per copy
                    warn(primitive_path(mi, pi) + ".attributes.WEIGHTS_0",
                         "the skin weights of " + std::to_string(off) + " of " + std::to_string(nv) +
                             " vertices do not sum to 1 (off by up to " + num(worst) + "); normalised");
            } else if (prim.skinned()) {
                // Joints without a skin on the node that draws the mesh: drawn rigid (glTF 3.7.3).
                prim.joints.clear();
                prim.weights.clear();
                prim.influence_sets = 0;
            }
            if (prim.skinned() || !prim.targets.empty()) prim.rest = prim.vertices;
        }
    }
}

// The rest pose of skins and morph targets computed by pose_scene must be usable geometry.
void Loader::check_posed(const Scene& scene) const {
    auto finite = [](const glm::vec3& v) { return std::isfinite(v.x) && std::isfinite(v.y) && std::isfinite(v.z); };
    for (size_t mi = 0; mi < scene.meshes.size(); ++mi)
        for (size_t pi = 0; pi < scene.meshes[mi].primitives.size(); ++pi) {
            const Primitive& prim = scene.meshes[mi].primitives[pi];
            if (!prim.deformable()) continue;
            for (size_t v = 0; v < prim.vertices.size(); ++v)
                if (!finite(prim.vertices[v].position) || !finite(prim.vertices[v].normal) || !finite(glm::vec3(prim.vertices[v].tangent)))
                    fail(primitive_path(mi, pi), "vertex " + std::to_string(v) +
                                                     " is not finite after skinning and morphing (the joints' matrices or the morph deltas overflow a 32-bit float)");
        }
}

void Loader::build_environment(Scene& scene) {
    if (m_.scenes.empty()) return;
    const size_t si = m_.defaultScene >= 0 && static_cast<size_t>(m_.defaultScene) < m_.scenes.size()
                          ? static_cast<size_t>(m_.defaultScene) : 0;
    const Value& extras = m_.scenes[si].extras;
    if (!extras.IsObject()) return;
    const std::string path = idx("scenes", si) + ".extras";
    scene.environment.radiance = factors<3>(path, extras, "environment_radiance", glm::vec3(0.0f), 0.0f, 1e6f);
    scene.environment.intensity = factor(path, extras, "environment_intensity", 1.0, 0.0f, 1e6f);
    if (extras.Has("environment_map") && extras.Get("environment_map").IsString()) {
        const fs::path map = dir_ / extras.Get("environment_map").Get<std::string>();
        if (fs::exists(map)) scene.environment.map = map;
        else warn(path + ".environment_map", "cannot find '" + map.string() + "'; using environment_radiance instead");
    }
}

Scene Loader::build() {
    Scene scene;
    scene.source = file_;
    build_images(scene);
    scene.materials.reserve(m_.materials.size());
    for (size_t i = 0; i < m_.materials.size(); ++i) scene.materials.push_back(build_material(i));
    // The fallback image is appended so that texture refs with image -2 resolve to it.
    int fallback = -1;
    auto resolve = [&](TextureRef& ref) {
        if (ref.image >= 0 && !scene.images[static_cast<size_t>(ref.image)].valid) ref.image = -2;
        if (ref.image == -2) {
            if (fallback < 0) {
                Image img;
                img.name = "fallback";
                img.width = img.height = 8;
                img.valid = true;
                for (int y = 0; y < 8; ++y)
                    for (int x = 0; x < 8; ++x) {
                        const bool on = ((x / 2) + (y / 2)) % 2 == 0;  // magenta/black checker
                        img.rgba8.insert(img.rgba8.end(), {static_cast<uint8_t>(on ? 255 : 0), 0, static_cast<uint8_t>(on ? 255 : 0), 255});
                    }
                scene.images.push_back(std::move(img));
                fallback = static_cast<int>(scene.images.size()) - 1;
            }
            ref.image = fallback;
        }
    };
    for (Material& m : scene.materials)
        for (TextureRef* r : {&m.base_color_texture, &m.metallic_roughness_texture, &m.normal_texture,
                              &m.occlusion_texture, &m.emissive_texture})
            resolve(*r);
    std::vector<int> unknown_lights;
    for (size_t i = 0; i < m_.lights.size(); ++i) {
        const tinygltf::Light& src = m_.lights[i];
        Light light;
        light.name = src.name.empty() ? idx("lights", i) : src.name;
        if (src.type == "directional") light.type = LightType::directional;
        else if (src.type == "spot") light.type = LightType::spot;
        else if (src.type == "point") light.type = LightType::point;
        else unknown_lights.push_back(static_cast<int>(i));  // warned by the validation; its nodes lose it below
        const std::string lpath = "extensions.KHR_lights_punctual." + idx("lights", i);
        if (src.color.size() == 3) light.color = factors<3>(lpath + ".color", src.color, 0.0f, 1.0f);
        light.intensity = factor(lpath + ".intensity", src.intensity, 0.0f, 1e12f);
        light.range = factor(lpath + ".range", src.range, 0.0f, std::numeric_limits<float>::max());
        light.inner_cone = f32(lpath + ".spot.innerConeAngle", src.spot.innerConeAngle);
        light.outer_cone = f32(lpath + ".spot.outerConeAngle", src.spot.outerConeAngle);
        if (light.type == LightType::spot) {
            light.outer_cone = std::clamp(light.outer_cone, 1e-4f, 1.5707963f);
            light.inner_cone = std::clamp(light.inner_cone, 0.0f, light.outer_cone * 0.9999f);
        }
        scene.lights.push_back(light);
    }
    for (size_t i = 0; i < m_.meshes.size(); ++i) scene.meshes.push_back(build_mesh(i, scene));
    build_nodes(scene);
    build_skins(scene);
    build_animations(scene);
    build_deformation(scene);
    // The rest pose (no animation), so that every consumer sees skinned and morphed geometry.
    pose_scene(scene, -1, 0.0f);
    check_posed(scene);
    for (Node& node : scene.nodes)
        if (std::find(unknown_lights.begin(), unknown_lights.end(), node.light) != unknown_lights.end()) node.light = -1;
    for (size_t i = 0; i < scene.nodes.size(); ++i)
        for (int k = 0; k < 16; ++k)
            if (!std::isfinite(glm::value_ptr(scene.nodes[i].world)[k]))
                fail(idx("nodes", i), "the world transform overflows a 32-bit float (large scales or translations along the hierarchy)");
    if (const Bounds b = scene.world_bounds(); !b.empty() && !(std::isfinite(b.max.x - b.min.x) && std::isfinite(b.max.y - b.min.y) &&
                                                               std::isfinite(b.max.z - b.min.z)))
        fail("nodes", "the scene's world-space extent overflows a 32-bit float");
    for (size_t i = 0; i < scene.nodes.size(); ++i) {
        const Node& node = scene.nodes[i];
        if (node.camera < 0) continue;
        const tinygltf::Camera& src = m_.cameras[static_cast<size_t>(node.camera)];
        Camera cam;
        cam.name = src.name.empty() ? node.name : src.name;
        cam.node = static_cast<int>(i);
        cam.world = node.world;
        if (src.type == "orthographic") {
            cam.orthographic = true;
            const std::string cpath = idx("cameras", static_cast<size_t>(node.camera)) + ".orthographic";
            cam.xmag = std::fabs(f32(cpath + ".xmag", src.orthographic.xmag));
            cam.ymag = std::fabs(f32(cpath + ".ymag", src.orthographic.ymag));
            cam.znear = f32(cpath + ".znear", src.orthographic.znear);
            cam.zfar = f32(cpath + ".zfar", src.orthographic.zfar);
            if (!(cam.ymag > 0.0f)) fail(idx("cameras", static_cast<size_t>(node.camera)) + ".orthographic.ymag", "must be positive");
        } else {
            const std::string cpath = idx("cameras", static_cast<size_t>(node.camera)) + ".perspective";
            cam.yfov = f32(cpath + ".yfov", src.perspective.yfov);
            cam.aspect_ratio = std::max(0.0f, f32(cpath + ".aspectRatio", src.perspective.aspectRatio));
            cam.znear = f32(cpath + ".znear", src.perspective.znear);
            cam.zfar = f32(cpath + ".zfar", src.perspective.zfar);
            if (!(cam.yfov > 0.0f && cam.yfov < 3.14f))
                fail(idx("cameras", static_cast<size_t>(node.camera)) + ".perspective.yfov", "must be in (0, pi)");
            if (!(cam.znear > 0.0f))
                fail(idx("cameras", static_cast<size_t>(node.camera)) + ".perspective.znear", "must be positive");
        }
        const std::string cpath = idx("cameras", static_cast<size_t>(node.camera));
        if (cam.orthographic && !(cam.znear >= 0.0f)) fail(cpath + ".orthographic.znear", "must not be negative");
        if (cam.zfar != 0.0f && !(cam.zfar > cam.znear)) fail(cpath + (cam.orthographic ? ".orthographic" : ".perspective") + ".zfar", "must be greater than znear");
        // The thin lens (depth of field): extras.aperture is the lens radius, extras.focus_distance the
        // distance in focus along the view axis, both in scene units (0 or absent: a pinhole;
        // auto focus, focus_distance_or_auto).
        auto lens_number = [&](const char* key) {
            if (!src.extras.IsObject() || !src.extras.Has(key)) return 0.0f;
            const Value& v = src.extras.Get(key);
            const std::string where = cpath + ".extras." + key;
            if (!v.IsNumber()) fail(where, "must be a number >= 0 (scene units)");
            const double d = v.GetNumberAsDouble();
            if (!(d >= 0.0)) fail(where, num(d) + " is negative; must be >= 0 (scene units)");
            return f32(where, d);
        };
        cam.aperture = lens_number("aperture");
        cam.focus_distance = lens_number("focus_distance");
        if (cam.orthographic && cam.aperture > 0.0f)
            warn(cpath + ".extras.aperture", "ignored: an orthographic camera has no depth of field");
        scene.cameras.push_back(cam);
    }
    build_environment(scene);
    const SanitizeReport& s = scene.sanitized;
    if (s.nonfinite_positions) log::warn(file_ + ": " + std::to_string(s.nonfinite_positions) + " non-finite vertex positions replaced by 0");
    if (s.bad_normals) log::warn(file_ + ": " + std::to_string(s.bad_normals) + " zero-length or non-finite normals replaced by face normals");
    return scene;
}

std::string read_file(const fs::path& path) {
    std::ifstream in(path, std::ios::binary);
    if (!in) throw bad_input(path.string() + ": cannot open (" + std::strerror(errno) + ")");
    std::ostringstream ss;
    ss << in.rdbuf();
    return ss.str();
}

// Checks what tinygltf reports only vaguely: JSON syntax (with line and column) and external
// buffer files that are missing or shorter than their byteLength.
nlohmann::json precheck_gltf_json(const fs::path& path, std::string_view text) {
    nlohmann::json j;
    // RFC 8259 and the glTF spec (3.2) forbid a byte order mark; nlohmann::json would skip it.
    if (text.substr(0, 3) == "\xEF\xBB\xBF") {
        log::warn(path.string() + ": the JSON starts with a UTF-8 byte order mark, which glTF does not allow; ignored");
        text.remove_prefix(3);
    }
    try {
        j = nlohmann::json::parse(text);
    } catch (const nlohmann::json::exception& e) {
        // parse_error, and out_of_range for a number beyond double (e.g. 1e400; found by fuzzing).
        std::string what = e.what();
        const auto pos = what.find("] ");
        throw bad_input(path.string() + ": invalid JSON: " + (pos == std::string::npos ? what : what.substr(pos + 2)));
    }
    if (!j.is_object()) throw bad_input(path.string() + ": the top level is not a JSON object");
    if (!j.contains("asset")) throw bad_input(path.string() + ": asset: missing (not a glTF 2.0 file?)");
    if (!j.contains("buffers")) return j;
    if (!j["buffers"].is_array()) throw bad_input(path.string() + ": buffers: not an array");
    const auto& buffers = j["buffers"];
    for (size_t i = 0; i < buffers.size(); ++i) {
        const auto& b = buffers[i];
        const std::string bpath = path.string() + ": " + idx("buffers", i);
        if (!b.is_object() || !b.contains("byteLength") || !b["byteLength"].is_number_unsigned())
            throw bad_input(bpath + ".byteLength: missing or not a non-negative integer");
        if (!b.contains("uri") || !b["uri"].is_string()) continue;
        const std::string uri = b["uri"].get<std::string>();
        if (uri.rfind("data:", 0) == 0 || !gltf::buffer_available(b, false, i)) continue;
        const fs::path file = path.parent_path() / uri;
        std::error_code ec;
        const auto size = fs::file_size(file, ec);
        if (ec) throw bad_input(bpath + ".uri: cannot open '" + file.string() + "' (" + ec.message() + ")");
        const auto need = b["byteLength"].get<std::uint64_t>();
        if (size < need)
            throw bad_input(bpath + ": '" + uri + "' has " + std::to_string(size) + " bytes but byteLength is " +
                            std::to_string(need) + " (truncated buffer)");
    }
    return j;
}

std::string base64(std::string_view bytes) {
    static const char* abc = "ABCDEFGHIJKLMNOPQRSTUVWXYZabcdefghijklmnopqrstuvwxyz0123456789+/";
    std::string out;
    out.reserve((bytes.size() + 2) / 3 * 4);
    for (size_t i = 0; i < bytes.size(); i += 3) {
        uint32_t v = static_cast<uint8_t>(bytes[i]) << 16;
        if (i + 1 < bytes.size()) v |= static_cast<uint8_t>(bytes[i + 1]) << 8;
        if (i + 2 < bytes.size()) v |= static_cast<uint8_t>(bytes[i + 2]);
        out += abc[(v >> 18) & 63];
        out += abc[(v >> 12) & 63];
        out += i + 1 < bytes.size() ? abc[(v >> 6) & 63] : '=';
        out += i + 2 < bytes.size() ? abc[v & 63] : '=';
    }
    return out;
}

// tinygltf refuses some valid files: buffers without data (no uri, http://), data URIs that are
// not base64, accessors of unknown type (that nothing reads, or validation would have failed),
// and indices accessors without a bufferView (all zeros). It gets a rewritten document; the
// stand-in buffers are marked unavailable (nothing Candela reads lies in them) and the indices
// are restored in its model. Returns the rewritten .gltf/.glb bytes, or "" when none is needed.
std::string for_tinygltf(const std::string& file, const nlohmann::json& doc, bool glb, std::string_view bytes, std::vector<bool>* unavailable,
                         std::vector<std::pair<std::pair<size_t, size_t>, int>>* indices_without_view) {
    nlohmann::json out = doc;
    bool changed = false;
    if (auto b = out.find("buffers"); b != out.end() && b->is_array()) {
        unavailable->assign(b->size(), false);
        for (size_t i = 0; i < b->size(); ++i) {
            nlohmann::json& buf = (*b)[i];
            const uint64_t len = buf.value("byteLength", uint64_t(0));
            auto uri = buf.find("uri");
            if (!gltf::buffer_available(buf, glb, i)) {
                constexpr uint64_t kMaxStandIn = uint64_t(1) << 26;
                if (len > kMaxStandIn)
                    throw bad_input(file + ": " + idx("buffers", i) + ": has no data Candela can read and is too large to stand in for");
                buf["uri"] = "data:application/octet-stream;base64," + base64(std::string(len, '\0'));
                (*unavailable)[i] = changed = true;
            } else if (uri != buf.end() && uri->is_string() && uri->get<std::string>().rfind("data:", 0) == 0) {
                const std::string u = uri->get<std::string>();
                const size_t comma = u.find(',');
                if (comma == std::string::npos || u.substr(0, comma).find(";base64") != std::string::npos) continue;
                std::string decoded;
                for (size_t k = comma + 1; k < u.size(); ++k) {
                    if (u[k] == '%' && k + 2 < u.size()) {
                        decoded += static_cast<char>(std::stoi(u.substr(k + 1, 2), nullptr, 16));
                        k += 2;
                    } else {
                        decoded += u[k];
                    }
                }
                *uri = "data:application/octet-stream;base64," + base64(decoded);
                changed = true;
            }
        }
    }
    if (auto a = out.find("accessors"); a != out.end() && a->is_array())
        for (auto& acc : *a) {
            if (!acc.is_object()) continue;
            const std::string type = acc.value("type", std::string("SCALAR"));
            if (type != "SCALAR" && type != "VEC2" && type != "VEC3" && type != "VEC4" && type != "MAT2" && type != "MAT3" && type != "MAT4")
                acc["type"] = "SCALAR", changed = true;
            const int ct = acc.value("componentType", 5126);
            if (ct < 5120 || ct > 5126 || ct == 5124) acc["componentType"] = 5126, changed = true;
        }
    if (auto m = out.find("meshes"); m != out.end() && m->is_array())
        for (size_t mi = 0; mi < m->size(); ++mi) {
            auto prims = (*m)[mi].find("primitives");
            if (prims == (*m)[mi].end() || !prims->is_array()) continue;
            for (size_t pi = 0; pi < prims->size(); ++pi) {
                nlohmann::json& prim = (*prims)[pi];
                auto ind = prim.find("indices");
                if (ind == prim.end() || !ind->is_number_integer()) continue;
                const size_t a = ind->get<size_t>();
                if (!out.contains("accessors") || a >= out["accessors"].size()) continue;
                const nlohmann::json& acc = out["accessors"][a];
                if (acc.contains("bufferView") || acc.contains("sparse")) continue;
                indices_without_view->push_back({{mi, pi}, static_cast<int>(a)});
                prim.erase("indices");
                changed = true;
            }
        }
    // Integers written as floats (1.0): tinygltf wants integers where glTF has them; it reads any
    // JSON number where glTF has a float, so every integral float becomes an integer.
    std::function<void(nlohmann::json&)> integers = [&](nlohmann::json& v) {
        if (v.is_number_float()) {
            const double d = v.get<double>();
            if (std::isfinite(d) && std::floor(d) == d && std::fabs(d) < 9e15) v = static_cast<int64_t>(d), changed = true;
        } else if (v.is_structured()) {
            for (auto& child : v) integers(child);
        }
    };
    for (const char* key : {"buffers", "bufferViews", "accessors", "meshes", "nodes", "scenes", "textures", "images", "samplers",
                            "skins", "animations", "scene"})
        if (auto it = out.find(key); it != out.end()) {
            // Only where integers live: floats inside material factors etc. stay untouched.
            if (std::strcmp(key, "meshes") == 0 || std::strcmp(key, "nodes") == 0) {
                for (auto& item : *it) {
                    if (!item.is_object()) continue;
                    for (const char* k : {"mesh", "camera", "skin", "children", "primitives"})
                        if (auto c = item.find(k); c != item.end()) {
                            if (std::strcmp(k, "primitives") != 0) integers(*c);
                            else
                                for (auto& prim : *c)
                                    if (prim.is_object())
                                        for (const char* pk : {"attributes", "indices", "material", "mode", "targets"})
                                            if (auto pc = prim.find(pk); pc != prim.end()) integers(*pc);
                        }
                }
            } else if (std::strcmp(key, "accessors") == 0) {
                for (auto& acc : *it)
                    if (acc.is_object())
                        for (auto f = acc.begin(); f != acc.end(); ++f)
                            if (f.key() != "min" && f.key() != "max") integers(f.value());
            } else {
                integers(*it);
            }
        }
    if (!changed) return {};
    const std::string text = out.dump();
    if (!glb) return text;
    // The same .glb with the new JSON chunk (padded with spaces to 4 bytes) and the old chunks after it.
    uint32_t old_json = 0;
    std::memcpy(&old_json, bytes.data() + 12, 4);
    const std::string_view rest = bytes.substr(20 + old_json);
    const uint32_t json_len = static_cast<uint32_t>((text.size() + 3) / 4 * 4);
    const uint32_t total = static_cast<uint32_t>(20 + json_len + rest.size());
    std::string glb_out = std::string(bytes.substr(0, 8));
    glb_out.append(reinterpret_cast<const char*>(&total), 4);
    glb_out.append(reinterpret_cast<const char*>(&json_len), 4);
    glb_out.append("JSON", 4);
    glb_out += text;
    glb_out.append(json_len - text.size(), ' ');
    glb_out += rest;
    return glb_out;
}

// The first error of a validation pass is bad input; warnings go to the log, at most
// kMaxValidationWarnings of them (a file with a million bad normals says so once per accessor).
void report(const std::string& file, const std::vector<gltf::Issue>& issues) {
    constexpr size_t kMaxValidationWarnings = 20;
    size_t errors = 0;
    for (const gltf::Issue& i : issues) errors += i.error;
    for (const gltf::Issue& i : issues)
        if (i.error)
            throw bad_input(file + ": " + (i.path.empty() ? "" : i.path + ": ") + i.what +
                            (errors > 1 ? " (and " + std::to_string(errors - 1) + " more problems)" : ""));
    for (size_t k = 0; k < issues.size() && k < kMaxValidationWarnings; ++k)
        log::warn(file + ": " + (issues[k].path.empty() ? "" : issues[k].path + ": ") + issues[k].what);
    if (issues.size() > kMaxValidationWarnings)
        log::warn(file + ": " + std::to_string(issues.size() - kMaxValidationWarnings) + " more problems not shown");
}

}  // namespace

Scene load_gltf(const fs::path& path) {
    std::error_code ec;
    if (!fs::exists(path, ec)) throw bad_input(path.string() + ": no such file");
    if (fs::is_directory(path, ec)) throw bad_input(path.string() + ": is a directory, not a glTF file");
    return load_gltf_from_memory(path, read_file(path));
}

Scene load_gltf_from_memory(const fs::path& path, std::string_view bytes) {
    const std::string file = path.string();
    // A .glb by its magic, or by its name (then a wrong magic is reported as such).
    const bool binary = (bytes.size() >= 4 && bytes.compare(0, 4, "glTF") == 0) || path.extension() == ".glb";
    int64_t bin_size = -1;
    std::vector<gltf::Issue> container;
    const std::string_view json_text = binary ? gltf::glb_json_chunk(file, bytes, &bin_size, &container) : bytes;
    report(file, container);
    const nlohmann::json doc = precheck_gltf_json(path, json_text);
    // The glTF spec (3.12): a file whose required extension a loader does not implement must
    // not load. Checked first, so that such a file is refused for that reason.
    if (auto req = doc.find("extensionsRequired"); req != doc.end() && req->is_array())
        for (const auto& ext : *req)
            if (ext.is_string() && !gltf::extension_implemented(ext.get<std::string>()))
                throw bad_input(file + ": extensionsRequired: '" + ext.get<std::string>() + "' is not supported");
    report(file, gltf::validate_document(doc, binary, bin_size));

    std::vector<bool> unavailable;
    std::vector<std::pair<std::pair<size_t, size_t>, int>> indices_without_view;
    const std::string rewritten = for_tinygltf(file, doc, binary, bytes, &unavailable, &indices_without_view);
    if (!rewritten.empty()) bytes = rewritten;

    tinygltf::TinyGLTF gltf;
    ImageDecodeLog image_log;
    gltf.SetImageLoader(keep_image_bytes, &image_log);
    tinygltf::Model model;
    std::string err, warn;
    const std::string base_dir = path.parent_path().string();
    const bool ok = binary
        ? gltf.LoadBinaryFromMemory(&model, &err, &warn, reinterpret_cast<const unsigned char*>(bytes.data()),
                                    static_cast<unsigned>(bytes.size()), base_dir)
        : gltf.LoadASCIIFromString(&model, &err, &warn, bytes.data(), static_cast<unsigned>(bytes.size()), base_dir);
    if (!ok) throw bad_input(file + ": " + (err.empty() ? "not a valid glTF 2.0 file" : trim(err)));
    decode_images(image_log);
    // tinygltf's image warnings are restated by the loader with the JSON path; pass on the rest.
    std::istringstream lines(warn);
    for (std::string line; std::getline(lines, line);)
        if (!line.empty() && line.find("image") == std::string::npos && line.rfind("File not found", 0) != 0)
            log::warn(file + ": " + line);
    for (const auto& [where, accessor] : indices_without_view)
        if (where.first < model.meshes.size() && where.second < model.meshes[where.first].primitives.size())
            model.meshes[where.first].primitives[where.second].indices = accessor;
    std::vector<std::string_view> buffers;
    for (size_t i = 0; i < model.buffers.size(); ++i)
        buffers.emplace_back(i < unavailable.size() && unavailable[i] ? std::string_view()
                                 : std::string_view(reinterpret_cast<const char*>(model.buffers[i].data.data()), model.buffers[i].data.size()));
    report(file, gltf::validate_data(doc, buffers));
    Scene scene = Loader(path, model, image_log, unavailable).build();
    // What Candela does not implement is named once per kind, in the Scene and on stderr.
    for (const gltf::IgnoredFeature& f : gltf::ignored_features(doc)) {
        log::warn(file + ": " + f.first_path + ": " + f.phrase + " ignored (not implemented)");
        scene.ignored.push_back(f.phrase);
    }
    return scene;
}

}  // namespace candela
