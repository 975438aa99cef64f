#pragma once
// The shadow budget: every shadow view is a square tile of a depth-array layer (the atlas). A
// full-resolution tile fills a layer (shadows.resolution texels a side); a light of lower priority
// may get tiles of half, a quarter, ... of that side, four, sixteen, ... to a layer. The layers the
// atlas may use are bounded by a memory budget (shadows.budget_mb) and by the context's
// GL_MAX_ARRAY_TEXTURE_LAYERS, so any number of shadowed lights fits: what does not fit at the
// smallest tile is left unshadowed, lowest priority first.
#include <string>
#include <vector>

namespace candela {

// What a light asks for: `views` tiles (0: no shadow) and its priority (higher: more resolution).
struct ShadowRequest {
    int views = 0;
    float priority = 0.0f;
};

// A view's tile: texels [x, x + size) x [y, y + size) of array layer `layer`.
struct ShadowTile {
    int layer = 0, x = 0, y = 0, size = 0;
    bool operator==(const ShadowTile&) const = default;
};

struct ShadowAtlas {
    int resolution = 0;            // a layer's side in texels: the full-resolution tile
    int layers = 0;                // array layers used (at least 1 when any view is placed)
    int budget_layers = 0;         // layers the budget and the context allow
    std::vector<int> level;        // per light: -1 no shadow views, else tiles of resolution >> level
    std::vector<int> first_view;   // per light: its first view (tiles index), -1 without
    std::vector<ShadowTile> tiles; // per view, the views of each light consecutive, in light order
    int requested = 0;             // lights that asked for shadow views
    int reduced = 0;               // of them, shadowed below full resolution
    int unshadowed = 0;            // of them, left without shadow views by the budget
    // "4 of 4 lights at 1024 texels, 12 layers (48 MiB of 512)", with the reduced and left-out ones.
    std::string text(double budget_mb) const;
};

// Bytes of one layer (32-bit float depth).
double shadow_layer_bytes(int resolution);

// Places the requests' views. The budget is spent by priority: every light starts at full
// resolution; while the views do not fit in `max_layers` layers, the lowest-priority light among
// those with the largest tiles is halved (so a light is never halved twice before every light of
// lower priority has been halved as often, and resolution never rises as priority falls); when
// every light is at the smallest tile (`min_tile` texels, at most `max_level` halvings), the
// lowest-priority lights are left unshadowed. Tiles are packed largest first, each aligned to its
// own size, so no tile overlaps another or a layer's edge.
ShadowAtlas allocate_shadow_atlas(const std::vector<ShadowRequest>& lights, int resolution, int max_layers, int min_tile = 128,
                                  int max_level = 3);

}  // namespace candela
