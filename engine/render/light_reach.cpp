#include "render/light_reach.hpp"

#include <algorithm>
#include <cmath>
#include <cstdio>
#include <vector>

#include "render/gpu_scene.hpp"

namespace candela {

namespace {

constexpr int kReachTile = 16;  // the tiled passes' tile (deferred/light.comp, forward/light_tiles.comp)

// The pixel rectangle [x0, x1) x [y0, y1) that a sphere covers, from the clip-space corners of its
// bounding box; the whole image if some corners are behind the eye (conservative, as the GPU's
// planes are). Empty (x0 >= x1) if it lies outside the view or wholly behind the eye.
void reach_sphere_rect(const glm::mat4& view_proj, glm::vec3 c, float r, int w, int h, int& x0, int& y0, int& x1, int& y1) {
    glm::vec2 lo(1e30f), hi(-1e30f);
    int behind = 0;
    for (int k = 0; k < 8; ++k) {
        const glm::vec3 corner = c + r * glm::vec3(k & 1 ? 1.0f : -1.0f, k & 2 ? 1.0f : -1.0f, k & 4 ? 1.0f : -1.0f);
        const glm::vec4 q = view_proj * glm::vec4(corner, 1.0f);
        if (!(q.w > 1e-6f)) {
            ++behind;
            continue;
        }
        const glm::vec2 ndc = glm::vec2(q) / q.w;
        lo = glm::min(lo, ndc), hi = glm::max(hi, ndc);
    }
    if (behind == 8) {  // wholly behind the eye
        x0 = x1 = y0 = y1 = 0;
        return;
    }
    if (behind > 0) lo = glm::vec2(-1.0f), hi = glm::vec2(1.0f);
    lo = glm::max(lo, glm::vec2(-1.0f)), hi = glm::min(hi, glm::vec2(1.0f));
    x0 = static_cast<int>(std::floor((lo.x * 0.5f + 0.5f) * static_cast<float>(w)));
    x1 = static_cast<int>(std::ceil((hi.x * 0.5f + 0.5f) * static_cast<float>(w)));
    y0 = static_cast<int>(std::floor((lo.y * 0.5f + 0.5f) * static_cast<float>(h)));
    y1 = static_cast<int>(std::ceil((hi.y * 0.5f + 0.5f) * static_cast<float>(h)));
}

}  // namespace

LightReach light_reach(const Scene& scene, float cutoff, const glm::mat4& view_proj, int width, int height) {
    LightReach r;
    r.width = std::max(width, 1), r.height = std::max(height, 1);
    const int tx = (r.width + kReachTile - 1) / kReachTile, ty = (r.height + kReachTile - 1) / kReachTile;
    r.tiles = tx * ty;
    // Each light adds 1 over its rectangle of tiles: a 2D difference array, summed at the end,
    // so that a light costs the same whatever its size (the viewer runs this every frame).
    std::vector<int> diff(static_cast<size_t>((tx + 1) * (ty + 1)), 0);
    const auto add_rect = [&](int ax, int ay, int bx, int by) {  // tiles [ax, bx] x [ay, by]
        diff[static_cast<size_t>(ay * (tx + 1) + ax)] += 1;
        diff[static_cast<size_t>(ay * (tx + 1) + bx + 1)] -= 1;
        diff[static_cast<size_t>((by + 1) * (tx + 1) + ax)] -= 1;
        diff[static_cast<size_t>((by + 1) * (tx + 1) + bx + 1)] += 1;
    };
    const auto placed = scene.placed_lights();
    const std::vector<float> cutoffs = unranged_light_cutoffs(scene, cutoff);  // the light buffer's
    bool first_cut = true;
    for (size_t i = 0; i < placed.size(); ++i) {
        const Scene::PlacedLight& pl = placed[i];
        ++r.lights;
        float reach = 0.0f;  // 0: every tile
        if (pl.light->type != LightType::directional && pl.light->range > 0.0f) {
            reach = pl.light->range, ++r.ranged;
        } else if (cutoffs[i] > 0.0f) {
            reach = cutoffs[i], ++r.cut;
            r.cut_min = first_cut ? reach : std::min(r.cut_min, reach);
            r.cut_max = first_cut ? reach : std::max(r.cut_max, reach);
            first_cut = false;
        }
        if (!(reach > 0.0f)) {
            ++r.unbounded;
            continue;
        }
        int x0, y0, x1, y1;
        reach_sphere_rect(view_proj, pl.position, reach, r.width, r.height, x0, y0, x1, y1);
        if (x0 >= x1 || y0 >= y1) continue;
        const int ax = std::max(x0 / kReachTile, 0), bx = std::min((x1 - 1) / kReachTile, tx - 1);
        const int ay = std::max(y0 / kReachTile, 0), by = std::min((y1 - 1) / kReachTile, ty - 1);
        if (ax <= bx && ay <= by) add_rect(ax, ay, bx, by);
    }
    // Prefix sums over the difference array give each tile's count; unbounded lights are in all.
    double sum = 0;
    std::vector<int> row(static_cast<size_t>(tx + 1), 0);
    for (int y = 0; y < ty; ++y) {
        int run = 0;
        for (int x = 0; x < tx; ++x) {
            run += diff[static_cast<size_t>(y * (tx + 1) + x)];
            row[static_cast<size_t>(x)] += run;
            const int n = row[static_cast<size_t>(x)] + r.unbounded;
            sum += n;
            r.per_tile_max = std::max(r.per_tile_max, n);
        }
    }
    r.per_tile_mean = r.tiles > 0 ? sum / r.tiles : 0.0;
    return r;
}

std::string LightReach::text() const {
    char buf[320];
    std::string s;
    std::snprintf(buf, sizeof buf, "%d punctual light(s): %d with a range, %d cut by lights.cutoff", lights, ranged, cut);
    s = buf;
    if (cut > 0) {
        std::snprintf(buf, sizeof buf, " (reach %.3g-%.3g)", static_cast<double>(cut_min), static_cast<double>(cut_max));
        s += buf;
    }
    std::snprintf(buf, sizeof buf, ", %d everywhere; per 16x16 tile at %dx%d: %.1f mean, %d at most (screen bounds)", unbounded, width, height,
                  per_tile_mean, per_tile_max);
    return s + buf;
}

}  // namespace candela
