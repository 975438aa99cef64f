#pragma once
// CPU bounding volume hierarchy for the compute-shader ray tracer (docs/design.md, rt/).
// The builder sees only primitive boxes: triangles and analytic spheres are alike to it. The node
// array is uploaded to the GPU unchanged, so its layout is part of the contract with shaders/rt.
#include <cstdint>
#include <limits>
#include <vector>

#include <glm/glm.hpp>

namespace candela::rt {

// Axis-aligned box. The default box is empty as +inf/-inf so that extending it by anything gives
// that thing. A box with a NaN coordinate also counts as empty: every comparison with NaN fails.
struct Aabb {
    glm::vec3 min{+std::numeric_limits<float>::infinity()};
    glm::vec3 max{-std::numeric_limits<float>::infinity()};

    void extend(const glm::vec3& p) {
        min = glm::min(min, p);
        max = glm::max(max, p);
    }
    void extend(const Aabb& b) {
        min = glm::min(min, b.min);
        max = glm::max(max, b.max);
    }
    // Meaningless for an empty box.
    glm::vec3 centroid() const { return (min + max) * 0.5f; }
    // 0 for an empty box, so that empty boxes weigh nothing in SAH sums.
    float surface_area() const {
        if (empty()) return 0.0f;
        const glm::vec3 d = max - min;
        return 2.0f * (d.x * d.y + d.y * d.z + d.z * d.x);
    }
    bool empty() const { return !(min.x <= max.x && min.y <= max.y && min.z <= max.z); }
};

// 32 bytes, uploaded as-is to a std430 SSBO as { vec3 bmin; int a; vec3 bmax; int b; }.
// Depth-first layout: an interior node's left child is the next node (index + 1), right_or_first is
// the index of its right child and count is 0. A leaf has count > 0 primitives starting at
// Bvh::prim_indices[right_or_first].
// Empty nodes (the empty BVH, and the subtree holding non-finite primitives) keep the inverted box
// bmin = +inf, bmax = -inf. A slab test that picks the near and far plane by the sign of the ray
// direction (Williams et al. 2005, "An efficient and robust ray-box intersection algorithm") misses
// such a box for every ray; one that sorts t0/t1 with min/max does not, and would enter them.
struct BvhNode {
    glm::vec3 bmin;
    std::int32_t right_or_first;
    glm::vec3 bmax;
    std::int32_t count;
    bool leaf() const { return count > 0; }
};
static_assert(sizeof(BvhNode) == 32);

// No leaf is deeper than this (root = depth 0), so a GPU traversal stack of this many entries
// always suffices. The builder trades SAH for balance only on inputs that would go deeper.
inline constexpr int kBvhMaxDepth = 48;

// Out-of-range values are clamped into range; non-finite or negative costs fall back to 1.
struct BvhOptions {
    int bins = 32;          // [4, 256] centroid bins per axis (binned builder only; see below)
    int max_leaf_size = 4;  // [1, 64] primitives; a leaf is smaller when the SAH prefers, never larger
    // Surface area heuristic constants (MacDonald & Booth 1990): the expected cost of a node is
    // traversal_cost + intersection_cost * sum over children of P(hit child | hit node) * count(child),
    // with P taken as the ratio of surface areas. Only their ratio matters to the build.
    float traversal_cost = 1.0f;     // >= 0, per interior node visited
    float intersection_cost = 1.0f;  // > 0, per primitive tested
};

struct BvhStats {
    int node_count = 0;
    int leaf_count = 0;
    int max_depth = 0;  // deepest leaf, root = 0
    double sah_cost = 0.0;  // sah_cost(bvh, options) of the finished tree
    double build_ms = 0.0;  // wall time of the whole build, std::chrono::steady_clock
    int max_leaf_prims = 0;
};

struct Bvh {
    std::vector<BvhNode> nodes;
    std::vector<std::uint32_t> prim_indices;  // leaves index into this; it holds every input index once
    BvhStats stats;
};

// Binned SAH (Wald 2007, "On fast construction of SAH-based bounding volume hierarchies"): at each
// node the centroids are binned along every axis and the best bin boundary is taken. A node of n
// primitives uses min(bins, max(8, n / 2)) bins; below 16 primitives the split is found exactly
// instead (every cut up to 4 primitives, a sweep over the centroid orders up to 15), which costs
// less there and is never worse for that node. A node the SAH would keep whole although it holds
// more than max_leaf_size primitives, or whose SAH split would pass kBvhMaxDepth, is split at the
// object median of the best axis. Single-threaded, no recursion.
//
// Inputs the builder copes with rather than rejects:
// - No primitives: one node with count 0 and an empty box. It is not a leaf by leaf(); the GPU side
//   treats "one node, count 0" as "no hit". Stats: 1 node, 1 leaf, depth 0, SAH cost 0.
// - Boxes that are non-finite or inverted (min > max on some axis) are treated as empty: they go into
//   leaves of their own under an empty subtree, the root's right child, and never widen any box.
// - Coincident centroids, which no split separates: split in the middle of the range, so leaves
//   still hold at most max_leaf_size primitives.
// Throws std::length_error past 2^30 primitives (node indices are int32).
Bvh build_bvh_binned_sah(const std::vector<Aabb>& prims, const BvhOptions& options = {});

// Reference builder for comparison only: at each node, sorts the centroids along each axis and
// evaluates every split position, O(n log^2 n). Same tree rules and layout as the binned builder.
Bvh build_bvh_sweep_sah(const std::vector<Aabb>& prims, const BvhOptions& options = {});

// Refit (posed geometry): keeps the tree's topology (nodes, prim_indices) and recomputes
// every node's box bottom-up from `prims`, one box per primitive index as at the build (the same
// count; throws std::invalid_argument otherwise). Primitives whose box is now empty or non-finite
// widen nothing (a ray never reaches them through their box). stats.sah_cost is recomputed with
// `options`; the other stats keep the build's values. Returns the refit's wall time in ms. The
// tree stays valid for any motion; its quality drops as primitives move away from where the
// build put them (measured in tests/bench/bench_rt_motion.cpp).
double refit_bvh(Bvh& bvh, const std::vector<Aabb>& prims, const BvhOptions& options = {});

// Normalised SAH cost of a built tree: sum over nodes of area(node) / area(root) times
// traversal_cost for interior nodes and intersection_cost * count for leaves. A root of zero area
// (all primitives on one line or point) counts every node with weight 1.
double sah_cost(const Bvh& bvh, const BvhOptions& options = {});

}  // namespace candela::rt
