// Multisampling must not darken shadowed lighting at triangle edges: every pixel of a 4-sample
// image lies within [min, max] of the 1-sample image's 3x3 neighbourhood (the values a pixel-centre
// renderer takes around it), on both render paths and both backends.
//
// A multisampled pixel that straddles an edge is shaded once per triangle, at a point inside the
// triangle and the pixel (centroid interpolation). That point has to lie on the surface: a light a
// few centimetres away turns a receiver millimetres off its surface into a shadowed one (behind
// the caster in the shadow map) or a much brighter one (1 / r^2). Both scenes put a light that
// close to a receiver made of many edges, away from the world origin where an interpolation error
// proportional to the position shows most.
//
// The same fragments read every other centroid input (colour, texture coordinates, normal) off the
// surface too, scaled by the same factor, which can be far from 1 and negative where the
// triangle's plane is seen edge-on: a saved random scene whose 4-sample image had a negative pixel
// is checked against a 4x finer 1-sample image.
#include <gtest/gtest.h>

#include <algorithm>
#include <cmath>
#include <cstdio>
#include <cstdlib>
#include <filesystem>
#include <string>

#include <glm/gtc/matrix_transform.hpp>

#include "gl_fixture.hpp"
#include "image/image.hpp"
#include "render/settings.hpp"
#include "render/still.hpp"
#include "rt/view_lighting.hpp"
#include "scene/generate.hpp"
#include "scene/gltf_loader.hpp"
#include "scene/lighting.hpp"
#include "scene/mesh_utils.hpp"

namespace candela {
namespace {

constexpr int kMsaaShadowSize = 128;

// The report's scene: a 6 m x 6 m ceiling of two triangles (shared edge along its diagonal), a
// point light 3 cm under it, the camera below looking up past the light.
Scene ceiling_scene() {
    Scene scene;
    scene.source = "test:msaa_shadows_ceiling";
    scene.materials.push_back(lambert_material("ceiling", glm::vec3(0.8f)));
    Primitive ceiling;
    ceiling.material = 0;
    append_quad(ceiling, {-3, 2, -3}, {6, 0, 0}, {0, 0, 6});  // facing -y, down to the room
    add_mesh_node(scene, "ceiling", std::move(ceiling));
    Light bulb;
    bulb.name = "bulb";
    bulb.intensity = 5.0f;
    add_light_node(scene, bulb, glm::translate(glm::mat4(1.0f), glm::vec3(0, 1.97f, 0)));
    add_look_at_camera(scene, {0.12f, 1.55f, 0.3f}, {0.0f, 2.0f, 0.0f}, 1.0f, glm::vec3(0, 0, 1));
    scene.update_world_transforms();
    return scene;
}

// A second receiver of many differently oriented triangles: a shallow vault (a spherical cap of
// radius 6 m, 1.6 m across, seen from below) tessellated into 14 x 14 cells with smooth normals,
// 40 m from the world origin, lit by a spot light 3 cm under its apex and pointing up. From inside
// the cap every point of it sees the light (it is convex around the light), so any shadow there
// is the receiver shadowing itself.
Scene vault_scene() {
    const glm::vec3 o(40.0f, 7.0f, -30.0f);  // the apex
    const float radius = 2.0f, half = 0.2f;
    const glm::vec3 centre = o - glm::vec3(0, radius, 0);
    Scene scene;
    scene.source = "test:msaa_shadows_vault";
    scene.materials.push_back(lambert_material("vault", glm::vec3(0.7f, 0.75f, 0.8f)));
    Primitive vault;
    vault.material = 0;
    const int n = 20;
    for (int j = 0; j <= n; ++j)
        for (int i = 0; i <= n; ++i) {
            const float x = -half + 2.0f * half * static_cast<float>(i) / n, z = -half + 2.0f * half * static_cast<float>(j) / n;
            const glm::vec3 dir = glm::normalize(glm::vec3(x, radius, z));
            Vertex v;
            v.position = centre + dir * radius;
            v.normal = -dir;  // facing the inside, down to the light
            vault.vertices.push_back(v);
        }
    for (int j = 0; j < n; ++j)
        for (int i = 0; i < n; ++i) {
            const auto a = static_cast<std::uint32_t>(j * (n + 1) + i), b = a + 1, c = a + n + 1, d = c + 1;
            // Alternating diagonals: the shared edges run in three directions. Counter-clockwise
            // seen from below.
            if ((i + j) % 2 == 0) vault.indices.insert(vault.indices.end(), {a, b, d, a, d, c});
            else vault.indices.insert(vault.indices.end(), {a, b, c, b, d, c});
        }
    add_mesh_node(scene, "vault", std::move(vault));
    Light spot;
    spot.name = "spot";
    spot.type = LightType::spot;
    spot.intensity = 3.0f;
    spot.outer_cone = 1.2f;
    spot.inner_cone = 0.9f;
    // A node's -z is where the light points: up (+y).
    add_light_node(scene, spot,
                   glm::translate(glm::mat4(1.0f), o - glm::vec3(0, 0.03f, 0)) * glm::rotate(glm::mat4(1.0f), 1.5707963f, glm::vec3(1, 0, 0)));
    add_look_at_camera(scene, o + glm::vec3(0.06f, -0.3f, 0.12f), o + glm::vec3(-0.01f, 0.0f, -0.01f), 1.0f, glm::vec3(0, 0, 1));
    scene.update_world_transforms();
    return scene;
}

struct MsaaShadowCase {
    Backend backend;
    RenderPath path;
};
Backend msaa_shadow_backend(const MsaaShadowCase& c) { return c.backend; }

class MsaaShadowTest : public test::GlContextTestOf<MsaaShadowCase, msaa_shadow_backend> {
protected:
    ImageF render(const Scene& scene, int samples, int width = kMsaaShadowSize, int height = kMsaaShadowSize) {
        StillOptions so;
        so.width = width;
        so.height = height;
        so.settings.path = GetParam().path;
        apply_effects(so.settings, "shadows");
        if (samples > 1) {
            apply_knob(so.settings, "aa.mode=msaa");
            apply_knob(so.settings, "aa.samples=" + std::to_string(samples));
        }
        StillResult r = render_still(scene, lib_, so);
        EXPECT_EQ(count_nonfinite(r.radiance), 0u) << samples << " sample(s)";
        bool shadows = false, resolve = false;
        for (const auto& p : r.report.passes) {
            shadows = shadows || p.name == "shadow_maps";
            resolve = resolve || p.name.rfind("aa_resolve", 0) == 0;
        }
        EXPECT_TRUE(shadows) << "the shadow maps did not run";
        EXPECT_EQ(resolve, samples > 1) << samples << " sample(s): the resolve";
        return std::move(r.radiance);
    }

    // The neighbourhood rule over every pixel and colour channel. Returns the number of pixels
    // outside [min - tol, max + tol] of the 1-sample 3x3 neighbourhood, tol = kRelTol x max.
    // Why a tolerance: the 4 samples are shaded at points up to 0.5 pixel from the centre, and
    // the lighting is not linear between pixel centres; next to the light's foot it changes by up
    // to ~40 % from one pixel to the next, and a point between two centres can lie a few percent
    // beyond both. 15 % holds that with room, and is far below what an off-surface receiver does
    // (half a pixel shadowed, or lit up to 2-3x by 1 / r^2).
    int outside_neighbourhood(const ImageF& one, const ImageF& msaa, float peak, const char* what) {
        constexpr float kRelTol = 0.03f;
        int bad = 0;
        float worst = 0.0f;
        for (int y = 0; y < one.height; ++y)
            for (int x = 0; x < one.width; ++x)
                for (int c = 0; c < 3; ++c) {
                    float lo = 3.4e38f, hi = 0.0f;
                    for (int dy = -1; dy <= 1; ++dy)
                        for (int dx = -1; dx <= 1; ++dx) {
                            const float v = one.at(std::clamp(x + dx, 0, one.width - 1), std::clamp(y + dy, 0, one.height - 1))[c];
                            lo = std::min(lo, v);
                            hi = std::max(hi, v);
                        }
                    const float m = msaa.at(x, y)[c], tol = kRelTol * hi + 1e-6f;
                    const float excess = std::max(lo - m, m - hi) / std::max(hi, 1e-3f * peak);
                    if (m < lo - tol || m > hi + tol) {
                        if (bad < 5)
                            ADD_FAILURE() << what << ": pixel (" << x << ", " << y << ") channel " << c << " is " << m
                                          << " with 4 samples, outside the 1-sample neighbourhood [" << lo << ", " << hi
                                          << "] (centre " << one.at(x, y)[c] << ")";
                        ++bad;
                    }
                    worst = std::max(worst, excess);
                }
        std::printf("%s: %d pixel channel(s) outside the 1-sample neighbourhood, worst excess %.3f of its max\n", what, bad, worst);
        return bad;
    }

    void check(const Scene& scene, const char* name) {
        const ImageF one = render(scene, 1), msaa = render(scene, 4);
        const std::string what = std::string(name) + (GetParam().path == RenderPath::forward ? " forward" : " deferred");
        if (const char* dir = std::getenv("CANDELA_TEST_DUMP")) {  // to look at the images
            const std::string stem = std::string(dir) + "/msaa_shadows_" + name + "_" + to_string(GetParam().backend) +
                                     (GetParam().path == RenderPath::forward ? "_forward" : "_deferred");
            write_image(stem + "_1.exr", one);
            write_image(stem + "_4.exr", msaa);
            write_image(stem + "_4.png", msaa, -4.0f);
        }
        // The light is in view: the image is not black (which would pass trivially).
        float peak = 0.0f;
        for (int y = 0; y < one.height; ++y)
            for (int x = 0; x < one.width; ++x) peak = std::max(peak, one.at(x, y)[0]);
        EXPECT_GT(peak, 1.0f) << what;
        EXPECT_EQ(outside_neighbourhood(one, msaa, peak, what.c_str()), 0) << what;
    }

    ShaderLibrary lib_{ShaderLibrary::default_root()};
};

// The report: a point light 3 cm under a two-triangle ceiling; at 4 samples the pixels along the
// diagonal came out at about half their value.
TEST_P(MsaaShadowTest, PointLightUnderATwoTriangleCeiling) { check(ceiling_scene(), "ceiling"); }

// Many edges in three directions between differently oriented triangles, far from the origin,
// under a spot light (one perspective shadow view instead of a cube).
TEST_P(MsaaShadowTest, SpotLightUnderATessellatedVaultFarFromTheOrigin) { check(vault_scene(), "vault"); }

// A saved random scene (tests/data/random_regressions), as `candela render --size 64x48` sees
// it: at 4 samples forward, one fragment of the edge pixel (2, 39) (a box's side seen edge-on, one
// sample covered) read its colour, normal and position scaled by -149, and the pixel came out at
// -3.4 instead of 0.07. Here every pixel of the 4-sample image lies within 3 % of [min, max] of
// the 4 x 4 pixels of a 1-sample image at 4x the resolution that cover it. Why that bound and not
// the 3 x 3 neighbourhood above: at 64 x 48 some faces are thinner than a pixel (a box's top
// seen at grazing), which the 4 samples see and no neighbouring pixel centre does (forward and
// deferred alike, up to 19 % above the neighbourhood); the finer image samples the same footprint
// that the 4 samples and their centroids lie in, 16 times. Before the fix: 8 pixel channels
// outside, the worst 36x below its block.
TEST_P(MsaaShadowTest, SavedRandomSceneEdgeOnFaceAtFourSamples) {
    constexpr int kW = 64, kH = 48, kFine = 4;
    const std::filesystem::path file =
        std::filesystem::path(CANDELA_SOURCE_DIR) / "tests" / "data" / "random_regressions" / "msaa_negative_pixel_seed46.gltf";
    Scene scene = load_gltf(file);
    const float aspect = static_cast<float>(kW) / kH;
    LightingChoice choice = apply_lighting(scene, LightingMode::auto_select, scene.select_camera("", aspect));
    complete_lighting(scene, choice, lib_, scene.select_camera("", aspect), aspect);

    const ImageF msaa = render(scene, 4, kW, kH), fine = render(scene, 1, kW * kFine, kH * kFine);
    const std::string what = std::string("seed46") + (GetParam().path == RenderPath::forward ? " forward" : " deferred");
    if (const char* dir = std::getenv("CANDELA_TEST_DUMP")) {
        const std::string stem = std::string(dir) + "/msaa_shadows_seed46_" + to_string(GetParam().backend) +
                                 (GetParam().path == RenderPath::forward ? "_forward" : "_deferred");
        write_image(stem + "_fine.exr", fine);
        write_image(stem + "_4.exr", msaa);
        write_image(stem + "_4.png", msaa);
    }
    constexpr float kRelTol = 0.03f;
    int negative = 0, bad = 0;
    float lit = 0.0f;
    for (int y = 0; y < kH; ++y)
        for (int x = 0; x < kW; ++x)
            for (int c = 0; c < 3; ++c) {
                const float m = msaa.at(x, y)[c];
                if (!(m >= 0.0f)) ++negative;  // negative or NaN
                float lo = 3.4e38f, hi = 0.0f;
                for (int fy = y * kFine; fy < (y + 1) * kFine; ++fy)
                    for (int fx = x * kFine; fx < (x + 1) * kFine; ++fx) {
                        lo = std::min(lo, fine.at(fx, fy)[c]);
                        hi = std::max(hi, fine.at(fx, fy)[c]);
                    }
                lit = std::max(lit, hi);
                const float tol = kRelTol * hi + 1e-6f;
                if (!(m >= lo - tol && m <= hi + tol)) {
                    if (bad < 5)
                        ADD_FAILURE() << what << ": pixel (" << x << ", " << y << ") channel " << c << " is " << m
                                      << " with 4 samples, outside [" << lo << ", " << hi << "] of the 1-sample pixels at "
                                      << kFine << "x the resolution that cover it";
                    ++bad;
                }
            }
    EXPECT_GT(lit, 0.1f) << what << ": the image is dark (which would pass trivially)";
    EXPECT_EQ(negative, 0) << what << ": negative or NaN pixel channels";
    EXPECT_EQ(bad, 0) << what << ": pixel channels outside the finer image's block";
}

INSTANTIATE_TEST_SUITE_P(BackendsAndPaths, MsaaShadowTest,
                         ::testing::Values(MsaaShadowCase{Backend::egl, RenderPath::forward},
                                           MsaaShadowCase{Backend::egl, RenderPath::deferred},
                                           MsaaShadowCase{Backend::osmesa, RenderPath::forward},
                                           MsaaShadowCase{Backend::osmesa, RenderPath::deferred}),
                         [](const ::testing::TestParamInfo<MsaaShadowCase>& info) {
                             return std::string(to_string(info.param.backend)) +
                                    (info.param.path == RenderPath::forward ? "_forward" : "_deferred");
                         });

}  // namespace
}  // namespace candela
