// Animation, skins and morph targets: known keyframes give known transforms at chosen
// times (LINEAR with slerp, STEP, CUBICSPLINE with its tangents scaled by the keyframe interval),
// a two-bone skin bends a bar to a known shape, and raster and tracer draw the same bent bar.
#include <gtest/gtest.h>

#include <cmath>
#include <cstdlib>

#include <glm/gtc/matrix_transform.hpp>

#include "gl_fixture.hpp"
#include "image/image.hpp"
#include "image/image_io.hpp"
#include "render/gpu_scene.hpp"
#include "render/still.hpp"
#include "rt/ray_tracer.hpp"
#include "scene/animation.hpp"
#include "scene/gltf_loader.hpp"
#include "scene/lighting.hpp"
#include "scene/mesh_utils.hpp"

namespace candela {
namespace {

constexpr float kEps = 1e-5f;

AnimationSampler sampler(std::vector<float> times, std::vector<float> values, int width, Interpolation interp) {
    AnimationSampler s;
    s.times = std::move(times);
    s.values = std::move(values);
    s.width = width;
    s.interpolation = interp;
    return s;
}

// One node animated by `s` on `path`.
Scene one_node(const AnimationSampler& s, AnimationPath path) {
    Scene scene;
    Node n;
    n.name = "animated";
    scene.nodes.push_back(n);
    scene.roots.push_back(0);
    Animation a;
    a.name = "test";
    a.samplers.push_back(s);
    a.channels.push_back({0, 0, path});
    a.start = s.times.front();
    a.end = s.times.back();
    scene.animations.push_back(a);
    return scene;
}

glm::vec3 translation_at(const Scene& scene, float t) { return glm::vec3(evaluate_pose(scene, 0, t).world[0][3]); }

TEST(AnimationTest, LinearTranslationAtChosenTimesAndClampedOutside) {
    const Scene scene = one_node(sampler({0, 1, 3}, {0, 0, 0, 2, 0, 0, 2, 4, 0}, 3, Interpolation::linear), AnimationPath::translation);
    EXPECT_NEAR(glm::distance(translation_at(scene, 0.5f), glm::vec3(1, 0, 0)), 0.0f, kEps);
    EXPECT_NEAR(glm::distance(translation_at(scene, 2.0f), glm::vec3(2, 2, 0)), 0.0f, kEps);
    EXPECT_NEAR(glm::distance(translation_at(scene, 1.0f), glm::vec3(2, 0, 0)), 0.0f, kEps);
    EXPECT_NEAR(glm::distance(translation_at(scene, -1.0f), glm::vec3(0, 0, 0)), 0.0f, kEps);  // before the first key
    EXPECT_NEAR(glm::distance(translation_at(scene, 7.0f), glm::vec3(2, 4, 0)), 0.0f, kEps);   // after the last
}

TEST(AnimationTest, StepHoldsEachKeyUntilTheNext) {
    const Scene scene = one_node(sampler({0, 1, 3}, {0, 0, 0, 2, 0, 0, 2, 4, 0}, 3, Interpolation::step), AnimationPath::translation);
    EXPECT_NEAR(glm::distance(translation_at(scene, 0.99f), glm::vec3(0, 0, 0)), 0.0f, kEps);
    EXPECT_NEAR(glm::distance(translation_at(scene, 1.0f), glm::vec3(2, 0, 0)), 0.0f, kEps);
    EXPECT_NEAR(glm::distance(translation_at(scene, 2.9f), glm::vec3(2, 0, 0)), 0.0f, kEps);
}

TEST(AnimationTest, CubicSplineScalesTangentsByTheKeyframeInterval) {
    // Keys at 0 and 2 (interval 2), values 0; out-tangent of key 0 = (1, 0, 0), in-tangent of key
    // 1 = (0, 1, 0). At s = 1/2: x = td (s^3 - 2 s^2 + s) = 2 * 0.125, y = td (s^3 - s^2) = 2 * -0.125.
    // Without the scaling by td the values would be half.
    const std::vector<float> v = {0, 0, 0, /*v0*/ 0, 0, 0, /*b0*/ 1, 0, 0, /*a1*/ 0, 1, 0, /*v1*/ 0, 0, 0, /*b1*/ 0, 0, 0};
    const Scene scene = one_node(sampler({0, 2}, v, 3, Interpolation::cubic_spline), AnimationPath::translation);
    const glm::vec3 p = translation_at(scene, 1.0f);
    EXPECT_NEAR(p.x, 0.25f, kEps);
    EXPECT_NEAR(p.y, -0.25f, kEps);
    // At s = 1/4: x = 2 (1/64 - 2/16 + 1/4) = 0.28125, y = 2 (1/64 - 1/16) = -0.09375.
    const glm::vec3 q = translation_at(scene, 0.5f);
    EXPECT_NEAR(q.x, 0.28125f, kEps);
    EXPECT_NEAR(q.y, -0.09375f, kEps);
    // The keys themselves are the values (not the tangents).
    EXPECT_NEAR(glm::length(translation_at(scene, 0.0f)), 0.0f, kEps);
    EXPECT_NEAR(glm::length(translation_at(scene, 2.0f)), 0.0f, kEps);
}

TEST(AnimationTest, LinearRotationSlerpsAlongTheShorterArc) {
    // 0 to 90 degrees about z, the second key stored as the negated quaternion (the same rotation):
    // halfway is 45 degrees, not the long way round.
    const float h = std::sqrt(0.5f);
    const Scene scene = one_node(sampler({0, 1}, {0, 0, 0, 1, 0, 0, -h, -h}, 4, Interpolation::linear), AnimationPath::rotation);
    const glm::mat4 m = evaluate_pose(scene, 0, 0.5f).world[0];
    const glm::vec3 x = glm::vec3(m * glm::vec4(1, 0, 0, 0));
    EXPECT_NEAR(std::atan2(x.y, x.x), 0.7853982f, 1e-5f);
    EXPECT_NEAR(glm::length(x), 1.0f, 1e-5f);  // normalised, no scaling
    // A third of the way: 30 degrees (slerp is uniform in angle).
    const glm::vec3 x3 = glm::vec3(evaluate_pose(scene, 0, 1.0f / 3.0f).world[0] * glm::vec4(1, 0, 0, 0));
    EXPECT_NEAR(std::atan2(x3.y, x3.x), 0.5235988f, 1e-5f);
}

TEST(AnimationTest, CubicSplineRotationIsNormalised) {
    const float h = std::sqrt(0.5f);
    // Tangents that pull the interpolated quaternion off the unit sphere.
    const std::vector<float> v = {0, 0, 0, 0, /*v0*/ 0, 0, 0, 1, /*b0*/ 0, 0, 3, 3, /*a1*/ 0, 0, 3, 3, /*v1*/ 0, 0, h, h, /*b1*/ 0, 0, 0, 0};
    const Scene scene = one_node(sampler({0, 1}, v, 4, Interpolation::cubic_spline), AnimationPath::rotation);
    const glm::mat3 m(evaluate_pose(scene, 0, 0.5f).world[0]);
    EXPECT_NEAR(glm::determinant(m), 1.0f, 1e-4f);
    EXPECT_NEAR(glm::length(m[0]), 1.0f, 1e-4f);
}

TEST(AnimationTest, ParentsComposeAndUnanimatedNodesKeepTheirTransform) {
    Scene scene = one_node(sampler({0, 1}, {0, 0, 0, 0, 2, 0}, 3, Interpolation::linear), AnimationPath::translation);
    Node child;
    child.name = "child";
    child.parent = 0;
    child.local = glm::translate(glm::mat4(1.0f), glm::vec3(1, 0, 0));  // placed through `local` only
    scene.nodes.push_back(child);
    scene.nodes[0].children.push_back(1);
    pose_scene(scene, 0, 0.5f);
    EXPECT_NEAR(glm::distance(glm::vec3(scene.nodes[1].world[3]), glm::vec3(1, 1, 0)), 0.0f, kEps);
    pose_scene(scene, -1, 0.0f);  // the rest pose again
    EXPECT_NEAR(glm::distance(glm::vec3(scene.nodes[1].world[3]), glm::vec3(1, 0, 0)), 0.0f, kEps);
    EXPECT_NEAR(glm::distance(glm::vec3(scene.nodes[0].world[3]), glm::vec3(0, 0, 0)), 0.0f, kEps);
}

// A flat bar along x from 0 to 2 (y in [-0.1, 0.1], z = 0, facing +z), skinned to two joints: joint
// 0 at the origin, joint 1 (its child) at x = 1. Vertices left of x = 1 follow joint 0, right of
// it joint 1, at x = 1 half each. Animation 0 turns joint 1 by `angle` about z over one second.
// The bar's own node sits at `mesh_offset`: a skinned mesh ignores its node's transform.
Scene two_bone_bar(float angle, glm::vec3 mesh_offset, int columns = 9) {
    Scene scene;
    scene.source = "test:two_bone_bar";
    Material m;
    m.base_color = glm::vec4(0, 0, 0, 1);
    m.emissive = glm::vec3(1.0f);
    m.metallic = 0.0f;
    m.double_sided = true;
    scene.materials.push_back(m);
    Primitive p;
    p.material = 0;
    p.influence_sets = 1;
    for (int i = 0; i < columns; ++i) {
        const float x = 2.0f * static_cast<float>(i) / static_cast<float>(columns - 1);
        for (float y : {-0.1f, 0.1f}) {
            Vertex v;
            v.position = glm::vec3(x, y, 0.0f);
            v.normal = glm::vec3(0, 0, 1);
            v.tangent = glm::vec4(1, 0, 0, 1);
            p.vertices.push_back(v);
            p.joints.push_back(glm::u16vec4(0, 1, 0, 0));
            const float w1 = x < 1.0f - 1e-6f ? 0.0f : x > 1.0f + 1e-6f ? 1.0f : 0.5f;
            p.weights.push_back(glm::vec4(1.0f - w1, w1, 0, 0));
        }
        if (i + 1 < columns) {
            const std::uint32_t a = static_cast<std::uint32_t>(2 * i);
            p.indices.insert(p.indices.end(), {a, a + 2, a + 3, a, a + 3, a + 1});
        }
    }
    p.rest = p.vertices;
    compute_bounds(p);
    scene.meshes.push_back({"bar", {std::move(p)}, {}});
    Node bar, j0, j1;
    bar.name = "bar";
    bar.mesh = 0;
    bar.skin = 0;
    bar.translation = mesh_offset;
    bar.local = glm::translate(glm::mat4(1.0f), mesh_offset);
    j0.name = "joint0";
    j0.children = {2};
    j1.name = "joint1";
    j1.parent = 1;
    j1.translation = glm::vec3(1, 0, 0);
    j1.local = glm::translate(glm::mat4(1.0f), j1.translation);
    scene.nodes = {bar, j0, j1};
    scene.roots = {0, 1};
    Skin skin;
    skin.joints = {1, 2};
    skin.inverse_bind = {glm::mat4(1.0f), glm::translate(glm::mat4(1.0f), glm::vec3(-1, 0, 0))};
    scene.skins.push_back(skin);
    Animation a;
    a.name = "bend";
    const glm::quat q = glm::angleAxis(angle, glm::vec3(0, 0, 1));
    a.samplers.push_back(sampler({0, 1}, {0, 0, 0, 1, q.x, q.y, q.z, q.w}, 4, Interpolation::linear));
    a.channels.push_back({0, 2, AnimationPath::rotation});
    a.end = 1.0f;
    scene.animations.push_back(a);
    scene.update_world_transforms();
    return scene;
}

// The bent bar's known shape: a point (x, y) right of the joint turns by `angle` about (1, 0).
glm::vec2 bent(glm::vec2 p, float angle) {
    const glm::vec2 d = p - glm::vec2(1, 0);
    return glm::vec2(1, 0) + glm::vec2(d.x * std::cos(angle) - d.y * std::sin(angle), d.x * std::sin(angle) + d.y * std::cos(angle));
}

TEST(SkinTest, TwoBoneSkinBendsABarToItsKnownShape) {
    const float angle = 1.5707963f;
    Scene scene = two_bone_bar(angle, glm::vec3(5, 0, 0));
    pose_scene(scene, 0, 1.0f);
    const Primitive& p = scene.meshes[0].primitives[0];
    const glm::mat4& world = scene.nodes[0].world;
    ASSERT_EQ(p.vertices.size(), p.rest.size());
    for (size_t v = 0; v < p.vertices.size(); ++v) {
        const glm::vec2 rest(p.rest[v].position);
        const glm::vec3 got = glm::vec3(world * glm::vec4(p.vertices[v].position, 1.0f));  // what the draw and the tracer see
        glm::vec2 want = rest;
        if (rest.x > 1.0f + 1e-6f) want = bent(rest, angle);
        else if (std::fabs(rest.x - 1.0f) < 1e-6f) want = 0.5f * (rest + bent(rest, angle));  // linear blend of the two joints
        EXPECT_NEAR(got.x, want.x, 1e-5f) << "vertex " << v;
        EXPECT_NEAR(got.y, want.y, 1e-5f) << "vertex " << v;
        EXPECT_NEAR(got.z, 0.0f, 1e-5f);
        // Normals of a bend about z stay +z; tangents turn with the joint.
        EXPECT_NEAR(p.vertices[v].normal.z, 1.0f, 1e-5f);
        if (rest.x > 1.0f + 1e-6f) EXPECT_NEAR(p.vertices[v].tangent.y, 1.0f, 1e-5f);
    }
    // The bounds follow the pose.
    EXPECT_GT(p.bounds.max.y, 0.9f);
    // The rest pose is the bar as given (the skeleton's rest matches the inverse binds).
    pose_scene(scene, -1, 0.0f);
    for (size_t v = 0; v < p.vertices.size(); ++v) {
        const glm::vec3 got = glm::vec3(scene.nodes[0].world * glm::vec4(p.vertices[v].position, 1.0f));
        EXPECT_NEAR(glm::distance(got, p.rest[v].position), 0.0f, 1e-5f);
    }
}

TEST(MorphTest, WeightsBlendTargetsAndAnimatedWeightsFollowTheirKeys) {
    Scene scene;
    Primitive p;
    for (int i = 0; i < 3; ++i) {
        Vertex v;
        v.position = glm::vec3(static_cast<float>(i), 0, 0);
        p.vertices.push_back(v);
    }
    p.indices = {0, 1, 2};
    MorphTarget up, out;
    up.position = {glm::vec3(0, 1, 0), glm::vec3(0, 2, 0), glm::vec3(0, 3, 0)};
    up.normal = {glm::vec3(1, 0, -1), glm::vec3(1, 0, -1), glm::vec3(1, 0, -1)};
    out.position = {glm::vec3(0, 0, 1), glm::vec3(0, 0, 1), glm::vec3(0, 0, 1)};
    p.targets = {up, out};
    p.rest = p.vertices;
    scene.meshes.push_back({"m", {p}, {0.5f, 0.0f}});
    Node n;
    n.mesh = 0;
    n.rest_weights = {0.5f, 0.0f};
    scene.nodes.push_back(n);
    scene.roots.push_back(0);
    Animation a;
    a.samplers.push_back(sampler({0, 1}, {0, 0, 1, 2}, 2, Interpolation::linear));
    a.channels.push_back({0, 0, AnimationPath::weights});
    a.end = 1.0f;
    scene.animations.push_back(a);
    // The rest pose: the default weights (0.5, 0).
    pose_scene(scene, -1, 0.0f);
    EXPECT_NEAR(scene.meshes[0].primitives[0].vertices[2].position.y, 1.5f, kEps);
    EXPECT_NEAR(scene.meshes[0].primitives[0].vertices[2].position.z, 0.0f, kEps);
    // Weights animated to (0.5, 1) at t = 0.5: y = 0.5 * 3, z = 1.
    pose_scene(scene, 0, 0.5f);
    const Vertex& v = scene.meshes[0].primitives[0].vertices[2];
    EXPECT_NEAR(v.position.y, 1.5f, kEps);
    EXPECT_NEAR(v.position.z, 1.0f, kEps);
    EXPECT_NEAR(glm::length(v.normal), 1.0f, 1e-5f);  // morphed normals are renormalised
    EXPECT_GT(v.normal.x, 0.1f);
}

TEST(AnimationTest, FindsAnimationsByIndexOrNameAndNamesTheChoicesOtherwise) {
    Scene scene = two_bone_bar(1.0f, glm::vec3(0.0f));
    EXPECT_EQ(find_animation(scene, "0"), 0);
    EXPECT_EQ(find_animation(scene, "bend"), 0);
    try {
        find_animation(scene, "walk");
        FAIL() << "an unknown animation must be bad input";
    } catch (const Error& e) {
        EXPECT_EQ(e.code(), ExitCode::bad_input);
        EXPECT_NE(std::string(e.what()).find("0 'bend'"), std::string::npos) << e.what();
    }
    EXPECT_THROW(find_animation(scene, "3"), Error);
}

TEST(AnimationTest, ShutterIntervalIsCentredOnTheFrameTime) {
    const ShutterInterval s = shutter_interval(2.0f, 0.5f, 25.0f);
    EXPECT_NEAR(s.open, 2.0f - 0.01f, 1e-6f);
    EXPECT_NEAR(s.close, 2.0f + 0.01f, 1e-6f);
    EXPECT_TRUE(shutter_interval(2.0f, 0.0f, 25.0f).instant());
}

// Raster and tracer draw the same bent bar: the emissive bar on black, pixel centres on both
// sides (aa off, rt.jitter off), so the images agree up to pixels whose centre lies on an edge.
class SkinRasterTracerTest : public test::GlContextTest {};

TEST_P(SkinRasterTracerTest, RasterAndTracerAgreeOnTheBentBar) {
    const ShaderLibrary lib(ShaderLibrary::default_root());
    const int w = 96, h = 64;
    Scene scene = two_bone_bar(1.2f, glm::vec3(0.0f), 17);
    Camera cam;
    cam.orthographic = true;
    cam.xmag = 1.5f;
    cam.ymag = 1.0f;
    cam.znear = 0.1f;
    cam.zfar = 10.0f;
    cam.world = glm::translate(glm::mat4(1.0f), glm::vec3(1.0f, 0.5f, 3.0f));
    scene.cameras.push_back(cam);
    auto raster = [&] {
        StillOptions so;
        so.width = w;
        so.height = h;
        apply_effects(so.settings, "none");
        StillResult r = render_still(scene, lib, so);
        EXPECT_EQ(count_nonfinite(r.radiance), 0u);
        return r.radiance;
    };
    auto trace = [&] {
        rt::Options o;
        o.mode = rt::Mode::direct;
        o.spp = 1;
        o.jitter = 0;
        GpuScene gpu(scene);
        rt::Result r = rt::RayTracer(lib, scene, gpu, o).render(scene.select_camera("", static_cast<float>(w) / h), w, h);
        EXPECT_EQ(count_nonfinite(r.image), 0u);
        return r.image;
    };
    const ImageF rest = raster();
    pose_scene(scene, 0, 1.0f);
    const ImageF a = raster(), b = trace();
    if (const char* dir = std::getenv("CANDELA_TEST_DUMP")) {  // to look at the images
        write_image(std::string(dir) + "/bar_rest.png", rest, 0.0f);
        write_image(std::string(dir) + "/bar_raster.png", a, 0.0f);
        write_image(std::string(dir) + "/bar_tracer.png", b, 0.0f);
    }
    int covered = 0, differ = 0, moved = 0;
    for (int y = 0; y < h; ++y)
        for (int x = 0; x < w; ++x) {
            const bool ra = a.at(x, y)[0] > 0.5f, rb = b.at(x, y)[0] > 0.5f;
            covered += ra;
            differ += ra != rb;
            moved += ra != (rest.at(x, y)[0] > 0.5f);
        }
    // The bar covers about 2 x 0.2 world units of the 3 x 2 view: ~6 % of 6144 pixels.
    EXPECT_GT(covered, 250);
    EXPECT_GT(moved, 100) << "the pose must move the bar's right half";
    EXPECT_LE(differ, covered / 25) << differ << " of " << covered << " pixels differ between raster and tracer";
}

// MorphStressTest (Khronos sample, tests/data/models): its animation's weights deform it as the
// file says. The posed vertices are the rest ones plus the targets weighted by the file's own
// sampler at that time, and the image at that time equals the one rendered from those weights set
// by hand (no animation), and differs from the rest pose.
class MorphStressTest : public test::GlContextTest {};

TEST_P(MorphStressTest, AnimatedWeightsDeformItAsTheFileSays) {
    Scene scene = load_gltf(std::filesystem::path(CANDELA_SOURCE_DIR) / "tests/data/models/MorphStressTest/MorphStressTest.gltf");
    ASSERT_FALSE(scene.animations.empty());
    apply_lighting(scene, LightingMode::auto_select, scene.select_camera("", 4.0f / 3.0f));  // the default rig, as render does
    const int anim = find_animation(scene, "TheWave");
    const float t = 1.0f;
    // The file's weights at t, from its sampler.
    const Animation& a = scene.animations[static_cast<size_t>(anim)];
    ASSERT_EQ(a.channels.size(), 1u);
    ASSERT_EQ(a.channels[0].path, AnimationPath::weights);
    const AnimationSampler& smp = a.samplers[static_cast<size_t>(a.channels[0].sampler)];
    std::vector<float> w(static_cast<size_t>(smp.width));
    sample_animation(smp, AnimationPath::weights, t, w.data());
    float wsum = 0.0f;
    for (float x : w) wsum += x;
    ASSERT_GT(wsum, 0.1f) << "the wave must be under way at t = 1";
    const int node = a.channels[0].node;
    const Mesh& mesh = scene.meshes[static_cast<size_t>(scene.nodes[static_cast<size_t>(node)].mesh)];

    const ShaderLibrary lib(ShaderLibrary::default_root());
    StillOptions so;
    so.width = 128;
    so.height = 96;
    apply_effects(so.settings, "none");
    FrameLoop loop(scene, lib, so);  // one context, GPU scene and program set for all three poses
    auto raster = [&] {
        loop.measure_frame();
        StillResult r = loop.finish();
        EXPECT_EQ(count_nonfinite(r.radiance), 0u);
        return r.radiance;
    };
    const ImageF rest = raster();
    loop.set_pose(scene, anim, t);
    // Vertices: rest + sum_k w_k delta_k.
    double worst = 0.0;
    for (const Primitive& p : mesh.primitives) {
        if (p.targets.empty()) continue;
        for (size_t v = 0; v < p.vertices.size(); v += 7) {
            glm::vec3 want = p.rest[v].position;
            for (size_t k = 0; k < p.targets.size() && k < w.size(); ++k)
                if (v < p.targets[k].position.size()) want += w[k] * p.targets[k].position[v];
            worst = std::max(worst, static_cast<double>(glm::distance(want, p.vertices[v].position)));
        }
    }
    EXPECT_LT(worst, 1e-5);
    const ImageF posed = raster();
    // The same weights by hand, without the animation.
    scene.nodes[static_cast<size_t>(node)].rest_weights = w;
    loop.set_pose(scene, -1, 0.0f);
    const ImageF by_hand = raster();
    int changed = 0, mismatched = 0;
    for (int y = 0; y < rest.height; ++y)
        for (int x = 0; x < rest.width; ++x) {
            changed += std::fabs(posed.at(x, y)[0] - rest.at(x, y)[0]) + std::fabs(posed.at(x, y)[1] - rest.at(x, y)[1]) > 0.05f;
            mismatched += std::fabs(posed.at(x, y)[0] - by_hand.at(x, y)[0]) > 1e-4f;
        }
    EXPECT_GT(changed, 30) << "the weights must change the image";
    EXPECT_EQ(mismatched, 0);
}

// EGL only: both backends are the same llvmpipe; the Fox goldens run on both.
INSTANTIATE_TEST_SUITE_P(Backends, MorphStressTest, ::testing::Values(Backend::egl), test::backend_name);

INSTANTIATE_TEST_SUITE_P(Backends, SkinRasterTracerTest, ::testing::Values(Backend::egl, Backend::osmesa), test::backend_name);

}  // namespace
}  // namespace candela
