// GI probes and transmissive (glass) surfaces. A probe ray that hits glass must see what the
// tracer's camera paths see there: a smooth dielectric that reflects or refracts the ray, with no
// diffuse lobe of its own, so the ray goes on to what lies beyond the glass. Two closed grey
// rooms, each lit by one spot, check both sides of that:
// - the spot's cone falls on a solid glass block alone. Its light reaches the room only through
//   the glass (a caustic: a punctual light seen through a smooth dielectric, which next-event
//   estimation cannot connect), so `path` finds no light on any surface, and the probes must not
//   find any either. A probe ray that shaded the glass with an opaque BRDF lit the whole room
//   with the light on the block's top face;
// - a thin glass partition splits the room; the spot lights the far half, the camera sees only
//   the near half, whose light all came through the partition. The raster image's mean is within
//   10 % of `path` (every bounce), measured in 4 independent batches whose own noise is checked
//   to be far below that. A probe ray that stopped at the glass left the near half dark.
#include <gtest/gtest.h>

#include <cmath>
#include <cstdio>

#include <glm/gtc/matrix_transform.hpp>

#include "reference_fixture.hpp"
#include "spot_room.hpp"
#include "scene/generate.hpp"
#include "scene/mesh_utils.hpp"

namespace candela {
namespace {

constexpr int kSize = 64;

Material glass_material(float thickness) {
    Material m;
    m.name = "glass";
    m.base_color = glm::vec4(0.95f, 0.95f, 0.95f, 1.0f);
    m.metallic = 0.0f;
    m.roughness = 0.0f;
    m.transmission = 1.0f;
    m.ior = 1.5f;
    m.thickness = thickness;  // 0: thin-walled
    return m;
}


// The spot 2.9 m above the floor's centre, its cone (0.23 rad: 0.49 m at the block's top) inside
// the top of a 1.2 m x 0.8 m x 1.2 m block on the floor, solid glass (`glass`) or, for the scale
// of the test, diffuse (albedo 0.8). The camera looks up from a corner at the far upper corner.
Scene block_room(bool glass) {
    Scene scene = test::spot_room(glass ? "test:gi_glass_block_room" : "test:gi_diffuse_block_room", {0, 2.9f, 0}, 0.184f, 0.23f,
                            {1.8f, 1.0f, 1.8f}, {-1.5f, 2.2f, -1.5f});
    scene.materials.push_back(glass ? glass_material(1.2f) : lambert_material("block", glm::vec3(0.8f)));
    Primitive block;
    append_box(block, {-0.6f, 0.0f, -0.6f}, {0.6f, 0.8f, 0.6f});
    block.material = 1;
    add_mesh_node(scene, "block", std::move(block));
    scene.update_world_transforms();
    return scene;
}

// A thin-walled glass partition (2 cm) across the whole room at x = 0; the spot 2.9 m above the
// floor at x = 1 (cone 0.3 rad: 0.9 m on the floor, all of it at x > 0). The camera at x < 0 looks
// away from the partition (no ray of its view reaches x = 0).
Scene partition_room() {
    Scene scene = test::spot_room("test:gi_glass_partition_room", {1.0f, 2.9f, 0}, 0.24f, 0.3f, {-0.3f, 1.0f, 1.9f}, {-2.0f, 2.2f, -0.5f});
    scene.materials.push_back(glass_material(0.0f));
    Primitive wall;
    append_box(wall, {-0.01f, 0.0f, -2.0f}, {0.01f, 3.0f, 2.0f});
    wall.material = 1;
    add_mesh_node(scene, "partition", std::move(wall));
    scene.update_world_transforms();
    return scene;
}

class GlassGiTest : public test::ReferenceTest {
protected:
    // The probes always run, with enough bounces for the room: the test is about what a probe ray
    // brings back, not about the planner's choice.
    static RenderSettings probes_on() { return settings("", {"gi.threshold=0", "gi.bounces=12"}); }
};

TEST_P(GlassGiTest, ProbesFindNoLightThatOnlyACausticThroughGlassCarries) {
    const double lit = mean_luminance(raster(block_room(false), kSize, kSize, probes_on()));
    const Scene scene = block_room(true);
    const double m = mean_luminance(raster(scene, kSize, kSize, probes_on()));
    double se = 0.0;
    const double ref = path_mean_luminance(scene, kSize, kSize, 64, se);
    std::printf("glass block room: path mean %.3g (standard error %.3g); raster %.3g; the same room with a diffuse block: "
                "raster %.5f\n", ref, se, m, lit);
    ASSERT_GT(lit, 0.0);  // the setting of the test: a lit block lights the room
    EXPECT_LT(ref, 1e-3 * lit);
    EXPECT_LT(m, 1e-2 * lit);
}

TEST_P(GlassGiTest, ProbesSeeThroughAThinGlassPartition) {
    const Scene scene = partition_room();
    const double m = mean_luminance(raster(scene, kSize, kSize, probes_on()));
    double se = 0.0;
    const double ref = path_mean_luminance(scene, kSize, kSize, 1024, se);
    RenderSettings off = probes_on();
    off.set_on("gi", false);
    const double no_gi = mean_luminance(raster(scene, kSize, kSize, off));
    std::printf("glass partition room: path mean %.5f (standard error %.5f); raster %.5f (%+.2f %%), without GI %.5f (%+.2f %%)\n",
                ref, se, m, 100.0 * (m / ref - 1.0), no_gi, 100.0 * (no_gi / ref - 1.0));
    ASSERT_GT(ref, 0.0);
    EXPECT_LT(se, 0.01 * ref);       // the reference's noise does not decide the test
    EXPECT_LT(no_gi, 0.1 * ref);     // the setting of the test: the light came through the glass
    EXPECT_LT(std::abs(m / ref - 1.0), 0.10);
}

INSTANTIATE_TEST_SUITE_P(Backends, GlassGiTest, ::testing::Values(Backend::egl), test::backend_name);

}  // namespace
}  // namespace candela
