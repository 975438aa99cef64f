#include "effects/shadows/shadow_views.hpp"

#include "effects/shadows/shadows.hpp"

#include <algorithm>
#include <cmath>

#include <glm/gtc/matrix_transform.hpp>

namespace candela {
namespace {

// Reversed-Z orthographic projection of the light-space box [l, r] x [b, t] x depth [n, f].
glm::mat4 ortho_reversed(float l, float r, float b, float t, float n, float f) {
    glm::mat4 p(0.0f);
    p[0][0] = 2.0f / (r - l);
    p[1][1] = 2.0f / (t - b);
    p[3][0] = -(r + l) / (r - l);
    p[3][1] = -(t + b) / (t - b);
    p[2][2] = 1.0f / (f - n);  // z = -n -> 1, z = -f -> 0
    p[3][2] = f / (f - n);
    p[3][3] = 1.0f;
    return p;
}

// Reversed-Z perspective with an infinite far plane: depth = near / distance along the axis.
glm::mat4 perspective_reversed_infinite(float tan_half_fov, float near) {
    glm::mat4 p(0.0f);
    p[0][0] = 1.0f / tan_half_fov;
    p[1][1] = 1.0f / tan_half_fov;
    p[2][3] = -1.0f;
    p[3][2] = near;
    return p;
}

glm::vec3 any_perpendicular_up(const glm::vec3& dir) {
    return std::abs(dir.y) < 0.99f ? glm::vec3(0, 1, 0) : glm::vec3(1, 0, 0);
}

std::array<glm::vec3, 8> bounds_corners(const Bounds& b) {
    std::array<glm::vec3, 8> c;
    for (int i = 0; i < 8; ++i)
        c[static_cast<size_t>(i)] = glm::vec3(i & 1 ? b.max.x : b.min.x, i & 2 ? b.max.y : b.min.y, i & 4 ? b.max.z : b.min.z);
    return c;
}

// Near plane of a perspective shadow view: a small fraction of the farthest scene point's
// distance, so that it scales with the scene.
float perspective_near(const glm::vec3& pos, const Bounds& bounds) {
    float far = 0.0f;
    for (const glm::vec3& c : bounds_corners(bounds)) far = std::max(far, glm::length(c - pos));
    return std::max(far * 1e-3f, 1e-30f);
}

}  // namespace

ShadowViewData directional_scene_view(const glm::vec3& direction, const Bounds& bounds, int resolution) {
    const glm::vec3 dir = glm::normalize(direction);
    const glm::mat4 light_view = glm::lookAt(glm::vec3(0.0f), dir, any_perpendicular_up(dir));
    Bounds ls;
    for (const glm::vec3& c : bounds_corners(bounds)) ls.extend(glm::vec3(light_view * glm::vec4(c, 1.0f)));
    const float size = std::max({ls.max.x - ls.min.x, ls.max.y - ls.min.y, 1e-30f});
    const glm::vec2 centre = (glm::vec2(ls.min) + glm::vec2(ls.max)) * 0.5f;
    const float margin = (ls.max.z - ls.min.z) * 0.01f + 1e-30f;
    const float n = -ls.max.z - margin, f = -ls.min.z + margin;
    const glm::mat4 proj = ortho_reversed(centre.x - size * 0.5f, centre.x + size * 0.5f, centre.y - size * 0.5f,
                                          centre.y + size * 0.5f, n, f);
    ShadowViewData v{};
    v.view_proj = proj * light_view;
    v.kind = 0.0f;
    v.texel_size = size / static_cast<float>(resolution);
    v.depth_range = f - n;
    return v;
}

std::vector<float> cascade_splits(float near, float far, int cascades, float lambda) {
    std::vector<float> s(static_cast<size_t>(cascades) + 1);
    for (int i = 0; i <= cascades; ++i) {
        const float t = static_cast<float>(i) / static_cast<float>(cascades);
        const float log_split = near * std::pow(far / near, t);
        const float uniform_split = near + (far - near) * t;
        s[static_cast<size_t>(i)] = lambda * log_split + (1.0f - lambda) * uniform_split;
    }
    s.front() = near;
    s.back() = far;
    return s;
}

ShadowViews build_shadow_views(const GpuScene& gpu, const Bounds& bounds, const Camera& camera, float aspect,
                               const ShadowsOptions& settings) {
    ShadowViews out;
    const int total = gpu.shadow_view_count();
    out.views.resize(static_cast<size_t>(total));
    out.light.assign(static_cast<size_t>(total), -1);
    out.skip.assign(static_cast<size_t>(total), false);
    out.texel_world.assign(static_cast<size_t>(total), 0.0f);
    const ShadowAtlas& atlas = gpu.shadow_atlas();
    const float layer_res = static_cast<float>(std::max(atlas.resolution, 1));
    const auto corners = bounds_corners(bounds);
    const glm::vec3 cam_pos(camera.world[3]);

    const auto& infos = gpu.light_infos();
    for (size_t li = 0; li < infos.size(); ++li) {
        const LightInfo& info = infos[li];
        if (info.view_count == 0) continue;
        // This light's tiles (all of one size): its views' resolution.
        const float res = static_cast<float>(atlas.tiles[static_cast<size_t>(info.first_view)].size);
        // kind 0 orthographic, 1 perspective; `range`: the orthographic depth range or the near plane.
        auto set_view = [&](int k, const glm::mat4& vp, float kind, float texel_size, float range, float cascade_end) {
            const size_t layer = static_cast<size_t>(info.first_view + k);  // the view's index
            ShadowViewData& v = out.views[layer];
            v = ShadowViewData{};
            v.view_proj = vp;
            v.kind = kind;
            v.texel_size = texel_size;
            v.depth_range = range;
            const ShadowTile& tile = atlas.tiles[layer];
            v.layer = static_cast<float>(tile.layer);
            v.tile_u = static_cast<float>(tile.x) / layer_res;
            v.tile_v = static_cast<float>(tile.y) / layer_res;
            v.tile_scale = static_cast<float>(tile.size) / layer_res;
            v.tile_texels = static_cast<float>(tile.size);
            v.cascade_end = cascade_end;
            v.light_size = info.size;
            out.light[layer] = static_cast<int>(li);
        };
        if (info.kind == LightInfo::Kind::directional) {
            const glm::vec3 dir = glm::normalize(info.direction);
            // Light space starts at the scene's centre, not at the world's origin: the cascades'
            // boxes snap to texels of this space, so the grid stands where the scene stands and a
            // scene moved anywhere (the loader moves a far one by its own centre) keeps its shadow
            // edges on the same texels. Snapped from the world's origin, a move by a fraction of a
            // texel moved every hard shadow edge by a texel (FarOriginTest: 11 of 3072 pixels).
            const glm::vec3 anchor = bounds.empty() ? glm::vec3(0.0f) : bounds.center();
            const glm::mat4 light_view = glm::lookAt(anchor, anchor + dir, any_perpendicular_up(dir));
            // The scene in light space: depth range for casters, xy clip for receivers.
            Bounds scene_ls;
            for (const glm::vec3& c : corners) scene_ls.extend(glm::vec3(light_view * glm::vec4(c, 1.0f)));
            // The camera's depth range over the scene.
            // (In the camera's own units: its world matrix may carry a scale.)
            float cam_far = camera.zfar > camera.znear ? camera.zfar : 0.0f;
            float scene_far = 0.0f;
            const glm::vec3 fwd = -glm::vec3(camera.world[2]);
            const float cam_scale = std::max(glm::length(fwd), 1e-30f);
            for (const glm::vec3& c : corners)
                scene_far = std::max(scene_far, glm::dot(c - cam_pos, fwd / cam_scale) / cam_scale);
            cam_far = cam_far > 0.0f ? std::min(cam_far, scene_far) : scene_far;
            // (An orthographic glTF camera may have znear 0: keep the logarithmic splits finite.)
            const float cam_near = std::max(camera.znear, 1e-4f * scene_far);
            cam_far = std::max(cam_far, cam_near * 2.0f);
            const std::vector<float> splits = cascade_splits(cam_near, cam_far, info.view_count, settings.split_lambda);
            for (int k = 0; k < info.view_count; ++k) {
                const float z0 = splits[static_cast<size_t>(k)], z1 = splits[static_cast<size_t>(k) + 1];
                Bounds slice;
                for (int c = 0; c < 8; ++c) {
                    const float z = c & 4 ? z1 : z0;
                    float hx, hy;
                    if (camera.orthographic) {
                        hy = camera.ymag;
                        hx = camera.ymag * aspect;
                    } else {
                        hy = z * std::tan(camera.yfov * 0.5f);
                        hx = hy * aspect;
                    }
                    const glm::vec3 p_cam(c & 1 ? hx : -hx, c & 2 ? hy : -hy, -z);
                    slice.extend(glm::vec3(light_view * camera.world * glm::vec4(p_cam, 1.0f)));
                }
                // Only where there is geometry.
                glm::vec2 lo = glm::max(glm::vec2(slice.min), glm::vec2(scene_ls.min));
                glm::vec2 hi = glm::min(glm::vec2(slice.max), glm::vec2(scene_ls.max));
                if (hi.x <= lo.x || hi.y <= lo.y) {
                    lo = glm::vec2(scene_ls.min);
                    hi = glm::vec2(scene_ls.max);
                }
                // Square texels, the box snapped to the texel grid; a one-texel guard band.
                float size = std::max(hi.x - lo.x, hi.y - lo.y);
                size = std::max(size, 1e-30f) * res / (res - 2.0f);
                const float texel = size / res;
                const glm::vec2 centre = (lo + hi) * 0.5f;
                glm::vec2 mn = glm::floor((centre - size * 0.5f) / texel) * texel;
                const glm::vec2 mx = mn + glm::vec2(size);
                // Depth: every caster of the scene, with a small margin. Light space looks down -z.
                const float depth_margin = (scene_ls.max.z - scene_ls.min.z) * 0.01f + 1e-30f;
                const float n = -scene_ls.max.z - depth_margin, f = -scene_ls.min.z + depth_margin;
                const glm::mat4 proj = ortho_reversed(mn.x, mx.x, mn.y, mx.y, n, f);
                set_view(k, proj * light_view, 0.0f, texel, f - n, z1);
                out.texel_world[static_cast<size_t>(info.first_view + k)] = texel;
            }
        } else if (info.kind == LightInfo::Kind::spot) {
            const glm::vec3 dir = glm::normalize(info.direction);
            const float half = std::min(info.outer_cone + 0.02f, glm::radians(80.0f));
            const float tan_half = std::tan(half);
            const float near = perspective_near(info.position, bounds);
            const glm::mat4 view = glm::lookAt(info.position, info.position + dir, any_perpendicular_up(dir));
            set_view(0, perspective_reversed_infinite(tan_half, near) * view, 1.0f, 2.0f * tan_half / res, near, 0.0f);
        } else {
            // Cube faces +X, -X, +Y, -Y, +Z, -Z; the 90-degree face fills the inner res - 2*guard
            // texels.
            static const glm::vec3 axes[6] = {{1, 0, 0}, {-1, 0, 0}, {0, 1, 0}, {0, -1, 0}, {0, 0, 1}, {0, 0, -1}};
            static const glm::vec3 ups[6] = {{0, -1, 0}, {0, -1, 0}, {0, 0, 1}, {0, 0, -1}, {0, -1, 0}, {0, -1, 0}};
            const float guard = std::min(settings.max_radius + 2.0f, res * 0.25f);
            const float tan_half = res / (res - 2.0f * guard);
            const float near = perspective_near(info.position, bounds);
            for (int k = 0; k < 6; ++k) {
                const glm::mat4 view = glm::lookAt(info.position, info.position + axes[k], ups[k]);
                set_view(k, perspective_reversed_infinite(tan_half, near) * view, 1.0f, 2.0f * tan_half / res, near, 0.0f);
                // A one-sided emitter sends nothing into a face whose whole frustum lies behind it
                // (the face axis within 35.26 degrees of the back normal).
                if (info.kind == LightInfo::Kind::area && !info.double_sided && glm::dot(axes[k], -info.direction) > 0.8165f)
                    out.skip[static_cast<size_t>(info.first_view + k)] = true;
            }
        }
    }
    return out;
}

}  // namespace candela
