#pragma once
// Validation of a glTF 2.0 file before Candela builds a Scene from it, organised by glTF object
// kind (asset, buffers, bufferViews, accessors, meshes, nodes, scenes, cameras, materials,
// textures, images, samplers, skins, animations, extensions). The rules are the glTF 2.0
// specification's (JSON schema and the "Properties Reference"), as glTF-Validator checks them.
//
// Severity policy: a problem that would make Candela's picture wrong or its reads unsafe (an
// unresolved reference, an accessor outside its buffer, a wrong component type, a broken node
// hierarchy, an impossible camera; for skins, animations and morph targets: what posing reads,
// i.e. joints that are not nodes, too few inverse bind matrices, keyframe times that are not
// finite and strictly increasing, non-finite keyframe values, output formats or counts that do
// not fit the input and the path, morph target counts that disagree) is an error: the load fails
// with bad_input (exit 2). A problem in data Candela ignores anyway (extensions it does not
// implement, a channel it drops) or one the loader repairs (a non-unit rotation, min/max that
// disagree with the data, skin weights that do not sum to 1) is a warning. Messages name the JSON path, e.g. "accessors[0].bufferView: bufferView 3 does not
// exist (the file has 1)".
#include <cstdint>
#include <string>
#include <string_view>
#include <vector>

#include <nlohmann/json.hpp>

namespace candela::gltf {

struct Issue {
    bool error = false;  // false: a warning
    std::string path;    // JSON path, e.g. "meshes[0].primitives[1].indices"; "" for the file itself
    std::string what;
};

// The JSON chunk of a .glb after checking the container (header, chunk layout); `bin_size` gets
// the BIN chunk's length, or -1 without one. Throws bad_input naming `file` and the byte offset.
// Bytes after the declared length are a warning and are cut off `bytes`.
std::string_view glb_json_chunk(const std::string& file, std::string_view& bytes, int64_t* bin_size, std::vector<Issue>* warnings);

// Schema and semantic checks of the JSON document, without buffer contents. `glb_bin_size` is the
// BIN chunk's length for a .glb (-1: no BIN chunk or not a .glb).
std::vector<Issue> validate_document(const nlohmann::json& doc, bool glb, int64_t glb_bin_size);

// Checks of buffer contents that the document alone cannot tell (non-finite floats, min/max,
// animation times, unit quaternions, joint weights, inverse bind matrices). `buffers[i]` are the
// bytes of buffers[i]; call only after validate_document found no error.
std::vector<Issue> validate_data(const nlohmann::json& doc, const std::vector<std::string_view>& buffers);

// The glTF features the file uses that Candela does not implement, one phrase each
// ("KHR_materials_clearcoat on 4 materials", "morph targets of texture coordinates or colours on
// 1 mesh"), with the JSON path of the first occurrence.
struct IgnoredFeature {
    std::string phrase;
    std::string first_path;
};
std::vector<IgnoredFeature> ignored_features(const nlohmann::json& doc);

// Whether Candela can get a buffer's bytes: from a data: URI, a relative path, or a .glb's BIN
// chunk (buffer 0 without uri). A valid file may hold buffers it cannot (no uri, http://); they
// are fine as long as nothing Candela reads lies in them.
bool buffer_available(const nlohmann::json& buffer, bool glb, size_t index);

// Extensions the loader implements (everything else is ignored, or refused when required).
bool extension_implemented(std::string_view name);

}  // namespace candela::gltf
