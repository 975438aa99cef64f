#include "render/effect_registry.hpp"

#include "effects/aa/aa.hpp"
#include "effects/area_lights/area_lights.hpp"
#include "effects/dof/dof.hpp"
#include "effects/gi/gi.hpp"
#include "effects/motion_blur/motion_blur.hpp"
#include "effects/reflections/reflections.hpp"
#include "effects/rsm/rsm.hpp"
#include "effects/shadows/shadows.hpp"
#include "effects/ssao/ssao.hpp"
#include "effects/transparency/transparency.hpp"
#include "shader/shader_library.hpp"

namespace candela {

const std::vector<const Effect*>& effect_registry() {
    // One line per effect. Order: decisions are made in this order (rsm reads the shadows
    // and gi decisions), and within a stage passes run in this order (gi_probes before env_probe:
    // the reflection probes capture the room with its indirect light).
    static const std::vector<const Effect*> all = {
        &shadows_effect(),
        &area_lights_effect(),
        &gi_effect(),
        &reflections_effect(),
        &ssao_effect(),
        &rsm_effect(),
        &transparency_effect(),
        &aa_effect(),
        &motion_blur_effect(),  // before dof: see docs/effects/motion_blur.md (its velocity and depth match the sharp image)
        &dof_effect(),
    };
    return all;
}

std::vector<std::string> effect_shading_includes(const std::vector<const Effect*>& effects) {
    std::vector<std::string> files;
    for (const Effect* e : effects)
        if (const char* f = e->shading_include()) files.emplace_back(f);
    return files;
}

ShaderLibrary serve_effect_shading(ShaderLibrary shaders, const std::vector<const Effect*>& effects) {
    shaders.set_generated_include("shading_hooks.glsl", {}, shading_hook_prototypes());
    shaders.set_generated_include("effects_shading.glsl", effect_shading_includes(effects), shading_hook_definitions(effects));
    return shaders;
}

ShaderLibrary serve_effect_shading(ShaderLibrary shaders) { return serve_effect_shading(std::move(shaders), effect_registry()); }

const Effect* find_effect(std::string_view name) {
    for (const Effect* e : effect_registry())
        if (name == e->name()) return e;
    return nullptr;
}

}  // namespace candela
