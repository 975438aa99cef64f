// The automatic reflection probes are planned by what they contribute (effects/reflections/
// probes.hpp plan_probes): on a grid of 21 transmissive boxes the planned count stays within
// probe.budget, every transmissive object is served by a probe whose sphere holds it, and the
// objects that share a probe are neighbours; objects with nearly the same surroundings share one
// without any budget pressure; what shows least on screen gives up its own probe first. The
// renderer uses the plan as it is (no "first 16").
#include <gtest/gtest.h>

#include <set>

#include "effects/reflections/probes.hpp"
#include "effects/reflections/reflections.hpp"
#include "gltf_builder.hpp"
#include "reference_fixture.hpp"
#include "scene/gltf_loader.hpp"
#include "shapes.hpp"

namespace candela {
namespace {
namespace fs = std::filesystem;

constexpr int kColumns = 7, kRows = 3;
constexpr float kSpacing = 0.5f, kBoxSize = 0.2f;

// kColumns x kRows transmissive boxes in the plane z = 0 (centred on the origin), a diffuse
// backdrop behind them and a floor below, and a camera in front that sees the grid.
Scene probe_grid_scene() {
    test::GltfBuilder b;
    b.json()["materials"] = {
        {{"name", "glass"},
         {"pbrMetallicRoughness", {{"baseColorFactor", {0.9, 0.95, 1.0, 1.0}}, {"metallicFactor", 0}, {"roughnessFactor", 0}}},
         {"extensions", {{"KHR_materials_transmission", {{"transmissionFactor", 1.0}}}}}},
        {{"name", "wall"}, {"pbrMetallicRoughness", {{"baseColorFactor", {0.7, 0.6, 0.5, 1.0}}, {"metallicFactor", 0}, {"roughnessFactor", 0.8}}}}};
    const int glass = test::add_box(b, 0), wall = test::add_box(b, 1);
    for (int r = 0; r < kRows; ++r)
        for (int c = 0; c < kColumns; ++c)
            b.add_node({{"name", "glass " + std::to_string(r) + "," + std::to_string(c)},
                        {"mesh", glass},
                        {"translation", {(c - (kColumns - 1) / 2.0) * kSpacing, (r - (kRows - 1) / 2.0) * kSpacing, 0.0}},
                        {"scale", {kBoxSize, kBoxSize, kBoxSize}}});
    b.add_node({{"name", "backdrop"}, {"mesh", wall}, {"translation", {0.0, 0.0, -1.5}}, {"scale", {8.0, 5.0, 0.1}}});
    b.add_node({{"name", "floor"}, {"mesh", wall}, {"translation", {0.0, -1.2, 0.0}}, {"scale", {8.0, 0.1, 4.0}}});
    b.json()["cameras"] = {{{"type", "perspective"}, {"perspective", {{"yfov", 0.9}, {"znear", 0.05}, {"aspectRatio", 1.0}}}}};
    b.add_node({{"name", "camera"}, {"camera", 0}, {"translation", {0.0, 0.0, 3.5}}});
    return load_gltf(b.write(test::test_dir("probe_grid"), "probe_grid"));
}

float center_distance(const Bounds& a, const Bounds& b) { return glm::length(a.center() - b.center()); }

// Every object is served by a probe whose influence sphere holds its bounds.
void expect_every_object_served(const ProbePlan& plan) {
    ASSERT_EQ(plan.object_probe.size(), plan.objects.size());
    for (size_t i = 0; i < plan.objects.size(); ++i) {
        const int k = plan.object_probe[i];
        ASSERT_GE(k, 0) << plan.objects[i].name << " has no probe";
        ASSERT_LT(k, static_cast<int>(plan.probes.size()));
        const ProbePlacement& p = plan.probes[static_cast<size_t>(k)];
        const Bounds& b = plan.objects[i].bounds;
        for (int corner = 0; corner < 8; ++corner) {
            const glm::vec3 c(corner & 1 ? b.max.x : b.min.x, corner & 2 ? b.max.y : b.min.y, corner & 4 ? b.max.z : b.min.z);
            EXPECT_LE(glm::length(c - p.position), p.radius) << plan.objects[i].name << " sticks out of probe " << k;
        }
        EXPECT_NE(std::find(p.nodes.begin(), p.nodes.end(), plan.objects[i].node), p.nodes.end());
    }
}

TEST(ProbePlan, TwentyOneTransmissiveObjectsShareProbesWithinTheBudget) {
    const Scene scene = probe_grid_scene();
    const ProbeInputs in = probe_inputs(scene, 0.3f);
    ASSERT_EQ(in.objects.size(), static_cast<size_t>(kColumns * kRows)) << "the backdrop and the floor are not reflective";
    for (int budget : {1, 4, 8, 16}) {
        const ProbePlan plan = plan_probes(in, {budget, 0.25f});
        SCOPED_TRACE("budget " + std::to_string(budget) + ": " + plan.summary);
        EXPECT_LE(plan.probes.size(), static_cast<size_t>(budget));
        EXPECT_GE(plan.probes.size(), static_cast<size_t>(std::min(budget, kColumns * kRows)) - 1)
            << "merged more than the budget asks (the boxes are close to each other and to the backdrop)";
        expect_every_object_served(plan);
        // Objects that share a probe are neighbours: with 8 probes for 21 boxes no probe spans the
        // grid, every box shares with one within two grid steps.
        if (budget == 8) {
            for (size_t i = 0; i < plan.objects.size(); ++i) {
                float nearest_mate = 1e9f;
                for (size_t j = 0; j < plan.objects.size(); ++j)
                    if (j != i && plan.object_probe[j] == plan.object_probe[i])
                        nearest_mate = std::min(nearest_mate, center_distance(plan.objects[i].bounds, plan.objects[j].bounds));
                if (nearest_mate < 1e9f) EXPECT_LE(nearest_mate, 2.01f * kSpacing) << plan.objects[i].name;
            }
            for (const ProbePlacement& p : plan.probes) EXPECT_LT(p.radius, 2.0f * kSpacing) << p.origin;
        }
    }
}

TEST(ProbePlan, ObjectsWithTheSameSurroundingsShareAProbeWithoutBudgetPressure) {
    const Scene scene = probe_grid_scene();
    ProbeInputs in = probe_inputs(scene, 0.3f);
    // Far from every other surface (the grid, backdrop and floor are gone), two boxes 0.5 apart see
    // the same surroundings: one probe, even with a budget of 64.
    in.objects.resize(2);
    in.geometry.erase(std::remove_if(in.geometry.begin(), in.geometry.end(),
                                     [&](const auto& g) { return g.first != in.objects[0].node && g.first != in.objects[1].node; }),
                      in.geometry.end());
    const ProbePlan alone = plan_probes(in, {64, 0.25f});
    EXPECT_EQ(alone.probes.size(), 1u) << alone.summary;
    EXPECT_EQ(alone.merged_freely, 1);
    expect_every_object_served(alone);
    // In the grid (the neighbours 0.5 away are the surroundings), boxes keep their own probes
    // while the budget allows.
    const ProbePlan grid = plan_probes(probe_inputs(scene, 0.3f), {64, 0.25f});
    EXPECT_EQ(grid.probes.size(), static_cast<size_t>(kColumns * kRows)) << grid.summary;
}

TEST(ProbePlan, WhatShowsLeastGivesUpItsProbeFirst) {
    const Scene scene = probe_grid_scene();
    ProbeInputs in = probe_inputs(scene, 0.3f);
    // The top row covers much of the image, the others almost nothing.
    for (ProbeObject& o : in.objects) o.weight = o.bounds.center().y > 0.1f ? 1.0f : 1e-4f;
    const ProbePlan plan = plan_probes(in, {kColumns + 2, 0.25f});
    std::set<int> heavy_probes, light_probes;
    for (size_t i = 0; i < plan.objects.size(); ++i)
        (plan.objects[i].weight > 0.5f ? heavy_probes : light_probes).insert(plan.object_probe[i]);
    EXPECT_EQ(heavy_probes.size(), static_cast<size_t>(kColumns)) << "every box of the top row keeps its own probe; " << plan.summary;
    EXPECT_LE(light_probes.size(), 2u);
    // Ranked by weight: the top row's probes come first.
    for (int k : heavy_probes) EXPECT_LT(k, kColumns);
}

TEST(ProbePlan, ScreenCoverage) {
    Bounds b;
    b.extend(glm::vec3(-1.0f));
    b.extend(glm::vec3(1.0f));
    EXPECT_FLOAT_EQ(screen_coverage(b, glm::mat4(1.0f)), 1.0f);  // the whole image
    b = Bounds{};
    b.extend(glm::vec3(0.0f, 0.0f, 0.5f));
    b.extend(glm::vec3(0.5f, 0.5f, 0.5f));
    EXPECT_FLOAT_EQ(screen_coverage(b, glm::mat4(1.0f)), 0.0625f);
}

class ProbePlanRenderTest : public test::ReferenceTest {};

// The renderer's probes are the plan: at most probe.budget, every transmissive box served.
TEST_P(ProbePlanRenderTest, TheRendererUsesThePlanWithinTheBudget) {
    const Scene scene = probe_grid_scene();
    RenderSettings s;
    apply_knob(s, "probe.placement=auto");
    apply_knob(s, "probe.budget=6");
    apply_knob(s, "probe.resolution=16");
    GpuScene gpu(scene);
    Renderer r(lib_, scene, gpu, s);
    r.render(scene.select_camera("", 1.0f), 48, 48);
    EXPECT_EQ(count_nonfinite(r.read_radiance()), 0u);
    const auto* runtime = r.effect_runtime<ReflectionsRuntime>();
    ASSERT_NE(runtime, nullptr);
    const std::vector<ProbePlacement>& probes = runtime->placements();
    EXPECT_LE(probes.size(), 6u);
    EXPECT_GE(probes.size(), 5u);
    std::set<int> served;
    for (const ProbePlacement& p : probes) served.insert(p.nodes.begin(), p.nodes.end());
    for (size_t i = 0; i < scene.nodes.size(); ++i)
        if (scene.nodes[i].name.rfind("glass", 0) == 0) EXPECT_TRUE(served.count(static_cast<int>(i))) << scene.nodes[i].name;
    EXPECT_NE(runtime->plan_summary().find("21 reflective objects -> "), std::string::npos) << runtime->plan_summary();
}

INSTANTIATE_TEST_SUITE_P(Backends, ProbePlanRenderTest, ::testing::Values(Backend::egl), test::backend_name);

}  // namespace
}  // namespace candela
