#pragma once
#include <filesystem>
#include <string_view>

#include "scene/scene.hpp"

namespace candela {

// Loads a .gltf or .glb file. Every accessor, buffer view, index and reference is bounds-checked
// before use. Broken input throws candela::Error (bad_input) whose message names the file and the
// JSON path of the problem, e.g.
//   "box.gltf: meshes[0].primitives[1].indices: index 4096 out of range (accessor has 36 vertices)".
// Recoverable problems (missing texture, non-triangle primitive) are warnings, counted in
// Scene::sanitized.
Scene load_gltf(const std::filesystem::path& path);

// The same from bytes already in memory (.gltf JSON or .glb): `path` names the input in messages
// and its folder resolves relative URIs (buffers, images), as if the bytes had been read from it.
// The fuzz target uses this to skip the file system for the input itself.
Scene load_gltf_from_memory(const std::filesystem::path& path, std::string_view bytes);

}  // namespace candela
