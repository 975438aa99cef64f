// Hard cases that must stay numerically stable (an image must not depend on units or placement): the same
// scene at very different scales and far from the origin, depth precision at a distance,
// watertight meshes seen from inside, light and view at grazing angles, degenerate input data and
// materials at their limits.
// Raster and ray tracer; every image is scanned for NaN/Inf.
#include <gtest/gtest.h>

#include <algorithm>
#include <cmath>

#include <glm/gtx/quaternion.hpp>

#include "core/log.hpp"
#include "gl_fixture.hpp"
#include "gltf_builder.hpp"
#include "render/renderer.hpp"
#include "render/still.hpp"
#include "rt/ray_tracer.hpp"
#include "scene/gltf_loader.hpp"
#include "shapes.hpp"

namespace candela {
namespace {
namespace fs = std::filesystem;
using nlohmann::json;

json lambert(glm::vec3 c) {
    return {{"pbrMetallicRoughness", {{"baseColorFactor", {c.r, c.g, c.b, 1}}, {"metallicFactor", 0}, {"roughnessFactor", 0.8}}}};
}
json emitter(glm::vec3 c) {
    return {{"pbrMetallicRoughness", {{"baseColorFactor", {0, 0, 0, 1}}, {"metallicFactor", 0}}},
            {"emissiveFactor", {c.r, c.g, c.b}},
            {"extensions", {{"KHR_materials_specular", {{"specularFactor", 0}}}}}};
}
const json kFloorRotation = {-0.70710678, 0, 0, 0.70710678};  // the XY quad turned to face +Y

// A floor, a box and a point light seen by a perspective camera, everything scaled by `s` and
// moved by `offset`; the light's intensity scales with s^2 so that radiance is unchanged.
Scene box_on_floor(float s, glm::dvec3 offset, const std::string& name) {
    test::GltfBuilder b;
    b.json()["materials"] = {lambert({0.7f, 0.7f, 0.7f}), lambert({0.8f, 0.3f, 0.1f})};
    // The offset in double, as geospatial files write it (a float offset of 6.4e6 would itself
    // move the nodes by up to 0.25 m).
    auto at = [&](glm::vec3 p) { const glm::dvec3 q = glm::dvec3(p * s) + offset; return json{q.x, q.y, q.z}; };
    b.add_node({{"mesh", b.add_quad_mesh(0)}, {"translation", at({0, 0, 0})}, {"rotation", kFloorRotation}, {"scale", {3 * s, 3 * s, 3 * s}}});
    b.add_node({{"mesh", test::add_box(b, 1)}, {"translation", at({0, 0.5f, 0})}, {"rotation", {0, 0.2588190, 0, 0.9659258}}, {"scale", {s, s, s}}});
    b.json()["extensionsUsed"] = {"KHR_lights_punctual", "KHR_materials_specular"};
    b.json()["extensions"]["KHR_lights_punctual"]["lights"] = {{{"type", "point"}, {"color", {1, 1, 1}}, {"intensity", 12.0 * s * s}}};
    b.add_node({{"translation", at({1.5f, 3.0f, 1.0f})}, {"extensions", {{"KHR_lights_punctual", {{"light", 0}}}}}});
    b.json()["scenes"][0]["extras"]["environment_radiance"] = {0.15, 0.15, 0.15};
    // Looking down at the box from (0, 2.5, 5): -Z turned 26.6 degrees down about X.
    b.json()["cameras"] = {{{"type", "perspective"}, {"perspective", {{"yfov", 0.7}, {"znear", 0.05 * s}}}}};
    b.add_node({{"camera", 0}, {"translation", at({0, 2.5f, 5})}, {"rotation", {-0.2297529, 0, 0, 0.9732489}}});
    return load_gltf(b.write(test::test_dir(name), "scene"));
}

// Channel values of two display images differing by more than 2/255 (the golden tolerance counts
// pixels; a channel count is stricter).
double mismatch(const std::vector<std::uint8_t>& a, const std::vector<std::uint8_t>& b) {
    size_t off = 0, n = 0;
    for (size_t i = 0; i < a.size() && i < b.size(); ++i) {
        if (i % 4 == 3) continue;
        off += std::abs(static_cast<int>(a[i]) - static_cast<int>(b[i])) > 2;
        ++n;
    }
    return n ? static_cast<double>(off) / static_cast<double>(n) : 1.0;
}

class HardCaseTest : public test::GlContextTest {
protected:
    ShaderLibrary lib_{fs::path(CANDELA_SOURCE_DIR) / "shaders"};
    StillResult raster(const Scene& scene, RenderSettings s, int w = 96, int h = 72) {
        StillOptions o;
        o.width = w;
        o.height = h;
        o.settings = s;
        o.output = FrameOutput::display;
        StillResult r = render_still(scene, lib_, o);
        EXPECT_EQ(count_nonfinite(r.radiance), 0u);
        return r;
    }
    rt::Result traced(const Scene& scene, rt::Options o, int w = 96, int h = 72, const std::string& camera = "") {
        GpuScene gpu(scene);
        rt::RayTracer tracer(lib_, scene, gpu, o);
        rt::Result r = tracer.render(scene.select_camera(camera, static_cast<float>(w) / static_cast<float>(h)), w, h);
        EXPECT_EQ(r.nonfinite_samples, 0u);
        EXPECT_EQ(count_nonfinite(r.image), 0u);
        return r;
    }
};

// The scene at 1/1000 and 1000 times its size gives the image of size 1: shadow biases are in
// shadow texels, SSAO's radius in scene units, ray offsets relative to the hit's magnitude.
TEST_P(HardCaseTest, ScaleInvariance) {
    RenderSettings s;
    apply_effects(s, "shadows,ssao");
    std::map<float, StillResult> images;
    std::map<float, ImageF> traced_images;
    for (float scale : {0.001f, 1.0f, 1000.0f}) {
        const Scene scene = box_on_floor(scale, glm::vec3(0.0f), "scale");
        RenderSettings rs = s;
        rs.ao.radius = 0.5f * scale;
        images[scale] = raster(scene, rs);
        rt::Options o;
        o.mode = rt::Mode::visibility;
        o.spp = 1;
        traced_images[scale] = traced(scene, o).image;
    }
    for (float scale : {0.001f, 1000.0f}) {
        const double raster_off = mismatch(images[scale].display, images[1.0f].display);
        const CompareResult rt_off = compare(traced_images[scale], traced_images[1.0f], 0.5);
        std::printf("scale %g: raster %.4f%% channel values off by > 2/255; ray-traced visibility: %zu pixels differ\n", scale,
                    100.0 * raster_off, rt_off.failing_pixels);
        EXPECT_LE(raster_off, 0.001) << "scale " << scale;
        EXPECT_LE(rt_off.failing_pixels, 2u) << "scale " << scale;
    }
}

// Far from the origin float positions lose bits: at 6.4e6 (the Earth's radius) a float keeps
// steps of 0.5 m. The loader moves a scene that is far from the origin compared with its size
// next to it, in double (Scene::origin), so the raster and the tracer see the same numbers as
// at the origin but for the rounding of that move: the image is the origin's within the
// golden tolerance (2/255 on at most 0.1 % of the channel values) at every offset, on the
// axes, on the Earth's surface and at 1e7.
TEST_P(HardCaseTest, FarFromTheOrigin) {
    RenderSettings s;
    apply_effects(s, "shadows");
    const Scene at_origin = box_on_floor(1.0f, glm::dvec3(0.0), "origin");
    // Near the origin nothing moves: the file's numbers are the scene's.
    EXPECT_EQ(at_origin.origin, glm::dvec3(0.0));
    const StillResult origin = raster(at_origin, s);
    rt::Options o;
    o.mode = rt::Mode::visibility;
    const ImageF origin_rt = traced(at_origin, o).image;
    const glm::dvec3 earth = 6.4e6 * glm::normalize(glm::dvec3(3.0, 4.0, 3.5));
    for (const glm::dvec3 d : {glm::dvec3(1e4, 0, -1e4), glm::dvec3(1e5, 0, 0), glm::dvec3(0, 1e5, 0), glm::dvec3(0, 0, 1e5), earth,
                               glm::dvec3(1e7, 0, 0)}) {
        const Scene far = box_on_floor(1.0f, d, "far");
        EXPECT_NEAR(glm::length(far.origin - d), 0.0, 10.0) << "the scene is rendered next to its centre, not at the file's origin";
        const double off = mismatch(raster(far, s).display, origin.display);
        const size_t rt_off = compare(traced(far, o).image, origin_rt, 0.5).failing_pixels;
        std::printf("offset (%g, %g, %g): raster %.3f%% channel values off by > 2/255; ray-traced visibility: %zu pixels differ\n",
                    d.x, d.y, d.z, 100.0 * off, rt_off);
        EXPECT_LE(off, 0.001) << d.x << " " << d.y << " " << d.z;
        EXPECT_LE(rt_off, 2u) << d.x << " " << d.y << " " << d.z;
    }
}

// Two quads 1e-3 apart at a distance of 1000 with the near plane at 0.01: reversed-Z float depth
// keeps their order in every pixel (a [0,1] fixed-point or float depth would not).
TEST_P(HardCaseTest, DepthPrecisionAtADistance) {
    test::GltfBuilder b;
    b.json()["materials"] = {emitter({1, 0, 0}), emitter({0, 1, 0})};
    b.add_node({{"mesh", b.add_quad_mesh(0)}, {"translation", {0, 0, -1000}}, {"scale", {100, 100, 1}}});
    b.add_node({{"mesh", b.add_quad_mesh(1)}, {"translation", {0, 0, -1000.001}}, {"scale", {100, 100, 1}}});
    b.json()["cameras"] = {{{"type", "perspective"}, {"perspective", {{"yfov", 0.1}, {"znear", 0.01}}}}};
    b.add_node({{"camera", 0}});
    const Scene scene = load_gltf(b.write(test::test_dir("depth"), "quads"));
    RenderSettings s;
    apply_effects(s, "none");
    for (const char* path : {"forward", "deferred"}) {
        apply_knob(s, std::string("render.path=") + path);
        const ImageF img = raster(scene, s, 128, 128).radiance;
        size_t wrong = 0;
        for (int y = 0; y < img.height; ++y)
            for (int x = 0; x < img.width; ++x) wrong += !(img.at(x, y)[0] > 0.9f && img.at(x, y)[1] < 0.01f);
        EXPECT_EQ(wrong, 0u) << path << ": pixels where the farther quad won";
    }
    rt::Options o;
    o.mode = rt::Mode::whitted;
    o.max_depth = 0;
    o.spp = 1;
    const ImageF img = traced(scene, o, 128, 128).image;
    size_t wrong = 0;
    for (size_t i = 0; i < img.pixels.size(); i += 4) wrong += !(img.pixels[i] > 0.9f && img.pixels[i + 1] < 0.01f);
    EXPECT_EQ(wrong, 0u) << "ray tracer";
}

// A closed sphere seen from its centre with a bright environment outside: a ray (or a raster
// crack) that gets through shows the environment. Six 90-degree views cover every direction.
TEST_P(HardCaseTest, WatertightFromInside) {
    test::GltfBuilder b;
    b.json()["materials"] = {{{"pbrMetallicRoughness", {{"baseColorFactor", {0, 0, 0, 1}}, {"metallicFactor", 0}}},
                              {"doubleSided", true},
                              {"extensions", {{"KHR_materials_specular", {{"specularFactor", 0}}}}}}};
    b.json()["extensionsUsed"] = {"KHR_materials_specular"};
    // Scaled and turned off the axes so that no triangle edge lines up with the pixel grid.
    b.add_node({{"mesh", test::add_closed_sphere(b, 0, 48, 96)}, {"scale", {3, 3, 3}}, {"rotation", {0.1, 0.3, 0.05, 0.9483}}});
    b.json()["scenes"][0]["extras"]["environment_radiance"] = {1, 1, 1};
    const json views[6] = {{0, 0, 0, 1}, {0, 1, 0, 0}, {0, 0.7071068, 0, 0.7071068}, {0, -0.7071068, 0, 0.7071068},
                           {0.7071068, 0, 0, 0.7071068}, {-0.7071068, 0, 0, 0.7071068}};
    b.json()["cameras"] = {{{"type", "perspective"}, {"perspective", {{"yfov", 1.5708}, {"znear", 0.01}}}}};
    for (const json& q : views) b.add_node({{"camera", 0}, {"rotation", q}});
    const Scene scene = load_gltf(b.write(test::test_dir("watertight"), "inside"));
    RenderSettings s;
    apply_effects(s, "none");
    size_t leaks_rt = 0, leaks_raster = 0;
    for (int v = 0; v < 6; ++v) {
        rt::Options o;
        o.mode = rt::Mode::whitted;
        o.max_depth = 0;
        o.spp = 4;  // jittered: 4 rays per pixel at different sub-pixel positions
        const ImageF img = traced(scene, o, 128, 128, std::to_string(v)).image;
        for (size_t i = 0; i < img.pixels.size(); i += 4) leaks_rt += img.pixels[i] > 1e-4f;
        StillOptions so;
        so.width = so.height = 128;
        so.settings = s;
        so.camera = std::to_string(v);
        const ImageF r = render_still(scene, lib_, so).radiance;
        EXPECT_EQ(count_nonfinite(r), 0u);
        for (size_t i = 0; i < r.pixels.size(); i += 4) leaks_raster += r.pixels[i] > 1e-4f;
    }
    EXPECT_EQ(leaks_rt, 0u) << "ray-traced pixels that saw the environment through the mesh";
    EXPECT_EQ(leaks_raster, 0u) << "rasterized pixels where the sky showed through";
}

// Degenerate data and materials at their limits, in one scene: zero-area triangles, NaN normals
// and positions, a zero-scale and a negative-scale node; roughness 0 and 1, metallic 0 and 1,
// IOR 1.0 and 2.4, transmission with total internal reflection, emission 1e4, and a camera
// inside a glass sphere. Loaded with warnings, rendered by every path and mode without NaN.
TEST_P(HardCaseTest, DegenerateDataAndMaterialLimits) {
    test::GltfBuilder b;
    json mats = json::array();
    int i = 0;
    for (float rough : {0.0f, 1.0f})
        for (float metal : {0.0f, 1.0f})
            mats.push_back({{"pbrMetallicRoughness", {{"baseColorFactor", {0.8, 0.6, 0.4, 1}}, {"metallicFactor", metal}, {"roughnessFactor", rough}}}});
    for (float ior : {1.0f, 2.4f})
        mats.push_back({{"pbrMetallicRoughness", {{"baseColorFactor", {1, 1, 1, 1}}, {"metallicFactor", 0}, {"roughnessFactor", 0}}},
                        {"extensions", {{"KHR_materials_transmission", {{"transmissionFactor", 1}}}, {"KHR_materials_ior", {{"ior", ior}}},
                                        {"KHR_materials_volume", {{"thicknessFactor", 1}}}}}});
    mats.push_back({{"pbrMetallicRoughness", {{"baseColorFactor", {0, 0, 0, 1}}}}, {"emissiveFactor", {1, 0.9, 0.8}},
                    {"extensions", {{"KHR_materials_emissive_strength", {{"emissiveStrength", 1e4}}}}}});
    b.json()["materials"] = mats;
    b.json()["extensionsUsed"] = {"KHR_materials_transmission", "KHR_materials_ior", "KHR_materials_volume",
                                  "KHR_materials_emissive_strength", "KHR_lights_punctual"};
    for (i = 0; i < 7; ++i) {
        const int mesh = test::add_closed_sphere(b, i, 12, 24);
        b.add_node({{"mesh", mesh}, {"translation", {-3.0 + i, 0.5, 0}}, {"scale", {0.45, 0.45, 0.45}}});
    }
    // Degenerate geometry: a zero-area triangle, NaN/zero normals, a NaN position.
    const float nan = std::numeric_limits<float>::quiet_NaN();
    const std::vector<glm::vec3> p = {{0, 0, 0}, {1, 0, 0}, {2, 0, 0}, {0, 1, 0}, {1, 1, 0}, {nan, 0, 0}};
    const std::vector<glm::vec3> n = {{0, 0, 0}, {nan, 0, 1}, {0, 0, 1}, {0, 0, 1}, {0, 0, 1}, {0, 0, 1}};
    const int degenerate = b.add_mesh({{"POSITION", b.add_positions(p)}, {"NORMAL", b.add_vec3(n)}}, b.add_indices({0, 1, 2, 0, 1, 3, 1, 4, 3, 3, 4, 5}), 0);
    b.add_node({{"mesh", degenerate}, {"translation", {0, 1.5, 0}}});
    b.add_node({{"mesh", test::add_box(b, 0)}, {"scale", {0, 0, 0}}});                                 // zero scale
    b.add_node({{"mesh", test::add_box(b, 1)}, {"translation", {0, 0.5, 1.2}}, {"scale", {-0.5, 0.5, 0.5}}});  // mirrored
    b.add_node({{"mesh", b.add_quad_mesh(0)}, {"rotation", kFloorRotation}, {"scale", {6, 6, 6}}});
    b.json()["extensions"]["KHR_lights_punctual"]["lights"] = {{{"type", "point"}, {"intensity", 30}}};
    b.add_node({{"translation", {1, 4, 2}}, {"extensions", {{"KHR_lights_punctual", {{"light", 0}}}}}});
    b.json()["scenes"][0]["extras"]["environment_radiance"] = {0.2, 0.2, 0.2};
    b.json()["cameras"] = {{{"type", "perspective"}, {"perspective", {{"yfov", 0.9}, {"znear", 0.01}}}}};
    b.add_node({{"camera", 0}, {"translation", {0, 1.5, 6}}});
    b.add_node({{"camera", 0}, {"translation", {2.0, 0.5, 0}}});  // inside the IOR 2.4 glass sphere
    const int warnings_before = log::warning_count();
    const Scene scene = load_gltf(b.write(test::test_dir("limits"), "limits"));
    EXPECT_GT(scene.sanitized.bad_normals, 0);
    EXPECT_GT(scene.sanitized.nonfinite_positions, 0);
    EXPECT_GT(log::warning_count(), warnings_before) << "sanitizing is reported";
    for (const char* camera : {"0", "1"}) {
        SCOPED_TRACE(camera);
        for (const char* path : {"forward", "deferred"}) {
            RenderSettings s;
            apply_effects(s, "all");
            apply_knob(s, std::string("render.path=") + path);
            StillOptions so;
            so.width = 64;
            so.height = 48;
            so.settings = s;
            so.camera = camera;
            EXPECT_EQ(count_nonfinite(render_still(scene, lib_, so).radiance), 0u) << path;
        }
        for (rt::Mode m : {rt::Mode::path, rt::Mode::whitted, rt::Mode::direct, rt::Mode::ao, rt::Mode::indirect}) {
            rt::Options o;
            o.mode = m;
            o.spp = 2;
            traced(scene, o, 64, 48, camera);
        }
    }
}

// Grazing angles: a directional light 89 degrees from the floor's normal and a camera whose
// central ray meets the floor at 89 degrees, over a floor tessellated into 512 triangles (edges
// everywhere). Without an occluder in view, neither the shadow map nor the ray tracer's shadow rays
// (leaving the floor at 1 degree) may shadow a single floor pixel. With a post casting a 28-unit
// shadow towards the camera, every filter's visibility against the ray tracer's exact visibility:
// 0 acne and 0 leaked pixels away from the shadow's edges, and the edges (where a shadow texel is
// stretched 57 times) within 2 % of all pixels; no NaN anywhere.
TEST_P(HardCaseTest, GrazingLightAndView) {
    // The post stands either in view (its shadow runs towards the camera) or behind the camera
    // (the floor in view is all lit, and the shadow pass still runs: two primitives).
    const auto scene_with = [&](bool occluder) {
        test::GltfBuilder b;
        b.json()["materials"] = {lambert({0.7f, 0.7f, 0.7f})};
        const int n = 16;
        const float half = 30.0f;
        std::vector<glm::vec3> p, nrm;
        std::vector<uint32_t> idx;
        for (int j = 0; j <= n; ++j)
            for (int i = 0; i <= n; ++i) {
                p.push_back({-half + 2 * half * i / n, 0.0f, -half + 2 * half * j / n});
                nrm.push_back({0, 1, 0});
            }
        for (int j = 0; j < n; ++j)
            for (int i = 0; i < n; ++i) {
                const uint32_t a = static_cast<uint32_t>(j * (n + 1) + i), c = a + 1, bb = a + n + 1, d = bb + 1;
                idx.insert(idx.end(), {a, bb, c, bb, d, c});  // counter-clockwise seen from +Y
            }
        b.add_node({{"mesh", b.add_mesh({{"POSITION", b.add_positions(p)}, {"NORMAL", b.add_vec3(nrm)}}, b.add_indices(idx), 0)}});
        b.add_node({{"mesh", test::add_box(b, 0)}, {"translation", {0, 0.25, occluder ? -4 : 20}}, {"scale", {0.3, 0.5, 0.3}}});
        // Light travelling towards the camera (+Z) and 1 degree down: 89 degrees from the floor's
        // normal; the box's shadow runs 28 units towards the camera.
        const float e = glm::radians(1.0f);
        const glm::quat light = glm::rotation(glm::vec3(0, 0, -1), glm::normalize(glm::vec3(0.0f, -std::sin(e), std::cos(e))));
        b.json()["extensionsUsed"] = {"KHR_lights_punctual"};
        b.json()["extensions"]["KHR_lights_punctual"]["lights"] = {{{"type", "directional"}, {"intensity", 3.0}}};
        b.add_node({{"rotation", {light.x, light.y, light.z, light.w}}, {"extensions", {{"KHR_lights_punctual", {{"light", 0}}}}}});
        b.json()["scenes"][0]["extras"]["environment_radiance"] = {0.1, 0.1, 0.1};
        // Camera 0.2 above the floor looking 1 degree down: its central ray meets the floor
        // 11.5 units ahead at 89 degrees from the normal.
        const glm::quat cam = glm::angleAxis(-e, glm::vec3(1, 0, 0));
        b.json()["cameras"] = {{{"type", "perspective"}, {"perspective", {{"yfov", 0.35}, {"znear", 0.01}}}}};
        b.add_node({{"camera", 0}, {"translation", {0, 0.2, 8}}, {"rotation", {cam.x, cam.y, cam.z, cam.w}}});
        return load_gltf(b.write(test::test_dir("grazing"), occluder ? "grazing" : "grazing_open"));
    };
    const int w = 128, h = 96;
    const auto visibility = [&](const Scene& scene, std::vector<std::string> knobs) {
        RenderSettings s;
        apply_effects(s, "shadows");
        apply_knob(s, "debug.view=visibility");
        for (const auto& k : knobs) apply_knob(s, k);
        StillOptions so;
        so.width = w;
        so.height = h;
        so.settings = s;
        so.output = FrameOutput::hdr;
        ImageF img = render_still(scene, lib_, so).radiance;
        EXPECT_EQ(count_nonfinite(img), 0u);
        return img;
    };
    rt::Options o;
    o.mode = rt::Mode::visibility;
    o.spp = 1;
    // The floor covers the lower half of the image; without an occluder in view all of it is fully lit
    // (visibility 1: the hard filter is a 2x2 bilinear comparison, where acne on a plane shows as
    // about 0.5).
    const Scene open = scene_with(false);
    const ImageF open_rt = traced(open, o, w, h).image;
    const ImageF open_raster = visibility(open, {"shadows.filter=hard"});
    size_t floor_pixels = 0, rt_shadowed = 0, raster_shadowed = 0;
    for (int y = h / 2 + 2; y < h; ++y)  // rows below the horizon (row 0 is the top)
        for (int x = 0; x < w; ++x) {
            ++floor_pixels;
            rt_shadowed += open_rt.at(x, y)[0] < 0.99f;
            raster_shadowed += open_raster.at(x, y)[0] < 0.99f;
        }
    std::printf("grazing, open floor: %zu floor pixels, shadowed: ray tracer %zu, shadow map %zu\n", floor_pixels, rt_shadowed,
                raster_shadowed);
    EXPECT_EQ(rt_shadowed, 0u) << "ray-traced self-shadowing at 89 degrees";
    EXPECT_EQ(raster_shadowed, 0u) << "shadow-map acne at 89 degrees";
    // The check can see acne: without the biases the same open floor is covered in it.
    const ImageF unbiased = visibility(open, {"shadows.filter=hard", "shadows.normal_bias=0", "shadows.depth_bias=0",
                                              "shadows.slope_bias=0", "shadows.receiver_slope_bias=0"});
    size_t unbiased_shadowed = 0;
    for (int y = h / 2 + 2; y < h; ++y)
        for (int x = 0; x < w; ++x) unbiased_shadowed += unbiased.at(x, y)[0] < 0.99f;
    std::printf("grazing, open floor without biases: %zu shadowed pixels\n", unbiased_shadowed);
    EXPECT_GT(unbiased_shadowed, floor_pixels / 10);

    const Scene scene = scene_with(true);
    const ImageF reference = traced(scene, o, w, h).image;
    const auto ref_lit = [&](int x, int y) { return reference.at(x, y)[0] > 0.5f; };
    // Interior pixels: the reference has the same visibility everywhere within 2 pixels. At 89
    // degrees a shadow texel is stretched 57 times along the light, so the shadow's edges may move
    // by a pixel or two; acne and leaks are wrong pixels away from edges, and there must be none.
    const auto interior = [&](int x, int y) {
        for (int dy = -2; dy <= 2; ++dy)
            for (int dx = -2; dx <= 2; ++dx) {
                const int xx = std::clamp(x + dx, 0, w - 1), yy = std::clamp(y + dy, 0, h - 1);
                if (ref_lit(xx, yy) != ref_lit(x, y)) return false;
            }
        return true;
    };
    for (const char* filter : {"hard", "pcf", "pcss"}) {
        SCOPED_TRACE(filter);
        const ImageF v = visibility(scene, {std::string("shadows.filter=") + filter});
        int lit = 0, shadowed = 0, agree = 0, differ = 0, acne = 0, leaks = 0;
        for (int y = 0; y < h; ++y)
            for (int x = 0; x < w; ++x) {
                const bool truth = ref_lit(x, y), raster_lit = v.at(x, y)[0] > 0.5f;
                lit += truth;
                shadowed += !truth;
                agree += truth && raster_lit;
                differ += truth != raster_lit;
                if (truth != raster_lit && interior(x, y)) (truth ? acne : leaks) += 1;
            }
        const double agreement = lit ? static_cast<double>(agree) / lit : 0.0;
        std::printf("grazing %s: lit %d shadowed %d; acne %d, leaks %d; at edges: agreement %.5f, %d of %d pixels differ\n", filter,
                    lit, shadowed, acne, leaks, agreement, differ, w * h);
        EXPECT_GT(lit, w * h / 4);
        EXPECT_GT(shadowed - w * h / 2, 500) << "the post's long shadow is in view";
        EXPECT_EQ(acne, 0) << "lit pixels shadowed away from any shadow edge";
        EXPECT_EQ(leaks, 0) << "shadowed pixels lit away from any shadow edge";
        EXPECT_GE(agreement, 0.95);
        EXPECT_LT(static_cast<double>(differ) / (w * h), 0.02);
    }
}

INSTANTIATE_TEST_SUITE_P(Backends, HardCaseTest, ::testing::Values(Backend::egl), test::backend_name);

}  // namespace
}  // namespace candela
