#pragma once
// How far each point and spot light reaches and what that culls at a view: a light with a glTF
// `range` stops there; one without stops where lights.cutoff says (light_cutoff_distance); with
// lights.cutoff=0 it reaches everywhere. The tiled lighting of both paths (16x16 pixel tiles)
// skips a light in every tile its reach's sphere misses. This is the CPU's view of that culling,
// for `info` and the viewer's panel: each sphere's screen rectangle counted over the tiles
// (before the tiles' depth ranges, which the GPU also uses, so it counts at most what the GPU
// shades). Directional lights and unbounded lights count in every tile.
#include <string>

#include <glm/glm.hpp>

#include "scene/scene.hpp"

namespace candela {

struct LightReach {
    int lights = 0;              // punctual lights
    int ranged = 0;              // point/spot lights with a glTF range
    int cut = 0;                 // point/spot lights without one, cut by lights.cutoff
    int unbounded = 0;           // directional lights, and point/spot lights that nothing cuts
    float cut_min = 0, cut_max = 0;  // the cut lights' reach (scene units)
    int width = 0, height = 0;   // the image the tiles cover
    int tiles = 0;               // 16x16 pixel tiles
    double per_tile_mean = 0;    // lights a tile shades, mean over the tiles
    int per_tile_max = 0;        // ... and at most
    std::string text() const;    // one line for info and the viewer
};

// `view_proj`: the camera's (projection_matrix times the inverse of its world matrix).
LightReach light_reach(const Scene& scene, float cutoff, const glm::mat4& view_proj, int width, int height);

}  // namespace candela
