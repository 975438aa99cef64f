#include "rt/view_lighting.hpp"

#include <cstdio>
#include <cstring>

#include "core/error.hpp"
#include "core/log.hpp"
#include "render/gpu_scene.hpp"
#include "rt/view_light.hpp"

namespace candela {

void complete_lighting(Scene& scene, LightingChoice& choice, const ShaderLibrary& shaders, const Camera& camera, float aspect,
                       std::shared_ptr<rt::RtScene>* shared) {
    if (!choice.check_view) return;
    choice.check_view = false;
    if (scene.triangle_count() == 0) return;
    ViewLight v;
    {
        GpuScene gpu(scene);
        try {
            v = measure_view_light(shaders, scene, gpu, camera, aspect, 8, kViewLightPixels, shared);
        } catch (const Error& e) {
            if (e.code() == ExitCode::internal) throw;
            return;  // nothing to trace
        }
    }
    log::debug("lighting: view measurement " + v.text());
    char buf[320];
    std::snprintf(buf, sizeof buf, "%.0f %% of the surface in view (%d of %d px at %dx%d) is unlit by them", v.unlit_share * 100.0,
                  static_cast<int>(v.unlit_share * v.surface_pixels + 0.5), v.surface_pixels, v.width, v.height);
    if (v.surface_pixels == 0 || v.unlit_share <= kMostlyUnlit) {
        choice.reason += std::string("; ") + buf;
        return;
    }
    // A sky cannot light a closed room: it would only reach the rasterizer's ambient term, which
    // does not know the room is closed, and the tracer's image would stay as it is.
    if (v.sky_visibility < kSkyReaches) {
        std::snprintf(buf + std::strlen(buf), sizeof buf - std::strlen(buf), ", but a sky would not reach it (%.1f %% open)",
                      v.sky_visibility * 100.0);
        choice.reason += std::string("; ") + buf;
        return;
    }
    add_default_environment(scene);
    choice.environment_added = true;
    choice.reason += std::string("; ") + buf + ", so the default sky is added (--lighting file: the file's lights alone)";
}

}  // namespace candela
