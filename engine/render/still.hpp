#pragma once
// One still image of a scene with the current GL context: what `candela render` and the golden
// tests both do, so that they cannot drift apart.
#include <string>

#include "image/image.hpp"
#include "render/forward_renderer.hpp"
#include "scene/scene.hpp"
#include "shader/shader_library.hpp"

namespace candela {

struct StillOptions {
    int width = 512;   // pixels, 1..16384
    int height = 512;
    std::string camera;  // glTF camera index or name; empty: first camera, else framing camera
};

struct StillResult {
    ImageF radiance;  // linear, RGBA32F, top row first
    FrameStats stats;
    // Wall-clock phases in milliseconds (CPU timings; the GPU work is finished by the readback).
    double upload_ms = 0, shader_ms = 0, frame_ms = 0, readback_ms = 0;
};

// Throws candela::Error: bad_input for an unknown camera or unreadable environment map,
// internal for shader/framebuffer failures.
StillResult render_still(const Scene& scene, const ShaderLibrary& shaders, const StillOptions& options);

}  // namespace candela
