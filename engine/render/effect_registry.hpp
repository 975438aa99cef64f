#pragma once
// The effect registry: every effect module, in the order their decisions are made and their
// passes are added within a stage (an effect may depend on the decisions before it). The base
// declares it and iterates it; effects/registry.cpp, the one file that names every effect,
// defines it. So no header of the base includes an effect's, and the effects sit above the base.
#include <string>
#include <string_view>
#include <vector>

#include "render/effect.hpp"
#include "shader/shader_library.hpp"

namespace candela {

const std::vector<const Effect*>& effect_registry();
// nullptr for an unknown name.
const Effect* find_effect(std::string_view name);
// The shading includes (Effect::shading_include) of `effects`, in order: what the lighting code's
// "effects_shading.glsl" includes.
std::vector<std::string> effect_shading_includes(const std::vector<const Effect*>& effects);
// `shaders` serving what the lighting code includes from the effects: "shading_hooks.glsl" (the
// hook points' prototypes) and "effects_shading.glsl" (the shading includes of `effects`, then the
// hooks defined from them: render/shading_hooks.hpp). What every program that includes the
// lighting code is built with (ProgramCache does so for the renderer's programs, with the
// registry); a subset of the registry builds too (tested with each effect left out).
ShaderLibrary serve_effect_shading(ShaderLibrary shaders, const std::vector<const Effect*>& effects);
ShaderLibrary serve_effect_shading(ShaderLibrary shaders);

}  // namespace candela
