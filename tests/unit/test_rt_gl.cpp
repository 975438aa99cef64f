// The compute-shader ray tracer on analytic cases: white furnace, a point light over a Lambert
// plane, AO limits, Whitted mirrors and glass, determinism, shards, specialisation, and the
// GLSL intersection routines against their C++ twins.
#include <gtest/gtest.h>

#include <glm/gtc/matrix_transform.hpp>

#include <algorithm>
#include <cmath>
#include <fstream>
#include <random>

#include "gl/debug.hpp"
#include "gl_fixture.hpp"
#include "gltf_builder.hpp"
#include "rt_test_scenes.hpp"
#include "platform/context.hpp"
#include "render/still.hpp"
#include "rt/intersect.hpp"
#include "rt/ray_tracer.hpp"
#include "rt/rt_geometry.hpp"
#include "rt/shard_merge.hpp"
#include "scene/mesh_utils.hpp"
#include "scene/gltf_loader.hpp"

namespace candela {
namespace {
namespace fs = std::filesystem;
using nlohmann::json;
using test::add_sphere;
using test::kLookDown;
using test::lambert;
using test::ortho_camera;
using test::shader_lib;


class RtTest : public test::GlContextTest {
protected:
    rt::Result trace(const Scene& scene, rt::Options o, int w, int h, const std::string& camera = "") {
        GpuScene gpu(scene);
        rt::RayTracer tracer(shader_lib(), scene, gpu, o);
        rt::Result r = tracer.render(scene.select_camera(camera, static_cast<float>(w) / static_cast<float>(h)), w, h);
        EXPECT_EQ(r.nonfinite_samples, 0u);
        EXPECT_EQ(count_nonfinite(r.image), 0u);
        return r;
    }
};


TEST_P(RtTest, WhiteFurnace) {
    // A Lambert sphere of albedo 1 in a constant environment of radiance 1 reflects exactly 1.
    test::GltfBuilder b;
    b.json()["materials"] = {lambert(glm::vec3(1.0f))};
    b.add_node({{"mesh", add_sphere(b, 1.0f, 0)}, {"extras", {{"sphere", {{"radius", 1.0}}}}}});
    b.json()["scenes"][0]["extras"]["environment_radiance"] = {1, 1, 1};
    b.json()["cameras"] = {{{"type", "perspective"}, {"perspective", {{"yfov", 0.6}, {"znear", 0.1}}}}};
    b.add_node({{"camera", 0}, {"translation", {0, 0, 4}}});
    const Scene scene = load_gltf(b.write(test::test_dir("furnace"), "furnace"));
    rt::Options o;
    o.mode = rt::Mode::path;
    o.spp = 32;
    const rt::Result r = trace(scene, o, 24, 24);
    double sum = 0.0;
    int beyond = 0;
    for (int y = 0; y < 24; ++y)
        for (int x = 0; x < 24; ++x) {
            sum += r.image.at(x, y)[0];
            // Every sample is exactly 1 here, so the 4-sigma bound of a mean of 32 samples is tight.
            beyond += std::fabs(r.image.at(x, y)[0] - 1.0f) > 1e-4f;
        }
    EXPECT_NEAR(sum / (24 * 24), 1.0, 0.01);
    EXPECT_EQ(beyond, 0);
}

// A white Lambert floor (y = 0) seen from straight above by an orthographic camera, optionally
// with a point light at `light` of intensity I.
Scene lambert_floor(const std::string& name, bool with_light, glm::vec3 light, float intensity, bool env = false) {
    test::GltfBuilder b;
    b.json()["materials"] = {lambert(glm::vec3(1.0f))};
    const int quad = b.add_quad_mesh(0);
    b.add_node({{"mesh", quad}, {"rotation", {-0.70710678, 0, 0, 0.70710678}}, {"scale", {4, 4, 4}}});  // XY quad -> XZ floor facing +Y
    ortho_camera(b, {0, 5, 0}, kLookDown, 2.0f);
    if (with_light) {
        b.json()["extensions"]["KHR_lights_punctual"]["lights"] = {{{"type", "point"}, {"intensity", intensity}}};
        b.add_node({{"translation", {light.x, light.y, light.z}}, {"extensions", {{"KHR_lights_punctual", {{"light", 0}}}}}});
    }
    if (env) b.json()["scenes"][0]["extras"]["environment_radiance"] = {1, 1, 1};
    return load_gltf(b.write(test::test_dir(name), name));
}

TEST_P(RtTest, PointLightOverLambertPlaneIsICosOverDSquared) {
    const glm::vec3 light(0.3f, 2.0f, -0.2f);
    const float I = 10.0f;
    const Scene scene = lambert_floor("pointplane", true, light, I);
    rt::Options o;
    o.mode = rt::Mode::direct;
    o.spp = 1;
    o.jitter = 0;  // the closed form at pixel centres (test_rt_statistics.cpp checks pixel averages)
    const int n = 32;
    const rt::Result r = trace(scene, o, n, n);
    int checked = 0;
    for (int y = 0; y < n; ++y)
        for (int x = 0; x < n; ++x) {
            // Pixel centre to world: x to the right, image top = -z (camera looks down, up = -z).
            const glm::vec3 p(-2.0f + 4.0f * (static_cast<float>(x) + 0.5f) / n, 0.0f, -2.0f + 4.0f * (static_cast<float>(y) + 0.5f) / n);
            const glm::vec3 d = light - p;
            const float dist = glm::length(d);
            const float expected = (1.0f / 3.14159265f) * I * (d.y / dist) / (dist * dist);
            EXPECT_NEAR(r.image.at(x, y)[0], expected, expected * 0.01f) << x << "," << y;
            ++checked;
        }
    EXPECT_EQ(checked, n * n);
}

TEST_P(RtTest, PathAgreesWithRasterDirectLightWithoutShadows) {
    const Scene scene = lambert_floor("raster_vs_path", true, glm::vec3(-0.4f, 1.5f, 0.6f), 5.0f);
    rt::Options o;
    o.mode = rt::Mode::path;
    o.max_depth = 1;
    o.spp = 16;
    const rt::Result r = trace(scene, o, 32, 32);
    StillOptions so;
    so.width = so.height = 32;
    const StillResult raster = render_still(scene, shader_lib(), so);
    const CompareResult c = compare(r.image, raster.radiance, 1.0);
    double mean = 0.0;
    for (int i = 0; i < 32 * 32; ++i) mean += raster.radiance.pixels[static_cast<size_t>(i) * 4];
    mean /= 32 * 32;
    // Jittered primary rays average the pixel footprint; the raster samples its centre.
    EXPECT_LT(c.rmse / mean, 0.01) << "rmse " << c.rmse << " mean " << mean;
}

TEST_P(RtTest, AmbientOcclusionLimits) {
    // An open plane: nothing occludes, AO is exactly 1 everywhere.
    const Scene open = lambert_floor("ao_open", false, {}, 0.0f);
    rt::Options o;
    o.mode = rt::Mode::ao;
    o.spp = 8;
    o.ao_radius = 10.0f;
    const rt::Result r = trace(open, o, 16, 16);
    for (float v : r.image.pixels) EXPECT_TRUE(v == 1.0f || v == 8.0f);  // rgb = 1, alpha = 8 samples
    // Inside a closed box (the camera too), every AO ray hits a wall: AO is exactly 0.
    test::GltfBuilder b;
    b.json()["materials"] = {lambert(glm::vec3(1.0f))};
    const int quad = b.add_quad_mesh(0);
    const float h = 0.70710678f;
    const std::vector<json> faces = {{0, 0, 0, 1}, {0, 1, 0, 0}, {0, h, 0, h}, {0, -h, 0, h}, {h, 0, 0, h}, {-h, 0, 0, h}};
    const std::vector<glm::vec3> offsets = {{0, 0, -1}, {0, 0, 1}, {-1, 0, 0}, {1, 0, 0}, {0, 1, 0}, {0, -1, 0}};
    for (size_t i = 0; i < faces.size(); ++i)
        b.add_node({{"mesh", quad}, {"rotation", faces[i]}, {"translation", {offsets[i].x, offsets[i].y, offsets[i].z}}, {"scale", {1.001, 1.001, 1}}});
    b.json()["cameras"] = {{{"type", "perspective"}, {"perspective", {{"yfov", 1.2}, {"znear", 0.01}}}}};
    b.add_node({{"camera", 0}, {"translation", {0, 0, 0.5}}});
    const Scene box = load_gltf(b.write(test::test_dir("ao_box"), "ao_box"));
    const rt::Result rb = trace(box, o, 16, 16);
    for (int y = 0; y < 16; ++y)
        for (int x = 0; x < 16; ++x) EXPECT_EQ(rb.image.at(x, y)[0], 0.0f) << x << "," << y;
}

TEST_P(RtTest, WhittedMirrorShowsTheReflectedObjectWhereItShouldBe) {
    // Camera looks down -Z at a mirror turned 45 degrees, which sends the view up (+Y) to an
    // emissive red strip above it covering x in [0.2, 0.8].
    test::GltfBuilder b;
    b.json()["materials"] = {{{"pbrMetallicRoughness", {{"baseColorFactor", {1, 1, 1, 1}}, {"metallicFactor", 1}, {"roughnessFactor", 0}}}},
                             {{"pbrMetallicRoughness", {{"baseColorFactor", {0, 0, 0, 1}}}}, {"emissiveFactor", {1, 0, 0}}, {"doubleSided", true}}};
    const int mirror = b.add_quad_mesh(0);
    b.add_node({{"mesh", mirror}, {"rotation", {-0.38268343, 0, 0, 0.92387953}}, {"scale", {3, 3, 3}}});  // -45 deg about X: faces (+Y+Z)/sqrt2
    const int strip = b.add_quad_mesh(1);
    b.add_node({{"mesh", strip}, {"translation", {0.5, 3, 0}}, {"rotation", {0.70710678, 0, 0, 0.70710678}}, {"scale", {0.3, 2, 1}}});
    ortho_camera(b, {0, 0, 5}, {0, 0, 0, 1}, 1.0f);
    b.json()["scenes"][0]["extras"]["environment_radiance"] = {0, 0, 0.25};
    const Scene scene = load_gltf(b.write(test::test_dir("mirror"), "mirror"));
    rt::Options o;
    o.mode = rt::Mode::whitted;
    o.spp = 1;
    o.jitter = 0;
    const rt::Result r = trace(scene, o, 40, 40);
    const float* at_strip = r.image.at(30, 20);   // x = +0.5
    const float* elsewhere = r.image.at(10, 20);  // x = -0.5
    EXPECT_NEAR(at_strip[0], 1.0f, 1e-3f);
    EXPECT_NEAR(at_strip[2], 0.0f, 1e-3f);
    EXPECT_NEAR(elsewhere[0], 0.0f, 1e-3f);
    EXPECT_NEAR(elsewhere[2], 0.25f, 1e-3f);  // the mirror shows the environment there
}

Scene glass_scene(const std::string& name, float ior, bool with_sphere) {
    test::GltfBuilder b;
    b.json()["materials"] = {lambert(glm::vec3(0.2f, 0.6f, 0.9f)),
                             {{"pbrMetallicRoughness", {{"baseColorFactor", {1, 1, 1, 1}}, {"metallicFactor", 0}, {"roughnessFactor", 0}}},
                              {"extensions", {{"KHR_materials_transmission", {{"transmissionFactor", 1}}},
                                              {"KHR_materials_ior", {{"ior", ior}}},
                                              {"KHR_materials_volume", {{"thicknessFactor", 1.0}}}}}}};
    b.add_node({{"mesh", b.add_quad_mesh(0)}, {"translation", {0, 0, -2}}, {"scale", {3, 3, 1}}});
    b.json()["extensions"]["KHR_lights_punctual"]["lights"] = {{{"type", "directional"}, {"intensity", 2.0}}};
    b.add_node({{"extensions", {{"KHR_lights_punctual", {{"light", 0}}}}}});
    if (with_sphere) b.add_node({{"mesh", add_sphere(b, 0.5f, 1)}, {"extras", {{"sphere", {{"radius", 0.5}}}}}});
    b.json()["cameras"] = {{{"type", "perspective"}, {"perspective", {{"yfov", 0.8}, {"znear", 0.1}}}}};
    b.add_node({{"camera", 0}, {"translation", {0, 0, 3}}});
    b.json()["scenes"][0]["extras"]["environment_radiance"] = {0.1, 0.1, 0.1};
    return load_gltf(b.write(test::test_dir(name), name));
}

TEST_P(RtTest, WhittedGlassOfIorOneIsInvisibleAndTotalInternalReflectionIsFinite) {
    rt::Options o;
    o.mode = rt::Mode::whitted;
    o.spp = 1;
    o.jitter = 0;
    const rt::Result without = trace(glass_scene("glass_none", 1.0f, false), o, 32, 32);
    const rt::Result with = trace(glass_scene("glass_ior1", 1.0f, true), o, 32, 32);
    EXPECT_LT(compare(with.image, without.image, 1e-4).failing_pixels, 1u);
    const rt::Result diamond = trace(glass_scene("glass_ior24", 2.4f, true), o, 32, 32);  // TIR inside
    EXPECT_GT(compare(diamond.image, without.image, 1e-3).failing_pixels, 20u);  // visible
}

TEST_P(RtTest, DeterministicAndShardsMergeToTheSingleRun) {
    const Scene scene = load_gltf(fs::path(CANDELA_SOURCE_DIR) / "samples/scenes/cornell_box.gltf");
    rt::Options o;
    o.mode = rt::Mode::path;
    o.spp = 6;
    o.seed = 42;
    const rt::Result a = trace(scene, o, 20, 20);
    const rt::Result b = trace(scene, o, 20, 20);
    EXPECT_EQ(a.image.pixels, b.image.pixels);
    std::vector<ImageF> shards;
    for (int k = 0; k < 3; ++k) {
        rt::Options s = o;
        s.shard = k;
        s.shard_count = 3;
        shards.push_back(trace(scene, s, 20, 20).image);
        EXPECT_EQ(shards.back().at(0, 0)[3], 2.0f);
    }
    const ImageF merged = rt::merge_shards(shards);
    const CompareResult c = compare(merged, a.image, 1e-5);
    EXPECT_EQ(c.failing_pixels, 0u) << "max " << c.max_abs;
    o.seed = 43;
    EXPECT_NE(trace(scene, o, 20, 20).image.pixels, a.image.pixels);
}

// The GLSL traversal (shaders/rt/scene.glsl, trace()) against testing every triangle with the C++
// twins: a soup of 3000 overlapping triangles, each facing its own random direction, so a camera
// ray's output (the normal facing the ray, as 0.5 + 0.5 n) names the triangle it hit. The
// material is single-sided, so about half of them face away and are culled for camera rays.
TEST_P(RtTest, CameraRaysHitWhatTestingEveryTriangleHits) {
    Scene scene;
    scene.source = "triangle soup";
    Material m;
    m.name = "white";
    scene.materials.push_back(m);
    Primitive soup;
    soup.material = 0;
    std::mt19937 rng(17);
    std::uniform_real_distribution<float> u(-1.0f, 1.0f);
    for (std::uint32_t t = 0; t < 3000; ++t) {
        const glm::vec3 c(u(rng), u(rng), u(rng));
        glm::vec3 p[3];
        for (auto& q : p) q = c + 0.25f * glm::vec3(u(rng), u(rng), u(rng));
        const glm::vec3 n = glm::cross(p[1] - p[0], p[2] - p[0]);
        if (glm::length(n) < 1e-3f) continue;
        for (const auto& q : p) {
            Vertex v;
            v.position = q;
            v.normal = glm::normalize(n);
            soup.vertices.push_back(v);
        }
        const auto base = static_cast<std::uint32_t>(soup.vertices.size() - 3);
        soup.indices.insert(soup.indices.end(), {base, base + 1, base + 2});
    }
    compute_bounds(soup);
    scene.meshes.push_back({"soup", {std::move(soup)}});
    Node node;
    node.name = "soup";
    node.mesh = 0;
    scene.nodes = {node};
    scene.roots = {0};
    Camera camera;
    camera.name = "front";
    camera.yfov = 1.0f;
    camera.znear = 0.01f;
    camera.world = glm::inverse(glm::lookAt(glm::vec3(0.3f, 0.2f, 2.2f), glm::vec3(0.0f), glm::vec3(0, 1, 0)));
    scene.cameras.push_back(camera);
    scene.update_world_transforms();

    const int w = 96, h = 96;
    rt::Options o;
    o.mode = rt::Mode::primary;
    o.spp = 1;
    o.jitter = 0;
    const rt::Result r = trace(scene, o, w, h, "front");

    // The camera ray of shaders/rt/trace.comp at a pixel's centre, and the closest of all triangles.
    const rt::RtGeometry g = rt::build_rt_geometry(scene, static_cast<int>(scene.materials.size()));
    const Camera cam = scene.select_camera("front", 1.0f);
    glm::mat4 rotation = cam.world;
    rotation[3] = glm::vec4(0, 0, 0, 1);
    const glm::mat4 inv = glm::inverse(projection_matrix(cam, 1.0f) * glm::inverse(rotation));
    int differ = 0, hits = 0;
    for (int y = 0; y < h; ++y)
        for (int x = 0; x < w; ++x) {
            const glm::vec2 ndc((static_cast<float>(x) + 0.5f) / w * 2.0f - 1.0f, 1.0f - (static_cast<float>(y) + 0.5f) / h * 2.0f);
            const glm::vec4 far4 = inv * glm::vec4(ndc, 0.5f, 1.0f), near4 = inv * glm::vec4(ndc, 1.0f, 1.0f);
            const glm::vec3 a = glm::vec3(near4) / near4.w, b = glm::vec3(far4) / far4.w;
            const rt::Ray ray{glm::vec3(cam.world[3]) + a, glm::normalize(b - a)};
            const rt::WatertightRay wr = rt::watertight_setup(ray);
            float best = 3.0e38f;
            glm::vec3 expected(0.0f);
            for (const rt::TriangleGpu& t : g.triangles) {
                glm::vec2 bary;
                const float d = rt::intersect_triangle(wr, t.p0, t.p1, t.p2, best, bary);
                // The material is single-sided: a camera ray passes the back of a triangle.
                const bool back = glm::dot(glm::cross(glm::vec3(t.p1 - t.p0), glm::vec3(t.p2 - t.p0)), ray.dir) >= 0.0f;
                if (t.p2.w > 0.5f && back) continue;
                if (d > 0.0f && d < best) {
                    best = d;
                    glm::vec3 n = glm::normalize(glm::cross(glm::vec3(t.p1 - t.p0), glm::vec3(t.p2 - t.p0)));
                    if (glm::dot(n, ray.dir) > 0.0f) n = -n;
                    expected = 0.5f + 0.5f * n;
                }
            }
            hits += best < 3.0e38f;
            const float* px = r.image.at(x, y);
            const float err = std::max({std::abs(px[0] - expected.x), std::abs(px[1] - expected.y), std::abs(px[2] - expected.z)});
            differ += err > 0.01f;
        }
    std::printf("triangle soup: %d of %d pixels hit; %d differ from testing every triangle\n", hits, w * h, differ);
    EXPECT_GT(hits, w * h / 2);
    // Float differences between the two ray set-ups can only matter at an edge or where two
    // triangles cross: a handful of pixels, not a missed subtree.
    EXPECT_LE(differ, w * h / 500);
}

TEST_P(RtTest, ShadersAreSpecialisedToTheScene) {
    auto defines = [&](const char* name) {
        const Scene scene = load_gltf(fs::path(CANDELA_SOURCE_DIR) / "samples/scenes" / name);
        rt::Options o;
        o.spp = 1;
        return trace(scene, o, 4, 4).defines;
    };
    // What a scene lacks is compiled out too (RT_NO_*): llvmpipe runs untaken branches, masked.
    EXPECT_EQ(defines("cornell_point.gltf"), "MODE_PATH RT_NO_TEXTURES RT_NO_SPHERES");
    EXPECT_EQ(defines("cornell_box.gltf"), "MODE_PATH HAS_EMITTERS RT_NO_TEXTURES RT_NO_SPHERES");
    EXPECT_EQ(defines("reflections.gltf"), "MODE_PATH HAS_TRANSMISSION RT_NO_TEXTURES");
    // Alpha-masked and blended materials: the alpha test at candidate hits only where it is needed.
    EXPECT_EQ(defines("transparency.gltf"), "MODE_PATH HAS_BLEND HAS_MASK");
}

// The traversal counters (RT_STATS): nodes and primitives per camera ray, and the fraction of the
// SIMD lanes that did a traversal step while their subgroup ran one.
TEST_P(RtTest, TraversalStatisticsCountLanes) {
    const Scene scene = load_gltf(fs::path(CANDELA_SOURCE_DIR) / "samples/scenes/cornell_box.gltf");
    rt::Options o;
    o.mode = rt::Mode::primary;
    o.spp = 1;
    o.jitter = 0;
    o.traversal_stats = true;
    const rt::Result one = trace(scene, o, 1, 1);
    const rt::Result many = trace(scene, o, 64, 64);
    std::printf("cornell_box: 1x1 lanes %.4f; 64x64 lanes %.4f, %.2f nodes + %.2f primitives per ray\n", one.lane_utilisation,
                many.lane_utilisation, many.nodes_per_ray, many.primitives_per_ray);
    // A ray through the box's middle visits at least the root and a leaf; the box has 36 triangles.
    EXPECT_GE(one.nodes_per_ray, 2.0);
    EXPECT_GT(many.nodes_per_ray, 2.0);
    EXPECT_GT(many.primitives_per_ray, 0.0);
    EXPECT_LT(many.primitives_per_ray, 36.0);
    if (one.lane_utilisation == 0.0) GTEST_SKIP() << "no GL_ARB_shader_ballot: lane utilisation is not counted";
    // One pixel: one busy lane in its subgroup at every step, so the fraction is exactly one over
    // the subgroup's size (8 on llvmpipe with 256-bit vectors), whatever the step count.
    const double lanes = 1.0 / one.lane_utilisation;
    EXPECT_GE(lanes, 2.0);
    EXPECT_NEAR(lanes, std::round(lanes), 1e-9);
    // Neighbouring camera rays of a closed box take nearly the same path: most lanes are busy.
    EXPECT_GT(many.lane_utilisation, 0.5);
    EXPECT_LE(many.lane_utilisation, 1.0);
}

TEST_P(RtTest, TimeLimitStopsAtASampleBoundaryAndStillGivesAnImage) {
    const Scene scene = load_gltf(fs::path(CANDELA_SOURCE_DIR) / "samples/scenes/cornell_box.gltf");
    rt::Options o;
    o.mode = rt::Mode::path;
    o.spp = 100000;
    o.time_limit_s = 0.2;
    const rt::Result r = trace(scene, o, 16, 16);
    EXPECT_TRUE(r.stopped_early);
    EXPECT_GE(r.samples, 1);
    EXPECT_LT(r.samples, 100000);
    EXPECT_EQ(r.image.at(3, 3)[3], static_cast<float>(r.samples));
}

TEST_P(RtTest, GlslIntersectionMatchesTheCppTwins) {
    const auto dir = test::test_dir("rt_twin");
    fs::create_directories(dir / "rt");
    fs::copy_file(fs::path(CANDELA_SOURCE_DIR) / "shaders/rt/intersect.glsl", dir / "rt/intersect.glsl");
    std::ofstream(dir / "twin.comp") << R"(#version 450 core
#include "rt/intersect.glsl"
layout(local_size_x = 1) in;
struct Case { vec4 origin; vec4 dir; vec4 p0; vec4 p1; vec4 p2; vec4 sphere; };
layout(std430, binding = 0) readonly buffer Cases { Case cases[]; };
layout(std430, binding = 1) writeonly buffer Out { vec4 results[]; };
void main() {
    uint i = gl_GlobalInvocationID.x;
    Case c = cases[i];
    Ray r; r.origin = c.origin.xyz; r.dir = c.dir.xyz;
    vec2 bary;
    float tt = intersect_triangle(watertight_setup(r), c.p0.xyz, c.p1.xyz, c.p2.xyz, 1e30, bary);
    float ts = intersect_sphere(r, c.sphere.xyz, c.sphere.w, 0.0, 1e30);
    vec3 off = offset_ray(c.origin.xyz, normalize(c.dir.xyz), c.sphere.w * 1e-4);
    results[i * 2u] = vec4(tt, bary, ts);
    results[i * 2u + 1u] = vec4(off, 0.0);
}
)";
    struct Case { glm::vec4 origin, dir, p0, p1, p2, sphere; };
    std::vector<Case> cases;
    std::mt19937 rng(5);
    std::uniform_real_distribution<float> u(-1.0f, 1.0f);
    for (int i = 0; i < 256; ++i) {
        const float scale = std::pow(10.0f, static_cast<float>(i % 7) - 3.0f);
        const glm::vec3 o = glm::vec3(u(rng), u(rng), u(rng) + 3.0f) * scale;
        cases.push_back({glm::vec4(o, 0), glm::vec4(u(rng) * 0.3f, u(rng) * 0.3f, -1.0f, 0),
                         glm::vec4(glm::vec3(-1, -1, 0) * scale, 0), glm::vec4(glm::vec3(1, -1, 0) * scale, 0),
                         glm::vec4(glm::vec3(0, 1, 0) * scale, 0), glm::vec4(0, 0, 0, 0.7f * scale)});
    }
    const ShaderLibrary lib(dir);
    gl::Program program = lib.build_or_throw({"rt_twin", {{ShaderStage::compute, "twin.comp"}}, {}});
    gl::Buffer in(static_cast<GLsizeiptr>(cases.size() * sizeof(Case)), cases.data());
    gl::Buffer out(static_cast<GLsizeiptr>(cases.size() * 2 * 16), nullptr, GL_DYNAMIC_STORAGE_BIT);
    glUseProgram(program.id());
    glBindBufferBase(GL_SHADER_STORAGE_BUFFER, 0, in.id());
    glBindBufferBase(GL_SHADER_STORAGE_BUFFER, 1, out.id());
    glDispatchCompute(static_cast<GLuint>(cases.size()), 1, 1);
    glMemoryBarrier(GL_BUFFER_UPDATE_BARRIER_BIT);
    std::vector<glm::vec4> res(cases.size() * 2);
    glGetNamedBufferSubData(out.id(), 0, static_cast<GLsizeiptr>(res.size() * 16), res.data());
    int hits = 0;
    for (size_t i = 0; i < cases.size(); ++i) {
        const Case& c = cases[i];
        const rt::Ray ray{glm::vec3(c.origin), glm::vec3(c.dir)};
        glm::vec2 bary;
        const float tt = rt::intersect_triangle(rt::watertight_setup(ray), glm::vec3(c.p0), glm::vec3(c.p1), glm::vec3(c.p2), 1e30f, bary);
        const float ts = rt::intersect_sphere(ray, glm::vec3(c.sphere), c.sphere.w, 0.0f, 1e30f);
        const glm::vec3 off = rt::offset_ray(glm::vec3(c.origin), glm::normalize(glm::vec3(c.dir)), c.sphere.w * 1e-4f);
        EXPECT_EQ(tt > 0.0f, res[i * 2].x > 0.0f) << i;
        if (tt > 0.0f) EXPECT_NEAR(res[i * 2].x, tt, std::fabs(tt) * 1e-5f) << i;
        EXPECT_EQ(ts > 0.0f, res[i * 2].w > 0.0f) << i;
        if (ts > 0.0f) EXPECT_NEAR(res[i * 2].w, ts, std::fabs(ts) * 1e-5f) << i;
        for (int k = 0; k < 3; ++k) EXPECT_NEAR(res[i * 2 + 1][k], off[k], std::fabs(off[k]) * 1e-6f + 1e-12f) << i;
        hits += tt > 0.0f;
    }
    EXPECT_GT(hits, 30);  // the cases exercise hits, not only misses
}

INSTANTIATE_TEST_SUITE_P(Backends, RtTest, ::testing::Values(Backend::egl, Backend::osmesa), test::backend_name);

}  // namespace
}  // namespace candela

namespace candela {
namespace {

class RtIndirectTest : public test::GlContextTest {};

TEST_P(RtIndirectTest, WithoutOccludersBothIndirectVariantsAgree) {
    // A floor and a red wall meeting at a right angle, lit by a point light: nothing stands
    // between any two bounce points, so sampling y by ray casting (with occlusion) and by area
    // (without) estimate the same integral.
    test::GltfBuilder b;
    b.json()["materials"] = {lambert(glm::vec3(0.8f)), lambert(glm::vec3(0.9f, 0.1f, 0.1f))};
    b.add_node({{"mesh", b.add_quad_mesh(0)}, {"rotation", {-0.70710678, 0, 0, 0.70710678}}, {"scale", {2, 2, 2}}});
    b.add_node({{"mesh", b.add_quad_mesh(1)}, {"translation", {0, 2, -2}}, {"scale", {2, 2, 2}}});
    b.json()["extensions"]["KHR_lights_punctual"]["lights"] = {{{"type", "point"}, {"intensity", 8.0}}};
    b.add_node({{"translation", {0.5, 1.5, 0.5}}, {"extensions", {{"KHR_lights_punctual", {{"light", 0}}}}}});
    b.json()["cameras"] = {{{"type", "perspective"}, {"perspective", {{"yfov", 0.9}, {"znear", 0.05}}}}};
    b.add_node({{"camera", 0}, {"translation", {0, 1.2, 4}}});
    const Scene scene = load_gltf(b.write(test::test_dir("indirect_open"), "indirect_open"));
    GpuScene gpu(scene);
    auto mean_red = [&](bool occlusion) {
        rt::Options o;
        o.mode = rt::Mode::indirect;
        o.spp = 96;
        o.indirect_occlusion = occlusion;
        rt::RayTracer tracer(shader_lib(), scene, gpu, o);
        const rt::Result r = tracer.render(scene.select_camera("", 1.0f), 16, 16);
        EXPECT_EQ(r.nonfinite_samples, 0u);
        EXPECT_EQ(count_nonfinite(r.image), 0u);
        double sum = 0.0;
        for (int i = 0; i < 16 * 16; ++i) sum += r.image.pixels[static_cast<size_t>(i) * 4];
        return sum / (16 * 16);
    };
    const double with = mean_red(true), without = mean_red(false);
    EXPECT_GT(with, 0.0);
    EXPECT_NEAR(without, with, 0.08 * with) << "with occlusion " << with << ", without " << without;
}

INSTANTIATE_TEST_SUITE_P(Backends, RtIndirectTest, ::testing::Values(Backend::egl), test::backend_name);

}  // namespace
}  // namespace candela

namespace candela {
namespace {

class RtEnvTest : public test::GlContextTest {};

TEST_P(RtEnvTest, EnvironmentImportanceSamplingIsUnbiasedAndLessNoisy) {
    // A dim sky with a small, very bright sun: BRDF sampling rarely finds the sun; sampling the
    // map by luminance does. Both must agree on the mean; the importance-sampled image is smoother.
    const auto dir = test::test_dir("env_is");
    ImageF sky(64, 32, 4);
    for (int y = 0; y < 32; ++y)
        for (int x = 0; x < 64; ++x) {
            float* p = sky.at(x, y);
            const bool sun = (x == 40 || x == 41) && (y == 5 || y == 6);
            p[0] = p[1] = p[2] = sun ? 2000.0f : 0.2f;
            p[3] = 1.0f;
        }
    write_image(dir / "sky.exr", sky);
    test::GltfBuilder b;
    b.json()["materials"] = {lambert(glm::vec3(0.8f))};
    b.add_node({{"mesh", b.add_quad_mesh(0)}, {"rotation", {-0.70710678, 0, 0, 0.70710678}}, {"scale", {4, 4, 4}}});
    ortho_camera(b, {0, 5, 0}, kLookDown, 1.0f);
    b.json()["scenes"][0]["extras"]["environment_map"] = "sky.exr";
    const Scene scene = load_gltf(b.write(dir, "floor"));
    GpuScene gpu(scene);
    auto stats = [&](bool importance) {
        rt::Options o;
        o.mode = rt::Mode::direct;
        o.spp = 64;
        o.env_importance = importance;
        rt::RayTracer tracer(shader_lib(), scene, gpu, o);
        const rt::Result r = tracer.render(scene.select_camera("", 1.0f), 16, 16);
        EXPECT_EQ(r.nonfinite_samples, 0u);
        EXPECT_EQ(r.defines.find("HAS_ENV_MAP_SAMPLING") != std::string::npos, importance);
        // Every pixel of an unoccluded plane sees the same sky: the spread between pixels is noise.
        double sum = 0.0, sum2 = 0.0;
        for (int i = 0; i < 256; ++i) {
            const double v = r.image.pixels[static_cast<size_t>(i) * 4];
            sum += v;
            sum2 += v * v;
        }
        const double mean = sum / 256.0;
        return std::make_pair(mean, std::sqrt(std::max(0.0, sum2 / 256.0 - mean * mean)));
    };
    const auto [mean_is, std_is] = stats(true);
    const auto [mean_brdf, std_brdf] = stats(false);
    EXPECT_NEAR(mean_is, mean_brdf, 0.05 * mean_is + 2.0 * std_brdf / 16.0) << mean_is << " vs " << mean_brdf;
    EXPECT_LT(std_is * 3.0, std_brdf) << "importance sampling should cut the noise: " << std_is << " vs " << std_brdf;
}

INSTANTIATE_TEST_SUITE_P(Backends, RtEnvTest, ::testing::Values(Backend::egl), test::backend_name);

}  // namespace
}  // namespace candela


namespace candela {
namespace {

// The viewer's reference mode: stepping in small time budgets accumulates exactly the samples
// one render() traces (same sample indices and seed), however the steps fall.
TEST_P(RtTest, ProgressiveStepsEqualOneRender) {
    const Scene scene = load_gltf(fs::path(CANDELA_SOURCE_DIR) / "samples" / "scenes" / "cornell_box.gltf");
    rt::Options o;
    o.mode = rt::Mode::path;
    o.spp = 3;
    o.tile_rows = 8;
    const int w = 40, h = 30;
    const rt::Result once = trace(scene, o, w, h);
    GpuScene gpu(scene);
    rt::RayTracer tracer(shader_lib(), scene, gpu, o);
    tracer.progressive_restart(scene.select_camera("", static_cast<float>(w) / static_cast<float>(h)), w, h);
    int steps = 0;
    while (!tracer.progressive_done() && steps < 1000) {
        tracer.progressive_step(0.0);  // one tile per step
        ++steps;
    }
    EXPECT_EQ(steps, 3 * ((h + 7) / 8));
    EXPECT_EQ(tracer.progressive_samples(), 3);
    const ImageF img = tracer.progressive_image();
    ASSERT_EQ(img.pixels.size(), once.image.pixels.size());
    for (size_t i = 0; i < img.pixels.size(); ++i) ASSERT_FLOAT_EQ(img.pixels[i], once.image.pixels[i]) << i;
    // A restart forgets what was traced.
    tracer.progressive_restart(scene.select_camera("", 1.0f), w, h);
    EXPECT_EQ(tracer.progressive_samples(), 0);
    EXPECT_EQ(tracer.progressive_image().pixels[3], 0.0f);
}

// Scheduling: a dispatch traces several samples per pixel (path mode: each lane starts its next path
// when one ends). The grouping must not change a sample: one per dispatch, chunks that do not
// divide the count, and a shard's strided samples give the same image.
TEST_P(RtTest, SamplesPerDispatchDoNotChangeTheImage) {
    const Scene scene = load_gltf(fs::path(CANDELA_SOURCE_DIR) / "samples" / "scenes" / "cornell_box.gltf");
    for (rt::Mode mode : {rt::Mode::path, rt::Mode::ao}) {
        rt::Options o;
        o.mode = mode;
        o.spp = 7;
        o.shard = 1;
        o.shard_count = 2;  // samples 1, 3, 5
        o.samples_per_dispatch = 1;
        const rt::Result one = trace(scene, o, 16, 12);
        o.samples_per_dispatch = 2;  // chunks of 2 and 1
        const rt::Result two = trace(scene, o, 16, 12);
        EXPECT_EQ(one.samples, 3);
        EXPECT_EQ(two.samples, 3);
        ASSERT_EQ(one.image.pixels.size(), two.image.pixels.size());
        double sum = 0.0;
        for (size_t i = 0; i < one.image.pixels.size(); ++i) {
            ASSERT_FLOAT_EQ(one.image.pixels[i], two.image.pixels[i]) << rt::to_string(mode) << " " << i;
            sum += one.image.pixels[i];
        }
        EXPECT_GT(sum, 0.0);
    }
}

}  // namespace
}  // namespace candela
