#pragma once
// Image-based lighting built at start-up (Karis 2013, "Real Shading in Unreal Engine 4"): the
// split-sum BRDF LUT, and the static environment map as a cube map whose mip levels are
// GGX-prefiltered for rising roughness. The same prefilter turns captured reflection probes
// into rough reflections (an effect's probes).
#include <cstdint>
#include <optional>

#include "core/derived_cache.hpp"
#include "gl/handles.hpp"
#include "image/image.hpp"
#include "shader/shader_library.hpp"

namespace candela {

// Mip levels of a prefiltered cube of face size `size`: down to 4x4 faces (roughness 1 there).
int prefiltered_levels(int size);

// Levels 1.. of an RGBA32F texture (GL_TEXTURE_2D, or GL_TEXTURE_CUBE_MAP_ARRAY with `layers` =
// 6 x cubes) whose level 0 is filled: the texels glGenerateTextureMipmap makes, by a compute
// shader when both sides are powers of two (shaders/env/mip_halve.comp), else by
// glGenerateTextureMipmap itself. The point is time: on llvmpipe glGenerateTextureMipmap
// compiles a blit shader per format and target every run (about 0.1 s each, not in Mesa's disk
// cache), where this program comes from the cache. tests/unit/test_gl_worker.cpp compares every
// level bit for bit with glGenerateTextureMipmap's.
class FloatMipmaps {
public:
    explicit FloatMipmaps(const ShaderLibrary& shaders) : shaders_(shaders) {}
    // `levels` <= 0: the full chain. Throws candela::Error (internal) if the program does not build.
    void generate(const gl::Texture& texture, GLenum target, int width, int height, int layers, int levels) const;

private:
    const ShaderLibrary& shaders_;
    mutable gl::Program halve_2d_, halve_cube_;  // built on first use
};

class ImageBasedLighting {
public:
    // Builds the LUT; throws candela::Error (internal) if a shader does not build. `cache`: where
    // cube_from_equirect keeps prefiltered cubes between runs (core/derived_cache.hpp).
    explicit ImageBasedLighting(const ShaderLibrary& shaders, DerivedCache cache = DerivedCache());

    // size x size RG32F: x = NdotV, y = roughness, texel i at i / (size - 1); r = A, g = B.
    const gl::Texture& brdf_lut() const { return lut_; }
    static constexpr int kLutSize = 32;
    static constexpr int kLutSamples = 1024;

    // A cube-map array (1 cube) with prefiltered_levels(size) levels from an equirectangular
    // map (a texture with a full mip chain), prefiltered with `samples` GGX samples per texel.
    // `texels`: the map's level 0 as uploaded; with it the cube is looked up in the cache, by a
    // key over the texels, the map's filter and wrap modes, the sizes, the sources of the programs
    // that make the cube and the GL driver, and stored there when computed. The cached cube is
    // the computed one, bit for bit.
    gl::Texture cube_from_equirect(const gl::Texture& equirect, const ImageF* texels, int size, int samples) const;
    // Whether the last cube_from_equirect came from the cache.
    bool last_cube_cached() const { return last_cube_cached_; }
    // Fills levels 1.. of `dst` (a cube-map array with `cubes` cubes and `levels` levels) from
    // `source` (same size, a full mip chain whose level 0 is the capture); level 0 is copied.
    void prefilter(const gl::Texture& source, const gl::Texture& dst, int size, int levels, int cubes, int samples) const;
    const FloatMipmaps& float_mipmaps() const { return mips_; }
    // An RGBA32F cube-map array of `cubes` cubes, `levels` levels (0: full chain), linear filtering.
    static gl::Texture create_cube_array(int size, int cubes, int levels);

private:
    std::uint64_t cube_key(const gl::Texture& equirect, const ImageF& texels, int size, int samples, int levels) const;
    const ShaderLibrary& shaders_;
    DerivedCache cache_;
    mutable bool last_cube_cached_ = false;
    gl::Program lut_program_;
    mutable gl::Program to_cube_program_, prefilter_program_;  // built on first use
    FloatMipmaps mips_;
    gl::Texture lut_;
};

}  // namespace candela
