#include "render/still.hpp"

#include <chrono>

#include "core/error.hpp"

namespace candela {
namespace {
double ms_since(std::chrono::steady_clock::time_point t0) {
    return std::chrono::duration<double, std::milli>(std::chrono::steady_clock::now() - t0).count();
}
}  // namespace

StillResult render_still(const Scene& scene, const ShaderLibrary& shaders, const StillOptions& options) {
    if (options.width < 1 || options.height < 1 || options.width > 16384 || options.height > 16384)
        throw bad_input("--size " + std::to_string(options.width) + "x" + std::to_string(options.height) +
                        " is out of range (1..16384 per side)");
    StillResult result;
    const float aspect = static_cast<float>(options.width) / static_cast<float>(options.height);
    const Camera camera = scene.select_camera(options.camera, aspect);

    auto t0 = std::chrono::steady_clock::now();
    GpuScene gpu(scene);
    result.upload_ms = ms_since(t0);

    t0 = std::chrono::steady_clock::now();
    ForwardRenderer renderer(shaders, gpu);
    result.shader_ms = ms_since(t0);

    t0 = std::chrono::steady_clock::now();
    renderer.render(camera, options.width, options.height);
    glFinish();
    result.frame_ms = ms_since(t0);

    t0 = std::chrono::steady_clock::now();
    result.radiance = renderer.read_radiance();
    result.readback_ms = ms_since(t0);
    result.stats = renderer.stats();
    return result;
}

}  // namespace candela
