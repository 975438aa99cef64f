// The tracer's motion blur against its closed form, and the BVH refit it relies on.
//
// The scene: an emissive quad (radiance 1, black albedo, black background) W = 20 units wide and
// taller than the image, moved along +X by a glTF node animation with a LINEAR translation
// sampler: its left edge at a0 + D u over the shutter's u in [0, 1] (D = 12). An orthographic
// camera with 1 unit per pixel and the tracer's jitter off, so each sample of pixel column x
// looks at the point X = x + 0.5 - 24 and returns 1 exactly while the quad covers it. The pixel's
// expected value is the fraction of the shutter during which the quad covers X:
//     c(X) = max(0, min(1, (X - a0) / D) - max(0, (X - a0 - W) / D)).
// a0 is a quarter unit off the pixel centres so that no edge crosses a centre at shutter open or
// close. Columns with 0 < c < 1 are partial; W > D leaves some covered for the whole shutter.
//
// The samples of a render fall in time slices (Options::shutter_slices; 0: one per sample), slice
// k at (k + r_k) / S with r_k a hash of the seed and k: a jittered stratification of the shutter.
// Two kinds of batches, kBatches of each:
// - by seed (set_seed): complete renders, i.i.d.; only the strata that hold a coverage boundary
//   vary, so the standard error is small and the test sharp;
// - by shard (set_shard, as --spp-shard): one render split; the batches' jitters are independent,
//   but each takes every kBatches-th stratum, so its expectation differs from c by a Riemann-sum
//   term that cancels over the batches (the merged image is unbiased). That spread only widens
//   the batch standard error: this z is conservative (about 10x here), kept as the brief's check.
// Asserted for both: per ramp of partial columns (swept by the quad's left or right edge), the z
// of the pooled mean difference from c (pooled within a batch: the pixels share their sample
// times), every partial pixel's |z| below a bound, the mean |difference| small, covered and
// uncovered pixels exact. Also: the shards merge to the single run with motion (0 and 5
// slices); the progressive mode gives the render's image; pose_at's times are stratified and
// shard-independent, and the scene is left at u = 0.5. Then CPU tests (no GL): the BVH refit, and
// the tracer's triangles (bit for bit Scene::world_triangles()).
#include <gtest/gtest.h>

#include <glm/gtc/matrix_transform.hpp>

#include <algorithm>
#include <bit>
#include <cmath>
#include <cstdio>
#include <cstring>
#include <filesystem>
#include <random>
#include <vector>

#include "gl_fixture.hpp"
#include "image/batch_stats.hpp"
#include "image/image.hpp"
#include "render/gpu_scene.hpp"
#include "rt/bvh.hpp"
#include "rt/ray_tracer.hpp"
#include "rt/rt_geometry.hpp"
#include "rt/shard_merge.hpp"
#include "scene/animation.hpp"
#include "scene/gltf_loader.hpp"
#include "scene/mesh_utils.hpp"

namespace candela {
namespace {
namespace fs = std::filesystem;

constexpr int kWidth = 48, kHeight = 16;
constexpr float kHalfHeight = 8.0f;  // camera ymag: 1 unit per pixel (xmag = ymag * aspect = 24)
constexpr double kQuadWidth = 20.0;  // W
constexpr double kTravel = 12.0;     // D
constexpr double kLeft0 = -17.25;    // a0: the quad's left edge at shutter open
constexpr int kBatches = 16;
constexpr int kSppPerBatch = 16;
constexpr double kPooledZ = 4.0;
// 24 partial columns of t-distributed z with 15 degrees of freedom: P(|t15| > 7) = 4e-6 each.
constexpr double kPixelZ = 7.0;

double coverage(double X, double travel = kTravel) {
    const double a = std::min(1.0, (X - kLeft0) / travel), b = std::max(0.0, (X - kLeft0 - kQuadWidth) / travel);
    return std::max(0.0, a - b);
}
double column_x(int x) { return x + 0.5 - kWidth / 2.0; }

// The quad (node 0, a unit-free mesh W x 40 centred on its node) and its animation: translation
// from the centre at open (a0 + W / 2) to D further at close, keyframes at 0 and 1 s.
Scene moving_quad_scene() {
    Scene scene;
    scene.source = "moving quad";
    Material m;
    m.name = "emitter";
    m.base_color = glm::vec4(0.0f, 0.0f, 0.0f, 1.0f);
    m.metallic = 0.0f;
    m.roughness = 1.0f;
    m.emissive = glm::vec3(1.0f);
    scene.materials.push_back(m);
    Primitive quad;
    quad.material = 0;
    const float hw = static_cast<float>(kQuadWidth / 2.0), hh = 20.0f;
    const glm::vec2 corners[4] = {{-hw, -hh}, {hw, -hh}, {hw, hh}, {-hw, hh}};
    for (const glm::vec2& c : corners) {
        Vertex v;
        v.position = glm::vec3(c, 0.0f);
        v.normal = glm::vec3(0.0f, 0.0f, 1.0f);
        v.tangent = glm::vec4(1.0f, 0.0f, 0.0f, 1.0f);
        quad.vertices.push_back(v);
    }
    quad.indices = {0, 1, 2, 0, 2, 3};
    compute_bounds(quad);
    Mesh mesh;
    mesh.name = "quad";
    mesh.primitives.push_back(std::move(quad));
    scene.meshes.push_back(std::move(mesh));
    Node node;
    node.name = "mover";
    node.mesh = 0;
    const float x0 = static_cast<float>(kLeft0 + kQuadWidth / 2.0);
    node.translation = glm::vec3(x0, 0.0f, 0.0f);
    node.local = glm::translate(glm::mat4(1.0f), node.translation);
    scene.nodes.push_back(node);
    scene.roots = {0};
    Animation a;
    a.name = "slide";
    AnimationSampler s;
    s.times = {0.0f, 1.0f};
    s.values = {x0, 0.0f, 0.0f, x0 + static_cast<float>(kTravel), 0.0f, 0.0f};
    s.width = 3;
    s.interpolation = Interpolation::linear;
    a.samplers.push_back(s);
    a.channels.push_back({0, 0, AnimationPath::translation});
    a.start = 0.0f;
    a.end = 1.0f;
    scene.animations.push_back(a);
    scene.update_world_transforms();
    return scene;
}

Camera ortho_camera() {
    Camera c;
    c.name = "ortho";
    c.orthographic = true;
    c.ymag = kHalfHeight;
    c.xmag = kHalfHeight * kWidth / kHeight;
    c.znear = 0.1f;
    c.zfar = 20.0f;
    c.world = glm::translate(glm::mat4(1.0f), glm::vec3(0.0f, 0.0f, 5.0f));
    return c;
}

// The shutter of frame time 0.5 s, one frame per second, open the whole frame: [0, 1] s.
rt::Options motion_options(Scene& scene, int spp, std::vector<float>* times = nullptr) {
    const ShutterInterval shutter = shutter_interval(0.5f, 1.0f, 1.0f);
    rt::Options o;
    o.mode = rt::Mode::direct;
    o.spp = spp;
    o.jitter = 0;
    o.seed = 7;
    o.pose_at = [&scene, shutter, times](float u) {
        if (times) times->push_back(u);
        pose_scene(scene, 0, shutter.open + u * (shutter.close - shutter.open));
    };
    return o;
}


class RtMotionTest : public test::GlContextTest {
protected:
    ShaderLibrary shaders_{fs::path(CANDELA_SOURCE_DIR) / "shaders"};
};

// The batches' images against the closed form.
struct Agreement {
    int partial = 0, exact = 0, exact_mismatches = 0;
    double max_z = 0.0, mean_abs_error = 0.0;
    BatchMean ramp[2];  // per ramp (0: the quad's left edge sweeps these columns; 1: its right edge)
    double ramp_z[2] = {0.0, 0.0};
};
double z_of(const BatchMean& e, double expected) {
    const double d = e.mean - expected;
    if (std::fabs(d) < 1e-9) return 0.0;  // e.g. a column whose boundary falls on a stratum's edge: no noise at all
    return e.se > 0.0 ? d / e.se : INFINITY;
}
Agreement agreement(const std::vector<ImageF>& batches, double travel = kTravel) {
    Agreement a;
    const size_t n = batches.size();
    // Per batch, per ramp: the mean over the ramp's pixels of (value - c). The pixels share their
    // sample times, so they are pooled within a batch and the batches give the standard error. (Over
    // both ramps together the sum is constant: the quad always covers 20 columns.)
    std::vector<double> ramp_sum[2] = {std::vector<double>(n, 0.0), std::vector<double>(n, 0.0)};
    int ramp_count[2] = {0, 0};
    for (int y = 0; y < kHeight; ++y)
        for (int x = 0; x < kWidth; ++x) {
            const double X = column_x(x), c = coverage(X, travel);
            std::vector<double> v;
            for (const ImageF& img : batches) v.push_back(img.at(x, y)[0]);
            if (coverage(X) == 0.0 || coverage(X) == 1.0) {
                for (double value : v) a.exact_mismatches += value != c;
                ++a.exact;
                continue;
            }
            ++a.partial;
            const BatchMean e = batch_mean(v);
            a.mean_abs_error += std::fabs(e.mean - c);
            a.max_z = std::max(a.max_z, std::fabs(z_of(e, c)));
            const int ramp = X < kLeft0 + kQuadWidth ? 0 : 1;
            ++ramp_count[ramp];
            for (size_t b = 0; b < n; ++b) ramp_sum[ramp][b] += v[b] - c;
        }
    a.mean_abs_error /= std::max(a.partial, 1);
    for (int r = 0; r < 2; ++r) {
        for (double& d : ramp_sum[r]) d /= std::max(ramp_count[r], 1);
        a.ramp[r] = batch_mean(ramp_sum[r]);
        a.ramp_z[r] = z_of(a.ramp[r], 0.0);
    }
    return a;
}

void expect_closed_form(const Agreement& a, const char* what) {
    std::printf("%s: %d partial pixels, %d never or always covered (%d mismatches); mean |difference| %.5f, max |z| per pixel "
                "%.2f; pooled difference left ramp %+.6f +- %.6f (z %+.2f), right ramp %+.6f +- %.6f (z %+.2f)\n",
                what, a.partial, a.exact, a.exact_mismatches, a.mean_abs_error, a.max_z, a.ramp[0].mean, a.ramp[0].se,
                a.ramp_z[0], a.ramp[1].mean, a.ramp[1].se, a.ramp_z[1]);
    EXPECT_EQ(a.partial, 24 * kHeight) << what;  // columns the quad covers for part of the shutter
    EXPECT_EQ(a.exact_mismatches, 0) << what;
    EXPECT_LT(a.max_z, kPixelZ) << what;
    EXPECT_LT(std::fabs(a.ramp_z[0]), kPooledZ) << what;
    EXPECT_LT(std::fabs(a.ramp_z[1]), kPooledZ) << what;
    // A sharp image at the frame's time would be off by 0.25 per partial pixel on average.
    EXPECT_LT(a.mean_abs_error, 0.02) << what;
}

// Two kinds of batches. Seeds: kBatches renders of kSppPerBatch samples with seeds 1..kBatches,
// each a full jittered stratification of the shutter (i.i.d.: only the strata holding a coverage
// boundary vary, so the standard error is small and the test sharp). Shards: one render of
// kBatches * kSppPerBatch samples split by set_shard (independent, but each batch takes every
// kBatches-th stratum: the Riemann-sum spread makes its z conservative, about 10x here).
TEST_P(RtMotionTest, MovingQuadBlursToItsCoverageFraction) {
    const ShutterInterval shutter = shutter_interval(0.5f, 1.0f, 1.0f);
    ASSERT_FLOAT_EQ(shutter.open, 0.0f);
    ASSERT_FLOAT_EQ(shutter.close, 1.0f);
    Scene scene = moving_quad_scene();
    GpuScene gpu(scene);
    const Camera camera = ortho_camera();
    std::vector<ImageF> seeds, shards;
    {
        rt::RayTracer tracer(shaders_, scene, gpu, motion_options(scene, kSppPerBatch));
        for (int b = 0; b < kBatches; ++b) {
            tracer.set_seed(static_cast<std::uint32_t>(b + 1));
            const rt::Result r = tracer.render(camera, kWidth, kHeight);
            EXPECT_EQ(r.nonfinite_samples, 0u);
            EXPECT_EQ(r.shutter_slices, kSppPerBatch);  // one slice per sample
            seeds.push_back(r.image);
        }
    }
    {
        rt::RayTracer tracer(shaders_, scene, gpu, motion_options(scene, kBatches * kSppPerBatch));
        for (int b = 0; b < kBatches; ++b) {
            tracer.set_shard(b, kBatches);
            const rt::Result r = tracer.render(camera, kWidth, kHeight);
            EXPECT_EQ(r.samples, kSppPerBatch);
            shards.push_back(r.image);
        }
    }
    // The scene is left at the frame's time: the quad's centre halfway.
    EXPECT_NEAR(scene.nodes[0].world[3].x, kLeft0 + kQuadWidth / 2.0 + kTravel / 2.0, 1e-5);
    expect_closed_form(agreement(seeds), "batches by seed");
    expect_closed_form(agreement(shards), "batches by shard");
    // The test's power: the same images against the closed form of a 3 % shorter travel (a
    // shutter 3 % short) fail the pooled test by far with the seed batches.
    const Agreement wrong = agreement(seeds, 0.97 * kTravel);
    std::printf("against a 3 %% shorter travel: pooled z %+.1f (left ramp), %+.1f (right ramp), max |z| per pixel %.1f\n", wrong.ramp_z[0],
                wrong.ramp_z[1], wrong.max_z);
    EXPECT_GT(std::max(std::fabs(wrong.ramp_z[0]), std::fabs(wrong.ramp_z[1])), 2.0 * kPooledZ);
}

TEST_P(RtMotionTest, ShardsMergeToTheSingleRunAndProgressiveMatches) {
    for (const int slices : {0, 5}) {
        Scene scene = moving_quad_scene();
        GpuScene gpu(scene);
        std::vector<float> times;
        rt::Options o = motion_options(scene, 12, &times);
        o.shutter_slices = slices;
        o.jitter = 1;  // pixel jitter on too: its random stream must also be the single run's
        const Camera camera = ortho_camera();
        rt::RayTracer tracer(shaders_, scene, gpu, o);
        const rt::Result whole = tracer.render(camera, kWidth, kHeight);
        // pose_at(0.5) first (the frame's tree), one call per slice, pose_at(0.5) last.
        const int S = slices > 0 ? slices : 12;
        ASSERT_EQ(times.size(), static_cast<size_t>(S + 2)) << "slices " << slices;
        EXPECT_EQ(times.front(), 0.5f);
        EXPECT_EQ(times.back(), 0.5f);
        for (int k = 0; k < S; ++k) {
            const float u = times[static_cast<size_t>(k + 1)];
            EXPECT_GE(u, static_cast<float>(k) / S) << "slice " << k;
            EXPECT_LT(u, static_cast<float>(k + 1) / S) << "slice " << k;
        }
        const std::vector<float> whole_times(times.begin() + 1, times.end() - 1);
        std::vector<ImageF> shards;
        for (int k = 0; k < 3; ++k) {
            times.clear();
            tracer.set_shard(k, 3);
            shards.push_back(tracer.render(camera, kWidth, kHeight).image);
            // A shard visits a subset of the single run's slice times, the same values.
            for (size_t i = 1; i + 1 < times.size(); ++i)
                EXPECT_NE(std::find(whole_times.begin(), whole_times.end(), times[i]), whole_times.end());
        }
        const ImageF merged = rt::merge_shards(shards);
        const CompareResult c = compare(merged, whole.image, 1e-5);
        EXPECT_EQ(c.failing_pixels, 0u) << "slices " << slices << ": max " << c.max_abs;
        // The image is blurred: some pixels are neither 0 nor 1.
        int between = 0;
        for (int x = 0; x < kWidth; ++x) between += whole.image.at(x, kHeight / 2)[0] > 0.05f && whole.image.at(x, kHeight / 2)[0] < 0.95f;
        EXPECT_GT(between, 8) << "slices " << slices;

        // The viewer's progressive mode traces the same samples at the same times.
        tracer.set_shard(0, 1);
        tracer.progressive_restart(camera, kWidth, kHeight);
        while (!tracer.progressive_done()) tracer.progressive_step(1e9);
        const CompareResult p = compare(tracer.progressive_image(), whole.image, 1e-6);
        EXPECT_EQ(p.failing_pixels, 0u) << "slices " << slices << ": progressive max " << p.max_abs;
        EXPECT_NEAR(scene.nodes[0].world[3].x, kLeft0 + kQuadWidth / 2.0 + kTravel / 2.0, 1e-5);
    }
}

INSTANTIATE_TEST_SUITE_P(Backends, RtMotionTest, ::testing::Values(Backend::egl, Backend::osmesa), test::backend_name);

// --- the BVH refit (no GL) -----------------------------------------------------------------------

std::vector<rt::Aabb> soup_boxes(std::mt19937& rng, int n, float spread) {
    std::uniform_real_distribution<float> u(-1.0f, 1.0f);
    std::vector<rt::Aabb> boxes;
    for (int i = 0; i < n; ++i) {
        const glm::vec3 c(u(rng) * spread, u(rng) * spread, u(rng) * spread);
        rt::Aabb b;
        b.extend(c - 0.05f * glm::abs(glm::vec3(u(rng), u(rng), u(rng))));
        b.extend(c + 0.05f * glm::abs(glm::vec3(u(rng), u(rng), u(rng))));
        boxes.push_back(b);
    }
    return boxes;
}

bool inside(const rt::Aabb& inner, const glm::vec3& lo, const glm::vec3& hi) {
    return glm::all(glm::lessThanEqual(lo, inner.min)) && glm::all(glm::lessThanEqual(inner.max, hi));
}

// Every primitive inside its leaf's box, every child inside its parent's; non-finite ones inside
// nothing. Returns the number of violations.
int refit_violations(const rt::Bvh& bvh, const std::vector<rt::Aabb>& boxes) {
    int bad = 0;
    for (size_t i = 0; i < bvh.nodes.size(); ++i) {
        const rt::BvhNode& n = bvh.nodes[i];
        if (n.leaf()) {
            for (int j = 0; j < n.count; ++j) {
                const rt::Aabb& b = boxes[bvh.prim_indices[static_cast<size_t>(n.right_or_first + j)]];
                const bool finite = std::isfinite(b.min.x + b.min.y + b.min.z + b.max.x + b.max.y + b.max.z);
                if (finite && !b.empty() && !inside(b, n.bmin, n.bmax)) ++bad;
            }
        } else if (bvh.nodes.size() > 1) {
            for (size_t c : {i + 1, static_cast<size_t>(n.right_or_first)}) {
                const rt::Aabb child{bvh.nodes[c].bmin, bvh.nodes[c].bmax};
                if (!child.empty() && !inside(child, n.bmin, n.bmax)) ++bad;
            }
        }
    }
    return bad;
}

TEST(BvhRefit, UnchangedBoxesGiveTheBuiltTreeAndMovedOnesAValidOne) {
    std::mt19937 rng(5);
    std::vector<rt::Aabb> boxes = soup_boxes(rng, 2000, 1.0f);
    rt::Bvh bvh = rt::build_bvh_binned_sah(boxes);
    const rt::Bvh built = bvh;
    rt::refit_bvh(bvh, boxes);
    ASSERT_EQ(bvh.nodes.size(), built.nodes.size());
    for (size_t i = 0; i < bvh.nodes.size(); ++i) {
        EXPECT_EQ(bvh.nodes[i].bmin, built.nodes[i].bmin) << i;
        EXPECT_EQ(bvh.nodes[i].bmax, built.nodes[i].bmax) << i;
    }
    EXPECT_NEAR(bvh.stats.sah_cost, built.stats.sah_cost, 1e-9 * built.stats.sah_cost);

    // Move every box (a shear and a random jiggle), one to NaN and one to infinity.
    std::uniform_real_distribution<float> u(-0.2f, 0.2f);
    for (rt::Aabb& b : boxes) {
        const glm::vec3 d(0.5f * b.min.y + u(rng), u(rng), u(rng));
        b.min += d, b.max += d;
    }
    boxes[17].min.x = NAN;
    boxes[18].max.z = INFINITY;
    rt::refit_bvh(bvh, boxes);
    EXPECT_EQ(refit_violations(bvh, boxes), 0);
    EXPECT_EQ(bvh.prim_indices, built.prim_indices);
    // The refit tree is valid but worse than a new build over the moved boxes.
    const rt::Bvh rebuilt = rt::build_bvh_binned_sah(boxes);
    std::printf("refit SAH %.2f, rebuilt %.2f (before the motion %.2f)\n", bvh.stats.sah_cost, rebuilt.stats.sah_cost, built.stats.sah_cost);
    EXPECT_GT(bvh.stats.sah_cost, rebuilt.stats.sah_cost);
    EXPECT_THROW(rt::refit_bvh(bvh, std::vector<rt::Aabb>(5)), std::invalid_argument);
    // The empty tree stays empty.
    rt::Bvh empty = rt::build_bvh_binned_sah({});
    rt::refit_bvh(empty, {});
    EXPECT_TRUE((rt::Aabb{empty.nodes[0].bmin, empty.nodes[0].bmax}.empty()));
}

TEST(BvhRefit, PosedSceneKeepsTheTraversalLayoutValid) {
    Scene scene = moving_quad_scene();
    // A second, bigger mesh so the tree has interior nodes: a 20 x 20 grid of quads on node 1.
    Primitive grid;
    grid.material = 0;
    for (int j = 0; j <= 20; ++j)
        for (int i = 0; i <= 20; ++i) {
            Vertex v;
            v.position = glm::vec3(static_cast<float>(i), static_cast<float>(j), 0.0f) * 0.5f;
            v.normal = glm::vec3(0, 0, 1);
            grid.vertices.push_back(v);
        }
    for (std::uint32_t j = 0; j < 20; ++j)
        for (std::uint32_t i = 0; i < 20; ++i) {
            const std::uint32_t a = j * 21 + i;
            grid.indices.insert(grid.indices.end(), {a, a + 1, a + 22, a, a + 22, a + 21});
        }
    compute_bounds(grid);
    scene.meshes.push_back({"grid", {std::move(grid)}, {}});
    Node g;
    g.mesh = 1;
    scene.nodes.push_back(g);
    scene.roots.push_back(1);
    scene.update_world_transforms();
    rt::RtGeometry geometry = rt::build_rt_geometry(scene, 1);
    const std::vector<std::uint32_t> order = geometry.bvh.prim_indices;
    for (const float t : {0.0f, 0.3f, 1.0f}) {
        pose_scene(scene, 0, t);
        ASSERT_GE(rt::refit_rt_geometry(geometry, scene, 1), 0.0);
        EXPECT_EQ(geometry.bvh.prim_indices, order);
        EXPECT_EQ(rt::traversal_layout_violation(geometry, rt::pack_traversal(geometry)), "") << "t = " << t;
        // The quad's triangles moved with the node.
        float left = INFINITY;
        for (const rt::TriangleGpu& tri : geometry.triangles)
            if (std::bit_cast<int>(tri.p1.w) == 0) left = std::min({left, tri.p0.x, tri.p1.x, tri.p2.x});
        EXPECT_NEAR(left, kLeft0 + kTravel * t, 1e-4) << "t = " << t;
    }
    // A changed triangle count cannot be refit: the geometry is left as it was.
    scene.meshes[1].primitives[0].indices.resize(6);
    const size_t before = geometry.triangles.size();
    EXPECT_LT(rt::refit_rt_geometry(geometry, scene, 1), 0.0);
    EXPECT_EQ(geometry.triangles.size(), before);
}

// The tracer's triangles (written straight from the vertices, each transformed once per node)
// are Scene::world_triangles(), bit for bit: on the posed Fox (skinned), the Cornell box, and a
// scene with a mirrored, a non-uniformly scaled and a sphere node.
TEST(RtGeometry, TrianglesAreTheScenesWorldTrianglesBitForBit) {
    std::vector<Scene> scenes;
    scenes.push_back(load_gltf(fs::path(CANDELA_SOURCE_DIR) / "tests/data/models/Fox/Fox.glb"));
    pose_scene(scenes.back(), find_animation(scenes.back(), "Walk"), 0.37f);
    scenes.push_back(load_gltf(fs::path(CANDELA_SOURCE_DIR) / "samples/scenes/cornell_box.gltf"));
    {
        Scene s = moving_quad_scene();
        Node mirrored = s.nodes[0];
        mirrored.local = glm::scale(glm::rotate(glm::mat4(1.0f), 0.7f, glm::vec3(1, 2, 3)), glm::vec3(-1.0f, 2.0f, 0.5f));
        mirrored.parent = 0;
        s.nodes.push_back(mirrored);
        s.nodes[0].children = {1};
        Node sphere = s.nodes[0];
        sphere.children.clear();
        sphere.sphere_radius = 1.0f;
        s.nodes.push_back(sphere);
        s.roots = {0, 2};
        s.update_world_transforms();
        ASSERT_TRUE(s.nodes[1].mirrored());
        scenes.push_back(std::move(s));
    }
    for (const Scene& scene : scenes) {
        const int fallback = static_cast<int>(scene.materials.size());
        const rt::RtGeometry g = rt::build_rt_geometry(scene, fallback);
        std::vector<WorldTriangle> expected;
        for (const WorldTriangle& t : scene.world_triangles())
            if (!scene.nodes[static_cast<size_t>(t.node)].sphere_radius) expected.push_back(t);
        ASSERT_EQ(g.triangles.size(), expected.size()) << scene.source;
        int mismatches = 0;
        for (size_t i = 0; i < expected.size(); ++i) {
            const WorldTriangle& t = expected[i];
            rt::TriangleGpu w{};
            w.p0 = glm::vec4(t.p[0], std::bit_cast<float>(t.material >= 0 ? t.material : fallback));
            w.p1 = glm::vec4(t.p[1], std::bit_cast<float>(t.node));
            // p2.w: 1 where seeing rays cull the back face (a single-sided opaque material).
            const Material& m = scene.material(t.material);
            w.p2 = glm::vec4(t.p[2], !m.double_sided && m.transmission <= 0.0f ? 1.0f : 0.0f);
            w.n0 = glm::vec4(t.n[0], g.triangles[i].n0.w);  // n0.w: the emitter pdf, set afterwards
            w.n1 = glm::vec4(t.n[1], 0.0f);
            w.n2 = glm::vec4(t.n[2], 0.0f);
            w.uv_a = glm::vec4(t.uv0[0], t.uv0[1]);
            w.uv_b = glm::vec4(t.uv0[2], t.uv1[0]);
            w.uv_c = glm::vec4(t.uv1[1], t.uv1[2]);
            w.t0 = t.tangent[0], w.t1 = t.tangent[1], w.t2 = t.tangent[2];
            mismatches += std::memcmp(&w, &g.triangles[i], sizeof w) != 0;
        }
        EXPECT_EQ(mismatches, 0) << scene.source;
    }
}

}  // namespace
}  // namespace candela
