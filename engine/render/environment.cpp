#include "render/environment.hpp"

#include <algorithm>
#include <cmath>

#include "gpu/bindings.h"
#include "render/program_catalog.hpp"

namespace candela {

int prefiltered_levels(int size) {
    int levels = 1;
    while ((size >> levels) >= 4) ++levels;
    return levels;
}

gl::Texture ImageBasedLighting::create_cube_array(int size, int cubes, int levels) {
    if (levels <= 0) levels = gl::full_mip_levels(size, size);
    GLuint id = 0;
    glCreateTextures(GL_TEXTURE_CUBE_MAP_ARRAY, 1, &id);
    glTextureStorage3D(id, levels, GL_RGBA32F, size, size, 6 * cubes);
    glTextureParameteri(id, GL_TEXTURE_MIN_FILTER, levels > 1 ? GL_LINEAR_MIPMAP_LINEAR : GL_LINEAR);
    glTextureParameteri(id, GL_TEXTURE_MAG_FILTER, GL_LINEAR);
    glTextureParameteri(id, GL_TEXTURE_WRAP_S, GL_CLAMP_TO_EDGE);
    glTextureParameteri(id, GL_TEXTURE_WRAP_T, GL_CLAMP_TO_EDGE);
    glTextureParameteri(id, GL_TEXTURE_MAX_LEVEL, levels - 1);
    return gl::Texture::adopt(id, size, size, GL_RGBA32F);
}

ImageBasedLighting::ImageBasedLighting(const ShaderLibrary& shaders, DerivedCache cache)
    : shaders_(shaders), cache_(std::move(cache)), mips_(shaders) {
    lut_program_ = shaders.build_or_throw(program_desc("brdf_lut"));
    lut_ = gl::Texture::create_2d(GL_RG32F, kLutSize, kLutSize, 1);
    glTextureParameteri(lut_.id(), GL_TEXTURE_MIN_FILTER, GL_LINEAR);
    glTextureParameteri(lut_.id(), GL_TEXTURE_MAG_FILTER, GL_LINEAR);
    glTextureParameteri(lut_.id(), GL_TEXTURE_WRAP_S, GL_CLAMP_TO_EDGE);
    glTextureParameteri(lut_.id(), GL_TEXTURE_WRAP_T, GL_CLAMP_TO_EDGE);
    glUseProgram(lut_program_.id());
    glProgramUniform1i(lut_program_.id(), 0, kLutSize);
    glProgramUniform1i(lut_program_.id(), 1, kLutSamples);
    glBindImageTexture(DST_IMAGE, lut_.id(), 0, GL_FALSE, 0, GL_WRITE_ONLY, GL_RG32F);
    glDispatchCompute((kLutSize + 7) / 8, (kLutSize + 7) / 8, 1);
    glMemoryBarrier(GL_TEXTURE_FETCH_BARRIER_BIT);
    glUseProgram(0);
    glFinish();
}

namespace {
// Bump when cube_from_equirect's procedure changes in C++ (the shaders' sources are in the key).
constexpr int kCubeCacheVersion = 1;

// Bytes of one level of an RGBA32F cube of face size `size`, and of `levels` levels.
std::size_t cube_level_bytes(int size, int level) {
    const std::size_t s = static_cast<std::size_t>(std::max(size >> level, 1));
    return s * s * 6 * 4 * sizeof(float);
}
std::size_t cube_bytes(int size, int levels) {
    std::size_t n = 0;
    for (int level = 0; level < levels; ++level) n += cube_level_bytes(size, level);
    return n;
}
}  // namespace

std::uint64_t ImageBasedLighting::cube_key(const gl::Texture& equirect, const ImageF& texels, int size, int samples, int levels) const {
    Hasher h;
    h.text("environment cube").integer(kCubeCacheVersion).integer(size).integer(samples).integer(levels);
    // How the conversion samples the map (its own parameters: the program binds no sampler).
    for (const GLenum param : {GL_TEXTURE_MIN_FILTER, GL_TEXTURE_MAG_FILTER, GL_TEXTURE_WRAP_S, GL_TEXTURE_WRAP_T, GL_TEXTURE_IMMUTABLE_LEVELS}) {
        GLint value = 0;
        glGetTextureParameteriv(equirect.id(), param, &value);
        h.integer(value);
    }
    for (const GLenum name : {GL_VENDOR, GL_RENDERER, GL_VERSION})
        if (const auto* s = reinterpret_cast<const char*>(glGetString(name))) h.text(s);
    // Every program whose output reaches the cube: the map's own mipmaps (gpu_scene.cpp), the
    // conversion to a cube, the cube's mipmaps and the prefilter, as compiled (after #include).
    for (const char* program : {"mip_halve_2d", "equirect_to_cube", "mip_halve_cube_array", "prefilter"}) {
        const ProgramDesc& d = program_desc(program);
        for (const auto& [stage, file] : d.stages) h.text(shaders_.preprocess(file, d.defines).text);
    }
    h.integer(texels.width).integer(texels.height).integer(texels.channels);
    h.bytes(texels.pixels.data(), texels.pixels.size() * sizeof(float));
    return h.value();
}

gl::Texture ImageBasedLighting::cube_from_equirect(const gl::Texture& equirect, const ImageF* texels, int size, int samples) const {
    const int levels = prefiltered_levels(size);
    const std::size_t bytes = cube_bytes(size, levels);
    const bool cached = texels != nullptr;
    const std::uint64_t key = cached ? cube_key(equirect, *texels, size, samples, levels) : 0;
    last_cube_cached_ = false;
    if (cached)
        if (const auto data = cache_.load("envcube", key, bytes)) {
            gl::Texture cube = create_cube_array(size, 1, levels);
            std::size_t at = 0;
            for (int level = 0; level < levels; ++level) {
                const int s = std::max(size >> level, 1);
                glTextureSubImage3D(cube.id(), level, 0, 0, 0, s, s, 6, GL_RGBA, GL_FLOAT, data->data() + at);
                at += cube_level_bytes(size, level);
            }
            last_cube_cached_ = true;
            return cube;
        }
    // Built on first use: scenes without an environment map never compile it.
    if (!to_cube_program_)
        to_cube_program_ = shaders_.build_or_throw(program_desc("equirect_to_cube"));
    gl::Texture source = create_cube_array(size, 1, 0);
    glUseProgram(to_cube_program_.id());
    glProgramUniform1i(to_cube_program_.id(), 0, size);
    gl::bind_texture_unit(SOURCE_UNIT, equirect);
    glBindImageTexture(DST_IMAGE, source.id(), 0, GL_TRUE, 0, GL_WRITE_ONLY, GL_RGBA32F);
    glDispatchCompute(static_cast<GLuint>((size + 7) / 8), static_cast<GLuint>((size + 7) / 8), 6);
    glMemoryBarrier(GL_TEXTURE_FETCH_BARRIER_BIT | GL_TEXTURE_UPDATE_BARRIER_BIT);
    glUseProgram(0);
    mips_.generate(source, GL_TEXTURE_CUBE_MAP_ARRAY, size, size, 6, 0);
    gl::Texture cube = create_cube_array(size, 1, levels);
    prefilter(source, cube, size, levels, 1, samples);
    if (cached) {
        std::vector<std::uint8_t> data(bytes);
        std::size_t at = 0;
        for (int level = 0; level < levels; ++level) {
            const std::size_t n = cube_level_bytes(size, level);
            glGetTextureImage(cube.id(), level, GL_RGBA, GL_FLOAT, static_cast<GLsizei>(n), data.data() + at);
            at += n;
        }
        cache_.store("envcube", key, data);
    }
    return cube;
}

void FloatMipmaps::generate(const gl::Texture& texture, GLenum target, int width, int height, int layers, int levels) const {
    if (levels <= 0) levels = gl::full_mip_levels(width, height);
    const auto pot = [](int v) { return v > 0 && (v & (v - 1)) == 0; };
    const bool cube = target == GL_TEXTURE_CUBE_MAP_ARRAY;
    if (!pot(width) || !pot(height) || (!cube && target != GL_TEXTURE_2D)) {
        glGenerateTextureMipmap(texture.id());
        return;
    }
    // Level 0 may have just been written by a shader's imageStore (equirect_to_cube).
    glMemoryBarrier(GL_SHADER_IMAGE_ACCESS_BARRIER_BIT);
    gl::Program& program = cube ? halve_cube_ : halve_2d_;
    if (!program) program = shaders_.build_or_throw(program_desc(cube ? "mip_halve_cube_array" : "mip_halve_2d"));
    glUseProgram(program.id());
    int w = width, h = height;
    for (int level = 1; level < levels; ++level) {
        const int nw = std::max(w / 2, 1), nh = std::max(h / 2, 1);
        glProgramUniform2i(program.id(), 0, w, h);
        glProgramUniform2i(program.id(), 1, nw, nh);
        glBindImageTexture(MIP_SRC_IMAGE, texture.id(), level - 1, cube ? GL_TRUE : GL_FALSE, 0, GL_READ_ONLY, GL_RGBA32F);
        glBindImageTexture(MIP_DST_IMAGE, texture.id(), level, cube ? GL_TRUE : GL_FALSE, 0, GL_WRITE_ONLY, GL_RGBA32F);
        glDispatchCompute(static_cast<GLuint>((nw + 7) / 8), static_cast<GLuint>((nh + 7) / 8), static_cast<GLuint>(cube ? layers : 1));
        glMemoryBarrier(GL_SHADER_IMAGE_ACCESS_BARRIER_BIT);
        w = nw;
        h = nh;
    }
    glMemoryBarrier(GL_TEXTURE_FETCH_BARRIER_BIT | GL_TEXTURE_UPDATE_BARRIER_BIT);
    glBindImageTexture(MIP_SRC_IMAGE, 0, 0, GL_FALSE, 0, GL_READ_ONLY, GL_RGBA32F);
    glBindImageTexture(MIP_DST_IMAGE, 0, 0, GL_FALSE, 0, GL_WRITE_ONLY, GL_RGBA32F);
    glUseProgram(0);
}

void ImageBasedLighting::prefilter(const gl::Texture& source, const gl::Texture& dst, int size, int levels, int cubes,
                                   int samples) const {
    if (!prefilter_program_)
        prefilter_program_ = shaders_.build_or_throw(program_desc("prefilter"));
    const GLuint p = prefilter_program_.id();
    glUseProgram(p);
    gl::bind_texture_unit(SOURCE_UNIT, source);
    glProgramUniform1i(p, 2, samples);
    glProgramUniform1i(p, 3, size);
    for (int level = 0; level < levels; ++level) {
        const int s = std::max(size >> level, 1);
        glProgramUniform1i(p, 0, s);
        glProgramUniform1f(p, 1, levels > 1 ? static_cast<float>(level) / static_cast<float>(levels - 1) : 0.0f);
        glBindImageTexture(DST_IMAGE, dst.id(), level, GL_TRUE, 0, GL_WRITE_ONLY, GL_RGBA32F);
        glDispatchCompute(static_cast<GLuint>((s + 7) / 8), static_cast<GLuint>((s + 7) / 8), static_cast<GLuint>(6 * cubes));
    }
    glMemoryBarrier(GL_TEXTURE_FETCH_BARRIER_BIT);
    glUseProgram(0);
}

}  // namespace candela
