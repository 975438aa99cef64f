// The lighting's hook points (render/shading_hooks.hpp): the generated glue, and every lighting
// program building with any one effect taken out of the registry (the base names no effect).
#include <gtest/gtest.h>

#include <algorithm>
#include <filesystem>
#include <set>
#include <string>

#include "core/error.hpp"
#include "render/effect_registry.hpp"
#include "render/program_catalog.hpp"
#include "render/shading_hooks.hpp"
#include "shader/shader_library.hpp"

namespace candela {
namespace {
namespace fs = std::filesystem;

bool contains(const std::string& text, const std::string& what) { return text.find(what) != std::string::npos; }

TEST(ShadingHooks, WithoutProvidersEveryHookIsItsDefault) {
    const std::string protos = shading_hook_prototypes();
    const std::string defs = shading_hook_definitions({});
    for (const ShadingHookSpec& s : shading_hook_specs()) {
        SCOPED_TRACE(s.name);
        const std::string fn = std::string(s.rule == HookRule::sum ? "effect_add_" : "effect_") + s.name + "(";
        EXPECT_TRUE(contains(protos, fn));
        EXPECT_TRUE(contains(defs, fn));
        // A summed hook adds nothing; the others return their default.
        if (s.rule != HookRule::sum) EXPECT_TRUE(contains(defs, std::string(s.fallback))) << defs;
        EXPECT_EQ(&shading_hook_spec(s.hook), &s);
    }
    EXPECT_FALSE(contains(defs, "color +="));
}

TEST(ShadingHooks, ProvidersAreCalledInRegistryOrder) {
    const std::vector<const Effect*>& all = effect_registry();
    const std::string defs = shading_hook_definitions(all);
    // Each effect's hooks are called by their conventional name, once.
    for (const Effect* e : all)
        for (ShadingHook h : e->shading_hooks()) {
            const std::string call = std::string(e->name()) + "_" + shading_hook_spec(h).name + "(";
            EXPECT_TRUE(contains(defs, call)) << call;
            EXPECT_EQ(defs.find(call), defs.rfind(call)) << call;
        }
    // The summed indirect light adds the effects' terms in registry order.
    const Effect* gi = find_effect("gi");
    const Effect* rsm = find_effect("rsm");
    ASSERT_TRUE(gi && rsm);
    const auto gi_at = std::find(all.begin(), all.end(), gi), rsm_at = std::find(all.begin(), all.end(), rsm);
    EXPECT_EQ(defs.find("gi_indirect_light(") < defs.find("rsm_indirect_light("), gi_at < rsm_at);
}

TEST(ShadingHooks, AHookOfOneProviderRefusesTwo) {
    const Effect* reflections = find_effect("reflections");
    ASSERT_NE(reflections, nullptr);
    try {
        shading_hook_definitions({reflections, reflections});
        FAIL() << "two reflection sources accepted";
    } catch (const Error& e) {
        EXPECT_TRUE(contains(e.what(), "reflection_source")) << e.what();
    }
}

// The registry's effects without `left_out` (nullptr: all of them).
std::vector<const Effect*> registry_without(const Effect* left_out) {
    std::vector<const Effect*> out;
    for (const Effect* e : effect_registry())
        if (e != left_out) out.push_back(e);
    return out;
}

// Every program that includes the lighting code (and the forward variant with every define), with
// each effect taken out of the registry and with none left, compiles and links (glslang). Programs
// whose text is the same as one already checked are not checked again.
TEST(ShadingHooks, EveryLightingProgramBuildsWithAnyEffectTakenOut) {
    const ShaderLibrary plain(fs::path(CANDELA_SOURCE_DIR) / "shaders");
    const ShaderLibrary full = serve_effect_shading(plain);
    std::vector<ProgramDesc> lighting;
    for (const ProgramDesc& d : raster_programs())
        for (const auto& [stage, file] : d.stages)
            for (const fs::path& f : full.preprocess(file, d.defines).files)
                if (f.string() == "effects_shading.glsl (generated)" &&
                    std::none_of(lighting.begin(), lighting.end(), [&](const ProgramDesc& l) { return l.name == d.name; }))
                    lighting.push_back(d);
    ASSERT_GE(lighting.size(), 4u);  // forward and the three deferred lighting programs at least
    lighting.push_back(program_desc("forward#NO_PEELING,TILED_LIGHTS,NO_DEBUG_VIEW,REFLECTIONS_NO_REFRACTION,REFLECTIONS_NO_PROBES,"
                                    "AREA_LIGHTS_OFF,RSM_OFF,GI_OFF,NO_MATERIAL_TEXTURES"));

    std::vector<std::pair<std::string, std::vector<const Effect*>>> cases = {{"no effect", {}}};
    for (const Effect* e : effect_registry())
        if (e->shading_include() || !e->shading_hooks().empty()) cases.push_back({std::string("without ") + e->name(), registry_without(e)});
    ASSERT_GE(cases.size(), 7u);
    std::set<std::string> checked;
    for (const auto& [what, effects] : cases) {
        const ShaderLibrary lib = serve_effect_shading(plain, effects);
        for (const ProgramDesc& d : lighting)
            for (const auto& [stage, file] : d.stages) {
                const PreprocessedSource src = lib.preprocess(file, d.defines);
                if (!checked.insert(src.text).second) continue;
                EXPECT_EQ(validate_with_glslang(src, stage), "") << what << ": " << d.name << " " << file;
            }
    }
}

}  // namespace
}  // namespace candela
