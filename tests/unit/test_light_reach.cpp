// The lights' reach as info and the viewer report it (render/light_reach.hpp): what is culled per
// tile follows the lights' ranges and lights.cutoff, a light out of view is in no tile, a light
// that nothing bounds is in every tile, and the counts do not depend on where the scene sits
// (checked up to 1e5 from the origin).
#include <gtest/gtest.h>

#include <glm/gtc/matrix_transform.hpp>

#include "render/gpu_scene.hpp"
#include "render/light_reach.hpp"
#include "scene/generate.hpp"

namespace candela {
namespace {

constexpr int kW = 320, kH = 180;

glm::mat4 view_proj_of(const Scene& scene) {
    const float aspect = static_cast<float>(kW) / static_cast<float>(kH);
    const Camera cam = scene.select_camera("", aspect);
    return projection_matrix(cam, aspect) * glm::inverse(cam.world);
}

// A scene of one light (and no geometry), seen by a camera at the origin looking down -z.
Scene one_light(LightType type, glm::vec3 at, float range, float intensity = 1.0f) {
    Scene scene;
    Light l;
    l.type = type;
    l.range = range;
    l.intensity = intensity;
    scene.lights.push_back(l);
    Node n;
    n.light = 0;
    n.local = glm::translate(glm::mat4(1.0f), at);
    scene.roots.push_back(0);
    scene.nodes.push_back(n);
    add_look_at_camera(scene, glm::vec3(0.0f), glm::vec3(0.0f, 0.0f, -1.0f), 0.8f);
    scene.update_world_transforms();
    return scene;
}

TEST(LightReach, RangesCullAndUnboundedLightsReachEveryTile) {
    const int tiles = ((kW + 15) / 16) * ((kH + 15) / 16);
    {
        const Scene s = one_light(LightType::directional, glm::vec3(0.0f), 0.0f);
        const LightReach r = light_reach(s, 0.5f, view_proj_of(s), kW, kH);
        EXPECT_EQ(r.tiles, tiles);
        EXPECT_EQ(r.unbounded, 1);
        EXPECT_DOUBLE_EQ(r.per_tile_mean, 1.0);
        EXPECT_EQ(r.per_tile_max, 1);
    }
    {  // 1 m of range, 10 m in front: a small part of the image.
        const Scene s = one_light(LightType::point, glm::vec3(0.0f, 0.0f, -10.0f), 1.0f);
        const LightReach r = light_reach(s, 0.5f, view_proj_of(s), kW, kH);
        EXPECT_EQ(r.ranged, 1);
        EXPECT_EQ(r.per_tile_max, 1);
        EXPECT_GT(r.per_tile_mean, 0.0);
        EXPECT_LT(r.per_tile_mean, 0.2);
    }
    {  // The same light behind the camera, farther than its range: in no tile.
        const Scene s = one_light(LightType::point, glm::vec3(0.0f, 0.0f, 10.0f), 1.0f);
        const LightReach r = light_reach(s, 0.5f, view_proj_of(s), kW, kH);
        EXPECT_EQ(r.per_tile_max, 0);
    }
    {  // Beside the view, out of its frustum: in no tile.
        const Scene s = one_light(LightType::point, glm::vec3(50.0f, 0.0f, -10.0f), 1.0f);
        EXPECT_EQ(light_reach(s, 0.5f, view_proj_of(s), kW, kH).per_tile_max, 0);
    }
    {  // No range: lights.cutoff gives it a reach; with lights.cutoff=0 it reaches everywhere.
        const Scene s = one_light(LightType::point, glm::vec3(0.0f, 0.0f, -200.0f), 0.0f, 1e-3f);
        const LightReach cut = light_reach(s, 0.5f, view_proj_of(s), kW, kH);
        EXPECT_EQ(cut.cut, 1);
        EXPECT_FLOAT_EQ(cut.cut_min, light_cutoff_distance(1e-3f, 0.5f, 1));
        EXPECT_LT(cut.per_tile_mean, 1.0);
        const LightReach all = light_reach(s, 0.0f, view_proj_of(s), kW, kH);
        EXPECT_EQ(all.cut, 0);
        EXPECT_EQ(all.unbounded, 1);
        EXPECT_DOUBLE_EQ(all.per_tile_mean, 1.0);
    }
}

// On generated:lights-bounded:N each point of the floor is reached by about one light at any N:
// so is each tile, about, and the text says what info prints.
TEST(LightReach, BoundedLightsStayFewPerTileAtAnyCount) {
    for (const int n : {16, 64, 256}) {
        const Scene s = make_many_lights_scene(n, true);
        const LightReach r = light_reach(s, 0.5f, view_proj_of(s), kW, kH);
        EXPECT_EQ(r.lights, n);
        EXPECT_EQ(r.ranged, n);
        EXPECT_LT(r.per_tile_mean, 0.25 * n) << n << " lights: " << r.text();
        EXPECT_NE(r.text().find(std::to_string(n) + " punctual light(s): " + std::to_string(n) + " with a range"), std::string::npos) << r.text();
    }
}

// Moving the scene and the camera together culls the same.
TEST(LightReach, CountsAreInvariantUnderTranslation) {
    const Scene base = make_many_lights_scene(64, true);
    const LightReach r0 = light_reach(base, 0.5f, view_proj_of(base), kW, kH);
    for (const float offset : {1e3f, 1e5f}) {
        Scene moved = make_many_lights_scene(64, true);
        for (const int root : moved.roots) {
            Node& node = moved.nodes[static_cast<size_t>(root)];
            node.local = glm::translate(glm::mat4(1.0f), glm::vec3(offset, 0.5f * offset, -offset)) * node.local;
        }
        for (Camera& c : moved.cameras) c.world = glm::translate(glm::mat4(1.0f), glm::vec3(offset, 0.5f * offset, -offset)) * c.world;
        moved.update_world_transforms();
        const LightReach r = light_reach(moved, 0.5f, view_proj_of(moved), kW, kH);
        // A light's sphere on a tile's edge may fall either way in float at 1e5: within 2 %.
        EXPECT_NEAR(r.per_tile_mean, r0.per_tile_mean, 0.02 * r0.per_tile_mean) << offset;
    }
}

}  // namespace
}  // namespace candela
