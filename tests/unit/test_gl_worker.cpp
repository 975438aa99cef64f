// Texture mipmaps on a worker context: platform/gl_worker.hpp, gl/mipmaps.hpp and
// GpuScene's prefetch. The promise is that the images are the same as without the worker, so
// the tests compare bytes: drawn mipmaps against glGenerateTextureMipmap level by level, and
// renders of textured Khronos models with and without the worker.
#include <gtest/gtest.h>

#include <algorithm>
#include <atomic>
#include <chrono>
#include <cmath>
#include <cstring>
#include <cstdint>
#include <filesystem>
#include <random>
#include <stdexcept>
#include <thread>
#include <vector>

#include "core/error.hpp"
#include "gl/handles.hpp"
#include "gl/mipmaps.hpp"
#include "gl_fixture.hpp"
#include "platform/gl_worker.hpp"
#include "render/environment.hpp"
#include "render/still.hpp"
#include "scene/gltf_loader.hpp"
#include "scene/lighting.hpp"
#include "render/program_catalog.hpp"

namespace candela {
namespace {
namespace fs = std::filesystem;

using GlWorkerTest = test::GlContextTest;

// Counted independently of gl::full_mip_levels, which the code under test uses.
int full_levels(int w, int h) {
    int levels = 1;
    while ((std::max(w, h) >> levels) > 0) ++levels;
    return levels;
}

std::vector<std::uint8_t> level_bytes(GLuint tex, int level, int w, int h) {
    std::vector<std::uint8_t> out(static_cast<size_t>(std::max(w >> level, 1) * std::max(h >> level, 1) * 4));
    glGetTextureImage(tex, level, GL_RGBA, GL_UNSIGNED_BYTE, static_cast<GLsizei>(out.size()), out.data());
    return out;
}

// Every level of draw_mipmaps equals glGenerateTextureMipmap's, byte for byte: linear and sRGB,
// power-of-two, non-power-of-two, odd and one-texel-wide sizes, random texels (so any filter
// weight or rounding difference shows). It can fail: with texture coordinates computed from
// gl_FragCoord instead of interpolated over the blitter's rectangle, three sRGB sizes differ.
TEST_P(GlWorkerTest, DrawMipmapsEqualGenerateMipmap) {
    const ShaderLibrary shaders(ShaderLibrary::default_root());
    const gl::Program program = shaders.build_or_throw(program_desc("mip_downsample"));
    // The caller's bindings, which draw_mipmaps restores.
    const gl::VertexArray vao = gl::VertexArray::create();
    const gl::Texture bound = gl::Texture::create_2d(GL_RGBA8, 4, 4, 1);
    glBindVertexArray(vao.id());
    glBindTextureUnit(0, bound.id());
    glViewport(1, 2, 3, 4);
    std::mt19937 rng(23);
    const int sizes[][2] = {{64, 64}, {256, 128}, {100, 60}, {333, 17}, {1, 7}, {5, 1}, {128, 96}};
    for (const bool srgb : {false, true})
        for (const auto& size : sizes) {
            const int w = size[0], h = size[1], levels = full_levels(w, h);
            std::vector<std::uint8_t> texels(static_cast<size_t>(w * h * 4));
            for (auto& t : texels) t = static_cast<std::uint8_t>(rng() & 0xff);
            const GLenum format = srgb ? GL_SRGB8_ALPHA8 : GL_RGBA8;
            gl::Texture a = gl::Texture::create_2d(format, w, h, levels);
            gl::Texture b = gl::Texture::create_2d(format, w, h, levels);
            glTextureSubImage2D(a.id(), 0, 0, 0, w, h, GL_RGBA, GL_UNSIGNED_BYTE, texels.data());
            glTextureSubImage2D(b.id(), 0, 0, 0, w, h, GL_RGBA, GL_UNSIGNED_BYTE, texels.data());
            glGenerateTextureMipmap(a.id());
            gl::draw_mipmaps(program.id(), b.id(), format, w, h, levels);
            int differing_levels = 0;
            for (int level = 1; level < levels; ++level)
                if (level_bytes(a.id(), level, w, h) != level_bytes(b.id(), level, w, h)) ++differing_levels;
            EXPECT_EQ(differing_levels, 0) << (srgb ? "sRGB " : "linear ") << w << "x" << h << ", " << levels << " levels";
            // The mipmaps were made: level 1 is not what an untouched level holds.
            const std::vector<std::uint8_t> l1 = level_bytes(b.id(), 1, w, h);
            EXPECT_TRUE(std::any_of(l1.begin(), l1.end(), [](std::uint8_t v) { return v != 0; })) << w << "x" << h;
        }
    EXPECT_FALSE(glIsEnabled(GL_FRAMEBUFFER_SRGB)) << "draw_mipmaps left GL_FRAMEBUFFER_SRGB on";
    GLint binding = 0, viewport[4] = {0, 0, 0, 0};
    glGetIntegerv(GL_VERTEX_ARRAY_BINDING, &binding);
    EXPECT_EQ(static_cast<GLuint>(binding), vao.id());
    glGetIntegerv(GL_TEXTURE_BINDING_2D, &binding);
    EXPECT_EQ(static_cast<GLuint>(binding), bound.id());
    glGetIntegerv(GL_CURRENT_PROGRAM, &binding);
    EXPECT_EQ(binding, 0);
    glGetIntegerv(GL_DRAW_FRAMEBUFFER_BINDING, &binding);
    EXPECT_EQ(binding, 0);
    glGetIntegerv(GL_VIEWPORT, viewport);
    EXPECT_EQ(viewport[2], 3);
    EXPECT_EQ(viewport[3], 4);
    glBindVertexArray(0);
    glBindTextureUnit(0, 0);
}

std::vector<float> float_level(GLuint tex, int level, size_t count) {
    std::vector<float> out(count);
    glGetTextureImage(tex, level, GL_RGBA, GL_FLOAT, static_cast<GLsizei>(out.size() * sizeof(float)), out.data());
    return out;
}

// FloatMipmaps (the environment map's and the reflection cube's mipmaps by a
// compute shader) against glGenerateTextureMipmap, bit for bit on every level: 2D and cube-map
// arrays of power-of-two sizes, random radiance over nine decades, one or two cubes. Sizes
// that are not powers of two take glGenerateTextureMipmap itself (checked too).
TEST_P(GlWorkerTest, FloatMipmapsEqualGenerateMipmap) {
    const ShaderLibrary shaders(ShaderLibrary::default_root());
    const FloatMipmaps mips(shaders);
    std::mt19937 rng(7);
    std::uniform_real_distribution<float> exponent(-6.0f, 3.0f), mantissa(1.0f, 10.0f);
    const auto random_texels = [&](size_t n) {
        std::vector<float> v(n);
        for (size_t i = 0; i < n; ++i) v[i] = (i % 4 == 3) ? 1.0f : mantissa(rng) * std::pow(10.0f, exponent(rng));
        return v;
    };
    struct Case { GLenum target; int w, h, layers; };
    const Case cases[] = {{GL_TEXTURE_2D, 256, 128, 1}, {GL_TEXTURE_2D, 64, 64, 1}, {GL_TEXTURE_2D, 8, 2, 1},
                          {GL_TEXTURE_2D, 1, 4, 1},     {GL_TEXTURE_2D, 96, 48, 1}, {GL_TEXTURE_CUBE_MAP_ARRAY, 128, 128, 6},
                          {GL_TEXTURE_CUBE_MAP_ARRAY, 16, 16, 12}};
    for (const Case& c : cases) {
        const int levels = full_levels(c.w, c.h);
        const std::vector<float> texels = random_texels(static_cast<size_t>(c.w * c.h * 4 * c.layers));
        const auto make = [&] {
            if (c.target == GL_TEXTURE_2D) {
                gl::Texture t = gl::Texture::create_2d(GL_RGBA32F, c.w, c.h, levels);
                glTextureSubImage2D(t.id(), 0, 0, 0, c.w, c.h, GL_RGBA, GL_FLOAT, texels.data());
                return t;
            }
            gl::Texture t = ImageBasedLighting::create_cube_array(c.w, c.layers / 6, 0);
            glTextureSubImage3D(t.id(), 0, 0, 0, 0, c.w, c.h, c.layers, GL_RGBA, GL_FLOAT, texels.data());
            return t;
        };
        gl::Texture a = make(), b = make();
        glGenerateTextureMipmap(a.id());
        mips.generate(b, c.target, c.w, c.h, c.layers, levels);
        glFinish();
        for (int level = 1; level < levels; ++level) {
            const size_t n = static_cast<size_t>(std::max(c.w >> level, 1) * std::max(c.h >> level, 1) * 4 * c.layers);
            const std::vector<float> fa = float_level(a.id(), level, n), fb = float_level(b.id(), level, n);
            size_t differing = 0;
            for (size_t i = 0; i < n; ++i) differing += std::memcmp(&fa[i], &fb[i], sizeof(float)) != 0;
            EXPECT_EQ(differing, 0u) << c.w << "x" << c.h << "x" << c.layers << " level " << level;
        }
    }
}

// The worker runs jobs in its own context, after what the main context issued before submit(),
// and passes a job's exception to wait().
TEST_P(GlWorkerTest, JobsSeeTheMainContextsUploadsAndReportErrors) {
    GlWorker worker(context_->create_shared());
    ASSERT_TRUE(worker.running()) << "the backend made no shared context";
    const ShaderLibrary shaders(ShaderLibrary::default_root());
    const gl::Program program = shaders.build_or_throw(program_desc("mip_downsample"));
    const int w = 64, h = 32, levels = full_levels(w, h);
    std::vector<std::uint8_t> texels(static_cast<size_t>(w * h * 4));
    for (size_t i = 0; i < texels.size(); ++i) texels[i] = static_cast<std::uint8_t>((i * 37) & 0xff);
    gl::Texture mine = gl::Texture::create_2d(GL_SRGB8_ALPHA8, w, h, levels);
    gl::Texture theirs = gl::Texture::create_2d(GL_SRGB8_ALPHA8, w, h, levels);
    glTextureSubImage2D(mine.id(), 0, 0, 0, w, h, GL_RGBA, GL_UNSIGNED_BYTE, texels.data());
    glTextureSubImage2D(theirs.id(), 0, 0, 0, w, h, GL_RGBA, GL_UNSIGNED_BYTE, texels.data());
    std::atomic<bool> other_thread{false};
    const std::thread::id main_thread = std::this_thread::get_id();
    GlWorker::Ticket t = worker.submit([&] {
        other_thread = std::this_thread::get_id() != main_thread;
        gl::draw_mipmaps(program.id(), theirs.id(), GL_SRGB8_ALPHA8, w, h, levels);
    });
    glGenerateTextureMipmap(mine.id());
    GlWorker::wait(t);
    EXPECT_TRUE(other_thread.load());
    for (int level = 1; level < levels; ++level)
        EXPECT_EQ(level_bytes(mine.id(), level, w, h), level_bytes(theirs.id(), level, w, h)) << "level " << level;

    GlWorker::Ticket failing = worker.submit([] { throw std::runtime_error("job failed"); });
    EXPECT_THROW(GlWorker::wait(failing), std::runtime_error);
    // A GL error in a job (the worker's context has no debug callback) is an exception too.
    GlWorker::Ticket gl_error = worker.submit([] { glBindTexture(GL_TEXTURE_2D, 0x7fffffff); });  // not a texture name
    try {
        GlWorker::wait(gl_error);
        ADD_FAILURE() << "a GL error in a job went unreported";
    } catch (const Error& e) {
        EXPECT_EQ(e.code(), ExitCode::internal);
        EXPECT_NE(std::string(e.what()).find("GL error 0x0502"), std::string::npos) << e.what();
    }
    // The worker goes on after a failed job.
    std::atomic<int> ran{0};
    GlWorker::wait(worker.submit([&] { ++ran; }));
    EXPECT_EQ(ran.load(), 1);
}

// Destroying the worker with jobs queued runs them first (a GpuScene's textures must not be
// deleted under a job: GpuScene waits for its own, the worker for any left).
TEST_P(GlWorkerTest, DestructionFinishesQueuedJobs) {
    std::atomic<int> ran{0};
    std::vector<GlWorker::Ticket> tickets;
    {
        GlWorker worker(context_->create_shared());
        ASSERT_TRUE(worker.running());
        for (int i = 0; i < 8; ++i)
            tickets.push_back(worker.submit([&] {
                std::this_thread::sleep_for(std::chrono::milliseconds(2));
                ++ran;
            }));
    }
    EXPECT_EQ(ran.load(), 8);
    for (const auto& t : tickets) EXPECT_NO_THROW(GlWorker::wait(t));
}

// Without a shared context (a backend that has none) jobs run on the calling thread.
TEST_P(GlWorkerTest, NoSharedContextRunsJobsInline) {
    GlWorker worker(nullptr);
    EXPECT_FALSE(worker.running());
    const std::thread::id main_thread = std::this_thread::get_id();
    bool same_thread = false;
    GlWorker::wait(worker.submit([&] { same_thread = std::this_thread::get_id() == main_thread; }));
    EXPECT_TRUE(same_thread);
}

// Whole renders of textured Khronos models (tests/data/models): with the worker making the
// mipmaps, the linear radiance is bit-identical to the main thread making them; and the
// textures matter (a render with the textures replaced by white differs), so equal images are
// not equal for want of texturing.
TEST_P(GlWorkerTest, RendersAreIdenticalWithAndWithoutTheWorker) {
    const ShaderLibrary shaders(ShaderLibrary::default_root());
    for (const char* model : {"BoxTextured/BoxTextured.gltf", "TextureTransformTest/TextureTransformTest.gltf"}) {
        Scene scene = load_gltf(fs::path(CANDELA_SOURCE_DIR) / "tests/data/models" / model);
        StillOptions o;
        o.width = 160;
        o.height = 120;
        // As `candela render` lights a file without lights: the default rig, with its sky (an
        // environment map, whose mipmaps stay on the main thread).
        apply_lighting(scene, LightingMode::auto_select, scene.select_camera("", 160.0f / 120.0f));
        const StillResult main_thread = render_still(scene, shaders, o);
        GlWorker worker(context_->create_shared());
        ASSERT_TRUE(worker.running());
        o.mip_worker = &worker;
        const StillResult with_worker = render_still(scene, shaders, o);
        ASSERT_EQ(main_thread.radiance.pixels.size(), with_worker.radiance.pixels.size());
        size_t differing = 0, nonfinite = 0;
        for (size_t i = 0; i < main_thread.radiance.pixels.size(); ++i) {
            differing += main_thread.radiance.pixels[i] != with_worker.radiance.pixels[i];
            nonfinite += !std::isfinite(with_worker.radiance.pixels[i]);
        }
        EXPECT_EQ(differing, 0u) << model;
        EXPECT_EQ(nonfinite, 0u) << model;

        Scene untextured = scene;
        for (auto& img : untextured.images) img.valid = false;
        o.mip_worker = nullptr;
        const StillResult white = render_still(untextured, shaders, o);
        size_t textured_pixels = 0;
        for (size_t i = 0; i < white.radiance.pixels.size(); ++i)
            textured_pixels += std::abs(white.radiance.pixels[i] - with_worker.radiance.pixels[i]) > 1e-3f;
        EXPECT_GT(textured_pixels, white.radiance.pixels.size() / 50) << model << ": the textures hardly show";
    }
}

INSTANTIATE_TEST_SUITE_P(Backends, GlWorkerTest, ::testing::Values(Backend::egl, Backend::osmesa), test::backend_name);

}  // namespace
}  // namespace candela
