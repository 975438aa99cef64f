#include "rt/bvh.hpp"

#include <algorithm>
#include <array>
#include <bit>
#include <chrono>
#include <cmath>
#include <cstring>
#include <memory>
#include <optional>
#include <stdexcept>
#include <string>

namespace candela::rt {
namespace {

constexpr float kInf = std::numeric_limits<float>::infinity();

// Four float lanes of which the geometry uses three, as a GCC/Clang vector: each operation is one
// SSE/NEON instruction at any optimisation level. (Plain loops over float[4] vectorise at -O2 but
// GCC 12 turns some back into scalar code at -O3, costing a third of the build time.)
using Lanes = float __attribute__((vector_size(16)));
using IntLanes = std::int32_t __attribute__((vector_size(16)));

Lanes lanes_min(const Lanes& a, const Lanes& b) { return b < a ? b : a; }
Lanes lanes_max(const Lanes& a, const Lanes& b) { return b > a ? b : a; }

Lanes lanes_centroid(const Lanes& lo, const Lanes& hi) { return (lo + hi) * 0.5f; }

// The builder's box: Aabb with the lane layout above.
struct Box4 {
    Lanes lo{kInf, kInf, kInf, kInf};
    Lanes hi{-kInf, -kInf, -kInf, -kInf};

    void extend(const Lanes& l, const Lanes& h) {
        lo = lanes_min(lo, l);
        hi = lanes_max(hi, h);
    }
    void extend(const Box4& b) { extend(b.lo, b.hi); }
    void extend(const Lanes& p) { extend(p, p); }
    bool empty() const { return !(lo[0] <= hi[0] && lo[1] <= hi[1] && lo[2] <= hi[2]); }
    float extent(int axis) const { return hi[axis] - lo[axis]; }
    // Half the surface area. The builder compares SAH costs as area * cost without dividing by the
    // node's area, which keeps nodes of zero area (collinear or coincident boxes) free of 0/0.
    float half_area() const {
        const float dx = hi[0] - lo[0], dy = hi[1] - lo[1], dz = hi[2] - lo[2];
        return dx * dy + dy * dz + dz * dx;
    }
    Aabb aabb() const { return Aabb{{lo[0], lo[1], lo[2]}, {hi[0], hi[1], hi[2]}}; }
};

// A primitive's box and input index in 32 bytes. The builders partition these records in place, so
// every pass streams through memory instead of chasing indices into the input.
struct PrimRef {
    // Lane 3 of lo carries the input index, as the float whose bits are index + kIndexBias: a
    // normal number in [1, FLT_MAX] for every index below 2^30. Lane-wise arithmetic then never
    // meets a NaN or a denormal (slow on many CPUs), and no lane has to be cleared first.
    static constexpr std::uint32_t kIndexBias = 0x3F800000u;  // the bits of 1.0f

    Lanes lo;
    Lanes hi;  // lane 3: 0

    PrimRef() = default;
    PrimRef(const Aabb& box, std::uint32_t index)
        : lo{box.min.x, box.min.y, box.min.z, std::bit_cast<float>(index + kIndexBias)},
          hi{box.max.x, box.max.y, box.max.z, 0.0f} {}

    std::uint32_t index() const { return std::bit_cast<std::uint32_t>(lo[3]) - kIndexBias; }
    Lanes centroid() const { return lanes_centroid(lo, hi); }
    float centroid(int axis) const { return (lo[axis] + hi[axis]) * 0.5f; }
};
static_assert(sizeof(PrimRef) == 32);

bool finite(const glm::vec3& v) { return std::isfinite(v.x) && std::isfinite(v.y) && std::isfinite(v.z); }

struct Params {
    int bins;
    std::uint32_t max_leaf;
    float traversal;
    float intersection;
};

Params clamp_options(const BvhOptions& options) {
    Params p;
    p.bins = std::clamp(options.bins, 4, 256);
    p.max_leaf = static_cast<std::uint32_t>(std::clamp(options.max_leaf_size, 1, 64));
    const float ct = options.traversal_cost, ci = options.intersection_cost;
    p.traversal = std::isfinite(ct) && ct >= 0.0f ? ct : 1.0f;
    p.intersection = std::isfinite(ci) && ci > 0.0f ? ci : 1.0f;
    return p;
}

// How many halvings (keeping the larger half) bring n primitives down to leaf size: the depth a
// subtree of n needs when split at the median all the way down. ceil(log2(ceil(n / max_leaf))).
int levels_to_leaves(std::uint32_t n, std::uint32_t max_leaf) {
    if (n <= max_leaf) return 0;
    return std::bit_width((n + max_leaf - 1) / max_leaf - 1);
}

struct BuildTask {
    std::uint32_t begin = 0, end = 0;
    Box4 bounds;  // of the primitives' boxes; empty for the subtree of non-finite primitives
    Box4 centroid_bounds;
    int depth = 0;
    int right_of = -1;  // interior node whose right child this becomes; -1 for a left child
    std::uint32_t size() const { return end - begin; }
};

// The two children of a split: refs[begin, mid) and refs[mid, end).
struct Split {
    std::uint32_t mid = 0;
    Box4 bounds[2];
    Box4 centroid_bounds[2];

    void add(int side, const PrimRef& r) {
        bounds[side].extend(r.lo, r.hi);
        centroid_bounds[side].extend(r.centroid());
    }
};

// A split the SAH suggests, its cost in the unnormalised units of Box4::half_area.
struct Candidate {
    int axis = 0;
    float cost = 0.0f;
    std::uint32_t left_count = 0;
    std::uint32_t first_right_bin = 0;  // binned splits only
    std::uint32_t left_mask = 0;        // subset splits only: bit k set = k-th primitive goes left
    enum class Kind : std::uint8_t { binned, sweep, subset } kind = Kind::binned;
};

void bound_halves(const PrimRef* refs, const BuildTask& task, Split& split) {
    if (task.bounds.empty()) return;  // non-finite primitives: their subtree stays empty
    for (std::uint32_t i = task.begin; i < split.mid; ++i) split.add(0, refs[i]);
    for (std::uint32_t i = split.mid; i < task.end; ++i) split.add(1, refs[i]);
}

// The fallback when the SAH offers nothing usable: the object median along `axis`. It always
// halves the range, so depth grows only logarithmically and leaves stay bounded, even when every
// centroid is the same point (then the order is left alone and the range is cut in the middle).
Split split_at_median(PrimRef* refs, const BuildTask& task, int axis) {
    Split split;
    split.mid = task.begin + task.size() / 2;
    if (!task.centroid_bounds.empty() && task.centroid_bounds.extent(axis) > 0.0f) {
        std::nth_element(refs + task.begin, refs + split.mid, refs + task.end,
                         [axis](const PrimRef& a, const PrimRef& b) { return a.centroid(axis) < b.centroid(axis); });
    }
    bound_halves(refs, task, split);
    return split;
}

int widest_axis(const Box4& b) {
    const float x = b.extent(0), y = b.extent(1), z = b.extent(2);
    return x >= y && x >= z ? 0 : (y >= z ? 1 : 2);
}

// std::partition without data-dependent branches, after Edelkamp & Weiss 2016 ("BlockQuicksort:
// avoiding branch mispredictions in quicksort"): classify a block at each end into a list of
// misplaced offsets, then swap the lists pairwise. On unordered input a branchy partition
// mispredicts half its elements, and at every level of the tree.
template <class Pred>
PrimRef* partition_branch_free(PrimRef* first, PrimRef* last, Pred goes_left) {
    constexpr std::ptrdiff_t kBlock = 64;
    std::uint8_t misplaced_left[kBlock], misplaced_right[kBlock];  // offsets into each block
    int left_count = 0, right_count = 0, left_start = 0, right_start = 0;
    while (last - first > 2 * kBlock) {
        if (left_count == 0) {
            left_start = 0;
            for (std::ptrdiff_t i = 0; i < kBlock; ++i) {
                misplaced_left[left_count] = static_cast<std::uint8_t>(i);
                left_count += !goes_left(first[i]);
            }
        }
        if (right_count == 0) {
            right_start = 0;
            for (std::ptrdiff_t i = 0; i < kBlock; ++i) {
                misplaced_right[right_count] = static_cast<std::uint8_t>(i);
                right_count += goes_left(last[-1 - i]);
            }
        }
        const int swaps = std::min(left_count, right_count);
        for (int k = 0; k < swaps; ++k) {
            std::swap(first[misplaced_left[left_start + k]], last[-1 - misplaced_right[right_start + k]]);
        }
        left_count -= swaps;
        right_count -= swaps;
        left_start += swaps;
        right_start += swaps;
        if (left_count == 0) first += kBlock;
        if (right_count == 0) last -= kBlock;
    }
    // Everything before first goes left, everything from last on goes right; a block with misplaced
    // elements left over is still inside [first, last).
    return std::partition(first, last, goes_left);
}

// Every split position of the centroid order on each axis. The reference builder uses it for whole
// trees; the binned builder for small nodes, where it is cheaper than binning and exact.
class SweepSplitter {
public:
    SweepSplitter(const Params& params, std::size_t max_count)
        : params_(params), right_area_(max_count), scratch_(max_count), keyed_(max_count) {
        for (auto& order : order_) order.resize(max_count);
    }

    std::optional<Candidate> find(const PrimRef* refs, const BuildTask& task) {
        const std::uint32_t n = task.size();
        const PrimRef* r = refs + task.begin;
        const float node_cost = params_.traversal * task.bounds.half_area();
        if (n == 2) {
            // A third of all nodes: there is only one way to split them, whatever the axis.
            order_[0][0] = 0;
            order_[0][1] = 1;
            Box4 a, b;
            a.extend(r[0].lo, r[0].hi);
            b.extend(r[1].lo, r[1].hi);
            return Candidate{0, node_cost + params_.intersection * (a.half_area() + b.half_area()), 1, 0, 0,
                             Candidate::Kind::sweep};
        }
        std::optional<Candidate> best;
        for (int axis = 0; axis < 3; ++axis) {
            std::uint32_t* order = order_[static_cast<std::size_t>(axis)].data();
            order_by_centroid(r, n, axis, order);
            Box4 right;
            for (std::uint32_t k = n - 1; k > 0; --k) {
                right.extend(r[order[k]].lo, r[order[k]].hi);
                right_area_[k] = right.half_area();
            }
            Box4 left;
            for (std::uint32_t k = 1; k < n; ++k) {
                left.extend(r[order[k - 1]].lo, r[order[k - 1]].hi);
                const float cost =
                    node_cost + params_.intersection * (left.half_area() * static_cast<float>(k) +
                                                        right_area_[k] * static_cast<float>(n - k));
                if (!best || cost < best->cost) best = Candidate{axis, cost, k, 0, 0, Candidate::Kind::sweep};
            }
        }
        return best;
    }

    Split apply(PrimRef* refs, const BuildTask& task, const Candidate& candidate) {
        const std::uint32_t n = task.size();
        const std::uint32_t* order = order_[static_cast<std::size_t>(candidate.axis)].data();
        PrimRef* r = refs + task.begin;
        for (std::uint32_t k = 0; k < n; ++k) scratch_[k] = r[order[k]];
        std::copy_n(scratch_.begin(), n, r);
        Split split;
        split.mid = task.begin + candidate.left_count;
        bound_halves(refs, task, split);
        return split;
    }

private:
    static constexpr std::uint32_t kRankSortMax = 16;  // order_by_centroid unrolls four groups of four

    // order[k] = position in r of the k-th centroid along axis; ties broken by position so the
    // result does not depend on a sort's internals.
    void order_by_centroid(const PrimRef* r, std::uint32_t n, int axis, std::uint32_t* order) {
        if (n <= kRankSortMax) {
            // Most calls are for a handful of primitives. Ranking by counting, four keys at a time
            // in a fixed-size +inf-padded array, has no branches to mispredict: several times
            // faster than an insertion sort there.
            alignas(16) float key[kRankSortMax];
            for (std::uint32_t k = 0; k < kRankSortMax; ++k) key[k] = k < n ? r[k].centroid(axis) : kInf;
            Lanes keys[kRankSortMax / 4];
            std::memcpy(keys, key, sizeof(key));
            for (std::uint32_t i = 0; i < n; ++i) {
                const Lanes this_key{key[i], key[i], key[i], key[i]};
                const auto s = static_cast<std::int32_t>(i);
                const IntLanes this_slot{s, s, s, s};
                // Lanes are -1 where key j sorts before key i.
                const auto before = [&](int q) {
                    const IntLanes slot = IntLanes{0, 1, 2, 3} + 4 * q;
                    return (keys[q] < this_key) | ((keys[q] == this_key) & (slot < this_slot));
                };
                const IntLanes count = before(0) + before(1) + before(2) + before(3);
                order[-(count[0] + count[1] + count[2] + count[3])] = i;
            }
            return;
        }
        for (std::uint32_t k = 0; k < n; ++k) keyed_[k] = Keyed{r[k].centroid(axis), k};
        std::sort(keyed_.begin(), keyed_.begin() + n, [](const Keyed& a, const Keyed& b) {
            return a.key < b.key || (a.key == b.key && a.slot < b.slot);
        });
        for (std::uint32_t k = 0; k < n; ++k) order[k] = keyed_[k].slot;
    }

    struct Keyed {
        float key;
        std::uint32_t slot;
    };

    Params params_;
    std::array<std::vector<std::uint32_t>, 3> order_;
    std::vector<float> right_area_;
    std::vector<PrimRef> scratch_;
    std::vector<Keyed> keyed_;
};

// Binned SAH after Wald 2007: bin = floor(K * (1 - eps) * (c - cmin) / (cmax - cmin)) over the
// node's centroid bounds, then one sweep over the K - 1 bin boundaries per axis.
class BinnedSplitter {
public:
    // Below this many primitives an exact sweep over the centroid orders costs less than clearing
    // and sweeping 3 x bins bins.
    static constexpr std::uint32_t kSweepBelow = 16;
    static constexpr std::uint32_t kSubsetsUpTo = 4;

    explicit BinnedSplitter(const Params& params) : params_(params), small_(params, kSweepBelow) {}

    std::optional<Candidate> find(const PrimRef* refs, const BuildTask& task) {
        if (task.size() <= kSubsetsUpTo) return find_subset(refs, task);
        if (task.size() < kSweepBelow) return small_.find(refs, task);
        // A node of n primitives fills at most n bins, while clearing and sweeping costs the same for
        // every bin: nodes below 2 x bins primitives get n / 2 bins (at least 8). Measured here, this
        // costs under 0.2 % SAH and saves a tenth of the build time.
        const int bins = std::min(params_.bins, std::max(8, static_cast<int>(task.size() / 2)));
        set_up_mapping(task.centroid_bounds, bins);
        for (std::size_t axis = 0; axis < 3; ++axis) {
            std::fill_n(bin_box_[axis].begin(), bins, Box4{});
            std::fill_n(bin_count_[axis].begin(), bins, 0u);
        }
        for (std::uint32_t i = task.begin; i < task.end; ++i) add_to_bins(refs[i]);

        std::optional<Candidate> best;
        const float node_cost = params_.traversal * task.bounds.half_area();
        for (int axis = 0; axis < 3; ++axis) {
            if (scale_[axis] == 0.0f) continue;  // all centroids in one plane across this axis
            const auto& box = bin_box_[static_cast<std::size_t>(axis)];
            const auto& count = bin_count_[static_cast<std::size_t>(axis)];
            // Right to left first, so the left-to-right sweep can price each boundary as it goes.
            Box4 right;
            std::uint32_t right_count = 0;
            for (std::size_t i = static_cast<std::size_t>(bins) - 1; i > 0; --i) {
                right.extend(box[i]);
                right_count += count[i];
                right_box_[i] = right;
                right_area_[i] = right_count > 0 ? right.half_area() : 0.0f;
                right_count_[i] = right_count;
            }
            Box4 left;
            std::uint32_t left_count = 0;
            for (std::size_t i = 1; i < static_cast<std::size_t>(bins); ++i) {
                left.extend(box[i - 1]);
                left_count += count[i - 1];
                if (left_count == 0 || right_count_[i] == 0) continue;
                const float cost =
                    node_cost + params_.intersection * (left.half_area() * static_cast<float>(left_count) +
                                                        right_area_[i] * static_cast<float>(right_count_[i]));
                if (!best || cost < best->cost) {
                    best = Candidate{axis, cost, left_count, static_cast<std::uint32_t>(i), 0, Candidate::Kind::binned};
                    best_bounds_[0] = left;
                    best_bounds_[1] = right_box_[i];
                }
            }
        }
        return best;
    }

    // Partitions by bin. The children's boxes are the unions of their bins, known from find(). Their
    // centroid bounds are taken as the parent's clipped to the child's box, which holds every child
    // centroid: slightly loose, but it saves the builder's most expensive pass.
    Split apply(PrimRef* refs, const BuildTask& task, const Candidate& candidate) {
        if (candidate.kind == Candidate::Kind::sweep) return small_.apply(refs, task, candidate);
        if (candidate.kind == Candidate::Kind::subset) return apply_subset(refs, task, candidate);
        const int axis = candidate.axis;
        const int first_right_bin = static_cast<int>(candidate.first_right_bin);
        const auto goes_left = [&](const PrimRef& r) { return bin_of(r, axis) < first_right_bin; };
        Split split;
        PrimRef* const mid = partition_branch_free(refs + task.begin, refs + task.end, goes_left);
        split.mid = static_cast<std::uint32_t>(mid - refs);
        for (int side = 0; side < 2; ++side) {
            split.bounds[side] = best_bounds_[side];
            split.centroid_bounds[side].lo = lanes_max(task.centroid_bounds.lo, best_bounds_[side].lo);
            split.centroid_bounds[side].hi = lanes_min(task.centroid_bounds.hi, best_bounds_[side].hi);
        }
        return split;
    }

private:
    // Up to kSubsetsUpTo primitives, every one of the 2^(n-1) - 1 ways to cut the node in two is
    // priced: that includes whatever a sweep or binning could find, and costs less than sorting
    // three axes. The last primitive always stays right, so each cut is seen once.
    std::optional<Candidate> find_subset(const PrimRef* refs, const BuildTask& task) const {
        const std::uint32_t n = task.size();
        const PrimRef* r = refs + task.begin;
        const float node_cost = params_.traversal * task.bounds.half_area();
        std::optional<Candidate> best;
        for (std::uint32_t mask = 1; mask < (1u << (n - 1)); ++mask) {
            Box4 left, right;
            for (std::uint32_t k = 0; k < n; ++k) {
                Box4& side = (mask >> k) & 1 ? left : right;
                side.extend(r[k].lo, r[k].hi);
            }
            const auto left_count = static_cast<std::uint32_t>(std::popcount(mask));
            const float cost = node_cost + params_.intersection *
                                               (left.half_area() * static_cast<float>(left_count) +
                                                right.half_area() * static_cast<float>(n - left_count));
            if (!best || cost < best->cost) {
                best = Candidate{widest_axis(task.centroid_bounds), cost, left_count, 0, mask, Candidate::Kind::subset};
            }
        }
        return best;
    }

    static Split apply_subset(PrimRef* refs, const BuildTask& task, const Candidate& candidate) {
        PrimRef* r = refs + task.begin;
        PrimRef ordered[kSubsetsUpTo];
        std::uint32_t left = 0, right = candidate.left_count;
        for (std::uint32_t k = 0; k < task.size(); ++k) {
            ordered[(candidate.left_mask >> k) & 1 ? left++ : right++] = r[k];
        }
        std::copy_n(ordered, task.size(), r);
        Split split;
        split.mid = task.begin + candidate.left_count;
        bound_halves(refs, task, split);
        return split;
    }

    static constexpr std::size_t kMaxBins = 256;

    // Bins are computed from lo + hi, twice the centroid, as ((lo + hi) - origin) * scale: no
    // multiply feeds an add, so no compiler can fuse a step into an FMA in add_to_bins and not in
    // bin_of. The two must agree on every bin index, or a partition would not match the counts
    // and boxes it was priced by.
    void set_up_mapping(const Box4& centroid_bounds, int bins) {
        for (int axis = 0; axis < 3; ++axis) {
            const float extent = 2.0f * centroid_bounds.extent(axis);
            // The (1 - eps) keeps the largest centroid inside the last bin.
            const float scale = static_cast<float>(bins) * (1.0f - 1e-5f) / extent;
            const bool usable = extent > 0.0f && std::isfinite(extent) && std::isfinite(scale);
            origin_[axis] = 2.0f * centroid_bounds.lo[axis];
            scale_[axis] = usable ? scale : 0.0f;
        }
        origin_[3] = scale_[3] = 0.0f;
        last_bin_ = static_cast<float>(bins - 1);
    }

    // Clamped on the float side: NaN (inf - inf on absurd inputs) lands in bin 0 instead of
    // reaching an undefined float-to-int conversion.
    int bin_of(const PrimRef& r, int axis) const {
        float x = ((r.lo[axis] + r.hi[axis]) - origin_[axis]) * scale_[axis];
        x = x > 0.0f ? x : 0.0f;
        x = x < last_bin_ ? x : last_bin_;
        return static_cast<int>(x);
    }

    // bin_of for all three axes at once, lane for lane the same arithmetic.
    void add_to_bins(const PrimRef& r) {
        const Lanes zero{}, last{last_bin_, last_bin_, last_bin_, last_bin_};
        Lanes x = ((r.lo + r.hi) - origin_) * scale_;
        x = x > zero ? x : zero;
        x = x < last ? x : last;
        const IntLanes bin = __builtin_convertvector(x, IntLanes);
        for (std::size_t axis = 0; axis < 3; ++axis) {
            const auto b = static_cast<std::size_t>(bin[axis]);
            bin_box_[axis][b].extend(r.lo, r.hi);
            bin_count_[axis][b] += 1;
        }
    }

    Params params_;
    SweepSplitter small_;
    Lanes origin_{};  // lanes: 2 x the centroid bounds' minimum
    Lanes scale_{};   // lanes: bins per unit of lo + hi; 0 on an axis with no usable extent
    float last_bin_ = 0.0f;
    std::array<std::array<Box4, kMaxBins>, 3> bin_box_{};
    std::array<std::array<std::uint32_t, kMaxBins>, 3> bin_count_{};
    std::array<Box4, kMaxBins> right_box_{};
    std::array<float, kMaxBins> right_area_{};
    std::array<std::uint32_t, kMaxBins> right_count_{};
    Box4 best_bounds_[2];
};

BvhNode make_node(const Box4& bounds, std::uint32_t right_or_first, std::uint32_t count) {
    const Aabb box = bounds.aabb();
    return BvhNode{box.min, static_cast<std::int32_t>(right_or_first), box.max, static_cast<std::int32_t>(count)};
}

// Everything the two builders share: input screening, the explicit work stack (no recursion, so
// any tree depth is safe for the machine stack), the leaf/split/median decision, layout and stats.
template <class Splitter>
Bvh build(const std::vector<Aabb>& prims, const BvhOptions& options, Splitter& splitter) {
    const auto start = std::chrono::steady_clock::now();
    const Params params = clamp_options(options);
    const auto n = static_cast<std::uint32_t>(prims.size());

    // Valid primitives fill refs from the front, the others from the back. Not a std::vector: it
    // would zero 32 bytes per primitive only to overwrite them.
    const std::unique_ptr<PrimRef[]> refs(new PrimRef[n]);
    BuildTask valid, invalid;
    {
        std::uint32_t front = 0, back = n;
        for (std::uint32_t i = 0; i < n; ++i) {
            const Aabb& box = prims[i];
            if (!box.empty() && finite(box.min) && finite(box.max)) {
                refs[front] = PrimRef(box, i);
                valid.bounds.extend(refs[front].lo, refs[front].hi);
                valid.centroid_bounds.extend(refs[front].centroid());
                ++front;
            } else {
                refs[--back] = PrimRef(Aabb{glm::vec3(0.0f), glm::vec3(0.0f)}, i);
            }
        }
        valid.end = invalid.begin = front;
        invalid.end = n;
    }

    Bvh bvh;
    auto& nodes = bvh.nodes;
    // The most a tree can have (one primitive per leaf): growing instead would copy it, and pages
    // never written are never touched.
    nodes.reserve(std::max<std::size_t>(1, 2 * std::size_t{n}));
    std::vector<BuildTask> stack;
    if (valid.size() > 0 && invalid.size() > 0) {
        nodes.push_back(make_node(valid.bounds, 0, 0));
        valid.depth = invalid.depth = 1;
        invalid.right_of = 0;
        stack.push_back(invalid);
        stack.push_back(valid);
    } else if (n > 0) {
        stack.push_back(valid.size() > 0 ? valid : invalid);
    } else {
        nodes.push_back(make_node(Box4{}, 0, 0));
        bvh.stats.leaf_count = 1;
    }

    while (!stack.empty()) {
        const BuildTask task = stack.back();
        stack.pop_back();
        const auto node_index = static_cast<std::uint32_t>(nodes.size());
        if (task.right_of >= 0) {
            nodes[static_cast<std::size_t>(task.right_of)].right_or_first = static_cast<std::int32_t>(node_index);
        }
        const std::uint32_t count = task.size();

        std::optional<Candidate> candidate;
        if (count > 1 && !task.centroid_bounds.empty()) candidate = splitter.find(refs.get(), task);
        const auto depth_allows = [&](const Candidate& c) {
            const int deeper = std::max(levels_to_leaves(c.left_count, params.max_leaf),
                                        levels_to_leaves(count - c.left_count, params.max_leaf));
            return task.depth + 1 + deeper <= kBvhMaxDepth;
        };
        const float leaf_cost = params.intersection * static_cast<float>(count) * task.bounds.half_area();

        std::optional<Split> split;
        if (candidate && candidate->cost < leaf_cost && depth_allows(*candidate)) {
            split = splitter.apply(refs.get(), task, *candidate);
            // Cannot happen while binning and partitioning agree on every bin index; kept so that a
            // disagreement would cost quality, not termination.
            if (split->mid == task.begin || split->mid == task.end) split.reset();
        }
        if (!split && count > params.max_leaf) {
            // The SAH prefers a leaf that would be too large, finds no split, or would go too deep.
            // A median split keeps depth + levels_to_leaves(count) <= kBvhMaxDepth true for the
            // children as it is here; at the root it holds since levels_to_leaves(2^30) <= 30.
            const int axis = candidate ? candidate->axis : widest_axis(task.centroid_bounds);
            split = split_at_median(refs.get(), task, axis);
        }

        if (!split) {
            nodes.push_back(make_node(task.bounds, task.begin, count));
            bvh.stats.leaf_count += 1;
            bvh.stats.max_depth = std::max(bvh.stats.max_depth, task.depth);
            bvh.stats.max_leaf_prims = std::max(bvh.stats.max_leaf_prims, static_cast<int>(count));
            continue;
        }
        nodes.push_back(make_node(task.bounds, 0, 0));
        stack.push_back(
            BuildTask{split->mid, task.end, split->bounds[1], split->centroid_bounds[1], task.depth + 1,
                      static_cast<int>(node_index)});
        // Pushed last, popped next: the left child lands at node_index + 1.
        stack.push_back(
            BuildTask{task.begin, split->mid, split->bounds[0], split->centroid_bounds[0], task.depth + 1, -1});
    }

    bvh.prim_indices.resize(n);
    for (std::uint32_t i = 0; i < n; ++i) bvh.prim_indices[i] = refs[i].index();
    bvh.stats.node_count = static_cast<int>(nodes.size());
    bvh.stats.sah_cost = sah_cost(bvh, options);
    bvh.stats.build_ms = std::chrono::duration<double, std::milli>(std::chrono::steady_clock::now() - start).count();
    return bvh;
}

void check_size(std::size_t prim_count) {
    if (prim_count > (std::size_t{1} << 30)) {
        throw std::length_error("build_bvh: more than 2^30 primitives do not fit int32 node indices");
    }
}

double half_area_double(const BvhNode& node) {
    if (!(node.bmin.x <= node.bmax.x && node.bmin.y <= node.bmax.y && node.bmin.z <= node.bmax.z)) return 0.0;
    const glm::dvec3 d = glm::dvec3(node.bmax) - glm::dvec3(node.bmin);
    return d.x * d.y + d.y * d.z + d.z * d.x;
}

}  // namespace

Bvh build_bvh_binned_sah(const std::vector<Aabb>& prims, const BvhOptions& options) {
    check_size(prims.size());
    BinnedSplitter splitter(clamp_options(options));
    return build(prims, options, splitter);
}

Bvh build_bvh_sweep_sah(const std::vector<Aabb>& prims, const BvhOptions& options) {
    check_size(prims.size());
    SweepSplitter splitter(clamp_options(options), prims.size());
    return build(prims, options, splitter);
}

double refit_bvh(Bvh& bvh, const std::vector<Aabb>& prims, const BvhOptions& options) {
    const auto start = std::chrono::steady_clock::now();
    if (prims.size() != bvh.prim_indices.size())
        throw std::invalid_argument("refit_bvh: " + std::to_string(prims.size()) + " primitives for a tree built over " +
                                    std::to_string(bvh.prim_indices.size()));
    auto& nodes = bvh.nodes;
    // Children follow their parent in the depth-first layout (left = i + 1, right > i), so one
    // backward sweep sees every child before its parent.
    for (std::size_t i = nodes.size(); i-- > 0;) {
        BvhNode& node = nodes[i];
        Aabb box;
        if (node.leaf()) {
            const auto first = static_cast<std::size_t>(node.right_or_first);
            for (std::size_t j = first; j < first + static_cast<std::size_t>(node.count); ++j) {
                const Aabb& b = prims[bvh.prim_indices[j]];
                if (!b.empty() && finite(b.min) && finite(b.max)) box.extend(b);
            }
        } else if (i + 1 < nodes.size()) {  // not the empty BVH's lone node
            const BvhNode& left = nodes[i + 1];
            const BvhNode& right = nodes[static_cast<std::size_t>(node.right_or_first)];
            box.extend(Aabb{left.bmin, left.bmax});
            box.extend(Aabb{right.bmin, right.bmax});
        }
        node.bmin = box.min;
        node.bmax = box.max;
    }
    bvh.stats.sah_cost = sah_cost(bvh, options);
    return std::chrono::duration<double, std::milli>(std::chrono::steady_clock::now() - start).count();
}

double sah_cost(const Bvh& bvh, const BvhOptions& options) {
    if (bvh.nodes.empty() || (bvh.nodes.size() == 1 && bvh.nodes[0].count == 0)) return 0.0;  // the empty BVH
    const Params params = clamp_options(options);
    // Double precision: float areas overflow for boxes beyond ~1e19 and would round away the share
    // of small nodes in large scenes.
    const double root_area = half_area_double(bvh.nodes[0]);
    const bool weigh_by_area = root_area > 0.0;
    double cost = 0.0;
    for (const BvhNode& node : bvh.nodes) {
        const double weight = weigh_by_area ? half_area_double(node) / root_area : 1.0;
        cost += weight * (node.leaf() ? params.intersection * node.count : params.traversal);
    }
    return cost;
}

}  // namespace candela::rt
