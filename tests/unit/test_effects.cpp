// The effect registry (engine/effects/): every module is reachable by name, owns its knobs and
// programs, and its uniform block has the same layout in C++ and in the GL.
#include <gtest/gtest.h>

#include <algorithm>
#include <set>
#include <tuple>

#include <nlohmann/json.hpp>

#include "core/error.hpp"
#include "effects/aa/aa.hpp"
#include "effects/area_lights/area_lights_data.h"
#include "effects/reflections/reflections_data.h"
#include "effects/rsm/rsm_data.h"
#include "effects/shadows/shadows_data.h"
#include "render/effect_registry.hpp"
#include "gl_fixture.hpp"
#include "render/features.hpp"
#include "gpu/bindings.h"
#include "gpu/rt_frame.h"
#include "gpu/rt_scene.h"
#include "gpu/scene_blocks.h"
#include "render/gpu_scene.hpp"
#include "render/settings.hpp"
#include "rt/tracer_options.hpp"
#include "render/program_catalog.hpp"

namespace candela {
namespace {

// Every effect `info` names is either an --effects switch or refused with a message saying how
// it is planned instead (never "unknown effect"); a knob that asks for an effect's work turns it on.
TEST(EffectRegistry, EveryEffectNameIsASwitchOrSaysWhyNot) {
    for (const Effect* e : effect_registry()) {
        RenderSettings s;
        if (e->switchable()) {
            EXPECT_NO_THROW(apply_effects(s, e->name())) << e->name();
            EXPECT_TRUE(s.on(e->name()));
            continue;
        }
        try {
            apply_effects(s, e->name());
            ADD_FAILURE() << e->name() << " was accepted but switches nothing";
        } catch (const Error& err) {
            EXPECT_EQ(err.code(), ExitCode::bad_input);
            EXPECT_NE(std::string(err.what()).find("is not switched with --effects"), std::string::npos) << err.what();
            EXPECT_EQ(std::string(err.what()).find("unknown effect"), std::string::npos) << err.what();
        }
    }
}

TEST(EffectRegistry, AskingForSamplesTurnsMultisamplingOn) {
    RenderSettings s;
    EXPECT_EQ(s.get<AaOptions>().mode, AaMode::off);
    apply_knobs(s, {"aa.samples=4"});
    EXPECT_EQ(s.get<AaOptions>().mode, AaMode::msaa);
    EXPECT_EQ(static_cast<int>(s.get<AaOptions>().samples), 4);
    // Given with aa.mode, the mode says: in either order.
    for (const auto& list : {std::vector<std::string>{"aa.samples=4", "aa.mode=off"}, std::vector<std::string>{"aa.mode=off", "aa.samples=8"}}) {
        RenderSettings t;
        apply_knobs(t, list);
        EXPECT_EQ(t.get<AaOptions>().mode, AaMode::off);
    }
    RenderSettings one;
    apply_knobs(one, {"aa.samples=1"});
    EXPECT_EQ(one.get<AaOptions>().mode, AaMode::off);
}

TEST(EffectRegistry, NamesKnobsAndProgramsBelongToTheirEffect) {
    std::set<std::string> names, programs;
    for (const Effect* e : effect_registry()) {
        EXPECT_TRUE(names.insert(e->name()).second) << "duplicate effect " << e->name();
        EXPECT_EQ(find_effect(e->name()), e);
        // Its switch is an --effects name (unless it always runs when called for), and its knobs
        // are all "group.knob" for one of its groups.
        const bool listed = std::find(effect_names().begin(), effect_names().end(), e->name()) != effect_names().end();
        EXPECT_EQ(listed, e->switchable()) << e->name();
        for (const Knob& k : e->knobs()) {
            const auto groups = e->knob_groups();
            EXPECT_TRUE(std::any_of(groups.begin(), groups.end(), [&](const std::string& g) { return k.info.name.rfind(g + ".", 0) == 0; }))
                << k.info.name;
        }
        // Its programs are in the catalog, under names no other program has.
        for (const ProgramDesc& p : e->programs()) {
            EXPECT_TRUE(programs.insert(p.name).second) << "duplicate program " << p.name;
            EXPECT_EQ(program_desc(p.name).stages, p.stages);
        }
    }
    EXPECT_EQ(find_effect("bloom"), nullptr);
    std::set<std::string> knob_names;
    for (const Knob& k : knobs()) EXPECT_TRUE(knob_names.insert(k.info.name).second) << "duplicate knob " << k.info.name;
}

TEST(EffectRegistry, EveryKnobRoundTripsThroughItsRow) {
    // Writing each knob's JSON value back through --set leaves the settings unchanged, and a
    // value out of range names the knob.
    RenderSettings s;
    const nlohmann::json before = to_json(s);
    for (const Knob& k : knobs()) {
        const nlohmann::json v = k.get(s);
        const std::string text = v.is_string() ? v.get<std::string>() : v.is_boolean() ? (v.get<bool>() ? "1" : "0") : v.dump();
        EXPECT_NO_THROW(apply_knob(s, k.info.name + "=" + text)) << k.info.name;
        if (k.info.type == "int" || k.info.type == "float") {
            try {
                apply_knob(s, k.info.name + "=1e30");
                ADD_FAILURE() << k.info.name << " accepted 1e30";
            } catch (const Error& e) {
                EXPECT_NE(std::string(e.what()).find(k.info.name), std::string::npos);
            }
        }
    }
    EXPECT_EQ(to_json(s), before);
}

TEST(EffectRegistry, ChoiceKnobsAreEnumsWithNamedValues) {
    RenderSettings s;
    for (const Knob& k : knobs()) {
        if (k.info.type != "choice" || k.info.choices.empty()) continue;
        for (const std::string& c : k.info.choices) {
            apply_knob(s, k.info.name + "=" + c);
            EXPECT_EQ(k.get(s), c) << k.info.name;
        }
        EXPECT_THROW(apply_knob(s, k.info.name + "=nonsense"), Error);
    }
}

using EffectBlocks = test::GlContextTest;

TEST_P(EffectBlocks, CxxStructsMatchTheGlslBlocks) {
    const ShaderLibrary shaders = serve_effect_shading(ShaderLibrary(ShaderLibrary::default_root()));
    std::set<int> bindings = {FRAME_BINDING, RT_FRAME_BINDING};
    int checked = 0;
    for (const Effect* e : effect_registry())
        for (const GpuBlockInfo& b : e->gpu_blocks()) {
            EXPECT_TRUE(bindings.insert(b.binding).second) << b.block << ": binding " << b.binding << " taken";
            ShaderLibrary::BuildResult r = shaders.build(program_desc(b.program));
            ASSERT_TRUE(r.ok()) << r.log;
            const GLuint index = glGetProgramResourceIndex(r.program.id(), GL_UNIFORM_BLOCK, b.block);
            ASSERT_NE(index, GL_INVALID_INDEX) << b.block << " not in program " << b.program;
            const GLenum props[2] = {GL_BUFFER_DATA_SIZE, GL_BUFFER_BINDING};
            GLint values[2] = {0, -1};
            glGetProgramResourceiv(r.program.id(), GL_UNIFORM_BLOCK, index, 2, props, 2, nullptr, values);
            EXPECT_EQ(static_cast<std::size_t>(values[0]), b.size) << b.block << ": the C++ struct and the GLSL block differ";
            EXPECT_EQ(values[1], b.binding) << b.block;
            ++checked;
        }
    EXPECT_GT(checked, 0);
}

// The base's and the tracer's blocks (gpu/scene_blocks.h, gpu/rt_frame.h, gpu/rt_scene.h): the
// frame blocks and the storage buffers of materials, lights, spheres and emitters, whose size
// with one element is the C++ struct's; likewise the effects' storage buffers (shadow views, RSM
// views, area-light polygons, reflection probes).
TEST_P(EffectBlocks, BaseBlocksMatchTheGlsl) {
    const ShaderLibrary shaders = serve_effect_shading(ShaderLibrary(ShaderLibrary::default_root()));
    const ProgramDesc rt_path{"rt_path", {{ShaderStage::compute, "rt/modes/path.comp"}}, {}};
    const ProgramDesc rt_path_emitters{"rt_path", {{ShaderStage::compute, "rt/modes/path.comp"}}, {"HAS_EMITTERS"}};
    struct Block {
        GLenum interface;
        const char* name;
        int binding;
        std::size_t size;
        ProgramDesc program;
    };
    const Block blocks[] = {
        {GL_UNIFORM_BLOCK, "FrameData", FRAME_BINDING, sizeof(gpu::FrameData), program_desc("forward")},
        {GL_SHADER_STORAGE_BLOCK, "Materials", MATERIALS_BINDING, sizeof(gpu::MaterialData), program_desc("forward")},
        {GL_SHADER_STORAGE_BLOCK, "Lights", LIGHTS_BINDING, sizeof(gpu::LightData), program_desc("forward")},
        {GL_UNIFORM_BLOCK, "RtFrame", RT_FRAME_BINDING, sizeof(gpu::RtFrame), rt_path},
        {GL_SHADER_STORAGE_BLOCK, "Materials", MATERIALS_BINDING, sizeof(gpu::MaterialData), rt_path},
        {GL_SHADER_STORAGE_BLOCK, "Lights", LIGHTS_BINDING, sizeof(gpu::LightData), rt_path},
        {GL_SHADER_STORAGE_BLOCK, "Spheres", RT_SPHERES_BINDING, sizeof(gpu::RtSphere), rt_path_emitters},
        {GL_SHADER_STORAGE_BLOCK, "Emitters", RT_EMITTERS_BINDING, sizeof(gpu::Emitter), rt_path_emitters},
        {GL_SHADER_STORAGE_BLOCK, "ShadowViews", SHADOW_VIEWS_BINDING, sizeof(gpu::ShadowView), program_desc("forward")},
        {GL_SHADER_STORAGE_BLOCK, "PolygonLights", AREA_POLYGONS_BINDING, sizeof(gpu::PolygonLight), program_desc("forward")},
        {GL_SHADER_STORAGE_BLOCK, "Probes", REFLECTIONS_PROBES_BINDING, sizeof(gpu::ProbeData), program_desc("forward")},
        {GL_SHADER_STORAGE_BLOCK, "RsmViews", RSM_VIEWS_BINDING, sizeof(gpu::RsmView), program_desc("rsm_gather")},
    };
    for (const Block& b : blocks) {
        ShaderLibrary::BuildResult r = shaders.build(b.program);
        ASSERT_TRUE(r.ok()) << r.log;
        const GLuint index = glGetProgramResourceIndex(r.program.id(), b.interface, b.name);
        ASSERT_NE(index, GL_INVALID_INDEX) << b.name << " not in program " << b.program.name;
        const GLenum props[2] = {GL_BUFFER_DATA_SIZE, GL_BUFFER_BINDING};
        GLint values[2] = {0, -1};
        glGetProgramResourceiv(r.program.id(), b.interface, index, 2, props, 2, nullptr, values);
        EXPECT_EQ(static_cast<std::size_t>(values[0]), b.size) << b.name << " in " << b.program.name << ": the C++ struct and the GLSL differ";
        EXPECT_EQ(values[1], b.binding) << b.name << " in " << b.program.name;
    }
}

INSTANTIATE_TEST_SUITE_P(Backends, EffectBlocks, ::testing::Values(Backend::egl), test::backend_name);

}  // namespace
}  // namespace candela

namespace candela {
namespace {

// The tracer's options as a comparable tuple of what knobs can set.
auto tracer_fields(const rt::Options& o) {
    return std::make_tuple(o.ao_radius, o.whitted_max_roughness, o.indirect_occlusion, o.env_importance, o.visibility_light, o.jitter,
                           o.shutter_slices);
}

// One home for the tracer's settings: every knob the tracer reads (but the camera's, which reach
// it through the camera: with_lens, the shutter) changes what rt::tracer_options gives render,
// the viewer, bench accuracy and the farm; no rasterizer knob does.
TEST(TracerOptions, EveryTracerKnobReachesTheOptions) {
    const auto base = tracer_fields(rt::tracer_options(RenderSettings{}));
    int tracer_knobs = 0;
    for (const Knob& k : knobs()) {
        SCOPED_TRACE(k.info.name);
        RenderSettings s;
        const nlohmann::json now = k.get(s);
        std::string other;
        if (k.info.type == "bool") other = now.get<bool>() ? "0" : "1";
        else if (k.info.type == "int") other = std::to_string(static_cast<long long>(now.get<double>() == k.info.hi ? k.info.lo : k.info.hi));
        else if (k.info.type == "float") other = std::to_string(now.get<double>() == k.info.hi ? k.info.lo : k.info.hi);
        else
            for (const std::string& c : k.info.choices)
                if (c != now.get<std::string>()) other = c;
        ASSERT_FALSE(other.empty());
        apply_knob(s, k.info.name + "=" + other);
        const bool changed = tracer_fields(rt::tracer_options(s)) != base;
        if (k.info.name.rfind("camera.", 0) == 0) continue;
        EXPECT_EQ(changed, rt::tracer_reads_knob(k.info.name)) << "set to " << other;
        tracer_knobs += changed;
    }
    EXPECT_GE(tracer_knobs, 7);  // rt.* (5), ao.radius, debug.light
}

}  // namespace
}  // namespace candela
