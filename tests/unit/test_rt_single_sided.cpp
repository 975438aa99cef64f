// What a ray sees of a single-sided surface. glTF's doubleSided false means back-face culling: the
// rasterizer never draws the back of such a triangle, so the tracer's seeing rays (camera,
// reflection, refraction, bounce) pass through it, while occlusion rays (shadows, AO, next-event
// estimation) are blocked by both sides, as the shadow maps draw casters with no culling.
//
// The scene: four grey quads in one plane, facing the camera or away from it, plain or under a
// mirroring node (negative scale flips the winding, and glTF says the front then follows the
// transformed normal), in a constant sky. A culled quad shows the sky (0.5), a seen one its
// diffuse reflection of the sky (about 0.2 x 0.5). Both the raster and every tracer mode that
// looks must agree on which are seen; a shadow test checks that a culled wall still casts.
#include <gtest/gtest.h>

#include <cmath>
#include <cstdio>
#include <string>
#include <vector>

#include "gl_fixture.hpp"
#include "gltf_builder.hpp"
#include "image/image.hpp"
#include "render/still.hpp"
#include "rt/ray_tracer.hpp"
#include "scene/gltf_loader.hpp"

namespace candela {
namespace {
namespace fs = std::filesystem;
using nlohmann::json;

constexpr int kSidedSize = 96;
constexpr float kSidedSky = 0.5f;

struct SidedQuad {
    const char* what;
    float x;            // centre on the image's x axis (world units, camera at x = 0)
    bool double_sided;
    json scale;         // of the node
    float yaw;          // radians about +Y: 0 faces the camera, pi faces away
    bool seen;          // what the rasterizer's culling gives
};

const std::vector<SidedQuad>& sided_quads() {
    static const std::vector<SidedQuad> q = {
        {"single-sided, back to the camera", -3.0f, false, {1, 1, 1}, 3.14159265f, false},
        {"double-sided, back to the camera", -1.0f, true, {1, 1, 1}, 3.14159265f, true},
        {"single-sided, mirrored in x, facing the camera", 1.0f, false, {-1, 1, 1}, 0.0f, true},
        {"single-sided, mirrored in z, back to the camera", 3.0f, false, {1, 1, -1}, 0.0f, false},
    };
    return q;
}

Scene quads_scene(const fs::path& dir) {
    test::GltfBuilder b;
    b.json()["materials"] = {
        {{"pbrMetallicRoughness", {{"baseColorFactor", {0.2, 0.2, 0.2, 1}}, {"metallicFactor", 0}, {"roughnessFactor", 1}}}, {"doubleSided", false}},
        {{"pbrMetallicRoughness", {{"baseColorFactor", {0.2, 0.2, 0.2, 1}}, {"metallicFactor", 0}, {"roughnessFactor", 1}}}, {"doubleSided", true}}};
    const int single = b.add_quad_mesh(0), both = b.add_quad_mesh(1);
    for (const SidedQuad& q : sided_quads()) {
        const float h = q.yaw * 0.5f;
        b.add_node({{"mesh", q.double_sided ? both : single},
                    {"translation", {q.x, 0, 0}},
                    {"rotation", {0, std::sin(h), 0, std::cos(h)}},
                    {"scale", q.scale},
                    {"name", q.what}});
    }
    b.json()["scenes"][0]["extras"]["environment_radiance"] = {kSidedSky, kSidedSky, kSidedSky};
    b.json()["cameras"] = {{{"type", "orthographic"}, {"orthographic", {{"xmag", 4.5}, {"ymag", 4.5}, {"znear", 0.1}, {"zfar", 20}}}}};
    b.add_node({{"camera", 0}, {"translation", {0, 0, 5}}});
    return load_gltf(b.write(dir, "single_sided"));
}

// The pixel at the centre of quad q (the orthographic camera spans x, y in [-4.5, 4.5]).
glm::ivec2 sided_quad_pixel(const SidedQuad& q) {
    return {static_cast<int>((q.x + 4.5f) / 9.0f * kSidedSize), kSidedSize / 2};
}

class RtSingleSidedTest : public test::GlContextTest {
protected:
    ShaderLibrary lib_{ShaderLibrary::default_root()};
};

TEST_P(RtSingleSidedTest, SeeingRaysCullTheBackOfSingleSidedSurfacesAsTheRasterDoes) {
    const fs::path dir = test::test_dir("rt_single_sided");
    const Scene scene = quads_scene(dir);
    const Camera camera = scene.select_camera("", 1.0f);

    StillOptions so;
    so.width = so.height = kSidedSize;
    apply_effects(so.settings, "none");
    const StillResult raster = render_still(scene, lib_, so);
    ASSERT_EQ(count_nonfinite(raster.radiance), 0u);
    write_display_image(dir / "raster.png", raster.radiance);

    GpuScene gpu(scene);
    for (const rt::Mode mode : {rt::Mode::path, rt::Mode::whitted, rt::Mode::primary}) {
        rt::Options o;
        o.mode = mode;
        o.spp = 16;
        o.jitter = 0;
        rt::RayTracer tracer(lib_, scene, gpu, o);
        const rt::Result r = tracer.render(camera, kSidedSize, kSidedSize);
        const std::string name = rt::to_string(mode);
        SCOPED_TRACE(name);
        ASSERT_EQ(count_nonfinite(r.image), 0u);
        ASSERT_EQ(r.nonfinite_samples, 0u);
        write_display_image(dir / (name + ".png"), r.image);
        for (const SidedQuad& q : sided_quads()) {
            const glm::ivec2 p = sided_quad_pixel(q);
            const float v = r.image.at(p.x, p.y)[1], rv = raster.radiance.at(p.x, p.y)[1];
            if (mode != rt::Mode::primary) {
                // Path and whitted: the sky where culled, the grey quad's reflection where seen.
                EXPECT_EQ(q.seen, v < 0.3f) << q.what << ": tracer " << v;
            } else {
                // Primary shows the shading normal of what is hit (0.5 + 0.5 n: blue 1 for a quad
                // turned to the camera), black on a miss.
                const float blue = r.image.at(p.x, p.y)[2];
                EXPECT_EQ(q.seen, blue > 0.5f) << q.what << ": tracer's normal " << blue;
            }
            EXPECT_EQ(q.seen, rv < 0.3f) << q.what << ": raster " << rv;
        }
        // Coverage agreement over the whole image: the pixels that show a quad in the raster
        // show one in the tracer (edges may differ by a pixel; at most 2 % of the quads' area).
        if (mode != rt::Mode::primary) {
            int differ = 0, covered = 0;
            for (int y = 0; y < kSidedSize; ++y)
                for (int x = 0; x < kSidedSize; ++x) {
                    const bool a = raster.radiance.at(x, y)[1] < 0.3f, t = r.image.at(x, y)[1] < 0.3f;
                    covered += a;
                    differ += a != t;
                }
            EXPECT_GT(covered, 0);
            EXPECT_LE(differ, covered / 50) << differ << " of " << covered << " covered pixels differ";
        }
    }
    std::printf("images: %s\n", dir.string().c_str());
}

// A culled wall still blocks light: a single-sided quad with its back to a directional light,
// between the light and a floor, leaves its shadow in the tracer as in the raster.
TEST_P(RtSingleSidedTest, OcclusionRaysAreBlockedByBothSides) {
    const fs::path dir = test::test_dir("rt_single_sided_shadow");
    test::GltfBuilder b;
    b.json()["materials"] = {{{"pbrMetallicRoughness", {{"baseColorFactor", {0.8, 0.8, 0.8, 1}}, {"metallicFactor", 0}, {"roughnessFactor", 1}}}}};
    const int quad = b.add_quad_mesh(0);
    // Floor: the quad rotated to face +Y, 4 x 4.
    b.add_node({{"mesh", quad}, {"rotation", {-0.70710678, 0, 0, 0.70710678}}, {"scale", {2, 2, 1}}});
    // The occluder above the floor, facing down (its back to the light above): culled for the
    // camera above, which looks at its back too.
    b.add_node({{"mesh", quad}, {"translation", {0, 1, 0}}, {"rotation", {0.70710678, 0, 0, 0.70710678}}, {"scale", {0.5, 0.5, 1}}});
    b.json()["extensions"]["KHR_lights_punctual"]["lights"] = {{{"type", "directional"}, {"intensity", 3.0}}};
    b.json()["extensionsUsed"] = {"KHR_lights_punctual"};
    b.add_node({{"extensions", {{"KHR_lights_punctual", {{"light", 0}}}}}, {"rotation", {-0.70710678, 0, 0, 0.70710678}}});
    b.json()["cameras"] = {{{"type", "orthographic"}, {"orthographic", {{"xmag", 2}, {"ymag", 2}, {"znear", 0.1}, {"zfar", 20}}}}};
    b.add_node({{"camera", 0}, {"translation", {0, 5, 0}}, {"rotation", {-0.70710678, 0, 0, 0.70710678}}});
    const Scene scene = load_gltf(b.write(dir, "shadow"));
    const Camera camera = scene.select_camera("", 1.0f);
    GpuScene gpu(scene);
    rt::Options o;
    o.mode = rt::Mode::direct;
    o.spp = 4;
    o.jitter = 0;
    const rt::Result r = rt::RayTracer(lib_, scene, gpu, o).render(camera, kSidedSize, kSidedSize);
    ASSERT_EQ(count_nonfinite(r.image), 0u);
    write_display_image(dir / "direct.png", r.image);
    // The centre of the floor is in the occluder's shadow (the occluder itself is not seen from
    // above); a corner of the floor is lit: 0.8 / pi x 3.
    const float centre = r.image.at(kSidedSize / 2, kSidedSize / 2)[1], corner = r.image.at(kSidedSize / 16, kSidedSize / 16)[1];
    EXPECT_LT(centre, 0.01f) << "the culled occluder casts no shadow";
    EXPECT_GT(corner, 0.5f) << "the lit floor (about 0.8 / pi x 3)";
    std::printf("images: %s\n", dir.string().c_str());
}

INSTANTIATE_TEST_SUITE_P(Backends, RtSingleSidedTest, ::testing::Values(Backend::egl), test::backend_name);

}  // namespace
}  // namespace candela
