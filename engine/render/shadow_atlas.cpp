#include "render/shadow_atlas.hpp"

#include <algorithm>
#include <cstdio>
#include <numeric>

namespace candela {

double shadow_layer_bytes(int resolution) { return 4.0 * static_cast<double>(resolution) * static_cast<double>(resolution); }

ShadowAtlas allocate_shadow_atlas(const std::vector<ShadowRequest>& lights, int resolution, int max_layers, int min_tile, int max_level) {
    ShadowAtlas a;
    a.resolution = std::max(resolution, 1);
    a.budget_layers = std::max(max_layers, 1);
    a.level.assign(lights.size(), -1);
    a.first_view.assign(lights.size(), -1);
    // The deepest halving: tiles of at least min_tile texels (a full tile is always allowed).
    int deepest = 0;
    while (deepest < max_level && (a.resolution >> (deepest + 1)) >= std::max(min_tile, 1)) ++deepest;
    // Sizes in units of the smallest tile's area: a tile at level l is 4^(deepest - l) units.
    const auto units = [&](int level) { return 1LL << (2 * (deepest - level)); };
    const long long per_layer = units(0);
    const long long budget = per_layer * a.budget_layers;

    std::vector<size_t> order;  // the requesting lights, highest priority first
    for (size_t i = 0; i < lights.size(); ++i)
        if (lights[i].views > 0) order.push_back(i);
    std::stable_sort(order.begin(), order.end(), [&](size_t x, size_t y) { return lights[x].priority > lights[y].priority; });
    a.requested = static_cast<int>(order.size());
    long long cost = 0;
    for (size_t i : order) {
        a.level[i] = 0;
        cost += lights[i].views * units(0);
    }
    // Halve in rounds, from the lowest priority up; then leave out from the lowest priority.
    for (int round = 1; round <= deepest && cost > budget; ++round)
        for (size_t k = order.size(); k-- > 0 && cost > budget;) {
            const size_t i = order[k];
            cost -= lights[i].views * (units(a.level[i]) - units(round));
            a.level[i] = round;
        }
    while (cost > budget && !order.empty()) {
        const size_t i = order.back();
        order.pop_back();
        cost -= lights[i].views * units(a.level[i]);
        a.level[i] = -1;
        ++a.unshadowed;
    }
    for (size_t i : order) a.reduced += a.level[i] > 0 ? 1 : 0;

    // Views in light order; placed largest tile first (ties in light order), each at the next
    // multiple of its own size along a Z-order curve of the layer.
    for (size_t i = 0; i < lights.size(); ++i) {
        if (a.level[i] < 0) continue;
        a.first_view[i] = static_cast<int>(a.tiles.size());
        for (int k = 0; k < lights[i].views; ++k) a.tiles.push_back({0, 0, 0, a.resolution >> a.level[i]});
    }
    std::vector<size_t> by_size(a.tiles.size());
    std::iota(by_size.begin(), by_size.end(), size_t{0});
    std::stable_sort(by_size.begin(), by_size.end(), [&](size_t x, size_t y) { return a.tiles[x].size > a.tiles[y].size; });
    const int unit_side = a.resolution >> deepest;
    long long cursor = 0;
    for (size_t v : by_size) {
        ShadowTile& t = a.tiles[v];
        int level = 0;
        while ((a.resolution >> level) > t.size) ++level;
        t.layer = static_cast<int>(cursor / per_layer);
        // De-interleave the Z-order index within the layer into x and y (in smallest-tile units).
        const long long z = cursor % per_layer;
        int ux = 0, uy = 0;
        for (int bit = 0; bit < deepest; ++bit) {
            ux |= static_cast<int>((z >> (2 * bit)) & 1) << bit;
            uy |= static_cast<int>((z >> (2 * bit + 1)) & 1) << bit;
        }
        t.x = ux * unit_side;
        t.y = uy * unit_side;
        cursor += units(level);
    }
    a.layers = static_cast<int>((cursor + per_layer - 1) / per_layer);
    return a;
}

std::string ShadowAtlas::text(double budget_mb) const {
    const int shadowed = requested - unshadowed;
    char buf[256];
    std::snprintf(buf, sizeof buf, "%d of %d light(s) shadowed at %d texels, %d layer(s) (%.0f MiB of %.0f)", shadowed, requested,
                  resolution, layers, layers * shadow_layer_bytes(resolution) / (1024.0 * 1024.0), budget_mb);
    std::string s = buf;
    if (reduced > 0) {
        int smallest = resolution;
        for (int l : level)
            if (l >= 0) smallest = std::min(smallest, resolution >> l);
        std::snprintf(buf, sizeof buf, "; %d at lower resolution (down to %d texels) by the budget", reduced, smallest);
        s += buf;
    }
    if (unshadowed > 0) {
        std::snprintf(buf, sizeof buf, "; %d unshadowed by the budget (shadows.budget_mb)", unshadowed);
        s += buf;
    }
    return s;
}

}  // namespace candela
