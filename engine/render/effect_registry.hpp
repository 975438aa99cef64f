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
// The effects' shading includes (Effect::shading_include), registry order: what the lighting
// code's "effects_shading.glsl" includes.
std::vector<std::string> effect_shading_includes();
// `shaders` serving "effects_shading.glsl" (effect_shading_includes): what every program that
// includes the lighting code is built with (ProgramCache does so for the renderer's programs).
ShaderLibrary serve_effect_shading(ShaderLibrary shaders);

}  // namespace candela
