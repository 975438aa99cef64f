// KHR_draco_mesh_compression (Khronos glTF extension registry): a primitive whose extension names
// a bufferView holding a Draco-compressed mesh and, per attribute semantic, the Draco attribute's
// unique id. As the extension specifies, the decoded data replace the accessors the primitive's
// `attributes` and `indices` name (which keep their count, type, componentType, normalized, min
// and max, and have no bufferView); attributes not in the extension's map and morph targets stay
// uncompressed. The decoder (Draco) reports malformed streams as a failed status; every index and
// attribute read below is also checked against the decoded mesh's sizes.
#include "scene/gltf_decode.hpp"

#include <draco/compression/decode.h>

#include <cstdint>
#include <cstring>
#include <set>

#include "core/error.hpp"

namespace candela::gltf_loading {
namespace {

using json = nlohmann::json;

// One decoded value converted to the accessor's component type, `n` components.
template <typename T>
bool convert(const draco::PointAttribute& att, draco::AttributeValueIndex v, int n, unsigned char* out) {
    T tmp[16] = {};
    if (!att.ConvertValue<T>(v, static_cast<int8_t>(n), tmp)) return false;
    std::memcpy(out, tmp, sizeof(T) * static_cast<size_t>(n));
    return true;
}

int component_bytes(int type) {
    switch (type) {
        case TINYGLTF_COMPONENT_TYPE_BYTE: case TINYGLTF_COMPONENT_TYPE_UNSIGNED_BYTE: return 1;
        case TINYGLTF_COMPONENT_TYPE_SHORT: case TINYGLTF_COMPONENT_TYPE_UNSIGNED_SHORT: return 2;
        case TINYGLTF_COMPONENT_TYPE_UNSIGNED_INT: case TINYGLTF_COMPONENT_TYPE_FLOAT: return 4;
        default: return 0;
    }
}

class PrimitiveDecoder {
public:
    PrimitiveDecoder(const std::string& file, json& plain, tinygltf::Model& model, size_t mi, size_t pi, std::set<int>& decoded)
        : file_(file), plain_(plain), m_(model), mi_(mi), pi_(pi), decoded_(decoded),
          path_("meshes[" + std::to_string(mi) + "].primitives[" + std::to_string(pi) + "]"),
          ext_path_(path_ + ".extensions.KHR_draco_mesh_compression") {}

    void run(const json& ext) {
        tinygltf::Primitive& prim = m_.meshes[mi_].primitives[pi_];
        const int view = ext.value("bufferView", -1);
        if (view < 0 || static_cast<size_t>(view) >= m_.bufferViews.size()) fail(ext_path_ + ".bufferView", "missing or not a bufferView of the file");
        const tinygltf::BufferView& bv = m_.bufferViews[static_cast<size_t>(view)];
        if (bv.buffer < 0 || static_cast<size_t>(bv.buffer) >= m_.buffers.size()) fail(ext_path_ + ".bufferView", "its buffer does not exist");
        const std::vector<unsigned char>& data = m_.buffers[static_cast<size_t>(bv.buffer)].data;
        if (bv.byteOffset > data.size() || bv.byteLength > data.size() - bv.byteOffset)
            fail(ext_path_ + ".bufferView", "bufferView " + std::to_string(view) + " lies outside its buffer");
        if (prim.mode != TINYGLTF_MODE_TRIANGLES && prim.mode != -1)
            fail(path_ + ".mode", "a Draco-compressed primitive must be TRIANGLES (4) here, not " + std::to_string(prim.mode));

        draco::DecoderBuffer buffer;
        buffer.Init(reinterpret_cast<const char*>(data.data() + bv.byteOffset), bv.byteLength);
        const auto type = draco::Decoder::GetEncodedGeometryType(&buffer);
        if (!type.ok()) fail(ext_path_, "not a Draco stream (" + type.status().error_msg_string() + ")");
        if (type.value() != draco::TRIANGULAR_MESH) fail(ext_path_, "the Draco stream is a point cloud, not a triangle mesh");
        draco::Decoder decoder;
        auto decoded = decoder.DecodeMeshFromBuffer(&buffer);
        if (!decoded.ok()) fail(ext_path_, "the Draco data cannot be decoded (" + decoded.status().error_msg_string() + ")");
        mesh_ = std::move(decoded).value();
        if (!mesh_) fail(ext_path_, "the Draco decoder returned no mesh");

        if (prim.indices < 0) fail(path_, "a Draco-compressed primitive needs 'indices' (the decoded triangles)");
        decode_indices(prim.indices);
        const json& attrs = ext.at("attributes");
        for (auto it = attrs.begin(); it != attrs.end(); ++it) {
            const std::string where = ext_path_ + ".attributes." + it.key();
            auto a = prim.attributes.find(it.key());
            if (a == prim.attributes.end()) fail(where, "the primitive has no " + it.key() + " attribute to decode into");
            if (!it->is_number_integer() || it->get<int64_t>() < 0 || it->get<int64_t>() > INT32_MAX)
                fail(where, "must be a Draco attribute id (a non-negative integer)");
            decode_attribute(it.key(), a->second, static_cast<uint32_t>(it->get<int64_t>()), where);
        }
    }

private:
    [[noreturn]] void fail(const std::string& where, const std::string& what) const { throw bad_input(file_ + ": " + where + ": " + what); }

    // The accessor to write: `a` itself, or a copy when an earlier Draco primitive filled it.
    int target_accessor(int a) {
        if (decoded_.insert(a).second) return a;
        m_.accessors.push_back(m_.accessors[static_cast<size_t>(a)]);
        plain_["accessors"].push_back(plain_["accessors"][static_cast<size_t>(a)]);
        const int copy = static_cast<int>(m_.accessors.size()) - 1;
        decoded_.insert(copy);
        return copy;
    }

    void store(int accessor, std::vector<unsigned char> bytes, int target, const std::string& name) {
        const int b = append_decoded_buffer(plain_, m_, std::move(bytes), name);
        const size_t length = m_.buffers[static_cast<size_t>(b)].data.size();
        tinygltf::BufferView bv;
        bv.buffer = b;
        bv.byteOffset = 0;
        bv.byteLength = length;
        bv.target = target;
        m_.bufferViews.push_back(bv);
        plain_["bufferViews"].push_back({{"buffer", b}, {"byteOffset", 0}, {"byteLength", length}, {"target", target}});
        const int view = static_cast<int>(m_.bufferViews.size()) - 1;
        tinygltf::Accessor& acc = m_.accessors[static_cast<size_t>(accessor)];
        acc.bufferView = view;
        acc.byteOffset = 0;
        acc.sparse.isSparse = false;
        json& pa = plain_["accessors"][static_cast<size_t>(accessor)];
        pa["bufferView"] = view;
        pa["byteOffset"] = 0;
        pa.erase("sparse");
        // The declared min/max of a Draco attribute are its quantisation grid's bounds (Box-Draco:
        // +-0.500489 for decoded +-0.5); the data checks would warn about every such file.
        pa.erase("min");
        pa.erase("max");
    }

    void decode_indices(int accessor) {
        const std::string where = path_ + ".indices";
        if (static_cast<size_t>(accessor) >= m_.accessors.size()) fail(where, "accessor " + std::to_string(accessor) + " does not exist");
        const tinygltf::Accessor& acc = m_.accessors[static_cast<size_t>(accessor)];
        const uint64_t faces = mesh_->num_faces();
        if (acc.count != faces * 3)
            fail(where, "accessor " + std::to_string(accessor) + " has count " + std::to_string(acc.count) + " but the Draco mesh (" + ext_path_ +
                            ") has " + std::to_string(faces) + " triangles, " + std::to_string(faces * 3) + " indices");
        const int size = component_bytes(acc.componentType);
        if (acc.type != TINYGLTF_TYPE_SCALAR || (acc.componentType != TINYGLTF_COMPONENT_TYPE_UNSIGNED_BYTE &&
                                                 acc.componentType != TINYGLTF_COMPONENT_TYPE_UNSIGNED_SHORT &&
                                                 acc.componentType != TINYGLTF_COMPONENT_TYPE_UNSIGNED_INT))
            fail(where, "accessor " + std::to_string(accessor) + " must be SCALAR UNSIGNED_BYTE, _SHORT or _INT");
        const uint64_t limit = size == 1 ? 0xFFu : size == 2 ? 0xFFFFu : 0xFFFFFFFFu;
        const uint64_t points = mesh_->num_points();
        std::vector<unsigned char> out(static_cast<size_t>(faces * 3) * static_cast<size_t>(size));
        for (uint64_t f = 0; f < faces; ++f) {
            const draco::Mesh::Face& face = mesh_->face(draco::FaceIndex(static_cast<uint32_t>(f)));
            for (int k = 0; k < 3; ++k) {
                const uint64_t v = face[k].value();
                if (v >= points) fail(ext_path_, "the Draco mesh has a triangle corner " + std::to_string(v) + " beyond its " +
                                                     std::to_string(points) + " points (corrupt data)");
                if (v > limit) fail(where, "decoded index " + std::to_string(v) + " does not fit the accessor's componentType");
                unsigned char* dst = out.data() + (f * 3 + static_cast<uint64_t>(k)) * static_cast<uint64_t>(size);
                if (size == 1) *dst = static_cast<uint8_t>(v);
                else if (size == 2) { const auto s = static_cast<uint16_t>(v); std::memcpy(dst, &s, 2); }
                else { const auto s = static_cast<uint32_t>(v); std::memcpy(dst, &s, 4); }
            }
        }
        const int target = target_accessor(accessor);
        m_.meshes[mi_].primitives[pi_].indices = target;
        plain_["meshes"][mi_]["primitives"][pi_]["indices"] = target;
        store(target, std::move(out), TINYGLTF_TARGET_ELEMENT_ARRAY_BUFFER, "decoded " + where);
    }

    void decode_attribute(const std::string& name, int accessor, uint32_t id, const std::string& where) {
        if (accessor < 0 || static_cast<size_t>(accessor) >= m_.accessors.size())
            fail(path_ + ".attributes." + name, "accessor " + std::to_string(accessor) + " does not exist");
        const draco::PointAttribute* att = mesh_->GetAttributeByUniqueId(id);
        if (!att) fail(where, "the Draco mesh has no attribute with id " + std::to_string(id) + " (it has " +
                                  std::to_string(mesh_->num_attributes()) + " attributes)");
        const tinygltf::Accessor& acc = m_.accessors[static_cast<size_t>(accessor)];
        const uint64_t points = mesh_->num_points();
        if (acc.count != points)
            fail(where, "accessor " + std::to_string(accessor) + " has count " + std::to_string(acc.count) + " but the Draco mesh has " +
                            std::to_string(points) + " points");
        const int n = tinygltf::GetNumComponentsInType(static_cast<uint32_t>(acc.type));
        const int csize = component_bytes(acc.componentType);
        if (n <= 0 || n > 4 || csize == 0) fail(where, "accessor " + std::to_string(accessor) + " is not a SCALAR or VECn of a glTF component type");
        if (att->num_components() != n)
            fail(where, "the Draco attribute has " + std::to_string(att->num_components()) + " components, accessor " + std::to_string(accessor) +
                            " has " + std::to_string(n));
        const size_t elem = static_cast<size_t>(n * csize);
        std::vector<unsigned char> out(static_cast<size_t>(points) * elem);
        for (uint64_t p = 0; p < points; ++p) {
            const draco::PointIndex pi(static_cast<uint32_t>(p));
            if (!att->is_mapping_identity() && p >= att->indices_map_size()) fail(where, "the Draco attribute maps fewer points than the mesh has (corrupt data)");
            const draco::AttributeValueIndex v = att->mapped_index(pi);
            if (v.value() >= att->size()) fail(where, "the Draco attribute refers to value " + std::to_string(v.value()) + " of " +
                                                          std::to_string(att->size()) + " (corrupt data)");
            unsigned char* dst = out.data() + p * elem;
            bool ok = false;
            switch (acc.componentType) {
                case TINYGLTF_COMPONENT_TYPE_FLOAT: ok = convert<float>(*att, v, n, dst); break;
                case TINYGLTF_COMPONENT_TYPE_BYTE: ok = convert<int8_t>(*att, v, n, dst); break;
                case TINYGLTF_COMPONENT_TYPE_UNSIGNED_BYTE: ok = convert<uint8_t>(*att, v, n, dst); break;
                case TINYGLTF_COMPONENT_TYPE_SHORT: ok = convert<int16_t>(*att, v, n, dst); break;
                case TINYGLTF_COMPONENT_TYPE_UNSIGNED_SHORT: ok = convert<uint16_t>(*att, v, n, dst); break;
                case TINYGLTF_COMPONENT_TYPE_UNSIGNED_INT: ok = convert<uint32_t>(*att, v, n, dst); break;
                default: break;
            }
            if (!ok) fail(where, "the Draco attribute's values cannot be converted to the accessor's componentType");
        }
        const int target = target_accessor(accessor);
        if (target != accessor) {
            m_.meshes[mi_].primitives[pi_].attributes[name] = target;
            plain_["meshes"][mi_]["primitives"][pi_]["attributes"][name] = target;
        }
        store(target, std::move(out), TINYGLTF_TARGET_ARRAY_BUFFER, "decoded " + where);
    }

    const std::string& file_;
    json& plain_;
    tinygltf::Model& m_;
    size_t mi_, pi_;
    std::set<int>& decoded_;
    std::string path_, ext_path_;
    std::unique_ptr<draco::Mesh> mesh_;
};

}  // namespace

void decode_draco(const std::string& file, json& plain, tinygltf::Model& model) {
    auto meshes = plain.find("meshes");
    if (meshes == plain.end() || !meshes->is_array()) return;
    std::set<int> decoded;  // accessors already filled
    for (size_t mi = 0; mi < meshes->size() && mi < model.meshes.size(); ++mi) {
        const json& mesh = (*meshes)[mi];
        if (!mesh.is_object() || !mesh.contains("primitives") || !mesh["primitives"].is_array()) continue;
        for (size_t pi = 0; pi < mesh["primitives"].size() && pi < model.meshes[mi].primitives.size(); ++pi) {
            const json& prim = mesh["primitives"][pi];
            if (!prim.is_object() || !prim.contains("extensions") || !prim["extensions"].is_object()) continue;
            auto ext = prim["extensions"].find("KHR_draco_mesh_compression");
            if (ext == prim["extensions"].end() || !ext->is_object() || !ext->contains("attributes") || !(*ext)["attributes"].is_object())
                continue;  // reported by the validation
            const json copy = *ext;  // the decoder edits `plain`
            PrimitiveDecoder(file, plain, model, mi, pi, decoded).run(copy);
        }
    }
}

}  // namespace candela::gltf_loading
