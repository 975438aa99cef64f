#pragma once
// The hook points of the base lighting code (shaders/lighting/shading.glsl, forward/forward.frag,
// deferred/light.comp): what an effect may add to the shading of a surface point without the
// base naming the effect. Each hook is a GLSL function `effect_<hook>` (`effect_add_<hook>` for a
// summed one) that the base declares and calls. The shader library's generated includes define
// them from the effects that provide them (Effect::shading_hooks): an effect providing hook H
// defines `<effect name>_<hook name>` in its shading include, and the hook combines the
// providers by its rule, in registry order; with no provider the hook is its do-nothing default.
// So taking an effect out of the registry leaves every program building.
#include <string>
#include <vector>

namespace candela {

class Effect;

enum class ShadingHook {
    occlusion,            // float (vec2 pixel): ambient occlusion of the environment and indirect light; product, 1
    light_visibility,     // float (LightData light, vec3 p, vec3 n, vec3 l, vec2 pixel): share of a light reaching p; product, 1
    shaded_light_count,   // int (): the lights the per-light loops shade; one provider, frame.light_count
    direct_light,         // vec3 (BrdfInput bi, vec3 p, vec3 n, vec3 v, vec2 pixel, float transmission): light beyond the loop; sum, 0
    indirect_light,       // vec3 (BrdfInput bi, vec3 p, vec3 n, vec3 v, vec2 pixel, float occlusion, float transmission); sum, 0
    reflection_source,    // int (vec3 p, BrdfInput bi, float transmission): a local reflection source for p, -1 none; one provider
    reflection_radiance,  // vec3 (int k, vec3 p, vec3 r, float roughness, bool reflected): radiance from source k; one provider
    carries_sky,          // bool (): an effect's light already holds the sky's (the environment terms leave it out); any
    refraction,           // bool (): transmissive surfaces see refracted light this frame (else opaque); any
    capture_view,         // bool (): this view is a capture whose alpha carries the emission the direct-light hook adds; any
};

enum class HookRule {
    product,  // the providers' values multiplied, starting from the default (1)
    sum,      // `void effect_add_H(inout vec3 color, ...)`: each provider's value added to color in turn
    any,      // true when a provider says so
    one,      // at most one provider; the default without one
};

struct ShadingHookSpec {
    ShadingHook hook;
    const char* name;      // the hook's name: "occlusion"
    const char* type;      // the GLSL return type of a provider
    const char* params;    // the GLSL parameter list
    const char* args;      // the parameter names, comma-separated, as passed on
    HookRule rule;
    const char* fallback;  // the default (product: the start value)
    const char* doc;       // one line for the generated prototype's comment
};

const std::vector<ShadingHookSpec>& shading_hook_specs();
const ShadingHookSpec& shading_hook_spec(ShadingHook hook);

// The GLSL the base lighting includes first ("shading_hooks.glsl"): every hook's prototype.
std::string shading_hook_prototypes();
// The GLSL the base lighting includes last, after the effects' shading includes (the tail of
// "effects_shading.glsl"): every hook's definition from the providers in `effects`, in order.
// Throws candela::Error (internal) when a hook that takes one provider has two.
std::string shading_hook_definitions(const std::vector<const Effect*>& effects);

}  // namespace candela
