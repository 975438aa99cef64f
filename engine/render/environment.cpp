#include "render/environment.hpp"

#include <algorithm>
#include <cmath>

#include "shader/program_catalog.hpp"

namespace candela {

int prefiltered_levels(int size) {
    int levels = 1;
    while ((size >> levels) >= 4) ++levels;
    return levels;
}

gl::Texture ImageBasedLighting::create_cube_array(int size, int cubes, int levels) {
    if (levels <= 0) levels = 1 + static_cast<int>(std::floor(std::log2(static_cast<double>(size))));
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

ImageBasedLighting::ImageBasedLighting(const ShaderLibrary& shaders) : shaders_(shaders) {
    lut_program_ = shaders.build_or_throw(program_desc("brdf_lut"));
    lut_ = gl::Texture::create_2d(GL_RG32F, kLutSize, kLutSize, 1);
    glTextureParameteri(lut_.id(), GL_TEXTURE_MIN_FILTER, GL_LINEAR);
    glTextureParameteri(lut_.id(), GL_TEXTURE_MAG_FILTER, GL_LINEAR);
    glTextureParameteri(lut_.id(), GL_TEXTURE_WRAP_S, GL_CLAMP_TO_EDGE);
    glTextureParameteri(lut_.id(), GL_TEXTURE_WRAP_T, GL_CLAMP_TO_EDGE);
    glUseProgram(lut_program_.id());
    glProgramUniform1i(lut_program_.id(), 0, kLutSize);
    glProgramUniform1i(lut_program_.id(), 1, kLutSamples);
    glBindImageTexture(0, lut_.id(), 0, GL_FALSE, 0, GL_WRITE_ONLY, GL_RG32F);
    glDispatchCompute((kLutSize + 7) / 8, (kLutSize + 7) / 8, 1);
    glMemoryBarrier(GL_TEXTURE_FETCH_BARRIER_BIT);
    glUseProgram(0);
    glFinish();
}

gl::Texture ImageBasedLighting::cube_from_equirect(const gl::Texture& equirect, int size, int samples) const {
    // Built on first use: scenes without an environment map never compile it.
    if (!to_cube_program_)
        to_cube_program_ = shaders_.build_or_throw(program_desc("equirect_to_cube"));
    const int levels = prefiltered_levels(size);
    gl::Texture source = create_cube_array(size, 1, 0);
    glUseProgram(to_cube_program_.id());
    glProgramUniform1i(to_cube_program_.id(), 0, size);
    glBindTextureUnit(0, equirect.id());
    glBindSampler(0, 0);
    glBindImageTexture(0, source.id(), 0, GL_TRUE, 0, GL_WRITE_ONLY, GL_RGBA32F);
    glDispatchCompute(static_cast<GLuint>((size + 7) / 8), static_cast<GLuint>((size + 7) / 8), 6);
    glMemoryBarrier(GL_TEXTURE_FETCH_BARRIER_BIT | GL_TEXTURE_UPDATE_BARRIER_BIT);
    glUseProgram(0);
    glGenerateTextureMipmap(source.id());
    gl::Texture cube = create_cube_array(size, 1, levels);
    prefilter(source, cube, size, levels, 1, samples);
    return cube;
}

void ImageBasedLighting::prefilter(const gl::Texture& source, const gl::Texture& dst, int size, int levels, int cubes,
                                   int samples) const {
    if (!prefilter_program_)
        prefilter_program_ = shaders_.build_or_throw(program_desc("prefilter"));
    const GLuint p = prefilter_program_.id();
    glUseProgram(p);
    glBindTextureUnit(0, source.id());
    glBindSampler(0, 0);
    glProgramUniform1i(p, 2, samples);
    glProgramUniform1i(p, 3, size);
    for (int level = 0; level < levels; ++level) {
        const int s = std::max(size >> level, 1);
        glProgramUniform1i(p, 0, s);
        glProgramUniform1f(p, 1, levels > 1 ? static_cast<float>(level) / static_cast<float>(levels - 1) : 0.0f);
        glBindImageTexture(0, dst.id(), level, GL_TRUE, 0, GL_WRITE_ONLY, GL_RGBA32F);
        glDispatchCompute(static_cast<GLuint>((s + 7) / 8), static_cast<GLuint>((s + 7) / 8), static_cast<GLuint>(6 * cubes));
    }
    glMemoryBarrier(GL_TEXTURE_FETCH_BARRIER_BIT);
    glUseProgram(0);
}

}  // namespace candela
