// The frame graph without GL: culling, lifetimes, pool reuse, no aliasing; RenderSettings; the
// many-lights generator.
#include <gtest/gtest.h>

#include "core/error.hpp"
#include "render/frame_graph.hpp"
#include "effects/area_lights/area_lights.hpp"
#include "effects/reflections/reflections.hpp"
#include "render/settings.hpp"
#include "scene/generate.hpp"

namespace candela {
namespace {

// A pool whose "textures" are empty handles: slot bookkeeping only, no GL.
TexturePool fake_pool() {
    return TexturePool([](const TextureDesc&) { return gl::Texture(); });
}

struct Graph {
    FrameGraph graph;
    std::vector<std::string> executed;
    void pass(const std::string& name, const FrameGraph::Setup& setup) {
        graph.add_pass(name, setup, [this, name](FrameGraph::Context&) { executed.push_back(name); });
    }
    void run(TexturePool& pool) {
        graph.compile(pool);
        gl::StateCache state;
        graph.execute(state);
        graph.release(pool);
    }
};

const TextureDesc kColor{GL_RGBA16F, 64, 64};
const TextureDesc kDepth{GL_DEPTH_COMPONENT32F, 64, 64};

TEST(FrameGraph, PassWhoseOutputNobodyReadsIsCulledAndAllocatesNothing) {
    TexturePool pool = fake_pool();
    Graph g;
    FrameGraph::ResourceId out = -1, unused = -1;
    g.pass("main", [&](FrameGraph::Builder& b) { out = b.create("color", kColor); });
    g.pass("debug_view", [&](FrameGraph::Builder& b) {
        b.read(out);
        unused = b.create("debug", {GL_RGBA8, 64, 64});
    });
    g.graph.mark_output(out);
    g.run(pool);
    EXPECT_EQ(g.executed, std::vector<std::string>{"main"});
    EXPECT_TRUE(g.graph.passes()[1].culled);
    EXPECT_EQ(g.graph.resources()[static_cast<size_t>(unused)].slot, -1);
    EXPECT_EQ(pool.allocations(), 1);  // only "color"
}

TEST(FrameGraph, CullingFollowsDependenciesBackwards) {
    TexturePool pool = fake_pool();
    Graph g;
    FrameGraph::ResourceId a = -1, b_res = -1, c = -1;
    g.pass("make_a", [&](FrameGraph::Builder& b) { a = b.create("a", kColor); });
    g.pass("make_b", [&](FrameGraph::Builder& b) { b_res = b.create("b", kColor); });  // feeds nothing
    g.pass("make_c", [&](FrameGraph::Builder& b) {
        b.read(a);
        c = b.create("c", kColor);
    });
    g.pass("draw_over_c", [&](FrameGraph::Builder& b) { b.write(c); });
    g.graph.mark_output(c);
    g.run(pool);
    EXPECT_EQ(g.executed, (std::vector<std::string>{"make_a", "make_c", "draw_over_c"}));
}

TEST(FrameGraph, SideEffectPassesSurvive) {
    TexturePool pool = fake_pool();
    Graph g;
    g.pass("readback", [&](FrameGraph::Builder& b) {
        b.create("x", kColor);
        b.side_effect();
    });
    g.run(pool);
    EXPECT_EQ(g.executed, std::vector<std::string>{"readback"});
}

TEST(FrameGraph, PoolReusesTexturesOfDisjointLifetimesAndNeverAliasesLiveOnes) {
    TexturePool pool = fake_pool();
    Graph g;
    // A chain of blur-like passes: each reads the previous temporary and writes a new one.
    std::vector<FrameGraph::ResourceId> tmp(6, -1);
    g.pass("p0", [&](FrameGraph::Builder& b) { tmp[0] = b.create("t0", kColor); });
    for (int i = 1; i < 6; ++i)
        g.pass("p" + std::to_string(i), [&, i](FrameGraph::Builder& b) {
            b.read(tmp[static_cast<size_t>(i - 1)]);
            tmp[static_cast<size_t>(i)] = b.create("t" + std::to_string(i), kColor);
        });
    g.pass("depth_user", [&](FrameGraph::Builder& b) {
        b.read(tmp[5]);
        b.create("depth", kDepth);
        b.side_effect();
    });
    g.run(pool);
    EXPECT_EQ(g.executed.size(), 7u);
    // Two colour textures ping-pong for six temporaries, plus one depth.
    EXPECT_EQ(pool.allocations(), 3);
    EXPECT_LT(pool.allocations(), static_cast<int>(g.executed.size()));
    // No two resources with overlapping lifetimes share a slot.
    const auto& res = g.graph.resources();
    for (size_t i = 0; i < res.size(); ++i)
        for (size_t j = i + 1; j < res.size(); ++j) {
            if (res[i].slot < 0 || res[i].slot != res[j].slot) continue;
            const bool overlap = res[i].first <= res[j].last && res[j].first <= res[i].last;
            EXPECT_FALSE(overlap) << res[i].name << " and " << res[j].name << " share slot " << res[i].slot;
        }
    // The next frame allocates nothing new.
    Graph again;
    again.pass("p0", [&](FrameGraph::Builder& b) { tmp[0] = b.create("t0", kColor); });
    again.pass("p1", [&](FrameGraph::Builder& b) {
        b.read(tmp[0]);
        b.create("t1", kColor);
        b.side_effect();
    });
    again.run(pool);
    EXPECT_EQ(pool.allocations(), 3);
    EXPECT_EQ(pool.in_use(), 0);
}

TEST(FrameGraph, ReadingAResourceNoPassMadeIsAProgrammerError) {
    Graph g;
    EXPECT_THROW(g.pass("early_reader", [&](FrameGraph::Builder& b) { b.read(0); }), Error);
    EXPECT_THROW(g.pass("bad_writer", [&](FrameGraph::Builder& b) { b.write(7); }), Error);
}

// generated:lights-bounded:N keeps the lights that reach a point of the floor about constant in
// N (the scene on which the cost of many lights is judged); generated:lights:N does not.
TEST(ManyLightsScene, BoundedLightsReachEachPointAboutAsOftenAtAnyCount) {
    auto mean_reaching = [](const Scene& scene) {
        double sum = 0.0;
        int points = 0;
        for (float x = -9.0f; x <= 9.0f; x += 0.5f)
            for (float z = -9.0f; z <= 9.0f; z += 0.5f, ++points)
                for (const auto& placed : scene.placed_lights())
                    sum += glm::distance(placed.position, glm::vec3(x, 0.0f, z)) < placed.light->range;
        return sum / points;
    };
    const double few = mean_reaching(make_many_lights_scene(16, true)), many = mean_reaching(make_many_lights_scene(256, true));
    EXPECT_GT(few, 0.3);
    EXPECT_LT(many, 2.0 * few);
    EXPECT_GT(many, 0.5 * few);
    EXPECT_GT(mean_reaching(make_many_lights_scene(256, false)), 8.0 * few);  // the unbounded scene grows with N
    EXPECT_EQ(make_many_lights_scene(256, true).source, "generated:lights-bounded:256");
}

TEST(Settings, EffectsParsing) {
    RenderSettings s;
    apply_effects(s, "none");
    for (const std::string& n : effect_names()) EXPECT_FALSE(s.on(n)) << n;
    apply_effects(s, "ssao,transparency");
    EXPECT_TRUE(s.on("ssao") && s.on("transparency"));
    EXPECT_FALSE(s.on("shadows") || s.on("rsm") || s.on("reflections"));
    apply_effects(s, "all");
    for (const std::string& n : effect_names()) EXPECT_TRUE(s.on(n)) << n;
    try {
        apply_effects(s, "ssao,bloom");
        ADD_FAILURE();
    } catch (const Error& e) {
        EXPECT_EQ(e.code(), ExitCode::bad_input);
        EXPECT_NE(std::string(e.what()).find("unknown effect 'bloom'"), std::string::npos);
    }
}

TEST(Settings, KnobsAreRangeCheckedAndNamed) {
    RenderSettings s;
    apply_knob(s, "arealight.samples=5");
    EXPECT_EQ(s.get<AreaLightsOptions>().samples, 5);
    apply_knob(s, "forward.depth_prepass=on");
    EXPECT_TRUE(s.forward.depth_prepass);
    apply_knob(s, "reflections.max_roughness=0.5");
    EXPECT_FLOAT_EQ(s.get<ReflectionsOptions>().max_roughness, 0.5f);
    auto message = [&](const std::string& assignment) {
        try {
            apply_knob(s, assignment);
        } catch (const Error& e) {
            EXPECT_EQ(e.code(), ExitCode::bad_input);
            return std::string(e.what());
        }
        return std::string("(accepted)");
    };
    EXPECT_NE(message("arealight.samples=0").find("arealight.samples=0: expected int in [1, 64]"), std::string::npos);
    EXPECT_NE(message("arealight.samples=2.5").find("[1, 64]"), std::string::npos);
    EXPECT_NE(message("shadows.filter=blur").find("hard|pcf|pcss"), std::string::npos);
    EXPECT_NE(message("reflections.max_roughness=nan").find("[0, 1]"), std::string::npos);
    EXPECT_NE(message("forward.depth_prepass=maybe").find("bool"), std::string::npos);
    EXPECT_NE(message("bloom.strength=1").find("unknown knob 'bloom.strength'"), std::string::npos);
    EXPECT_NE(message("novalue").find("expected KNOB=VALUE"), std::string::npos);
    EXPECT_EQ(s.get<AreaLightsOptions>().samples, 5);  // rejected values change nothing
}

}  // namespace
}  // namespace candela
