// The BVH's GPU traversal layout (rt::pack_traversal): its structure, checked by
// rt::traversal_layout_violation, and a C++ walk of it that follows trace() in shaders/rt/scene.glsl
// step by step, compared with testing every primitive.
#include <gtest/gtest.h>

#include <bit>
#include <cmath>
#include <limits>
#include <random>
#include <vector>

#include "rt/intersect.hpp"
#include "rt/rt_geometry.hpp"

namespace candela::rt {
namespace {

constexpr float kInf = std::numeric_limits<float>::infinity();

TriangleGpu triangle(glm::vec3 a, glm::vec3 b, glm::vec3 c) {
    TriangleGpu t{};
    t.p0 = glm::vec4(a, 0.0f);
    t.p1 = glm::vec4(b, 0.0f);
    t.p2 = glm::vec4(c, 0.0f);
    return t;
}

SphereGpu sphere(glm::vec3 c, float r) {
    SphereGpu s{};
    s.center = c;
    s.radius = r;
    return s;
}

// Builds the BVH over g's primitives as build_rt_geometry does (triangles first, then spheres).
void build(RtGeometry& g, int max_leaf_size = 4) {
    BvhOptions o;
    o.max_leaf_size = max_leaf_size;
    g.bvh = build_bvh_binned_sah(primitive_boxes(g), o);
}

RtGeometry random_geometry(int triangles, int spheres, unsigned seed) {
    std::mt19937 rng(seed);
    std::uniform_real_distribution<float> pos(-10.0f, 10.0f), off(-0.8f, 0.8f), rad(0.05f, 0.6f);
    RtGeometry g;
    for (int i = 0; i < triangles; ++i) {
        const glm::vec3 c(pos(rng), pos(rng), pos(rng));
        g.triangles.push_back(triangle(c + glm::vec3(off(rng), off(rng), off(rng)), c + glm::vec3(off(rng), off(rng), off(rng)),
                                       c + glm::vec3(off(rng), off(rng), off(rng))));
    }
    for (int i = 0; i < spheres; ++i) g.spheres.push_back(sphere(glm::vec3(pos(rng), pos(rng), pos(rng)), rad(rng)));
    build(g);
    return g;
}

// shaders/rt/intersect.glsl's slab test.
float intersect_aabb(glm::vec3 bmin, glm::vec3 bmax, glm::vec3 origin, glm::vec3 inv_dir, float tmax) {
    const glm::bvec3 negative = glm::lessThan(inv_dir, glm::vec3(0.0f));
    const glm::vec3 tn = (glm::mix(bmin, bmax, negative) - origin) * inv_dir;
    const glm::vec3 tf = (glm::mix(bmax, bmin, negative) - origin) * inv_dir;
    const float enter = std::max(std::max(tn.x, tn.y), std::max(tn.z, 0.0f));
    const float leave = std::min(std::min(tf.x, tf.y), std::min(tf.z, tmax));
    return enter <= leave ? enter : -1.0f;
}

struct Hit {
    float t;
    int prim = -1;
};

// trace() of shaders/rt/scene.glsl over the packed layout, statement for statement: the
// while-while loop, near child first, any hit returning at the first hit.
Hit trace_packed(const TraversalLayout& l, std::size_t triangle_count, const Ray& ray, float tmax, bool any_hit) {
    constexpr std::int32_t kDone = kTraversalNoChild;
    Hit hit{tmax};
    const WatertightRay w = watertight_setup(ray);
    const glm::vec3 inv_dir = 1.0f / ray.dir;
    std::vector<std::int32_t> stack;
    auto pop = [&] {
        if (stack.empty()) return kDone;
        const std::int32_t r = stack.back();
        stack.pop_back();
        return r;
    };
    std::int32_t ref = 0;
    while (true) {
        while (ref >= 0) {
            const glm::vec4* n = &l.nodes[static_cast<std::size_t>(ref) * 4];
            const float tl = intersect_aabb(n[0], n[1], ray.origin, inv_dir, hit.t);
            const float tr = intersect_aabb(n[2], n[3], ray.origin, inv_dir, hit.t);
            const std::int32_t left = std::bit_cast<std::int32_t>(n[0].w), right = std::bit_cast<std::int32_t>(n[2].w);
            const bool hl = tl >= 0.0f, hr = tr >= 0.0f;
            if (hl && hr) {
                const bool left_first = tl <= tr;
                stack.push_back(left_first ? right : left);
                ref = left_first ? left : right;
            } else if (hl || hr) {
                ref = hl ? left : right;
            } else {
                ref = pop();
            }
        }
        if (ref == kDone) break;
        while (ref < 0 && ref != kDone) {
            const std::int32_t code = -1 - ref;
            const int first = code >> 6, count = (code & 63) + 1;
            for (int i = 0; i < count; ++i) {
                const glm::vec4* a = &l.prims[static_cast<std::size_t>(first + i) * 3];
                const int prim = std::bit_cast<std::int32_t>(a[0].w);
                glm::vec2 bary;
                const float t = static_cast<std::size_t>(prim) < triangle_count
                                    ? intersect_triangle(w, a[0], a[1], a[2], hit.t, bary)
                                    : intersect_sphere(ray, a[0], a[1].x, 0.0f, hit.t);
                if (t > 0.0f && t < hit.t) {
                    hit.t = t;
                    hit.prim = prim;
                    if (any_hit) return hit;
                }
            }
            ref = pop();
        }
        if (ref == kDone) break;
    }
    return hit;
}

Hit brute_force(const RtGeometry& g, const Ray& ray, float tmax) {
    Hit hit{tmax};
    const WatertightRay w = watertight_setup(ray);
    for (std::size_t i = 0; i < g.triangles.size(); ++i) {
        glm::vec2 bary;
        const TriangleGpu& tr = g.triangles[i];
        const float t = intersect_triangle(w, tr.p0, tr.p1, tr.p2, hit.t, bary);
        if (t > 0.0f && t < hit.t) hit = {t, static_cast<int>(i)};
    }
    for (std::size_t i = 0; i < g.spheres.size(); ++i) {
        const float t = intersect_sphere(ray, g.spheres[i].center, g.spheres[i].radius, 0.0f, hit.t);
        if (t > 0.0f && t < hit.t) hit = {t, static_cast<int>(g.triangles.size() + i)};
    }
    return hit;
}

TEST(TraversalLayout, RandomScenesHoldEveryPrimitiveOnce) {
    for (unsigned seed = 1; seed <= 4; ++seed) {
        const RtGeometry g = random_geometry(500 * static_cast<int>(seed), 20, seed);
        const TraversalLayout l = pack_traversal(g);
        EXPECT_EQ(traversal_layout_violation(g, l), "") << "seed " << seed;
        // One 4-texel record per interior node of the BVH.
        std::size_t interior = 0;
        for (const BvhNode& n : g.bvh.nodes) interior += n.leaf() ? 0 : 1;
        EXPECT_EQ(l.nodes.size(), interior * 4);
    }
}

TEST(TraversalLayout, ClosestAndAnyHitMatchTestingEveryPrimitive) {
    const RtGeometry g = random_geometry(3000, 40, 7);
    const TraversalLayout l = pack_traversal(g);
    ASSERT_EQ(traversal_layout_violation(g, l), "");
    std::mt19937 rng(11);
    std::uniform_real_distribution<float> u(-1.0f, 1.0f);
    int hits = 0, misses = 0;
    for (int i = 0; i < 4000; ++i) {
        Ray ray{glm::vec3(u(rng), u(rng), u(rng)) * 14.0f, glm::vec3(u(rng), u(rng), u(rng))};
        if (glm::length(ray.dir) < 1e-3f) continue;
        const float tmax = i % 3 == 0 ? 5.0f : 3.0e38f;  // some rays end inside the scene
        const Hit expected = brute_force(g, ray, tmax);
        const Hit closest = trace_packed(l, g.triangles.size(), ray, tmax, false);
        ASSERT_EQ(closest.prim, expected.prim) << "ray " << i;
        if (expected.prim >= 0) {
            EXPECT_EQ(closest.t, expected.t) << "ray " << i;
            ++hits;
        } else {
            ++misses;
        }
        EXPECT_EQ(trace_packed(l, g.triangles.size(), ray, tmax, true).prim >= 0, expected.prim >= 0) << "ray " << i;
    }
    // Both outcomes are exercised.
    EXPECT_GT(hits, 400);
    EXPECT_GT(misses, 400);
}

TEST(TraversalLayout, RootLeafAndEmptyScene) {
    RtGeometry one;
    one.triangles.push_back(triangle({0, 0, 0}, {1, 0, 0}, {0, 1, 0}));
    build(one);
    ASSERT_TRUE(one.bvh.nodes[0].leaf());
    const TraversalLayout l = pack_traversal(one);
    EXPECT_EQ(traversal_layout_violation(one, l), "");
    ASSERT_EQ(l.nodes.size(), 4u);  // the root leaf on the left, an empty box on the right
    EXPECT_EQ(l.nodes[2].x, kInf);
    EXPECT_EQ(l.nodes[3].x, -kInf);
    EXPECT_EQ(std::bit_cast<std::int32_t>(l.nodes[2].w), kTraversalNoChild);
    EXPECT_EQ(trace_packed(l, 1, Ray{{0.2f, 0.2f, 1.0f}, {0, 0, -1}}, 3e38f, false).prim, 0);
    EXPECT_EQ(trace_packed(l, 1, Ray{{2.0f, 2.0f, 1.0f}, {0, 0, -1}}, 3e38f, false).prim, -1);

    RtGeometry none;
    build(none);
    const TraversalLayout e = pack_traversal(none);
    EXPECT_EQ(traversal_layout_violation(none, e), "");
    EXPECT_TRUE(e.prims.empty());
    EXPECT_EQ(trace_packed(e, 0, Ray{{0, 0, 1}, {0, 0, -1}}, 3e38f, false).prim, -1);
}

TEST(TraversalLayout, LeavesOfSixtyFourPrimitives) {
    // Identical triangles cannot be split by the SAH: leaves fill up to the largest size the
    // leaf ref encodes (count - 1 in 6 bits).
    RtGeometry g;
    for (int i = 0; i < 128; ++i) g.triangles.push_back(triangle({0, 0, 0}, {1, 0, 0}, {0, 1, 0}));
    build(g, 64);
    int largest = 0;
    for (const BvhNode& n : g.bvh.nodes) largest = std::max(largest, n.count);
    EXPECT_EQ(largest, 64);
    const TraversalLayout l = pack_traversal(g);
    EXPECT_EQ(traversal_layout_violation(g, l), "");
    const Hit any = trace_packed(l, g.triangles.size(), Ray{{0.2f, 0.2f, 1.0f}, {0, 0, -1}}, 3e38f, true);
    EXPECT_GE(any.prim, 0);
}

TEST(TraversalLayout, NonFinitePrimitivesAreReachableButNeverHit) {
    RtGeometry g = random_geometry(100, 0, 3);
    const float nan = std::numeric_limits<float>::quiet_NaN();
    g.triangles.push_back(triangle({nan, 0, 0}, {1, 0, 0}, {0, 1, 0}));
    g.spheres.push_back(sphere({0, 0, 0}, kInf));
    build(g);
    const TraversalLayout l = pack_traversal(g);
    EXPECT_EQ(traversal_layout_violation(g, l), "");
    std::mt19937 rng(5);
    std::uniform_real_distribution<float> u(-1.0f, 1.0f);
    for (int i = 0; i < 500; ++i) {
        const Ray ray{glm::vec3(u(rng), u(rng), u(rng)) * 14.0f, glm::vec3(u(rng), u(rng), u(rng))};
        const Hit h = trace_packed(l, g.triangles.size(), ray, 3e38f, false);
        EXPECT_LT(h.prim, 100) << "ray " << i;
    }
}

TEST(TraversalLayout, DetectsABrokenLayout) {
    const RtGeometry g = random_geometry(300, 5, 9);
    TraversalLayout l = pack_traversal(g);
    ASSERT_EQ(traversal_layout_violation(g, l), "");
    TraversalLayout moved = l;
    moved.prims[3].x += 1.0f;  // the second record's p0
    EXPECT_NE(traversal_layout_violation(g, moved), "");
    TraversalLayout lost = l;
    lost.nodes[0].w = std::bit_cast<float>(std::int32_t{1 << 20});  // the root's left child out of range
    EXPECT_NE(traversal_layout_violation(g, lost), "");
    TraversalLayout shrunk = l;
    shrunk.nodes[4].x = shrunk.nodes[5].x;  // node 1's left box is no longer inside node 0's
    shrunk.nodes[4].x += 100.0f;
    shrunk.nodes[5].x += 100.0f;
    EXPECT_NE(traversal_layout_violation(g, shrunk), "");
}

}  // namespace
}  // namespace candela::rt
