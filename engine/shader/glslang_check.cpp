// Offline GLSL validation with glslang: the same sources the engine compiles, checked (compiled
// and each stage linked) without a GL context (tests validate every shader this way; the GL driver's own compile still decides).
#include <glslang/Public/ResourceLimits.h>
#include <glslang/Public/ShaderLang.h>

#include <mutex>

#include "shader/shader_library.hpp"

namespace candela {

std::string validate_with_glslang(const PreprocessedSource& source, ShaderStage stage) {
    static std::once_flag init;
    std::call_once(init, [] { glslang::InitializeProcess(); });
    const EShLanguage lang = stage == ShaderStage::vertex ? EShLangVertex
                             : stage == ShaderStage::fragment ? EShLangFragment
                                                              : EShLangCompute;
    glslang::TShader shader(lang);
    const char* text = source.text.c_str();
    shader.setStrings(&text, 1);
    shader.setEnvInput(glslang::EShSourceGlsl, lang, glslang::EShClientOpenGL, 450);
    shader.setEnvClient(glslang::EShClientOpenGL, glslang::EShTargetOpenGL_450);
    const auto messages = static_cast<EShMessages>(EShMsgDefault);
    if (!shader.parse(GetDefaultResources(), 450, ECoreProfile, false, false, messages)) return source.map_log(shader.getInfoLog());
    // The stage linked on its own: a function declared and called but never defined (a shading
    // hook without its definition) is a link error, not a compile error.
    glslang::TProgram program;
    program.addShader(&shader);
    if (program.link(messages)) return {};
    return source.map_log(program.getInfoLog());
}

}  // namespace candela
