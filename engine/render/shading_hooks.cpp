#include "render/shading_hooks.hpp"

#include <algorithm>

#include "core/error.hpp"
#include "render/effect.hpp"

namespace candela {

const std::vector<ShadingHookSpec>& shading_hook_specs() {
    using H = ShadingHook;
    using R = HookRule;
    static const std::vector<ShadingHookSpec> specs = {
        {H::occlusion, "occlusion", "float", "vec2 pixel", "pixel", R::product, "1.0",
         "occlusion of the environment and indirect light at a pixel (never of direct light)"},
        {H::light_visibility, "light_visibility", "float", "LightData light, vec3 p, vec3 n, vec3 l, vec2 pixel",
         "light, p, n, l, pixel", R::product, "1.0", "the share of `light` (towards l) that reaches p: 1 lit, 0 shadowed"},
        {H::shaded_light_count, "shaded_light_count", "int", "", "", R::one, "frame.light_count",
         "how many lights of the light buffer the per-light loops shade (the rest only cast shadows)"},
        {H::direct_light, "direct_light", "vec3", "BrdfInput bi, vec3 p, vec3 n, vec3 v, vec2 pixel, float transmission",
         "bi, p, n, v, pixel, transmission", R::sum, "vec3(0.0)", "direct light the per-light loops do not shade, towards v"},
        {H::indirect_light, "indirect_light", "vec3",
         "BrdfInput bi, vec3 p, vec3 n, vec3 v, vec2 pixel, float occlusion, float transmission",
         "bi, p, n, v, pixel, occlusion, transmission", R::sum, "vec3(0.0)",
         "light of later bounces reflected towards v (`occlusion`: the material's)"},
        {H::reflection_source, "reflection_source", "int", "vec3 p, BrdfInput bi, float transmission", "p, bi, transmission",
         R::one, "-1", "the local reflection source that serves p on such a surface; -1: the environment"},
        {H::reflection_radiance, "reflection_radiance", "vec3", "int k, vec3 p, vec3 r, float roughness, bool reflected",
         "k, p, r, roughness, reflected", R::one, "vec3(0.0)",
         "radiance from source k arriving at p from r, prefiltered for roughness (`reflected`: without the direct-light hook's emitters)"},
        {H::carries_sky, "carries_sky", "bool", "", "", R::any, "false",
         "an effect's indirect light carries the sky's: the environment's terms leave it out"},
        {H::refraction, "refraction", "bool", "", "", R::any, "false",
         "transmissive surfaces show refracted light this frame (without: opaque dielectrics)"},
        {H::capture_view, "capture_view", "bool", "", "", R::any, "false",
         "this view is captured for reflections: alpha carries the luminance of the emission that the direct-light hook adds"},
    };
    return specs;
}

const ShadingHookSpec& shading_hook_spec(ShadingHook hook) {
    for (const ShadingHookSpec& s : shading_hook_specs())
        if (s.hook == hook) return s;
    throw Error(ExitCode::internal, "shading hook without a spec");
}

namespace {

std::string hook_function(const ShadingHookSpec& s) {
    return std::string(s.rule == HookRule::sum ? "effect_add_" : "effect_") + s.name;
}

std::string hook_signature(const ShadingHookSpec& s) {
    const std::string params = s.params;
    if (s.rule == HookRule::sum) return "void " + hook_function(s) + "(inout vec3 color" + (params.empty() ? "" : ", " + params) + ")";
    return std::string(s.type) + " " + hook_function(s) + "(" + params + ")";
}

}  // namespace

std::string shading_hook_prototypes() {
    std::string out =
        "// Generated (render/shading_hooks.cpp): the hook points of the lighting code, defined after the\n"
        "// effects' shading includes from the effects that provide them.\n";
    for (const ShadingHookSpec& s : shading_hook_specs()) out += "// " + std::string(s.doc) + "\n" + hook_signature(s) + ";\n";
    return out;
}

std::string shading_hook_definitions(const std::vector<const Effect*>& effects) {
    std::string out = "// Generated (render/shading_hooks.cpp): each hook from the effects that provide it.\n";
    for (const ShadingHookSpec& s : shading_hook_specs()) {
        std::vector<std::string> providers;
        for (const Effect* e : effects) {
            const std::vector<ShadingHook> hooks = e->shading_hooks();
            if (std::find(hooks.begin(), hooks.end(), s.hook) != hooks.end()) providers.push_back(std::string(e->name()) + "_" + s.name);
        }
        if (s.rule == HookRule::one && providers.size() > 1)
            throw Error(ExitCode::internal, std::string("shading hook '") + s.name + "' takes one provider; " + providers[0] + " and " +
                                                providers[1] + " both define it");
        const std::string call_args = std::string("(") + s.args + ")";
        std::string body;
        switch (s.rule) {
            case HookRule::product:
                body = "    " + std::string(s.type) + " value = " + s.fallback + ";\n";
                for (const std::string& p : providers) body += "    value *= " + p + call_args + ";\n";
                body += "    return value;\n";
                break;
            case HookRule::sum:
                for (const std::string& p : providers) body += "    color += " + p + call_args + ";\n";
                break;
            case HookRule::any: {
                std::string expr;
                for (const std::string& p : providers) expr += (expr.empty() ? "" : " || ") + p + call_args;
                body = "    return " + (expr.empty() ? std::string(s.fallback) : expr) + ";\n";
                break;
            }
            case HookRule::one:
                body = "    return " + (providers.empty() ? std::string(s.fallback) : providers[0] + call_args) + ";\n";
                break;
        }
        out += hook_signature(s) + " {\n" + body + "}\n";
    }
    return out;
}

}  // namespace candela
