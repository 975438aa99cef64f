// Tests that need a GL context: contexts on both headless backends, GL error detection, the
// GLSL/C++ twins, and the forward path's physical units on analytic cases.
#include <gtest/gtest.h>

#include <algorithm>
#include <cmath>
#include <fstream>

#include "core/error.hpp"
#include "gl/debug.hpp"
#include "gl_fixture.hpp"
#include "gltf_builder.hpp"
#include "image/image.hpp"
#include "platform/context.hpp"
#include "render/frame_graph.hpp"
#include "render/gpu_scene.hpp"
#include "render/still.hpp"
#include "scene/generate.hpp"
#include "scene/gltf_loader.hpp"

namespace candela {
namespace {
namespace fs = std::filesystem;

ShaderLibrary shaders() { return ShaderLibrary(fs::path(CANDELA_SOURCE_DIR) / "shaders"); }

using GlTest = test::GlContextTest;

TEST_P(GlTest, ContextIsCore45WithComputeShaders) {
    EXPECT_EQ(context_->backend(), GetParam());
    EXPECT_FALSE(context_->renderer().empty());
    GLint major = 0, minor = 0, invocations = 0;
    glGetIntegerv(GL_MAJOR_VERSION, &major);
    glGetIntegerv(GL_MINOR_VERSION, &minor);
    glGetIntegerv(GL_MAX_COMPUTE_WORK_GROUP_INVOCATIONS, &invocations);
    EXPECT_GE(major * 10 + minor, 45);
    EXPECT_GE(invocations, 1024);
}

TEST_P(GlTest, DebugOutputCountsGlErrors) {
    glEnable(0x1234);  // GL_INVALID_ENUM
    EXPECT_EQ(gl::debug_error_count(), 1);
    gl::reset_debug_error_count();
}

// A texture a pass reads at a unit is bound there while the pass runs, with no sampler object,
// and unbound after (the pool may attach it to a framebuffer next).
TEST_P(GlTest, TheFrameGraphBindsAndUnbindsDeclaredInputs) {
    const GLuint unit = 5;
    gl::Sampler stale = gl::Sampler::create(GL_NEAREST, GL_NEAREST, GL_REPEAT, GL_REPEAT);
    glBindSampler(unit, stale.id());
    TexturePool pool;
    FrameGraph graph;
    FrameGraph::ResourceId made = -1;
    graph.add_pass("make", [&](FrameGraph::Builder& b) { made = b.create("made", {GL_RGBA16F, 8, 8}); }, [](FrameGraph::Context&) {});
    GLint bound_inside = -1, sampler_inside = -1;
    GLuint expected = 0;
    graph.add_pass(
        "read",
        [&](FrameGraph::Builder& b) {
            b.read(made, unit);
            b.side_effect();
        },
        [&](FrameGraph::Context& ctx) {
            expected = ctx.texture(made).id();
            glActiveTexture(GL_TEXTURE0 + unit);
            glGetIntegerv(GL_TEXTURE_BINDING_2D, &bound_inside);
            glGetIntegerv(GL_SAMPLER_BINDING, &sampler_inside);
        });
    graph.compile(pool);
    gl::StateCache state;
    graph.execute(state);
    GLint bound_after = -1;
    glActiveTexture(GL_TEXTURE0 + unit);
    glGetIntegerv(GL_TEXTURE_BINDING_2D, &bound_after);
    glActiveTexture(GL_TEXTURE0);
    graph.release(pool);
    EXPECT_NE(expected, 0u);
    EXPECT_EQ(static_cast<GLuint>(bound_inside), expected);
    EXPECT_EQ(sampler_inside, 0);
    EXPECT_EQ(bound_after, 0);
    // One unit, two inputs: a programmer error.
    FrameGraph twice;
    twice.add_pass("make", [&](FrameGraph::Builder& b) { made = b.create("made", {GL_RGBA16F, 8, 8}); }, [](FrameGraph::Context&) {});
    auto bind_twice = [&](FrameGraph::Builder& b) {
        b.read(made, unit);
        b.read(made, unit);
    };
    EXPECT_THROW(twice.add_pass("read", bind_twice, [](FrameGraph::Context&) {}), Error);
}

TEST_P(GlTest, GlslDisplayTransformMatchesCpp) {
    const auto dir = test::test_dir("twin_tonemap");
    std::ofstream(dir / "twin.comp") << R"(#version 450 core
#include "common/tonemap.glsl"
layout(local_size_x = 64) in;
layout(std430, binding = 0) buffer Data { vec4 values[]; };
void main() {
    uint i = gl_GlobalInvocationID.x;
    values[i] = vec4(display_transform(values[i].xyz, values[i].w), 0.0);
}
)";
    fs::create_directories(dir / "common");
    fs::copy_file(fs::path(CANDELA_SOURCE_DIR) / "shaders/common/tonemap.glsl", dir / "common/tonemap.glsl");
    const ShaderLibrary lib(dir);
    gl::Program program = lib.build_or_throw({"twin", {{ShaderStage::compute, "twin.comp"}}, {}});
    std::vector<glm::vec4> values;
    for (int i = 0; i < 256; ++i) {
        const float x = std::pow(10.0f, -4.0f + 7.0f * static_cast<float>(i) / 255.0f);
        values.emplace_back(x, x * 0.5f, x * 0.01f, static_cast<float>(i % 5) - 2.0f);
    }
    gl::Buffer buffer(static_cast<GLsizeiptr>(values.size() * 16), values.data(), GL_DYNAMIC_STORAGE_BIT);
    glUseProgram(program.id());
    glBindBufferBase(GL_SHADER_STORAGE_BUFFER, 0, buffer.id());
    glDispatchCompute(4, 1, 1);
    glMemoryBarrier(GL_BUFFER_UPDATE_BARRIER_BIT);
    std::vector<glm::vec4> out(values.size());
    glGetNamedBufferSubData(buffer.id(), 0, static_cast<GLsizeiptr>(out.size() * 16), out.data());
    for (size_t i = 0; i < values.size(); ++i) {
        const glm::vec3 expected = display_transform(glm::vec3(values[i]), values[i].w);
        for (int c = 0; c < 3; ++c) EXPECT_NEAR(out[i][c], expected[c], 2e-5f) << "value " << i;
    }
}

TEST_P(GlTest, ShaderErrorsNameFileAndLine) {
    const auto dir = test::test_dir("gl_shader_error");
    std::ofstream(dir / "broken.comp") << "#version 450 core\nlayout(local_size_x = 1) in;\nvoid main() {\n  oops;\n}\n";
    const ShaderLibrary lib(dir);
    const auto result = lib.build({"broken", {{ShaderStage::compute, "broken.comp"}}, {}});
    EXPECT_FALSE(result.ok());
    EXPECT_NE(result.log.find("broken.comp:4:"), std::string::npos) << result.log;
    gl::reset_debug_error_count();  // the compile failure is expected
}

// A Lambertian (specularFactor 0) square facing +Z, seen head-on by an orthographic camera.
fs::path lambert_plane_scene(const std::string& name, const nlohmann::json& light, const nlohmann::json& env_radiance,
                             bool mirrored = false) {
    test::GltfBuilder b;
    b.json()["materials"] = {{{"pbrMetallicRoughness", {{"baseColorFactor", {1, 1, 1, 1}}, {"metallicFactor", 0}}},
                              {"extensions", {{"KHR_materials_specular", {{"specularFactor", 0}}}}}}};
    b.json()["cameras"] = {{{"type", "orthographic"},
                            {"orthographic", {{"xmag", 2}, {"ymag", 2}, {"znear", 0.1}, {"zfar", 20}}}}};
    b.add_node({{"camera", 0}, {"translation", {0, 0, 5}}});
    nlohmann::json plane = {{"mesh", b.add_quad_mesh(0)}};
    if (mirrored) plane["scale"] = {-1, 1, 1};
    b.add_node(plane);
    if (!light.is_null()) {
        b.json()["extensions"]["KHR_lights_punctual"]["lights"] = {light};
        b.add_node({{"extensions", {{"KHR_lights_punctual", {{"light", 0}}}}}});  // points along -Z
    }
    if (!env_radiance.is_null()) b.json()["scenes"][0]["extras"]["environment_radiance"] = env_radiance;
    return b.write(test::test_dir(name), name);
}

TEST_P(GlTest, LambertPlaneUnderDirectionalLightIsEOverPi) {
    // Irradiance E = 2 W/m^2 at normal incidence: radiance = albedo / pi * E.
    const Scene scene = load_gltf(lambert_plane_scene("lambert", {{"type", "directional"}, {"intensity", 2.0}}, nullptr));
    StillOptions o;
    o.width = o.height = 32;
    const StillResult r = render_still(scene, shaders(), o);
    EXPECT_EQ(count_nonfinite(r.radiance), 0u);
    EXPECT_NEAR(r.radiance.at(16, 16)[0], 2.0f / 3.14159265f, 1e-4f);
    EXPECT_NEAR(r.radiance.at(16, 16)[2], 2.0f / 3.14159265f, 1e-4f);
    // The plane (half-size 1) covers the middle half of the 2x2-unit view; outside is black.
    EXPECT_FLOAT_EQ(r.radiance.at(1, 1)[0], 0.0f);
}

TEST_P(GlTest, ConstantEnvironmentLightsLambertAndBackground) {
    // Constant radiance L from every direction: a white Lambert surface reflects exactly L.
    const Scene scene = load_gltf(lambert_plane_scene("ambient", nullptr, {0.5, 0.25, 0.125}));
    StillOptions o;
    o.width = o.height = 32;
    const StillResult r = render_still(scene, shaders(), o);
    EXPECT_NEAR(r.radiance.at(16, 16)[0], 0.5f, 1e-4f);
    EXPECT_NEAR(r.radiance.at(16, 16)[1], 0.25f, 1e-4f);
    EXPECT_NEAR(r.radiance.at(1, 1)[2], 0.125f, 1e-6f);  // background sees the environment
}

// The forward pass's per-tile light culling (forward.light_tiles, light_tiles.comp) leaves out
// only lights that add exactly nothing to a tile: the image is the untiled one, bit for bit, at
// a size whose tiles do not divide it and with multisampling.
TEST_P(GlTest, ForwardLightTilesGiveTheUntiledImage) {
    const Scene scene = make_many_lights_scene(64, true);
    for (const char* aa : {"aa.mode=off", "aa.mode=msaa"}) {
        SCOPED_TRACE(aa);
        StillOptions tiled;
        tiled.width = 100;
        tiled.height = 60;
        tiled.settings.path = RenderPath::forward;
        apply_knob(tiled.settings, aa);
        StillOptions untiled = tiled;
        apply_knob(untiled.settings, "forward.light_tiles=0");
        const StillResult a = render_still(scene, shaders(), tiled);
        const StillResult b = render_still(scene, shaders(), untiled);
        EXPECT_TRUE(a.features.forward_light_tiles);
        EXPECT_FALSE(b.features.forward_light_tiles);
        EXPECT_EQ(count_nonfinite(a.radiance), 0u);
        ASSERT_EQ(a.radiance.pixels.size(), b.radiance.pixels.size());
        size_t differ = 0;
        for (size_t i = 0; i < a.radiance.pixels.size(); ++i) differ += a.radiance.pixels[i] != b.radiance.pixels[i];
        EXPECT_EQ(differ, 0u);
        double sum = 0.0;
        for (float v : a.radiance.pixels) sum += v;
        EXPECT_GT(sum, 0.0) << "the lights light the floor";
    }
}

// Point lights without a range (the glTF default) reach as far as their share of lights.cutoff
// of one display step allows: beyond that the tiles of both paths skip them. A street of 64
// lamps, 20 m apart, no range, seen along the street (generated:street:64): the image stays within lights.cutoff of a
// display step of the unbounded one wherever the light is Lambertian (here: within one step, the
// goldens' tolerance being two), and the forward tiles still give the untiled image.
TEST(LightCutoff, DisplayQuantumIsOneStepAtTheSteepestSlope) {
    double steepest = 0.0;
    for (double x = 1e-5; x < 1.0; x *= 1.0005) {
        const double h = x * 1e-3;
        const double a = display_transform(glm::vec3(static_cast<float>(x)), 0.0f).x;
        const double b = display_transform(glm::vec3(static_cast<float>(x + h)), 0.0f).x;
        steepest = std::max(steepest, (b - a) / h);
    }
    EXPECT_NEAR((1.0 / 255.0) / steepest, kDisplayQuantum, 0.01 * kDisplayQuantum);
    // The reach: a white Lambertian surface facing the light there gets its share of the fraction.
    const float reach = light_cutoff_distance(2.0f, 0.5f, 64);
    EXPECT_NEAR(2.0 / (3.14159265 * reach * reach), 0.5 * kDisplayQuantum / 64.0, 1e-3 * 0.5 * kDisplayQuantum / 64.0);
    EXPECT_EQ(light_cutoff_distance(2.0f, 0.0f, 64), 0.0f) << "lights.cutoff=0: unbounded";
}

TEST_P(GlTest, LightsWithoutARangeStopWhereTheirLightIsBelowTheCutoff) {
    const int lamps = 64;
    const Scene scene = make_street_scene(lamps);
    const float fraction = RenderSettings{}.lights.cutoff;
    ASSERT_GT(fraction, 0.0f);
    const float reach = light_cutoff_distance(2.0f, fraction, lamps);
    std::printf("reach %.0f m along a %d m street\n", reach, 20 * lamps);
    EXPECT_LT(reach, 0.5f * 20.0f * static_cast<float>(lamps)) << "the far lamps must be out of the near tiles' reach";
    for (const RenderPath path : {RenderPath::forward, RenderPath::deferred}) {
        SCOPED_TRACE(path == RenderPath::forward ? "forward" : "deferred");
        StillOptions cut;
        cut.width = 100;
        cut.height = 60;
        cut.settings.path = path;
        StillOptions whole = cut;
        apply_knob(whole.settings, "lights.cutoff=0");
        const StillResult a = render_still(scene, shaders(), cut);
        const StillResult b = render_still(scene, shaders(), whole);
        EXPECT_EQ(a.features.ranged_lights, lamps);
        EXPECT_EQ(b.features.ranged_lights, 0);
        EXPECT_EQ(count_nonfinite(a.radiance), 0u);
        EXPECT_EQ(count_nonfinite(b.radiance), 0u);
        double worst = 0.0, worst_linear = 0.0, brightest = 0.0;
        for (int y = 0; y < a.radiance.height; ++y)
            for (int x = 0; x < a.radiance.width; ++x) {
                const glm::vec3 la(a.radiance.at(x, y)[0], a.radiance.at(x, y)[1], a.radiance.at(x, y)[2]);
                const glm::vec3 lb(b.radiance.at(x, y)[0], b.radiance.at(x, y)[1], b.radiance.at(x, y)[2]);
                const glm::vec3 d = glm::abs(display_transform(la, 0.0f) - display_transform(lb, 0.0f));
                worst = std::max(worst, static_cast<double>(std::max({d.x, d.y, d.z})));
                worst_linear = std::max(worst_linear, static_cast<double>(lb.x - la.x));
                brightest = std::max(brightest, static_cast<double>(lb.x));
                EXPECT_LE(la.x, lb.x) << "a cut only takes light away";
            }
        std::printf("largest display difference %.5f (one 8-bit step %.5f), linear %.3g (the cut's bound %.3g), brightest %.3f\n",
                    worst, 1.0 / 255.0, worst_linear, fraction * kDisplayQuantum, brightest);
        EXPECT_LE(worst_linear, fraction * kDisplayQuantum * 0.5 * 1.001) << "asphalt of albedo 0.5: half the white bound";
        EXPECT_LE(worst, 1.0 / 255.0);
        EXPECT_GT(worst_linear, 0.0) << "the cut changes something";
        EXPECT_GT(brightest, 0.05) << "the lamps light the road";
        if (path == RenderPath::forward) {
            StillOptions untiled = cut;
            apply_knob(untiled.settings, "forward.light_tiles=0");
            const StillResult c = render_still(scene, shaders(), untiled);
            EXPECT_EQ(count_nonfinite(c.radiance), 0u);
            EXPECT_TRUE(a.features.forward_light_tiles);
            EXPECT_EQ(a.radiance.pixels, c.radiance.pixels) << "a light beyond its reach adds exactly 0";
        }
    }
}

TEST_P(GlTest, MirroredNodeIsNotCulled) {
    const Scene scene = load_gltf(lambert_plane_scene("mirrored", {{"type", "directional"}, {"intensity", 1.0}}, nullptr, true));
    StillOptions o;
    o.width = o.height = 16;
    const StillResult r = render_still(scene, shaders(), o);
    EXPECT_NEAR(r.radiance.at(8, 8)[0], 1.0f / 3.14159265f, 1e-4f);
}

INSTANTIATE_TEST_SUITE_P(Backends, GlTest, ::testing::Values(Backend::egl, Backend::osmesa), test::backend_name);

}  // namespace
}  // namespace candela

namespace candela {
namespace {

TEST(Contexts, WindowWithoutDisplayIsAClearErrorNotACrash) {
    const char* saved = std::getenv("DISPLAY");
    const std::string keep = saved ? saved : "";
    unsetenv("DISPLAY");
    unsetenv("WAYLAND_DISPLAY");
    ContextResult r = create_context(Backend::glfw, {});
    if (!keep.empty()) setenv("DISPLAY", keep.c_str(), 1);
    ASSERT_FALSE(r.context);
    EXPECT_NE(r.error.find("glfw"), std::string::npos) << r.error;
    EXPECT_NE(r.error.find("xvfb-run"), std::string::npos) << r.error;
}

TEST(Contexts, MissingFeaturesAreNamedOnlyWhenNeitherCoreNorExtension) {
    // A 4.5 driver lacks nothing, whatever it lists.
    EXPECT_EQ(detail::missing_gl_features(45, {}), "");
    // 4.4 with clip control as an extension lacks nothing; without it, exactly the 4.5 features
    // that are not listed.
    EXPECT_EQ(detail::missing_gl_features(44, {"GL_ARB_clip_control", "GL_ARB_direct_state_access",
                                               "GL_ARB_texture_barrier"}), "");
    const std::string m44 = detail::missing_gl_features(44, {"GL_ARB_direct_state_access", "GL_ARB_texture_barrier"});
    EXPECT_EQ(m44, "GL_ARB_clip_control (reversed-Z depth)");
    // 3.3 with no extensions lacks compute among others, and not timer queries (core in 3.3).
    const std::string m33 = detail::missing_gl_features(33, {});
    EXPECT_NE(m33.find("GL_ARB_compute_shader"), std::string::npos) << m33;
    EXPECT_EQ(m33.find("GL_ARB_timer_query"), std::string::npos) << m33;
}

}  // namespace
}  // namespace candela

namespace candela {
namespace {

const fs::path kSceneDir = fs::path(CANDELA_SOURCE_DIR) / "samples" / "scenes";

StillResult render_sample(const std::string& scene_name, const std::string& effects, int size = 48,
                          const std::vector<std::string>& knobs = {}) {
    const Scene scene = load_gltf(kSceneDir / (scene_name + ".gltf"));
    StillOptions o;
    o.width = o.height = size;
    o.verify_state = true;  // every pass must leave GL as the state cache believes
    apply_effects(o.settings, effects);
    for (const auto& k : knobs) apply_knob(o.settings, k);
    return render_still(scene, shaders(), o);
}

std::vector<std::string> pass_names(const StillResult& r) {
    std::vector<std::string> names;
    for (const auto& p : r.report.passes) names.push_back(p.name);
    return names;
}

// The frame plan per sample scene and the images of unneeded effects switched: the plan is CPU
// code and both backends run the same llvmpipe, so these run on egl only (CI time: 34 s a
// backend); every sample scene renders on osmesa in golden.samples.osmesa, forward and deferred.
class GlPlanTest : public test::GlContextTest {};
INSTANTIATE_TEST_SUITE_P(Egl, GlPlanTest, ::testing::Values(Backend::egl), test::backend_name);

TEST_P(GlPlanTest, ExecutedPassesPerSampleScene) {
    using V = std::vector<std::string>;
    const std::vector<std::tuple<std::string, std::string, V>> expected = {
        // cornell_box: area light only, no ambient. Both boxes are closed rooms: the GI probes carry
        // their indirect light, and RSM (switched on by "all") stays off so as not to add the first
        // bounce twice.
        {"cornell_box", "all", V{"shadow_maps", "gi_probes", "forward_opaque"}},
        {"cornell_box", "shadows,rsm", V{"shadow_maps", "rsm", "depth_normal_prepass", "rsm_indirect", "forward_opaque"}},
        {"cornell_point", "all", V{"shadow_maps", "gi_probes", "forward_opaque"}},
        {"cornell_point", "shadows", V{"shadow_maps", "forward_opaque"}},
        {"cornell_point", "none", V{"forward_opaque"}},
        // spheres (17 %) and transparency (20 %) measure more indirect light than gi.threshold:
        // the probes carry it, and RSM stays off.
        {"spheres", "all", V{"shadow_maps", "gi_probes", "env_probe", "depth_normal_prepass", "ssao", "ssao_blur_x", "ssao_blur_y", "forward_opaque", "sky"}},
        {"shadow_test", "shadows,ssao", V{"shadow_maps", "depth_normal_prepass", "ssao", "ssao_blur_x", "ssao_blur_y", "forward_opaque", "sky"}},
        {"shadow_test", "shadows,rsm", V{"shadow_maps", "rsm", "depth_normal_prepass", "rsm_indirect", "forward_opaque", "sky"}},
        {"transparency", "all", V{"shadow_maps", "gi_probes", "depth_normal_prepass", "ssao", "ssao_blur_x", "ssao_blur_y", "forward_opaque", "sky", "transparent"}},
        {"transparency", "none", V{"forward_opaque", "sky"}},
        {"reflections", "shadows", V{"shadow_maps", "forward_opaque", "sky"}},
        {"reflections", "shadows,reflections", V{"shadow_maps", "env_probe", "forward_opaque", "sky"}},
        {"reflections", "reflections --path deferred", V{"env_probe", "gbuffer", "deferred_lighting", "transmissive", "sky"}},
        {"cornell_point", "shadows --path deferred", V{"shadow_maps", "gbuffer", "deferred_lighting"}},
        {"cornell_point", "shadows,rsm --path deferred", V{"shadow_maps", "rsm", "gbuffer", "rsm_indirect", "deferred_lighting"}},
        {"transparency", "shadows,ssao,transparency --path deferred", V{"shadow_maps", "gbuffer", "ssao", "ssao_blur_x", "ssao_blur_y", "deferred_lighting", "sky", "transparent"}},
        {"cornell_point", "none --path deferred", V{"gbuffer", "deferred_lighting"}},
    };
    for (const auto& [scene, effects_and_path, passes] : expected) {
        SCOPED_TRACE(scene + " --effects " + effects_and_path);
        const size_t space = effects_and_path.find(' ');
        const std::string effects = effects_and_path.substr(0, space);
        std::vector<std::string> knobs;
        if (space != std::string::npos) knobs.push_back("render.path=deferred");
        const StillResult r = render_sample(scene, effects, 48, knobs);
        EXPECT_EQ(pass_names(r), passes);
        // The tonemap pass is declared every frame; for an HDR-only frame nobody reads it.
        ASSERT_EQ(r.report.culled.size(), 1u);
        EXPECT_EQ(r.report.culled[0].first, "tonemap");
        EXPECT_EQ(count_nonfinite(r.radiance), 0u);
        for (const auto& p : r.report.passes) {
            EXPECT_GE(p.gpu_ms, 0.0) << p.name;  // the timer query answered
            EXPECT_GT(p.counters.draw_calls + p.counters.dispatches, 0) << p.name;
        }
    }
}

TEST_P(GlTest, GpuTonemapMatchesTheCppTransform) {
    const Scene scene = load_gltf(kSceneDir / "spheres.gltf");
    StillOptions o;
    o.width = o.height = 40;
    o.output = FrameOutput::display;
    o.exposure_ev = 0.5f;
    const StillResult r = render_still(scene, shaders(), o);
    ASSERT_EQ(r.display.size(), 40u * 40u * 4u);
    EXPECT_EQ(r.report.passes.back().name, "tonemap");
    int off_by_more_than_one = 0;
    for (int y = 0; y < 40; ++y)
        for (int x = 0; x < 40; ++x) {
            const float* hdr = r.radiance.at(x, y);
            const glm::vec3 expected = display_transform(glm::vec3(hdr[0], hdr[1], hdr[2]), 0.5f) * 255.0f;
            for (int c = 0; c < 3; ++c)
                off_by_more_than_one += std::abs(r.display[static_cast<size_t>((y * 40 + x) * 4 + c)] - expected[c]) > 1.0f;
        }
    EXPECT_EQ(off_by_more_than_one, 0);
}

TEST_P(GlPlanTest, SwitchingAnUnneededEffectChangesNothing) {
    // cornell_point needs shadows and GI (which leaves RSM out): no transparency, reflections or
    // SSAO (no ambient light).
    const StillResult all = render_sample("cornell_point", "all");
    for (const char* effects : {"shadows,gi", "shadows,gi,rsm,transparency,reflections", "shadows,gi,ssao"}) {
        SCOPED_TRACE(effects);
        const StillResult other = render_sample("cornell_point", effects);
        EXPECT_EQ(pass_names(other), pass_names(all));
        EXPECT_EQ(other.radiance.pixels, all.radiance.pixels);  // bit-identical
    }
    // Shadows and GI are needed: switching either off changes the image.
    EXPECT_NE(render_sample("cornell_point", "gi").radiance.pixels, all.radiance.pixels);
    EXPECT_NE(render_sample("cornell_point", "shadows").radiance.pixels, all.radiance.pixels);
    // transparency.gltf does need transparency: switching it off must change the image.
    EXPECT_NE(render_sample("transparency", "none").radiance.pixels, render_sample("transparency", "all").radiance.pixels);
}

TEST_P(GlTest, DepthPrepassGivesTheSameImage) {
    for (const char* scene : {"spheres", "transparency"}) {
        SCOPED_TRACE(scene);
        // (SSAO off: with it the forward path always draws a depth + normal prepass.)
        const StillResult plain = render_sample(scene, "shadows,transparency");
        const StillResult prepass = render_sample(scene, "shadows,transparency", 48, {"forward.depth_prepass=1"});
        EXPECT_EQ(pass_names(prepass).at(1), "depth_prepass");  // after shadow_maps
        const CompareResult c = compare(prepass.radiance, plain.radiance, 1e-6);
        EXPECT_EQ(c.failing_pixels, 0u) << "max difference " << c.max_abs;
    }
}

TEST_P(GlTest, StateCacheSkipsRedundantCallsAndDetectsBypass) {
    gl::StateCache cache;
    gl::PipelineState ps;
    ps.depth_test = true;
    cache.apply(ps);
    const int real = cache.real_calls();
    cache.apply(ps);
    EXPECT_EQ(cache.real_calls(), real);  // nothing changed, nothing called
    EXPECT_GT(cache.skipped_calls(), 0);
    EXPECT_EQ(cache.verify(), "");
    glEnable(GL_BLEND);  // behind the cache's back
    EXPECT_EQ(cache.verify(), "GL_BLEND");
    cache.reset();
    cache.apply(ps);
    EXPECT_EQ(cache.verify(), "");
}

TEST_P(GlTest, TexturePoolKeepsTexturesAcrossFrames) {
    const Scene scene = load_gltf(kSceneDir / "transparency.gltf");
    GpuScene gpu(scene);
    const ShaderLibrary lib = shaders();  // the renderer keeps a reference
    Renderer renderer(lib, scene, gpu, RenderSettings{});
    const Camera camera = scene.select_camera("", 1.0f);
    renderer.render(camera, 32, 32);
    const int after_first = renderer.pool().allocations();
    // Depth, normals, the AO buffer and the first blur's target; the second blur reuses the AO
    // buffer's texture (its lifetime is over). The HDR output and shadow maps are the renderer's own.
    EXPECT_EQ(after_first, 4);
    for (int i = 0; i < 3; ++i) renderer.render(camera, 32, 32);
    EXPECT_EQ(renderer.pool().allocations(), after_first);
    EXPECT_EQ(renderer.pool().in_use(), 0);
}

}  // namespace
}  // namespace candela
