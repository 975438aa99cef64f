#pragma once
// Internal to the glTF loader (gltf_loader*.cpp): decoding of compressed geometry into plain glTF
// data before accessors are read.
//   gltf_meshopt.cpp  EXT_meshopt_compression: compressed bufferViews (vertex and index codecs,
//                     the octahedral, quaternion and exponential filters) with meshoptimizer
//   gltf_draco.cpp    KHR_draco_mesh_compression: compressed primitives with Draco
// Both rewrite the parsed tinygltf::Model and `plain`, a copy of the document that validate_data
// and the Loader then read as if the file had never been compressed: the decoded bytes go into
// new buffers appended after the file's, the decoded bufferViews and accessors point into them.
// A problem (a missing or corrupt stream, a decoder error, a decoded count that disagrees with the
// accessor) throws bad_input naming `file` and the JSON path of the extension.
// Not part of the engine's interface: include only from the loader's files.
#include <string>
#include <vector>

#include <nlohmann/json.hpp>
#include <tiny_gltf.h>

namespace candela::gltf_loading {

// Every bufferView with EXT_meshopt_compression now reads its decoded bytes.
void decode_meshopt(const std::string& file, nlohmann::json& plain, tinygltf::Model& model);
// Every primitive with KHR_draco_mesh_compression now has its decoded attributes and indices in
// the accessors its `attributes` and `indices` name (an accessor two Draco primitives share is
// copied for the second one). Call after decode_meshopt (a Draco stream may lie in a meshopt view).
void decode_draco(const std::string& file, nlohmann::json& plain, tinygltf::Model& model);

// Appends `bytes` as a new buffer to both the model and `plain`; returns its index.
int append_decoded_buffer(nlohmann::json& plain, tinygltf::Model& model, std::vector<unsigned char> bytes, const std::string& name);

}  // namespace candela::gltf_loading
