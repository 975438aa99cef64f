// Shader hot reload, headless: a copy of shaders/ is edited between frames. A changed include
// changes the next frame; a syntax error keeps the last good program and names the included
// file's line; fixing the file recovers; reloading 100 times leaks no GL objects.
#include <gtest/gtest.h>

#include <fstream>
#include <sstream>
#include <thread>

#include "gl/debug.hpp"
#include "gl_fixture.hpp"
#include "gltf_builder.hpp"
#include "render/renderer.hpp"
#include "scene/gltf_loader.hpp"
#include "shader/file_watcher.hpp"

#include "text_file.hpp"

namespace candela {
namespace {
namespace fs = std::filesystem;

using test::read_text;
using test::write_text;

// A white pure-Lambert quad filling an orthographic view, lit only by a constant environment
// of 0.5: every pixel's radiance is exactly 0.5 in each channel.
Scene lambert_quad() {
    test::GltfBuilder b;
    b.json()["materials"] = {{{"pbrMetallicRoughness", {{"baseColorFactor", {1, 1, 1, 1}}, {"metallicFactor", 0}}},
                              {"extensions", {{"KHR_materials_specular", {{"specularFactor", 0}}}}}}};
    b.add_node({{"mesh", b.add_quad_mesh(0)}, {"scale", {4, 4, 1}}});
    b.json()["scenes"][0]["extras"]["environment_radiance"] = {0.5, 0.5, 0.5};
    b.json()["cameras"] = {{{"type", "orthographic"}, {"orthographic", {{"xmag", 1}, {"ymag", 1}, {"znear", 0.01}, {"zfar", 10}}}}};
    b.add_node({{"camera", 0}, {"translation", {0, 0, 2}}});
    b.json()["extensionsUsed"] = {"KHR_materials_specular"};
    return load_gltf(b.write(test::test_dir("reload_scene"), "quad"));
}

class HotReloadTest : public test::GlContextTest {
protected:
    void SetUp() override {
        test::GlContextTest::SetUp();
        dir_ = test::test_dir("reload_shaders");
        fs::copy(fs::path(CANDELA_SOURCE_DIR) / "shaders", dir_, fs::copy_options::recursive);
    }
    glm::vec3 centre(Renderer& r, const Camera& cam) {
        r.render(cam, 16, 16);
        const ImageF img = r.read_radiance();
        EXPECT_EQ(count_nonfinite(img), 0u);
        const float* p = img.at(8, 8);
        return {p[0], p[1], p[2]};
    }
    fs::path dir_;
};

TEST_P(HotReloadTest, EditBreakFixAndNoLeaks) {
    const Scene scene = lambert_quad();
    ShaderLibrary lib(dir_);
    GpuScene gpu(scene);
    RenderSettings settings;
    apply_effects(settings, "none");
    Renderer renderer(lib, scene, gpu, settings);
    const Camera cam = scene.select_camera("", 1.0f);
    FileWatcher watcher(dir_);
    const glm::vec3 before = centre(renderer, cam);
    EXPECT_NEAR(before.g, 0.5f, 1e-4f);

    // 1. A colour constant in an included file: the environment's diffuse light loses green.
    const fs::path shading = dir_ / "lighting" / "shading.glsl";
    const std::string original = read_text(shading);
    const std::string anchor = "return PI * frame.env_radiance.rgb;";
    ASSERT_NE(original.find(anchor), std::string::npos) << "the test edits this line of shading.glsl";
    std::string edited = original;
    edited.replace(edited.find(anchor), anchor.size(), "return PI * frame.env_radiance.rgb * vec3(1.0, 0.0, 1.0);");
    write_text(shading, edited);
    const auto changed = watcher.poll();
    ASSERT_EQ(std::count(changed.begin(), changed.end(), fs::absolute(shading).lexically_normal()), 1) << "the watcher saw the save";
    ShaderReload r = renderer.reload_shaders(changed);
    EXPECT_TRUE(r.errors.empty());
    EXPECT_NE(std::find(r.rebuilt.begin(), r.rebuilt.end(), "forward"), r.rebuilt.end());
    const glm::vec3 after = centre(renderer, cam);
    EXPECT_NEAR(after.r, 0.5f, 1e-4f);
    EXPECT_NEAR(after.g, 0.0f, 1e-4f);
    EXPECT_NEAR(after.b, 0.5f, 1e-4f);

    // 2. A syntax error on a known line: the last good program stays, the message names it.
    std::string broken = edited;
    const size_t at = broken.find(anchor.substr(0, 10));
    const int line = 1 + static_cast<int>(std::count(broken.begin(), broken.begin() + static_cast<std::ptrdiff_t>(at), '\n'));
    broken.insert(broken.rfind('\n', at) + 1, "    this is not glsl;\n");
    write_text(shading, broken);
    r = renderer.reload_shaders(watcher.poll());
    EXPECT_TRUE(r.rebuilt.empty());
    ASSERT_FALSE(r.errors.empty());
    EXPECT_NE(r.errors[0].find("lighting/shading.glsl:" + std::to_string(line) + ":"), std::string::npos) << r.errors[0];
    // The driver also reports the failed compile through KHR_debug: expected here.
    gl::reset_debug_error_count();
    const glm::vec3 still = centre(renderer, cam);
    EXPECT_NEAR(still.g, 0.0f, 1e-4f) << "the last good (edited) program is still in use";

    // 3. Fixed: recovers without anything else.
    write_text(shading, original);
    r = renderer.reload_shaders(watcher.poll());
    EXPECT_TRUE(r.errors.empty());
    EXPECT_FALSE(r.rebuilt.empty());
    EXPECT_NEAR(centre(renderer, cam).g, 0.5f, 1e-4f);

    // 4. 100 reloads: as many programs and shaders alive afterwards as before.
    const int programs = gl::Program::live(), shaders = gl::Shader::live(), textures = gl::Texture::live();
    for (int i = 0; i < 100; ++i) {
        r = renderer.reload_shaders({shading});
        ASSERT_FALSE(r.rebuilt.empty());
        if (i % 10 == 0) renderer.render(cam, 16, 16);
    }
    EXPECT_EQ(gl::Program::live(), programs);
    EXPECT_EQ(gl::Shader::live(), shaders);
    EXPECT_EQ(gl::Texture::live(), textures);
}

INSTANTIATE_TEST_SUITE_P(Backends, HotReloadTest, ::testing::Values(Backend::egl), test::backend_name);

// Both ways of watching see a save, a new file and a removal, and report nothing otherwise.
TEST(FileWatcher, SeesWritesCreationsAndRemovals) {
    for (bool polling : {false, true}) {
        SCOPED_TRACE(polling ? "polling" : "inotify");
        const fs::path dir = test::test_dir(polling ? "watch_poll" : "watch_inotify");
        fs::create_directories(dir / "sub");
        write_text(dir / "sub" / "a.glsl", "one");
        FileWatcher w(dir, polling);
        if (!polling) EXPECT_TRUE(w.uses_inotify());
        EXPECT_TRUE(w.poll().empty());
        write_text(dir / "sub" / "a.glsl", "two, longer");
        write_text(dir / "b.glsl", "new");
        auto changed = w.poll();
        EXPECT_EQ(changed, (std::vector<fs::path>{(dir / "b.glsl").lexically_normal(), (dir / "sub" / "a.glsl").lexically_normal()}));
        EXPECT_TRUE(w.poll().empty());
        fs::remove(dir / "b.glsl");
        EXPECT_EQ(w.poll(), std::vector<fs::path>{(dir / "b.glsl").lexically_normal()});
    }
}

}  // namespace
}  // namespace candela
