#pragma once
// Writes a Scene as one self-contained .gltf (JSON, the binary buffer embedded as a base64 data
// URI) that load_gltf reads back to the same Scene: what the random-scene tests save a failing
// seed with, so that it stays a regression file that the normal loader renders.
//
// Written: meshes (positions, normals, the first UV set when any is non-zero, 32-bit indices, one
// glTF primitive per Primitive), materials (metallic-roughness factors, emission with
// KHR_materials_emissive_strength, KHR_materials_specular, _ior, _transmission, _volume, alpha
// mode, double-sidedness), nodes (as matrices; extras.sphere), KHR_lights_punctual, cameras (a
// camera not placed by a node gets a root node at its world transform; extras.aperture and
// focus_distance) and the constant environment (scene extras.environment_radiance and
// environment_intensity). Numbers are written so that they read back bit for bit.
// Not written (writing such a scene throws candela::Error, bad_input, naming what): textures,
// skins, morph targets, animations, reflection probes and environment maps.
#include <filesystem>
#include <string>

#include "scene/scene.hpp"

namespace candela {

std::string gltf_text(const Scene& scene);
void write_gltf(const Scene& scene, const std::filesystem::path& path);

}  // namespace candela
