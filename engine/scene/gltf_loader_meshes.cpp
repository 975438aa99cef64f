// glTF loading of accessors, meshes and primitives, with their skin attributes and morph targets.
#include "scene/gltf_loader_internal.hpp"

#include <cmath>
#include <cstring>

#include "scene/mesh_utils.hpp"

namespace candela::gltf_loading {
namespace {

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

// KHR_materials_variants' names, in the file's order (extensions.KHR_materials_variants.variants;
// the validation has made sure that each is an object with a string name).
std::vector<std::string> variant_names(const tinygltf::Model& m) {
    std::vector<std::string> out;
    auto ext = m.extensions.find("KHR_materials_variants");
    if (ext == m.extensions.end() || !ext->second.IsObject() || !ext->second.Has("variants")) return out;
    const Value& list = ext->second.Get("variants");
    if (!list.IsArray()) return out;
    for (size_t i = 0; i < list.ArrayLen(); ++i) {
        const Value& v = list.Get(static_cast<int>(i));
        out.push_back(v.IsObject() && v.Has("name") && v.Get("name").IsString() ? v.Get("name").Get<std::string>()
                                                                                 : "variant " + std::to_string(i));
    }
    return out;
}

}  // namespace

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

Mesh Loader::build_mesh(size_t mi, Scene& scene) {
    const tinygltf::Mesh& src = m_.meshes[mi];
    if (primitive_source_.size() <= mi) primitive_source_.resize(mi + 1);
    Mesh mesh;
    mesh.name = src.name.empty() ? idx("meshes", mi) : src.name;
    if (mi == 0) scene.variants = variant_names(m_);
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
        prim.variants.default_material = p.material;
        // KHR_materials_variants: the material of each variant this primitive's mappings name.
        if (auto ext = p.extensions.find("KHR_materials_variants"); ext != p.extensions.end() && ext->second.IsObject() &&
                                                                    ext->second.Has("mappings") && ext->second.Get("mappings").IsArray()) {
            const std::string vpath = path + ".extensions.KHR_materials_variants.mappings";
            const Value& maps = ext->second.Get("mappings");
            prim.variants.by_variant.assign(scene.variants.size(), PrimitiveVariants::kUnmapped);
            for (size_t k = 0; k < maps.ArrayLen(); ++k) {
                const Value& map = maps.Get(static_cast<int>(k));
                const std::string mp = vpath + "[" + std::to_string(k) + "]";
                if (!map.IsObject() || !map.Has("material") || !map.Get("material").IsNumber())
                    fail(mp, "needs a 'material' index");
                const double material = map.Get("material").GetNumberAsDouble();
                if (material < 0 || material >= static_cast<double>(m_.materials.size()) || material != std::floor(material))
                    fail(mp + ".material", "material " + num(material) + " does not exist (the file has " +
                                               std::to_string(m_.materials.size()) + ")");
                const Value& vs = map.Get("variants");
                if (!vs.IsArray()) fail(mp, "needs a 'variants' array");
                for (size_t j = 0; j < vs.ArrayLen(); ++j) {
                    const Value& v = vs.Get(static_cast<int>(j));
                    const double vi = v.IsNumber() ? v.GetNumberAsDouble() : -1.0;
                    if (vi < 0 || vi >= static_cast<double>(scene.variants.size()) || vi != std::floor(vi))
                        fail(mp + ".variants[" + std::to_string(j) + "]",
                             "variant " + (v.IsNumber() ? num(vi) : std::string("(not a number)")) + " does not exist (the file has " +
                                 std::to_string(scene.variants.size()) + " in extensions.KHR_materials_variants.variants)");
                    prim.variants.by_variant[static_cast<size_t>(vi)] = static_cast<int>(material);
                }
            }
        }
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

}  // namespace candela::gltf_loading
