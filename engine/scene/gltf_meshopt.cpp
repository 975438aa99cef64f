// EXT_meshopt_compression (Khronos glTF extension registry, vendor extension by Kapoulkine and
// St. Pierre): a bufferView whose extension names a compressed byte range and how to decode it
// (mode ATTRIBUTES, TRIANGLES or INDICES; filter NONE, OCTAHEDRAL, QUATERNION or EXPONENTIAL).
// The bufferView's own buffer may be a "fallback" buffer without data; the decoded bytes replace
// it. meshoptimizer's decoders check their input and return an error for malformed streams.
#include "scene/gltf_decode.hpp"

#include <meshoptimizer.h>

#include <cstdint>

#include "core/error.hpp"

namespace candela::gltf_loading {
namespace {

using json = nlohmann::json;

std::string view_path(size_t i) { return "bufferViews[" + std::to_string(i) + "].extensions.EXT_meshopt_compression"; }

// A non-negative integer member; `fallback` when absent (the validation reported wrong types).
uint64_t member(const json& o, const char* key, uint64_t fallback) {
    auto it = o.find(key);
    if (it == o.end()) return fallback;
    if (it->is_number_unsigned()) return it->get<uint64_t>();
    if (it->is_number_integer() && it->get<int64_t>() >= 0) return static_cast<uint64_t>(it->get<int64_t>());
    return fallback;
}

}  // namespace

int append_decoded_buffer(json& plain, tinygltf::Model& model, std::vector<unsigned char> bytes, const std::string& name) {
    json entry = {{"byteLength", bytes.size()}, {"name", name}};
    tinygltf::Buffer b;
    b.name = name;
    b.data = std::move(bytes);
    model.buffers.push_back(std::move(b));
    if (!plain.contains("buffers") || !plain["buffers"].is_array()) plain["buffers"] = json::array();
    plain["buffers"].push_back(std::move(entry));
    return static_cast<int>(model.buffers.size()) - 1;
}

void decode_meshopt(const std::string& file, json& plain, tinygltf::Model& model) {
    auto views = plain.find("bufferViews");
    if (views == plain.end() || !views->is_array()) return;
    for (size_t i = 0; i < views->size() && i < model.bufferViews.size(); ++i) {
        json& view = (*views)[i];
        if (!view.is_object() || !view.contains("extensions") || !view["extensions"].is_object()) continue;
        auto ext_it = view["extensions"].find("EXT_meshopt_compression");
        if (ext_it == view["extensions"].end() || !ext_it->is_object()) continue;
        const json& ext = *ext_it;
        const std::string path = view_path(i);
        auto fail = [&](const std::string& where, const std::string& what) {
            throw bad_input(file + ": " + path + (where.empty() ? "" : "." + where) + ": " + what);
        };
        const uint64_t src = member(ext, "buffer", UINT64_MAX);
        const uint64_t offset = member(ext, "byteOffset", 0);
        const uint64_t length = member(ext, "byteLength", 0);
        const uint64_t stride = member(ext, "byteStride", 0);
        const uint64_t count = member(ext, "count", 0);
        const std::string mode = ext.value("mode", std::string());
        const std::string filter = ext.value("filter", std::string("NONE"));
        if (src >= model.buffers.size()) fail("buffer", "buffer " + std::to_string(src) + " does not exist");
        const std::vector<unsigned char>& data = model.buffers[src].data;
        if (offset > data.size() || length > data.size() - offset)
            fail("byteLength", "byteOffset " + std::to_string(offset) + " + byteLength " + std::to_string(length) + " exceeds buffers[" +
                                   std::to_string(src) + "] (" + std::to_string(data.size()) + " bytes)");
        if (count == 0 || stride == 0) fail("", "count and byteStride must be positive");
        const uint64_t view_length = model.bufferViews[i].byteLength;
        // Bounded by the validation (count * byteStride == the bufferView's byteLength, which fits its buffer).
        if (count > view_length / stride) fail("count", "count " + std::to_string(count) + " x byteStride " + std::to_string(stride) +
                                                            " is more than the bufferView's byteLength " + std::to_string(view_length));
        constexpr uint64_t kMaxDecoded = uint64_t(1) << 31;
        if (count * stride > kMaxDecoded)
            fail("count", std::to_string(count * stride) + " decoded bytes are more than Candela decodes in one bufferView (" +
                              std::to_string(kMaxDecoded) + ")");
        std::vector<unsigned char> out(static_cast<size_t>(count * stride));
        const unsigned char* in = data.data() + offset;
        int rc = 0;
        const char* decoder = "";
        if (mode == "ATTRIBUTES") {
            if (stride % 4 != 0 || stride > 256) fail("byteStride", std::to_string(stride) + " must be a multiple of 4 and at most 256 for ATTRIBUTES");
            decoder = "meshopt_decodeVertexBuffer";
            rc = meshopt_decodeVertexBuffer(out.data(), count, stride, in, length);
        } else if (mode == "TRIANGLES" || mode == "INDICES") {
            if (stride != 2 && stride != 4) fail("byteStride", std::to_string(stride) + " must be 2 or 4 for " + mode);
            if (mode == "TRIANGLES" && count % 3 != 0) fail("count", std::to_string(count) + " is not a multiple of 3 (mode TRIANGLES)");
            if (mode == "TRIANGLES") {
                decoder = "meshopt_decodeIndexBuffer";
                rc = meshopt_decodeIndexBuffer(out.data(), count, stride, in, length);
            } else {
                decoder = "meshopt_decodeIndexSequence";
                rc = meshopt_decodeIndexSequence(out.data(), count, stride, in, length);
            }
        } else {
            fail("mode", "'" + mode + "' is not ATTRIBUTES, TRIANGLES or INDICES");
        }
        if (rc != 0)
            fail("", "the compressed data is corrupt or not a meshopt stream (" + std::string(decoder) + " returned " + std::to_string(rc) + ")");
        if (filter != "NONE" && mode != "ATTRIBUTES") fail("filter", "'" + filter + "' needs mode ATTRIBUTES");
        if (filter == "OCTAHEDRAL") {
            if (stride != 4 && stride != 8) fail("byteStride", std::to_string(stride) + " must be 4 or 8 for the OCTAHEDRAL filter");
            meshopt_decodeFilterOct(out.data(), count, stride);
        } else if (filter == "QUATERNION") {
            if (stride != 8) fail("byteStride", std::to_string(stride) + " must be 8 for the QUATERNION filter");
            meshopt_decodeFilterQuat(out.data(), count, stride);
        } else if (filter == "EXPONENTIAL") {
            if (stride % 4 != 0) fail("byteStride", std::to_string(stride) + " must be a multiple of 4 for the EXPONENTIAL filter");
            meshopt_decodeFilterExp(out.data(), count, stride);
        } else if (filter != "NONE") {
            fail("filter", "'" + filter + "' is not NONE, OCTAHEDRAL, QUATERNION or EXPONENTIAL");
        }
        out.resize(static_cast<size_t>(view_length), 0);
        const int b = append_decoded_buffer(plain, model, std::move(out), "decoded " + view_path(i));
        model.bufferViews[i].buffer = b;
        model.bufferViews[i].byteOffset = 0;
        view["buffer"] = b;
        view["byteOffset"] = 0;
        view["extensions"].erase("EXT_meshopt_compression");
    }
}

}  // namespace candela::gltf_loading
