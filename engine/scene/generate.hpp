#pragma once
// Scenes made in code for benchmarks and stress tests.
#include <cstddef>

#include "scene/scene.hpp"

namespace candela {

// A bumpy sphere (a UV sphere with a deterministic radial displacement) of about `triangles`
// triangles on a ground quad, one white Lambert material, a directional light, a framing camera.
Scene make_bumpy_sphere_scene(std::size_t triangles);

// The forward-vs-deferred benchmark scene: a 20 x 20 floor with a grid of boxes, `lights` point
// lights of range 3 scattered over it (deterministic colours and positions), a little ambient
// light and a camera looking over it.
Scene make_many_lights_scene(int lights);

}  // namespace candela
