// GI probes and light that a metal surface sends onward: a closed grey room whose only light is
// a spot that shines onto a large rough metal plate on the floor and nowhere else. Every bit of
// light on the walls and the ceiling came off the metal first, so a probe ray that took only the
// Lambert part of what it hits (none, for a metal) left the room black. The probe rays take the
// direct light their hit reflects towards the probe with its full BRDF: the raster image's mean is
// within 8 % of the tracer's `path` (every bounce), measured in 4 independent batches whose own
// noise is checked to be far below that. The later bounces reflect the previous probes with both
// lobes too: a larger plate in a whiter room (2.4 m, albedo 0.8) sends much of the room's own
// light back into it, which probes whose later bounces were diffuse alone left out (-12 %).
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

// A 4 m x 3 m x 4 m room (rough, albedo 0.6 unless `room_albedo`), a `plate` m square metal
// plate (roughness 0.35) 1 cm above its floor, a spot 2.9 m above the plate's centre pointing down
// whose cone (0.23 rad) falls on the plate alone. The camera stands in a corner looking up across
// the room at the far upper corner: it sees the ceiling and the walls the plate lights, and
// little of the plate.
Scene metal_plate_room(float size = 1.6f, float room_albedo = 0.6f) {
    Scene scene = test::spot_room("test:gi_metal_plate_room", {0, 2.9f, 0}, 0.18f, 0.23f,  // 2.89 tan 0.23 = 0.68 m on the plate
                                  {1.8f, 1.0f, 1.8f}, {-1.5f, 2.2f, -1.5f});
    scene.materials[0].base_color = glm::vec4(glm::vec3(room_albedo), 1.0f);
    Material metal;
    metal.name = "plate";
    metal.base_color = glm::vec4(0.95f, 0.93f, 0.88f, 1.0f);
    metal.metallic = 1.0f;
    metal.roughness = 0.35f;
    scene.materials.push_back(metal);
    Primitive plate;
    plate.material = 1;
    append_quad(plate, {-0.5f * size, 0.01f, -0.5f * size}, {0, 0, size}, {size, 0, 0});  // +y
    add_mesh_node(scene, "plate", std::move(plate));
    scene.update_world_transforms();
    return scene;
}

class MetalGiTest : public test::ReferenceTest {
protected:
    // The raster image's mean against `path`, printed with the tracer's standard error.
    // lit_by_gi: the view's light is mostly indirect (without the probes, under half of it).
    void expect_within(const Scene& scene, const char* what, double bound, bool lit_by_gi = true);
};

void MetalGiTest::expect_within(const Scene& scene, const char* what, double bound, bool lit_by_gi) {
    // The probes always run, with enough bounces for a white room: the test is about what a
    // probe ray brings back, not about the planner's choice.
    const RenderSettings s = settings("", {"gi.threshold=0", "gi.bounces=12"});
    const ImageF image = raster(scene, kSize, kSize, s);
    const double m = mean_luminance(image);
    // `path` at pixel centres, 4 independent batches: the mean and the standard error of the mean.
    double se = 0.0;
    const double ref = path_mean_luminance(scene, kSize, kSize, 1024, se);
    // Without the probes: what the spot lights directly (the plate's highlight, if in view).
    RenderSettings off = s;
    off.set_on("gi", false);
    const ImageF no_gi = raster(scene, kSize, kSize, off);
    std::printf("%s: path mean %.5f (standard error %.5f); raster %.5f (%+.2f %%), without GI %.5f (%+.2f %%)\n",
                what, ref, se, m, 100.0 * (m / ref - 1.0), mean_luminance(no_gi), 100.0 * (mean_luminance(no_gi) / ref - 1.0));
    ASSERT_GT(ref, 0.0);
    EXPECT_LT(se, 0.01 * ref);  // the reference's noise does not decide the test
    if (lit_by_gi) EXPECT_LT(mean_luminance(no_gi), 0.5 * ref);  // the setting of the test: the light comes off the metal
    EXPECT_LT(std::abs(m / ref - 1.0), bound);
}

TEST_P(MetalGiTest, ProbesCarryLightAMetalPlateReflectsOntoTheRoom) {
    expect_within(metal_plate_room(), "metal plate room", 0.08);
}

// The room's own light that the plate reflects back into it: 2.4 m of metal under walls of
// albedo 0.8. Probes that reflect the previous bounces with the diffuse lobe alone: -12 %.
TEST_P(MetalGiTest, ProbesCarryTheRoomsLightThatTheMetalReflectsBackIntoIt) {
    expect_within(metal_plate_room(2.4f, 0.8f), "large plate, white room", 0.05);
}

// Every bounce keeps the share of light the tracer's BRDF keeps: a closed room of albedo 0.8
// with glTF's default dielectric (f0 0.04, roughness 1) and no metal, lit by a wide spot from
// below its ceiling. The probes' later bounces (and the raster's ambient term) weighted the
// diffuse lobe by the split sum's 1 - (f0 A + f90 B), which keeps for it the part of F(v.h)
// that the rough specular lobe loses to masking; the tracer's BRDF keeps 1 - F(v.h). A few per
// cent at each bounce, compounded by a bright room: +8.5 % in such a box.
TEST_P(MetalGiTest, ABrightClosedRoomGainsNoLightAtEachBounce) {
    Scene scene = test::spot_room("test:gi_white_room", {0.6f, 2.2f, -0.8f}, 1.2f, 1.5f, {-1.5f, 1.4f, 1.8f}, {0.3f, 1.2f, -2.0f});
    Material& room = scene.materials[0];
    room.base_color = glm::vec4(glm::vec3(0.8f), 1.0f);
    room.specular_factor = 1.0f;  // glTF's default dielectric, not Lambert
    room.roughness = 1.0f;
    scene.update_world_transforms();
    expect_within(scene, "white room", 0.03, false);
}

// The sky through the probes: a 4 m x 3 m x 4 m room (albedo 0.6) whose front wall is missing,
// under a constant sky and nothing else, seen from inside near the opening. The raster used to
// light every surface with the whole sky's irradiance (occluded by SSAO's few centimetres
// only): the room's back half, which sees the sky through the opening alone, was far too
// bright. The probes' rays that miss now bring the sky, and their irradiance replaces the
// environment's for the diffuse lobe.
TEST_P(MetalGiTest, ProbesLetTheSkyInOnlyWhereTheRoomIsOpen) {
    Scene scene;
    scene.source = "test:gi_open_room";
    scene.materials.push_back(lambert_material("room", glm::vec3(0.6f)));
    Primitive room;
    room.material = 0;
    append_quad(room, {-2, 0, -2}, {0, 0, 4}, {4, 0, 0});  // floor, +y
    append_quad(room, {-2, 3, -2}, {4, 0, 0}, {0, 0, 4});  // ceiling, -y
    append_quad(room, {-2, 0, -2}, {4, 0, 0}, {0, 3, 0});  // z = -2, +z (the front, z = 2, is open)
    append_quad(room, {-2, 0, -2}, {0, 3, 0}, {0, 0, 4});  // x = -2, +x
    append_quad(room, {2, 0, -2}, {0, 0, 4}, {0, 3, 0});   // x = 2, -x
    add_mesh_node(scene, "room", std::move(room));
    scene.environment.radiance = glm::vec3(0.5f);
    Camera cam;
    cam.name = "view";
    cam.yfov = 1.0f;
    cam.znear = 0.05f;
    cam.world = glm::inverse(glm::lookAt(glm::vec3(0.3f, 1.4f, 1.6f), glm::vec3(-0.4f, 1.1f, -2.0f), glm::vec3(0, 1, 0)));
    scene.cameras.push_back(cam);
    scene.update_world_transforms();
    expect_within(scene, "room open to the sky", 0.03, false);
}

INSTANTIATE_TEST_SUITE_P(Backends, MetalGiTest, ::testing::Values(Backend::egl), test::backend_name);

}  // namespace
}  // namespace candela
