#pragma once
// Scenes made in code for benchmarks and stress tests.
#include <cstddef>

#include "scene/scene.hpp"

namespace candela {

// A bumpy sphere (a UV sphere with a deterministic radial displacement) of about `triangles`
// triangles on a ground quad, one white Lambert material, a directional light, a framing camera.
Scene make_bumpy_sphere_scene(std::size_t triangles);

}  // namespace candela
