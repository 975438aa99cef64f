// Every shader compiles as GLSL 4.50 core under glslang (no GL needed), and the include machinery
// maps messages back to the right file and line.
#include <gtest/gtest.h>

#include <fstream>

#include "core/error.hpp"
#include "gltf_builder.hpp"
#include "render/effect_registry.hpp"
#include "shader/shader_library.hpp"

namespace candela {
namespace {
namespace fs = std::filesystem;

std::optional<ShaderStage> stage_of(const fs::path& p) {
    const auto e = p.extension();
    if (e == ".vert") return ShaderStage::vertex;
    if (e == ".frag") return ShaderStage::fragment;
    if (e == ".comp") return ShaderStage::compute;
    return std::nullopt;
}

TEST(Shaders, EveryStageValidatesWithGlslang) {
    const ShaderLibrary lib = serve_effect_shading(ShaderLibrary(fs::path(CANDELA_SOURCE_DIR) / "shaders"));
    int checked = 0;
    for (const auto& entry : fs::recursive_directory_iterator(lib.root())) {
        const auto stage = stage_of(entry.path());
        if (!stage) continue;
        SCOPED_TRACE(entry.path().string());
        const PreprocessedSource src = lib.preprocess(entry.path(), {});
        EXPECT_EQ(validate_with_glslang(src, *stage), "");
        ++checked;
    }
    EXPECT_GE(checked, 4);
}

class ShaderIncludes : public ::testing::Test {
protected:
    void SetUp() override {
        dir_ = test::test_dir("shader_includes");
        fs::create_directories(dir_ / "common");
        write("common/good.glsl", "float good() { return 1.0; }\n");
        write("common/bad.glsl", "float ok() { return 1.0; }\nfloat bad() { return undefined_name; }\n");
        write("uses_bad.frag",
              "#version 450 core\n#include \"common/good.glsl\"\n#include \"common/bad.glsl\"\n"
              "out vec4 c;\nvoid main() { c = vec4(good()); }\n");
        write("a.glsl", "#include \"b.glsl\"\n");
        write("b.glsl", "#include \"a.glsl\"\n");
        write("cycle.frag", "#version 450 core\n#include \"a.glsl\"\nvoid main() {}\n");
        write("missing.frag", "#version 450 core\n\n#include \"nope.glsl\"\nvoid main() {}\n");
        write("twice.frag", "#version 450 core\n#include \"common/good.glsl\"\n#include \"common/good.glsl\"\n"
                            "out vec4 c;\nvoid main() { c = vec4(good()); }\n");
    }
    void write(const std::string& name, const std::string& text) { std::ofstream(dir_ / name) << text; }
    fs::path dir_;
};

TEST_F(ShaderIncludes, ErrorsMapToTheIncludedFileAndLine) {
    const ShaderLibrary lib(dir_);
    const PreprocessedSource src = lib.preprocess("uses_bad.frag", {"FOO 1"});
    const std::string log = validate_with_glslang(src, ShaderStage::fragment);
    EXPECT_NE(log.find("bad.glsl:2:"), std::string::npos) << log;
    EXPECT_NE(src.text.find("#define FOO 1"), std::string::npos);
}

TEST_F(ShaderIncludes, EachFileIsIncludedOnce) {
    const ShaderLibrary lib(dir_);
    const PreprocessedSource src = lib.preprocess("twice.frag", {});
    EXPECT_EQ(validate_with_glslang(src, ShaderStage::fragment), "");
}

TEST_F(ShaderIncludes, CycleAndMissingIncludeAreReported) {
    const ShaderLibrary lib(dir_);
    try {
        lib.preprocess("cycle.frag", {});
        ADD_FAILURE() << "cycle not detected";
    } catch (const Error& e) {
        EXPECT_NE(std::string(e.what()).find("cycle"), std::string::npos);
    }
    try {
        lib.preprocess("missing.frag", {});
        ADD_FAILURE() << "missing include not detected";
    } catch (const Error& e) {
        EXPECT_NE(std::string(e.what()).find("missing.frag:3: cannot find include \"nope.glsl\""), std::string::npos) << e.what();
    }
}

// A generated include stands for the files it was given, in that order (the effects' shading
// code: "effects_shading.glsl"), and an error in one of them still names that file.
TEST_F(ShaderIncludes, GeneratedIncludeExpandsItsFilesInOrder) {
    write("common/first.glsl", "float first() { return 1.0; }\n");
    write("uses_generated.frag", "#version 450 core\n#include \"listed.glsl\"\nout vec4 c;\nvoid main() { c = vec4(first() + good()); }\n");
    ShaderLibrary lib(dir_);
    lib.set_generated_include("listed.glsl", {"common/first.glsl", "common/good.glsl"});
    const PreprocessedSource src = lib.preprocess("uses_generated.frag", {});
    EXPECT_EQ(validate_with_glslang(src, ShaderStage::fragment), "");
    ASSERT_NE(src.text.find("float first()"), std::string::npos);
    EXPECT_LT(src.text.find("float first()"), src.text.find("float good()"));
    lib.set_generated_include("listed.glsl", {"common/first.glsl", "common/bad.glsl"});
    const std::string log = validate_with_glslang(lib.preprocess("uses_generated.frag", {}), ShaderStage::fragment);
    EXPECT_NE(log.find("bad.glsl:2:"), std::string::npos) << log;
}

// The effects' shading include is served where it is asked for (serve_effect_shading, as the
// renderer's program cache does), and nowhere else: no library is changed behind its back.
TEST(Shaders, TheLightingIncludeOfTheEffectsIsGenerated) {
    const ShaderLibrary plain(fs::path(CANDELA_SOURCE_DIR) / "shaders");
    EXPECT_THROW(plain.preprocess("forward/forward.frag", {}), Error);
    const ShaderLibrary lib = serve_effect_shading(plain);
    const PreprocessedSource src = lib.preprocess("forward/forward.frag", {});
    bool ssao = false;
    for (const fs::path& f : src.files) ssao = ssao || f.filename() == "ssao_shading.glsl";
    EXPECT_TRUE(ssao);
}

}  // namespace
}  // namespace candela
