#include <gtest/gtest.h>

#include <cmath>
#include <cstring>
#include <limits>
#include <random>
#include <string>
#include <vector>

#include "rt/bvh.hpp"

namespace candela::rt {
namespace {

constexpr float kNaN = std::numeric_limits<float>::quiet_NaN();
constexpr float kInf = std::numeric_limits<float>::infinity();

Aabb box(glm::vec3 min, glm::vec3 max) { return Aabb{min, max}; }

bool usable(const Aabb& b) {
    return !b.empty() && std::isfinite(b.min.x) && std::isfinite(b.min.y) && std::isfinite(b.min.z) &&
           std::isfinite(b.max.x) && std::isfinite(b.max.y) && std::isfinite(b.max.z);
}

// An empty inner box is contained in anything: it widens nothing.
bool contains(const glm::vec3& min, const glm::vec3& max, const Aabb& inner) {
    if (inner.empty()) return true;
    return glm::all(glm::lessThanEqual(min, inner.min)) && glm::all(glm::lessThanEqual(inner.max, max));
}

Aabb node_box(const BvhNode& n) { return Aabb{n.bmin, n.bmax}; }
bool node_box_empty(const BvhNode& n) { return node_box(n).empty(); }

// Walks the tree from the root and checks every invariant the GPU traversal relies on. Stops
// after a few failures so that one broken tree does not print a million lines.
void expect_valid_bvh(const Bvh& bvh, const std::vector<Aabb>& prims, int max_leaf_size,
                      const BvhOptions& options = {}) {
    ASSERT_FALSE(bvh.nodes.empty());
    ASSERT_EQ(bvh.prim_indices.size(), prims.size());
    const auto node_count = static_cast<int>(bvh.nodes.size());
    std::vector<int> seen_prim(prims.size(), 0), seen_node(bvh.nodes.size(), 0);
    struct Visit {
        int node, depth;
    };
    std::vector<Visit> stack{{0, 0}};
    int leaves = 0, max_depth = 0, largest_leaf = 0, failures = 0;
    while (!stack.empty() && failures < 10) {
        const Visit v = stack.back();
        stack.pop_back();
        ++seen_node[static_cast<size_t>(v.node)];
        const BvhNode& n = bvh.nodes[static_cast<size_t>(v.node)];
        if (n.leaf()) {
            ++leaves;
            max_depth = std::max(max_depth, v.depth);
            largest_leaf = std::max(largest_leaf, n.count);
            if (max_leaf_size > 0 && n.count > max_leaf_size) {
                ++failures;
                ADD_FAILURE() << "leaf " << v.node << " holds " << n.count;
            }
            if (n.right_or_first < 0 || n.right_or_first + n.count > static_cast<int>(prims.size())) {
                ++failures;
                ADD_FAILURE() << "leaf " << v.node << " range out of bounds";
                continue;
            }
            for (int k = n.right_or_first; k < n.right_or_first + n.count; ++k) {
                const std::uint32_t p = bvh.prim_indices[static_cast<size_t>(k)];
                if (p >= prims.size()) {
                    ++failures;
                    ADD_FAILURE() << "primitive index " << p << " out of range";
                    continue;
                }
                ++seen_prim[p];
                if (usable(prims[p]) && !contains(n.bmin, n.bmax, prims[p])) {
                    ++failures;
                    ADD_FAILURE() << "leaf " << v.node << " does not contain primitive " << p;
                }
                // Non-finite primitives live in leaves of their own, whose box is empty.
                if (!usable(prims[p]) && !node_box_empty(n)) {
                    ++failures;
                    ADD_FAILURE() << "non-finite primitive " << p << " shares a non-empty leaf";
                }
            }
            continue;
        }
        const int left = v.node + 1, right = n.right_or_first;
        // Depth-first layout: left child follows, right child comes after the left subtree.
        if (left >= node_count || right <= left || right >= node_count) {
            ++failures;
            ADD_FAILURE() << "interior node " << v.node << " has children " << left << ", " << right;
            continue;
        }
        for (int child : {left, right}) {
            if (!contains(n.bmin, n.bmax, node_box(bvh.nodes[static_cast<size_t>(child)]))) {
                ++failures;
                ADD_FAILURE() << "node " << v.node << " does not contain child " << child;
            }
            stack.push_back({child, v.depth + 1});
        }
    }
    for (size_t i = 0; i < seen_node.size(); ++i) {
        if (seen_node[i] != 1) {
            ADD_FAILURE() << "node " << i << " reached " << seen_node[i] << " times";
            break;
        }
    }
    for (size_t p = 0; p < seen_prim.size(); ++p) {
        if (seen_prim[p] != 1) {
            ADD_FAILURE() << "primitive " << p << " appears " << seen_prim[p] << " times";
            break;
        }
    }
    EXPECT_EQ(bvh.stats.node_count, node_count);
    EXPECT_EQ(bvh.stats.leaf_count, leaves);
    EXPECT_EQ(bvh.stats.max_depth, max_depth);
    EXPECT_EQ(bvh.stats.max_leaf_prims, largest_leaf);
    EXPECT_LE(bvh.stats.max_depth, kBvhMaxDepth);
    EXPECT_DOUBLE_EQ(bvh.stats.sah_cost, sah_cost(bvh, options));
    EXPECT_GE(bvh.stats.build_ms, 0.0);
}

std::vector<Aabb> random_small_boxes(int count, unsigned seed) {
    std::mt19937 rng(seed);
    std::uniform_real_distribution<float> unit(0.0f, 1.0f), half_size(0.0f, 0.01f);
    std::vector<Aabb> prims;
    for (int i = 0; i < count; ++i) {
        const glm::vec3 c(unit(rng), unit(rng), unit(rng)), e(half_size(rng), half_size(rng), half_size(rng));
        prims.push_back(box(c - e, c + e));
    }
    return prims;
}

Aabb triangle_box(const glm::vec3& a, const glm::vec3& b, const glm::vec3& c) {
    Aabb t;
    t.extend(a);
    t.extend(b);
    t.extend(c);
    return t;
}

// The triangles of a UV sphere: thin slivers at the poles, regular quads at the equator.
std::vector<Aabb> uv_sphere_triangles(int stacks, int slices, const glm::vec3& center, float radius) {
    const float pi = 3.14159265f;
    auto point = [&](int i, int j) {
        const float theta = pi * static_cast<float>(i) / static_cast<float>(stacks);
        const float phi = 2.0f * pi * static_cast<float>(j) / static_cast<float>(slices);
        const glm::vec3 normal(std::sin(theta) * std::cos(phi), std::cos(theta), std::sin(theta) * std::sin(phi));
        return center + radius * normal;
    };
    std::vector<Aabb> prims;
    for (int i = 0; i < stacks; ++i) {
        for (int j = 0; j < slices; ++j) {
            const glm::vec3 a = point(i, j), b = point(i + 1, j), c = point(i + 1, j + 1), d = point(i, j + 1);
            prims.push_back(triangle_box(a, b, c));
            prims.push_back(triangle_box(a, c, d));
        }
    }
    return prims;
}

// A Cornell box: five walls, a light and two blocks as large flat boxes (two triangles per quad),
// and a finely tessellated sphere standing in the room.
std::vector<Aabb> cornell_like() {
    std::vector<Aabb> prims;
    auto quad = [&](glm::vec3 min, glm::vec3 max) {
        prims.push_back(box(min, max));
        prims.push_back(box(min, max));
    };
    quad({0, 0, 0}, {1, 0, 1});        // floor
    quad({0, 1, 0}, {1, 1, 1});        // ceiling
    quad({0, 0, 0}, {0, 1, 1});        // left
    quad({1, 0, 0}, {1, 1, 1});        // right
    quad({0, 0, 1}, {1, 1, 1});        // back
    quad({0.4f, 0.999f, 0.4f}, {0.6f, 0.999f, 0.6f});  // light
    for (const auto& [lo, hi] : {std::pair{glm::vec3(0.15f, 0, 0.2f), glm::vec3(0.45f, 0.6f, 0.5f)},
                                 std::pair{glm::vec3(0.55f, 0, 0.55f), glm::vec3(0.85f, 0.3f, 0.85f)}}) {
        quad({lo.x, lo.y, lo.z}, {hi.x, hi.y, lo.z});
        quad({lo.x, lo.y, hi.z}, {hi.x, hi.y, hi.z});
        quad({lo.x, lo.y, lo.z}, {lo.x, hi.y, hi.z});
        quad({hi.x, lo.y, lo.z}, {hi.x, hi.y, hi.z});
        quad({lo.x, hi.y, lo.z}, {hi.x, hi.y, hi.z});
    }
    const std::vector<Aabb> sphere = uv_sphere_triangles(60, 80, {0.7f, 0.45f, 0.7f}, 0.15f);
    prims.insert(prims.end(), sphere.begin(), sphere.end());
    return prims;
}

void expect_binned_close_to_sweep(const std::vector<Aabb>& prims) {
    const Bvh binned = build_bvh_binned_sah(prims);
    const Bvh sweep = build_bvh_sweep_sah(prims);
    expect_valid_bvh(binned, prims, BvhOptions{}.max_leaf_size);
    expect_valid_bvh(sweep, prims, BvhOptions{}.max_leaf_size);
    EXPECT_LE(binned.stats.sah_cost, 1.10 * sweep.stats.sah_cost)
        << "binned " << binned.stats.sah_cost << " vs sweep " << sweep.stats.sah_cost;
    const double ratio = binned.stats.sah_cost / sweep.stats.sah_cost;
    ::testing::Test::RecordProperty("sah_binned_over_sweep", std::to_string(ratio));
}

TEST(Bvh, RandomBoxesCloseToSweep) { expect_binned_close_to_sweep(random_small_boxes(20000, 1)); }

TEST(Bvh, SphereMeshCloseToSweep) { expect_binned_close_to_sweep(uv_sphere_triangles(100, 100, {0, 0, 0}, 1.0f)); }

TEST(Bvh, CornellBoxCloseToSweep) { expect_binned_close_to_sweep(cornell_like()); }

TEST(Bvh, SahCostOfTwoClusters) {
    // Two far-apart clusters: the root must separate them, and the SAH cost is then exactly
    // traversal + each leaf's count weighted by its area share.
    std::vector<Aabb> prims;
    for (int i = 0; i < 3; ++i) prims.push_back(box({0, 0, 0}, {1, 1, 1}));
    for (int i = 0; i < 3; ++i) prims.push_back(box({9, 0, 0}, {10, 1, 1}));
    const Bvh bvh = build_bvh_binned_sah(prims);
    expect_valid_bvh(bvh, prims, 4);
    ASSERT_EQ(bvh.nodes.size(), 3u);
    EXPECT_EQ(bvh.nodes[1].count, 3);
    EXPECT_EQ(bvh.nodes[2].count, 3);
    const double root_half_area = 10.0 * 1 + 1 * 1 + 1 * 10, leaf_half_area = 3.0;
    EXPECT_NEAR(bvh.stats.sah_cost, 1.0 + 2 * 3 * leaf_half_area / root_half_area, 1e-12);
    // The constants scale the terms they belong to.
    BvhOptions costly;
    costly.traversal_cost = 2.0f;
    costly.intersection_cost = 0.5f;
    EXPECT_NEAR(sah_cost(bvh, costly), 2.0 + 0.5 * 2 * 3 * leaf_half_area / root_half_area, 1e-12);
}

// The builders share their fallbacks (median splits, leaf rules), so agreeing with each other
// proves little on its own; these catch a builder that stopped following the SAH.
TEST(Bvh, SahIsolatesTheOutlier) {
    // Few enough for one leaf, yet the far box is worth a node of its own: a builder ignoring the
    // SAH would keep one leaf (or, forced to split, cut the cluster at the median).
    std::vector<Aabb> prims(6, box({0, 0, 0}, {1, 1, 1}));
    prims.push_back(box({9, 0, 0}, {10, 1, 1}));
    BvhOptions options;
    options.max_leaf_size = 8;
    for (const Bvh& bvh : {build_bvh_binned_sah(prims, options), build_bvh_sweep_sah(prims, options)}) {
        expect_valid_bvh(bvh, prims, 8, options);
        ASSERT_EQ(bvh.nodes.size(), 3u);
        EXPECT_EQ(bvh.nodes[1].count + bvh.nodes[2].count, 7);
        EXPECT_EQ(std::min(bvh.nodes[1].count, bvh.nodes[2].count), 1);
    }
}

TEST(Bvh, SahSplitsBelowTheLeafBound) {
    // With room for 64 per leaf, only the SAH makes leaves small on scattered boxes.
    const std::vector<Aabb> prims = random_small_boxes(20000, 9);
    BvhOptions options;
    options.max_leaf_size = 64;
    // Traversal priced so high that the SAH never splits: median splits down to 64 per leaf.
    const Bvh median = build_bvh_binned_sah(prims, BvhOptions{32, 64, 1e6f, 1.0f});
    for (const auto& [name, bvh] : {std::pair{"binned", build_bvh_binned_sah(prims, options)},
                                     std::pair{"sweep", build_bvh_sweep_sah(prims, options)}}) {
        EXPECT_GT(bvh.stats.leaf_count, 20000 / 4) << name;
        EXPECT_LT(bvh.stats.sah_cost, 0.5 * sah_cost(median, options)) << name;
        ::testing::Test::RecordProperty(std::string("sah_over_median_tree_") + name,
                                        std::to_string(bvh.stats.sah_cost / sah_cost(median, options)));
    }
}

TEST(Bvh, LeafSizeFollowsOptions) {
    const std::vector<Aabb> prims = random_small_boxes(5000, 2);
    for (int leaf_size : {1, 2, 8, 64}) {
        BvhOptions options;
        options.max_leaf_size = leaf_size;
        // Cheap traversal makes the SAH want big leaves; the bound must still hold.
        options.traversal_cost = 0.01f;
        expect_valid_bvh(build_bvh_binned_sah(prims, options), prims, leaf_size, options);
        expect_valid_bvh(build_bvh_sweep_sah(prims, options), prims, leaf_size, options);
    }
}

TEST(Bvh, OutOfRangeOptionsAreClamped) {
    const std::vector<Aabb> prims = random_small_boxes(3000, 3);
    BvhOptions options;
    options.bins = 100000;
    options.max_leaf_size = 0;
    options.traversal_cost = -1.0f;
    options.intersection_cost = kNaN;
    const Bvh bvh = build_bvh_binned_sah(prims, options);
    expect_valid_bvh(bvh, prims, 1, options);
    EXPECT_EQ(bvh.stats.max_leaf_prims, 1);
    options.bins = -5;
    options.max_leaf_size = 1000;
    expect_valid_bvh(build_bvh_binned_sah(prims, options), prims, 64, options);
}

TEST(Bvh, EmptyInputIsOneEmptyNode) {
    for (const Bvh& bvh : {build_bvh_binned_sah({}), build_bvh_sweep_sah({})}) {
        ASSERT_EQ(bvh.nodes.size(), 1u);
        EXPECT_EQ(bvh.nodes[0].count, 0);
        EXPECT_FALSE(bvh.nodes[0].leaf());
        EXPECT_TRUE(node_box_empty(bvh.nodes[0]));
        EXPECT_TRUE(bvh.prim_indices.empty());
        EXPECT_EQ(bvh.stats.node_count, 1);
        EXPECT_EQ(bvh.stats.leaf_count, 1);
        EXPECT_EQ(bvh.stats.max_depth, 0);
        EXPECT_EQ(bvh.stats.max_leaf_prims, 0);
        EXPECT_EQ(bvh.stats.sah_cost, 0.0);
    }
}

TEST(Bvh, SinglePrimitiveIsOneLeaf) {
    const std::vector<Aabb> prims{box({1, 2, 3}, {4, 5, 6})};
    const Bvh bvh = build_bvh_binned_sah(prims);
    expect_valid_bvh(bvh, prims, 1);
    ASSERT_EQ(bvh.nodes.size(), 1u);
    EXPECT_EQ(bvh.nodes[0].count, 1);
    EXPECT_EQ(bvh.nodes[0].bmin, glm::vec3(1, 2, 3));
    EXPECT_EQ(bvh.nodes[0].bmax, glm::vec3(4, 5, 6));
    EXPECT_DOUBLE_EQ(bvh.stats.sah_cost, 1.0);
}

TEST(Bvh, IdenticalBoxesSplitInTheMiddle) {
    const std::vector<Aabb> prims(1000, box({0, 0, 0}, {1, 1, 1}));
    for (const Bvh& bvh : {build_bvh_binned_sah(prims), build_bvh_sweep_sah(prims)}) {
        expect_valid_bvh(bvh, prims, 4);
        EXPECT_LE(bvh.stats.max_depth, 8);  // ceil(log2(1000 / 4)): balanced
    }
}

TEST(Bvh, FlatAndCollinearBoxes) {
    // Quads in one plane (zero thickness) and points on one line (a root of zero area).
    std::vector<Aabb> flat, line;
    std::mt19937 rng(4);
    std::uniform_real_distribution<float> unit(0.0f, 1.0f);
    for (int i = 0; i < 2000; ++i) {
        const float x = unit(rng), y = unit(rng);
        flat.push_back(box({x, y, 0.5f}, {x + 0.01f, y + 0.01f, 0.5f}));
        const glm::vec3 p(unit(rng), 0, 0);
        line.push_back(box(p, p));
    }
    for (const auto& prims : {flat, line}) {
        const Bvh binned = build_bvh_binned_sah(prims), sweep = build_bvh_sweep_sah(prims);
        expect_valid_bvh(binned, prims, 4);
        expect_valid_bvh(sweep, prims, 4);
        EXPECT_TRUE(std::isfinite(binned.stats.sah_cost));
    }
}

TEST(Bvh, NonFiniteBoxesAreSetAside) {
    std::vector<Aabb> prims = random_small_boxes(3000, 5);
    for (size_t i = 0; i < prims.size(); i += 7) prims[i].min.x = kNaN;
    for (size_t i = 3; i < prims.size(); i += 11) prims[i].max.y = kInf;
    for (size_t i = 5; i < prims.size(); i += 13) prims[i] = box({1, 1, 1}, {0, 0, 0});  // inverted
    prims.push_back(Aabb{});                                                            // empty
    Aabb valid_bounds;
    for (const Aabb& b : prims) {
        if (usable(b)) valid_bounds.extend(b);
    }
    for (const Bvh& bvh : {build_bvh_binned_sah(prims), build_bvh_sweep_sah(prims)}) {
        expect_valid_bvh(bvh, prims, 4);
        EXPECT_EQ(bvh.nodes[0].bmin, valid_bounds.min);
        EXPECT_EQ(bvh.nodes[0].bmax, valid_bounds.max);
        EXPECT_TRUE(std::isfinite(bvh.stats.sah_cost));
    }
    // Nothing usable at all.
    const std::vector<Aabb> all_bad(100, box({kNaN, 0, 0}, {1, 1, 1}));
    const Bvh bvh = build_bvh_binned_sah(all_bad);
    expect_valid_bvh(bvh, all_bad, 4);
    EXPECT_TRUE(node_box_empty(bvh.nodes[0]));
}

// The header promises that empty nodes are missed by a slab test choosing near and far planes by
// the sign of the ray direction (Williams et al. 2005), the form the GPU traversal must use.
TEST(Bvh, EmptyNodeBoxIsMissedBySignSlabTest) {
    const Bvh bvh = build_bvh_binned_sah({box({kNaN, 0, 0}, {1, 1, 1})});
    const BvhNode& n = bvh.nodes[0];
    std::mt19937 rng(6);
    std::uniform_real_distribution<float> coord(-10.0f, 10.0f);
    for (int i = 0; i < 1000; ++i) {
        glm::vec3 dir(coord(rng), coord(rng), coord(rng));
        if (i % 3 == 0) dir.x = 0.0f;  // axis-parallel rays: 1/d is infinite
        if (i % 5 == 0) dir.y = -0.0f;
        const glm::vec3 origin(coord(rng), coord(rng), coord(rng)), inv = 1.0f / dir;
        float t_near = 0.0f, t_far = 1e30f;
        for (int a = 0; a < 3; ++a) {
            const bool negative = std::signbit(inv[a]);
            t_near = std::max(t_near, ((negative ? n.bmax : n.bmin)[a] - origin[a]) * inv[a]);
            t_far = std::min(t_far, ((negative ? n.bmin : n.bmax)[a] - origin[a]) * inv[a]);
        }
        EXPECT_FALSE(t_near <= t_far) << "ray " << i << " enters the empty node";
    }
}

TEST(Bvh, LargeBuildStaysShallow) {
    const std::vector<Aabb> prims = random_small_boxes(200000, 7);
    const Bvh bvh = build_bvh_binned_sah(prims);
    expect_valid_bvh(bvh, prims, 4);
    EXPECT_LT(bvh.stats.max_depth, 64);
    // The same input gives the same tree, bit for bit.
    const Bvh again = build_bvh_binned_sah(prims);
    EXPECT_EQ(again.prim_indices, bvh.prim_indices);
    EXPECT_EQ(0, std::memcmp(again.nodes.data(), bvh.nodes.data(), bvh.nodes.size() * sizeof(BvhNode)));
}

TEST(Bvh, DepthIsBoundedOnClusteredInput) {
    // Boxes around the origin with radii spread over 30 decades: the SAH keeps peeling off the
    // outer shells, which left alone gives trees 60 to 120 deep (measured with the bound lifted).
    std::mt19937 rng(8);
    std::uniform_real_distribution<float> unit(0.0f, 1.0f);
    std::vector<Aabb> prims;
    for (int i = 0; i < 20000; ++i) {
        const float r = std::pow(10.0f, -30.0f * unit(rng));
        const glm::vec3 c = r * glm::normalize(glm::vec3(unit(rng) - 0.5f, unit(rng) - 0.5f, unit(rng) - 0.5f));
        prims.push_back(box(c - 0.01f * r, c + 0.01f * r));
    }
    BvhOptions few_bins;
    few_bins.bins = 4;
    for (const Bvh& bvh :
         {build_bvh_binned_sah(prims), build_bvh_binned_sah(prims, few_bins), build_bvh_sweep_sah(prims)}) {
        expect_valid_bvh(bvh, prims, 4);
        EXPECT_LE(bvh.stats.max_depth, kBvhMaxDepth);
    }
}

}  // namespace
}  // namespace candela::rt
