// The shadow budget (render/shadow_atlas.hpp) as properties over random requests: tiles never
// overlap and stay inside their layers, the layers stay within the budget, resolution never rises
// as priority falls, the budget leaves out only the lowest priorities, and nothing is reduced
// when everything fits.
#include <gtest/gtest.h>

#include <algorithm>
#include <random>

#include "render/shadow_atlas.hpp"

namespace candela {
namespace {

bool overlap(const ShadowTile& a, const ShadowTile& b) {
    return a.layer == b.layer && a.x < b.x + b.size && b.x < a.x + a.size && a.y < b.y + b.size && b.y < a.y + a.size;
}

TEST(ShadowAtlas, EverythingFitsAtFullResolutionWithinTheBudget) {
    // A directional light's 4 cascades, a spot light, two point lights: 17 views in 17 layers.
    const std::vector<ShadowRequest> r{{4, 1e30f}, {1, 2.0f}, {6, 3.0f}, {0, 9.0f}, {6, 1.0f}};
    const ShadowAtlas a = allocate_shadow_atlas(r, 1024, 17);
    EXPECT_EQ(a.layers, 17);
    EXPECT_EQ(a.reduced, 0);
    EXPECT_EQ(a.unshadowed, 0);
    EXPECT_EQ(a.requested, 4);
    EXPECT_EQ(a.level, (std::vector<int>{0, 0, 0, -1, 0}));
    // Views in light order, each a whole layer.
    EXPECT_EQ(a.first_view, (std::vector<int>{0, 4, 5, -1, 11}));
    for (const ShadowTile& t : a.tiles) EXPECT_EQ(t.size, 1024);
}

TEST(ShadowAtlas, TheLowestPriorityIsHalvedFirstAndLeftOutLast) {
    // Three point lights (18 views) in 8 layers: the dimmest two get half-size tiles (6 layers
    // + 2 * 1.5), which is 9 > 8, so the brightest one is halved as well: 4.5 layers.
    const std::vector<ShadowRequest> r{{6, 1.0f}, {6, 3.0f}, {6, 2.0f}};
    ShadowAtlas a = allocate_shadow_atlas(r, 1024, 8);
    EXPECT_EQ(a.level, (std::vector<int>{1, 1, 1}));
    EXPECT_EQ(a.layers, 5);
    a = allocate_shadow_atlas(r, 1024, 9);
    EXPECT_EQ(a.level, (std::vector<int>{1, 0, 1}));
    // One layer: quarter-size tiles (16 to a layer) for all, 1.125 layers, so the dimmest goes
    // on to eighth-size tiles (64 to a layer): 0.84 layers. With the smallest tile at 512 texels
    // (4 to a layer) a point light needs 1.5 layers: none fits in one, one fits in two.
    a = allocate_shadow_atlas(r, 1024, 1);
    EXPECT_EQ(a.level, (std::vector<int>{3, 2, 2}));
    EXPECT_EQ(a.layers, 1);
    a = allocate_shadow_atlas(r, 1024, 1, 512, 1);
    EXPECT_EQ(a.level, (std::vector<int>{-1, -1, -1}));
    EXPECT_EQ(a.unshadowed, 3);
    EXPECT_TRUE(a.tiles.empty());
    a = allocate_shadow_atlas(r, 1024, 2, 512, 1);
    EXPECT_EQ(a.level, (std::vector<int>{-1, 1, -1}));
    EXPECT_EQ(a.unshadowed, 2);
}

TEST(ShadowAtlas, RandomRequestsKeepEveryProperty) {
    std::mt19937 rng(20261207u);
    for (int trial = 0; trial < 400; ++trial) {
        SCOPED_TRACE(trial);
        const int n = std::uniform_int_distribution<int>(0, 300)(rng);
        std::vector<ShadowRequest> r(static_cast<size_t>(n));
        for (ShadowRequest& q : r) {
            const int kind = std::uniform_int_distribution<int>(0, 4)(rng);
            q.views = kind == 0 ? 0 : kind == 1 ? std::uniform_int_distribution<int>(1, 4)(rng) : kind == 2 ? 1 : 6;
            // Ties included: equal priorities keep the light order.
            q.priority = static_cast<float>(std::uniform_int_distribution<int>(0, 40)(rng));
        }
        const int resolution = 64 << std::uniform_int_distribution<int>(0, 6)(rng);
        const int max_layers = std::uniform_int_distribution<int>(1, 200)(rng);
        const ShadowAtlas a = allocate_shadow_atlas(r, resolution, max_layers);
        ASSERT_EQ(a.level.size(), r.size());
        EXPECT_LE(a.layers, max_layers);
        int views = 0, requested = 0, unshadowed = 0;
        for (size_t i = 0; i < r.size(); ++i) {
            requested += r[i].views > 0;
            unshadowed += r[i].views > 0 && a.level[i] < 0;
            if (r[i].views == 0) EXPECT_EQ(a.level[i], -1);
            if (a.level[i] < 0) continue;
            ASSERT_EQ(a.first_view[i], views);
            views += r[i].views;
            // Halvings stop at 128 texels (or at the full tile when that is smaller), at most 3.
            EXPECT_LE(a.level[i], 3);
            EXPECT_GE(resolution >> a.level[i], std::min(resolution, 128));
        }
        EXPECT_EQ(static_cast<int>(a.tiles.size()), views);
        EXPECT_EQ(a.requested, requested);
        EXPECT_EQ(a.unshadowed, unshadowed);
        // Priority order: a higher-priority light never has a smaller tile, and only a light of
        // no higher priority than every shadowed one is left out.
        for (size_t i = 0; i < r.size(); ++i)
            for (size_t j = 0; j < r.size(); ++j) {
                if (r[i].views == 0 || r[j].views == 0 || !(r[i].priority > r[j].priority)) continue;
                if (a.level[j] >= 0) {
                    EXPECT_GE(a.level[i], 0) << i << " left out, " << j << " of lower priority shadowed";
                    EXPECT_LE(a.level[i], a.level[j]);
                }
            }
        // Nothing reduced or left out when the full-resolution views fit.
        int full_views = 0;
        for (const ShadowRequest& q : r) full_views += q.views;
        if (full_views <= max_layers) {
            EXPECT_EQ(a.reduced, 0);
            EXPECT_EQ(a.unshadowed, 0);
        }
        // Tiles: inside their layer, aligned to their size, never overlapping.
        for (size_t v = 0; v < a.tiles.size(); ++v) {
            const ShadowTile& t = a.tiles[v];
            EXPECT_GE(t.layer, 0);
            EXPECT_LT(t.layer, a.layers);
            EXPECT_EQ(t.x % t.size, 0);
            EXPECT_EQ(t.y % t.size, 0);
            EXPECT_LE(t.x + t.size, resolution);
            EXPECT_LE(t.y + t.size, resolution);
        }
        std::vector<size_t> idx(a.tiles.size());
        for (size_t v = 0; v < idx.size(); ++v) idx[v] = v;
        std::sort(idx.begin(), idx.end(), [&](size_t p, size_t q) { return a.tiles[p].layer < a.tiles[q].layer; });
        for (size_t p = 0; p < idx.size(); ++p)
            for (size_t q = p + 1; q < idx.size() && a.tiles[idx[q]].layer == a.tiles[idx[p]].layer; ++q)
                EXPECT_FALSE(overlap(a.tiles[idx[p]], a.tiles[idx[q]])) << "tiles " << idx[p] << " and " << idx[q];
    }
}

}  // namespace
}  // namespace candela
