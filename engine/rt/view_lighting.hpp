#pragma once
// `--lighting auto` for files that bring their own lights: whether those lights light what the
// camera sees, measured with the tracer (rt/view_light.hpp) at the render's camera and aspect.
// When most of the passive surface in view is unlit (below kUnlitLevel of the typical directly
// lit pixel even with one bounce) and a sky could reach it, the default environment is added -
// never the key light, whose direction would compete with the file's - and the reason says so.
// A closed room, or any view its lights reach, stays as the file has it; `--lighting file` is
// never measured.
#include <memory>

#include "scene/lighting.hpp"
#include "scene/scene.hpp"

namespace candela {

namespace rt {
class RtScene;
}

class ShaderLibrary;

// More than this share of the seen surface unlit and `auto` adds the default environment, unless
// less than kSkyReaches of the seen surfaces' hemisphere is open (a closed room: no sky gets in).
constexpr double kMostlyUnlit = 0.5;
constexpr double kSkyReaches = 0.02;

// Needs a current GL context; does nothing unless choice.check_view. Call before uploading the
// scene (GpuScene) or building the tracer. Throws candela::Error (internal) if the tracer cannot
// be built.
// `shared`: as measure_view_light's (the caller's later measurements reuse the tracer geometry).
void complete_lighting(Scene& scene, LightingChoice& choice, const ShaderLibrary& shaders, const Camera& camera, float aspect,
                       std::shared_ptr<rt::RtScene>* shared = nullptr);

}  // namespace candela
