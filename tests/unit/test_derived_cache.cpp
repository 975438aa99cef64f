// The derived-data cache (core/derived_cache.hpp) and the prefiltered environment cube kept in it
// (render/environment.hpp). The promise is that a cached cube is the computed one, bit
// for bit, and that any changed input (texels, sizes, shader sources) or a damaged entry means
// computing it again, never a stale or broken cube.
#include <gtest/gtest.h>

#include <algorithm>
#include <chrono>
#include <cmath>
#include <cstdint>
#include <cstdlib>
#include <filesystem>
#include <fstream>
#include <random>
#include <set>
#include <string>
#include <vector>

#include <sys/stat.h>
#include <unistd.h>

#include "core/derived_cache.hpp"
#include "gl/handles.hpp"
#include "gl_fixture.hpp"
#include "render/environment.hpp"
#include "scene/lighting.hpp"

namespace candela {
namespace {
namespace fs = std::filesystem;

fs::path fresh_dir(const std::string& name) {
    const fs::path dir = fs::temp_directory_path() / ("candela_cache_test_" + name + "_" + std::to_string(::getpid()));
    fs::remove_all(dir);
    return dir;
}

std::vector<std::uint8_t> random_bytes(std::size_t n, unsigned seed) {
    std::mt19937 rng(seed);
    std::vector<std::uint8_t> v(n);
    for (auto& b : v) b = static_cast<std::uint8_t>(rng() & 0xff);
    return v;
}

TEST(Hasher, EveryByteAndBoundaryCounts) {
    const std::vector<std::uint8_t> data = random_bytes(1000, 1);
    const std::uint64_t h = Hasher().bytes(data.data(), data.size()).value();
    EXPECT_EQ(h, Hasher().bytes(data.data(), data.size()).value());
    std::set<std::uint64_t> seen{h};
    // A flipped bit anywhere (in the 32-byte blocks and in the tail) gives a new value.
    for (std::size_t i = 0; i < data.size(); i += 37) {
        std::vector<std::uint8_t> d = data;
        d[i] ^= 1;
        EXPECT_TRUE(seen.insert(Hasher().bytes(d.data(), d.size()).value()).second) << "byte " << i;
    }
    EXPECT_TRUE(seen.insert(Hasher().bytes(data.data(), data.size() - 1).value()).second);  // shorter
    EXPECT_TRUE(seen.insert(Hasher().text("ab").text("c").value()).second);
    EXPECT_TRUE(seen.insert(Hasher().text("a").text("bc").value()).second);  // the split counts
    EXPECT_TRUE(seen.insert(Hasher().integer(1).integer(2).value()).second);
    EXPECT_TRUE(seen.insert(Hasher().integer(2).integer(1).value()).second);
}

TEST(DerivedCache, StoresLoadsAndRejectsDamagedEntries) {
    const fs::path dir = fresh_dir("entries");
    const DerivedCache cache(dir / "nested");  // created on the first store
    const std::vector<std::uint8_t> data = random_bytes(4096, 2);
    EXPECT_FALSE(cache.load("t", 7, data.size()));
    ASSERT_TRUE(cache.store("t", 7, data));
    const auto loaded = cache.load("t", 7, data.size());
    ASSERT_TRUE(loaded);
    EXPECT_EQ(*loaded, data);
    EXPECT_FALSE(cache.load("t", 8, data.size())) << "another key";
    EXPECT_FALSE(cache.load("u", 7, data.size())) << "another kind";
    EXPECT_FALSE(cache.load("t", 7, data.size() - 4)) << "another size";
    const fs::path path = *cache.entry_path("t", 7);
    {  // a flipped payload byte: the checksum fails
        std::fstream f(path, std::ios::in | std::ios::out | std::ios::binary);
        f.seekp(100);
        f.put('\x5a' ^ static_cast<char>(data[100 - 24]));
    }
    EXPECT_FALSE(cache.load("t", 7, data.size()));
    ASSERT_TRUE(cache.store("t", 7, data));  // replaced
    EXPECT_TRUE(cache.load("t", 7, data.size()));
    fs::resize_file(path, fs::file_size(path) - 1);  // truncated
    EXPECT_FALSE(cache.load("t", 7, data.size()));
    ASSERT_TRUE(cache.store("t", 7, data));
    {  // a longer file
        std::ofstream f(path, std::ios::binary | std::ios::app);
        f.put('x');
    }
    EXPECT_FALSE(cache.load("t", 7, data.size()));
    // Something else at the entry's path: a directory, then a FIFO (which would block a reader).
    fs::remove(path);
    fs::create_directory(path);
    EXPECT_FALSE(cache.load("t", 7, data.size()));
    EXPECT_FALSE(cache.store("t", 7, data));
    fs::remove(path);
    ASSERT_EQ(::mkfifo(path.c_str(), 0600), 0);
    EXPECT_FALSE(cache.load("t", 7, data.size()));
    fs::remove(path);
    // No temporary files left behind.
    for (const auto& e : fs::directory_iterator(dir / "nested")) EXPECT_EQ(e.path().extension(), ".bin") << e.path();
    fs::remove_all(dir);
}

TEST(DerivedCache, OffOrUnwritableIsNeverAnError) {
    const DerivedCache off(std::nullopt);
    const std::vector<std::uint8_t> data = random_bytes(64, 3);
    EXPECT_FALSE(off.store("t", 1, data));
    EXPECT_FALSE(off.load("t", 1, data.size()));
    const fs::path dir = fresh_dir("unwritable");
    fs::create_directories(dir);
    std::ofstream(dir / "file") << "not a directory";
    const DerivedCache blocked(dir / "file" / "cache");
    EXPECT_FALSE(blocked.store("t", 1, data));
    EXPECT_FALSE(blocked.load("t", 1, data.size()));
    fs::remove_all(dir);
}

TEST(DerivedCache, KeepsAtMostMaxEntries) {
    const fs::path dir = fresh_dir("prune");
    const DerivedCache cache(dir);
    const std::vector<std::uint8_t> data = random_bytes(16, 4);
    // Distinct ages, oldest first (a file system's clock may not tell stores a moment apart).
    const auto base = fs::file_time_type::clock::now() - std::chrono::hours(1);
    for (int i = 0; i < DerivedCache::kMaxEntries + 5; ++i) {
        ASSERT_TRUE(cache.store("t", static_cast<std::uint64_t>(i), data));
        fs::last_write_time(*cache.entry_path("t", static_cast<std::uint64_t>(i)), base + std::chrono::seconds(i));
    }
    int entries = 0;
    for (const auto& e : fs::directory_iterator(dir)) entries += e.path().extension() == ".bin";
    EXPECT_EQ(entries, DerivedCache::kMaxEntries);
    EXPECT_TRUE(cache.load("t", DerivedCache::kMaxEntries + 4, data.size())) << "the newest entry went";
    fs::remove_all(dir);
}

TEST(DerivedCache, DirectoryFromTheEnvironment) {
    const char* saved = std::getenv("CANDELA_CACHE_DIR");
    const std::string keep = saved ? saved : "";
    setenv("CANDELA_CACHE_DIR", "off", 1);
    EXPECT_FALSE(DerivedCache::default_directory());
    setenv("CANDELA_CACHE_DIR", "", 1);
    EXPECT_FALSE(DerivedCache::default_directory());
    setenv("CANDELA_CACHE_DIR", "/some/where", 1);
    EXPECT_EQ(DerivedCache::default_directory(), fs::path("/some/where"));
    unsetenv("CANDELA_CACHE_DIR");
    const char* xdg = std::getenv("XDG_CACHE_HOME");
    const std::string keep_xdg = xdg ? xdg : "";
    setenv("XDG_CACHE_HOME", "/xdg", 1);
    EXPECT_EQ(DerivedCache::default_directory(), fs::path("/xdg/candela"));
    if (xdg) setenv("XDG_CACHE_HOME", keep_xdg.c_str(), 1);
    else unsetenv("XDG_CACHE_HOME");
    if (saved) setenv("CANDELA_CACHE_DIR", keep.c_str(), 1);
}

using EnvironmentCubeCacheTest = test::GlContextTest;

struct Equirect {
    ImageF texels;
    gl::Texture texture;
};

Equirect equirect(const ShaderLibrary& shaders, ImageF texels) {
    Equirect e{std::move(texels), {}};
    e.texture = gl::Texture::create_2d(GL_RGBA32F, e.texels.width, e.texels.height, 0);
    glTextureSubImage2D(e.texture.id(), 0, 0, 0, e.texels.width, e.texels.height, GL_RGBA, GL_FLOAT, e.texels.pixels.data());
    FloatMipmaps(shaders).generate(e.texture, GL_TEXTURE_2D, e.texels.width, e.texels.height, 1, 0);
    return e;
}

std::vector<float> cube_texels(const gl::Texture& cube, int size) {
    std::vector<float> all;
    for (int level = 0; level < prefiltered_levels(size); ++level) {
        const int s = std::max(size >> level, 1);
        std::vector<float> v(static_cast<std::size_t>(s) * s * 6 * 4);
        glGetTextureImage(cube.id(), level, GL_RGBA, GL_FLOAT, static_cast<GLsizei>(v.size() * sizeof(float)), v.data());
        all.insert(all.end(), v.begin(), v.end());
    }
    return all;
}

TEST_P(EnvironmentCubeCacheTest, CachedCubeIsTheComputedOneAndChangedInputsMiss) {
    const fs::path dir = fresh_dir(std::string("cube_") + to_string(GetParam()));
    const ShaderLibrary shaders(ShaderLibrary::default_root());
    const int size = 16, samples = 16;
    const Equirect sky = equirect(shaders, *default_sky_image(64));

    // Without texels there is no key: computed, nothing stored.
    const ImageBasedLighting uncached(shaders, DerivedCache(dir));
    const std::vector<float> reference = cube_texels(uncached.cube_from_equirect(sky.texture, nullptr, size, samples), size);
    EXPECT_FALSE(uncached.last_cube_cached());
    EXPECT_FALSE(fs::exists(dir));

    const ImageBasedLighting first(shaders, DerivedCache(dir));
    EXPECT_EQ(cube_texels(first.cube_from_equirect(sky.texture, &sky.texels, size, samples), size), reference);
    EXPECT_FALSE(first.last_cube_cached());
    const ImageBasedLighting second(shaders, DerivedCache(dir));
    EXPECT_EQ(cube_texels(second.cube_from_equirect(sky.texture, &sky.texels, size, samples), size), reference);
    EXPECT_TRUE(second.last_cube_cached());
    // The cube is not the sky's average everywhere (the comparison is not trivial), and finite.
    EXPECT_NE(reference[0], reference[reference.size() - 4]);
    EXPECT_TRUE(std::all_of(reference.begin(), reference.end(), [](float v) { return std::isfinite(v); }));

    // Other samples, another size: other entries.
    second.cube_from_equirect(sky.texture, &sky.texels, size, samples * 2);
    EXPECT_FALSE(second.last_cube_cached());
    second.cube_from_equirect(sky.texture, &sky.texels, size * 2, samples);
    EXPECT_FALSE(second.last_cube_cached());

    // One changed texel: another entry, and its own cube.
    ImageF changed = sky.texels;
    changed.at(10, 5)[1] += 0.25f;
    const Equirect other = equirect(shaders, changed);
    const std::vector<float> other_cube = cube_texels(second.cube_from_equirect(other.texture, &other.texels, size, samples), size);
    EXPECT_FALSE(second.last_cube_cached());
    EXPECT_NE(other_cube, reference);

    // Another wrap mode for the map: another entry.
    glTextureParameteri(sky.texture.id(), GL_TEXTURE_WRAP_S, GL_CLAMP_TO_EDGE);
    second.cube_from_equirect(sky.texture, &sky.texels, size, samples);
    EXPECT_FALSE(second.last_cube_cached());
    glTextureParameteri(sky.texture.id(), GL_TEXTURE_WRAP_S, GL_REPEAT);

    // A damaged entry: computed again, the same cube, and the entry repaired.
    int damaged = 0;
    for (const auto& e : fs::directory_iterator(dir)) {
        std::fstream f(e.path(), std::ios::in | std::ios::out | std::ios::binary);
        f.seekp(1000);
        f.put('\x7f');
        ++damaged;
    }
    EXPECT_EQ(damaged, 5);
    EXPECT_EQ(cube_texels(second.cube_from_equirect(sky.texture, &sky.texels, size, samples), size), reference);
    EXPECT_FALSE(second.last_cube_cached());
    second.cube_from_equirect(sky.texture, &sky.texels, size, samples);
    EXPECT_TRUE(second.last_cube_cached());

    // An edited shader (here only a comment in an included file) is another key.
    const fs::path edited = dir.string() + "_shaders";
    fs::copy(ShaderLibrary::default_root(), edited, fs::copy_options::recursive);
    std::ofstream(edited / "env" / "cube.glsl", std::ios::app) << "\n// edited\n";
    const ShaderLibrary edited_shaders(edited);
    const ImageBasedLighting third(edited_shaders, DerivedCache(dir));
    EXPECT_EQ(cube_texels(third.cube_from_equirect(sky.texture, &sky.texels, size, samples), size), reference);
    EXPECT_FALSE(third.last_cube_cached());
    fs::remove_all(edited);
    fs::remove_all(dir);
}

INSTANTIATE_TEST_SUITE_P(Backends, EnvironmentCubeCacheTest, ::testing::Values(Backend::egl, Backend::osmesa), test::backend_name);

}  // namespace
}  // namespace candela
