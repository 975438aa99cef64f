#include <gtest/gtest.h>

#include <filesystem>
#include <string>

#include "render/effect_registry.hpp"
#include "render/program_catalog.hpp"
#include "shader/shader_library.hpp"

namespace candela {
namespace {
namespace fs = std::filesystem;

// The forward program's specialised variants (render/passes/pass_env.hpp, forward_program_name)
// are not in the catalog's list that `shaders check` compiles: the variant with every base and
// effect define must still be valid GLSL, and program_desc must give it those defines.
const char* const kEffectLightingDefines = "REFLECTIONS_NO_REFRACTION,REFLECTIONS_NO_PROBES,AREA_LIGHTS_OFF,RSM_OFF,GI_OFF";

TEST(ForwardVariants, EverySpecialisationValidatesWithGlslang) {
    const std::string all = std::string("NO_PEELING,TILED_LIGHTS,NO_DEBUG_VIEW,") + kEffectLightingDefines + ",NO_MATERIAL_TEXTURES";
    const ProgramDesc& d = program_desc("forward#" + all);
    EXPECT_EQ(d.name, "forward#" + all);
    ASSERT_EQ(d.defines.size(), 9u);
    EXPECT_EQ(d.defines.front(), "NO_PEELING");
    EXPECT_EQ(d.defines.back(), "NO_MATERIAL_TEXTURES");
    EXPECT_EQ(&program_desc("forward#" + all), &d);  // built once, reference stays valid
    const ShaderLibrary lib = serve_effect_shading(ShaderLibrary(fs::path(CANDELA_SOURCE_DIR) / "shaders"));
    for (const auto& [stage, file] : d.stages) EXPECT_EQ(validate_with_glslang(lib.preprocess(file, d.defines), stage), "") << file;
    EXPECT_THROW(program_desc("no_such_program#GI_OFF"), std::exception);
}

// The deferred lighting programs take the same lighting defines (deferred_light_program_name),
// with every shadow filter mode: each combination must still compile.
TEST(ForwardVariants, DeferredSpecialisationsValidateWithGlslang) {
    const ShaderLibrary lib = serve_effect_shading(ShaderLibrary(fs::path(CANDELA_SOURCE_DIR) / "shaders"));
    for (const char* base : {"deferred_light", "deferred_light_ms", "deferred_light_ms_edges"})
        for (int mode = 0; mode <= 3; ++mode) {
            const std::string name =
                std::string(base) + "#NO_DEBUG_VIEW," + kEffectLightingDefines + ",SHADOW_FILTER_MODE " + std::to_string(mode);
            const ProgramDesc& d = program_desc(name);
            SCOPED_TRACE(name);
            EXPECT_EQ(d.defines.back(), "SHADOW_FILTER_MODE " + std::to_string(mode));
            for (const auto& [stage, file] : d.stages)
                EXPECT_EQ(validate_with_glslang(lib.preprocess(file, d.defines), stage), "") << file;
        }
}

}  // namespace
}  // namespace candela
