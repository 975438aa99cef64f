// The tracer's programs: one compute-shader file per mode (shaders/rt/modes/) over shared
// includes, with the scene features as the only defines; and hot reload of the tracer: an edit
// to a shared include or to a mode file is seen by the watcher, is in the set of files the
// library records for the program, and reaches the next tracer built; and set_mode, which
// switches a tracer's program over the same BVH and renders what a fresh tracer of the mode does.
#include <gtest/gtest.h>

#include <algorithm>
#include <cstring>
#include <fstream>
#include <set>
#include <sstream>

#include "gl_fixture.hpp"
#include "core/error.hpp"
#include "gltf_builder.hpp"
#include "rt/ray_tracer.hpp"
#include "scene/gltf_loader.hpp"
#include "scene/lighting.hpp"
#include "shader/file_watcher.hpp"
#include "render/program_catalog.hpp"

#include "text_file.hpp"

namespace candela {
namespace {
namespace fs = std::filesystem;

const rt::Mode kAllModes[] = {rt::Mode::whitted, rt::Mode::path,    rt::Mode::direct,     rt::Mode::indirect,
                              rt::Mode::ao,      rt::Mode::primary, rt::Mode::visibility, rt::Mode::bounce,
                              rt::Mode::hits};

using test::read_text;
using test::write_text;

bool lists(const std::vector<fs::path>& files, const fs::path& want) {
    return std::any_of(files.begin(), files.end(), [&](const fs::path& f) {
        return fs::weakly_canonical(f) == fs::weakly_canonical(want);
    });
}

TEST(RtModePrograms, EachModeIsItsOwnFileOverSharedIncludes) {
    const fs::path root = fs::path(CANDELA_SOURCE_DIR) / "shaders";
    const ShaderLibrary lib(root);
    const std::vector<ProgramDesc> variants = ray_tracer_variants();
    // Every mode's program is in the catalog (which `candela shaders check` builds), under the
    // same name and file the tracer uses.
    std::set<std::string> mode_files;
    for (rt::Mode m : kAllModes) {
        const rt::ModeProgram p = rt::mode_program(m);
        SCOPED_TRACE(rt::to_string(m));
        EXPECT_EQ(fs::path(p.file).parent_path(), fs::path("rt/modes"));
        mode_files.insert(p.file);
        const auto in_catalog = std::find_if(variants.begin(), variants.end(), [&](const ProgramDesc& d) {
            return d.name == std::string("trace ") + p.name && d.stages.size() == 1 && d.stages[0].second == p.file;
        });
        EXPECT_NE(in_catalog, variants.end());
    }
    EXPECT_EQ(mode_files.size(), 8u) << "direct shares path's program; every other mode has its own";
    for (const ProgramDesc& d : variants) {
        SCOPED_TRACE(d.name);
        ASSERT_EQ(d.stages.size(), 1u);
        for (const std::string& define : d.defines) EXPECT_EQ(define.rfind("MODE_", 0), std::string::npos) << define;
        const PreprocessedSource src = lib.preprocess(d.stages[0].second, d.defines);
        // No mode ladder is left in any file a tracer program is built from.
        EXPECT_EQ(src.text.find("MODE_"), std::string::npos);
        EXPECT_TRUE(lists(src.files, root / d.stages[0].second));
        EXPECT_TRUE(lists(src.files, root / "rt/trace_common.glsl"));
        EXPECT_TRUE(lists(src.files, root / "rt/scene.glsl"));
        EXPECT_EQ(validate_with_glslang(src, ShaderStage::compute), "");
    }
}

// A white Lambert quad filling an orthographic view with nothing above it: AO is exactly 1.
Scene open_quad() {
    test::GltfBuilder b;
    b.json()["materials"] = {{{"pbrMetallicRoughness", {{"baseColorFactor", {1, 1, 1, 1}}, {"metallicFactor", 0}}}}};
    b.add_node({{"mesh", b.add_quad_mesh(0)}, {"scale", {4, 4, 1}}});
    b.json()["scenes"][0]["extras"]["environment_radiance"] = {0.5, 0.5, 0.5};
    b.json()["cameras"] = {{{"type", "orthographic"}, {"orthographic", {{"xmag", 1}, {"ymag", 1}, {"znear", 0.01}, {"zfar", 10}}}}};
    b.add_node({{"camera", 0}, {"translation", {0, 0, 2}}});
    return load_gltf(b.write(test::test_dir("rt_modes_scene"), "quad"));
}

using RtModeReloadTest = test::GlContextTest;

TEST_P(RtModeReloadTest, EditsToASharedIncludeAndToAModeFileReachTheTracer) {
    const fs::path dir = test::test_dir("rt_modes_reload");
    fs::remove_all(dir / "shaders");
    fs::copy(fs::path(CANDELA_SOURCE_DIR) / "shaders", dir / "shaders", fs::copy_options::recursive);
    const fs::path shaders = dir / "shaders";
    const Scene scene = open_quad();
    GpuScene gpu(scene);
    const Camera cam = scene.select_camera("", 1.0f);
    // The centre pixel of a 16x16 AO render with the shaders as they are on disk now.
    auto ao_centre = [&](ShaderLibrary::BuildResult* build) {
        const ShaderLibrary lib(shaders);
        rt::Options o;
        o.mode = rt::Mode::ao;
        o.spp = 2;
        rt::RayTracer tracer(lib, scene, gpu, o);
        const rt::Result r = tracer.render(cam, 16, 16);
        EXPECT_EQ(r.nonfinite_samples, 0u);
        EXPECT_EQ(count_nonfinite(r.image), 0u);
        if (build) *build = lib.build({"trace", {{ShaderStage::compute, rt::mode_program(o.mode).file}}, {}});
        return r.image.at(8, 8)[1];
    };
    FileWatcher watcher(shaders);
    ShaderLibrary::BuildResult build;
    EXPECT_EQ(ao_centre(&build), 1.0f);
    ASSERT_TRUE(build.ok()) << build.log;

    // 1. The shared include: accumulate() in trace_common.glsl adds half of each sample.
    const fs::path common = shaders / "rt" / "trace_common.glsl";
    const std::string anchor = "accum[index] += vec4(sum, float(count));";
    std::string text = read_text(common);
    ASSERT_NE(text.find(anchor), std::string::npos) << "the test edits this line of trace_common.glsl";
    text.replace(text.find(anchor), anchor.size(), "accum[index] += vec4(sum * 0.5, float(count));");
    write_text(common, text);
    std::vector<fs::path> changed = watcher.poll();
    ASSERT_EQ(changed.size(), 1u);
    EXPECT_TRUE(lists(build.files, changed[0])) << "the edited include is in the program's recorded file set";
    EXPECT_EQ(ao_centre(nullptr), 0.5f);

    // 2. The mode file, in its own directory: AO reports the occluded fraction instead.
    const fs::path ao = shaders / "rt" / "modes" / "ao.comp";
    const std::string ao_anchor = "return vec3(occluded ? 0.0 : 1.0);";
    text = read_text(ao);
    ASSERT_NE(text.find(ao_anchor), std::string::npos) << "the test edits this line of ao.comp";
    text.replace(text.find(ao_anchor), ao_anchor.size(), "return vec3(occluded ? 1.0 : 0.0);");
    write_text(ao, text);
    changed = watcher.poll();
    ASSERT_EQ(changed.size(), 1u);
    EXPECT_TRUE(lists(build.files, changed[0])) << "the mode file is in the program's recorded file set";
    EXPECT_EQ(ao_centre(nullptr), 0.0f);
}

INSTANTIATE_TEST_SUITE_P(Backends, RtModeReloadTest, ::testing::Values(Backend::egl), test::backend_name);

// A floor and a back wall (light bounces between them) with a small emitter, under the default
// rig's sky map: what a mode switch has to redo is all there (the emitter define, environment-map
// sampling in path and direct only, the depth of each mode).
Scene lit_corner() {
    test::GltfBuilder b;
    nlohmann::json grey_material, glow_material;
    grey_material["pbrMetallicRoughness"] = {{"baseColorFactor", {0.8, 0.8, 0.8, 1}}, {"metallicFactor", 0}};
    glow_material["pbrMetallicRoughness"] = {{"baseColorFactor", {0, 0, 0, 1}}};
    glow_material["emissiveFactor"] = {1, 0.5, 0.2};
    b.json()["materials"] = nlohmann::json::array({grey_material, glow_material});
    const int grey = b.add_quad_mesh(0), glow = b.add_quad_mesh(1);
    b.add_node({{"mesh", grey}, {"scale", {2, 2, 1}}, {"rotation", {-0.70710678, 0, 0, 0.70710678}}});  // the floor, facing +Y
    b.add_node({{"mesh", grey}, {"translation", {0, 2, -2}}, {"scale", {2, 2, 1}}});                     // the wall, facing +Z
    b.add_node({{"mesh", glow}, {"translation", {0.8, 1.2, -1.9}}, {"scale", {0.3, 0.3, 1}}});
    b.json()["cameras"] = {{{"type", "perspective"}, {"perspective", {{"yfov", 0.9}, {"aspectRatio", 1.5}, {"znear", 0.05}}}}};
    b.add_node({{"camera", 0}, {"translation", {0, 1, 4}}});
    Scene scene = load_gltf(b.write(test::test_dir("rt_set_mode_scene"), "corner"));
    apply_lighting(scene, LightingMode::default_rig, scene.select_camera("", 1.5f));
    return scene;
}

using RtSetModeTest = test::GlContextTest;

// set_mode keeps the tracer's BVH and gives the images a tracer constructed with that mode gives,
// bit for bit: the planner's indirect estimate (engine/effects/gi/estimate.cpp) traces direct and
// indirect with one tracer and must plan what two tracers planned.
TEST_P(RtSetModeTest, SwitchedTracerRendersWhatAFreshOneRenders) {
    const Scene scene = lit_corner();
    GpuScene gpu(scene);
    ASSERT_TRUE(gpu.has_environment_map()) << "the default rig's sky, which direct and path importance-sample";
    const ShaderLibrary lib(fs::path(CANDELA_SOURCE_DIR) / "shaders");
    const int w = 24, h = 16;
    const Camera cam = scene.select_camera("", static_cast<float>(w) / static_cast<float>(h));
    rt::Options o;
    o.mode = rt::Mode::direct;
    o.spp = 4;
    o.tile_rows = h;
    rt::RayTracer tracer(lib, scene, gpu, o);
    const rt::Mode sequence[] = {rt::Mode::direct, rt::Mode::indirect, rt::Mode::path, rt::Mode::direct};
    std::vector<rt::Result> switched;
    for (rt::Mode m : sequence) {
        SCOPED_TRACE(rt::to_string(m));
        if (m != tracer.mode()) tracer.set_mode(m);
        EXPECT_EQ(tracer.mode(), m);
        switched.push_back(tracer.render(cam, w, h));
        rt::Options fresh_options = o;
        fresh_options.mode = m;
        const rt::Result fresh = rt::RayTracer(lib, scene, gpu, fresh_options).render(cam, w, h);
        const rt::Result& r = switched.back();
        EXPECT_EQ(r.defines, fresh.defines);
        EXPECT_EQ(r.nonfinite_samples, 0u);
        ASSERT_EQ(r.image.pixels.size(), fresh.image.pixels.size());
        size_t differ = 0;
        for (size_t i = 0; i < r.image.pixels.size(); ++i)
            differ += std::memcmp(&r.image.pixels[i], &fresh.image.pixels[i], sizeof(float)) != 0;
        EXPECT_EQ(differ, 0u) << "of " << r.image.pixels.size() << " floats";
    }
    // The comparisons above could fail: the scene has emitters and direct and path sample the sky
    // map (indirect does not), the bounce is not black, and path (unbounded) differs from direct
    // (one bounce), so a depth or distribution left over from the previous mode would show.
    EXPECT_NE(switched[0].defines.find("HAS_EMITTERS"), std::string::npos) << switched[0].defines;
    EXPECT_NE(switched[0].defines.find("HAS_ENV_MAP_SAMPLING"), std::string::npos) << switched[0].defines;
    EXPECT_EQ(switched[1].defines.find("HAS_ENV_MAP_SAMPLING"), std::string::npos) << switched[1].defines;
    EXPECT_NE(switched[2].defines.find("HAS_ENV_MAP_SAMPLING"), std::string::npos) << switched[2].defines;
    double bounce = 0.0;
    for (int y = 0; y < h; ++y)
        for (int x = 0; x < w; ++x) bounce += switched[1].image.at(x, y)[0];
    EXPECT_GT(bounce, 0.0);
    EXPECT_NE(switched[2].image.pixels, switched[0].image.pixels);
    EXPECT_EQ(switched[3].image.pixels, switched[0].image.pixels) << "direct again after path";

    // A switch the options do not allow (whitted's depth is at most 64) throws and changes nothing.
    rt::Options deep = o;
    deep.mode = rt::Mode::path;
    deep.max_depth = 100;
    rt::RayTracer deep_tracer(lib, scene, gpu, deep);
    const std::string defines = deep_tracer.render(cam, w, h).defines;
    EXPECT_THROW(deep_tracer.set_mode(rt::Mode::whitted), Error);
    EXPECT_EQ(deep_tracer.mode(), rt::Mode::path);
    EXPECT_EQ(deep_tracer.render(cam, w, h).defines, defines);
}

INSTANTIATE_TEST_SUITE_P(Backends, RtSetModeTest, ::testing::Values(Backend::egl), test::backend_name);

}  // namespace
}  // namespace candela
