#include "scene/scene.hpp"

#include <algorithm>
#include <cmath>

#include <glm/gtc/matrix_inverse.hpp>
#include <glm/gtc/matrix_transform.hpp>

#include "core/error.hpp"

namespace candela {

const Material& Scene::material(int index) const {
    static const Material default_material;
    if (index < 0 || index >= static_cast<int>(materials.size())) return default_material;
    return materials[static_cast<size_t>(index)];
}

void Scene::update_world_transforms() {
    // Iterative so that a deep hierarchy cannot overflow the stack; the loader has already
    // rejected cycles.
    std::vector<int> stack(roots.rbegin(), roots.rend());
    for (int r : roots) nodes[static_cast<size_t>(r)].world = nodes[static_cast<size_t>(r)].local;
    while (!stack.empty()) {
        const int i = stack.back();
        stack.pop_back();
        const Node& node = nodes[static_cast<size_t>(i)];
        for (int c : node.children) {
            Node& child = nodes[static_cast<size_t>(c)];
            child.world = node.world * child.local;
            stack.push_back(c);
        }
    }
    for (Camera& camera : cameras)
        if (camera.node >= 0) camera.world = nodes[static_cast<size_t>(camera.node)].world;
}

namespace {
template <typename F>
void for_each_drawn_node(const Scene& scene, F&& f) {
    // Only nodes reachable from the scene roots are drawn.
    std::vector<int> stack(scene.roots.begin(), scene.roots.end());
    while (!stack.empty()) {
        const int i = stack.back();
        stack.pop_back();
        const Node& node = scene.nodes[static_cast<size_t>(i)];
        if (node.mesh >= 0) f(i, node);
        stack.insert(stack.end(), node.children.begin(), node.children.end());
    }
}
}  // namespace

Bounds Scene::world_bounds() const {
    Bounds bounds;
    for_each_drawn_node(*this, [&](int, const Node& node) {
        for (const Primitive& prim : meshes[static_cast<size_t>(node.mesh)].primitives) {
            if (prim.bounds.empty()) continue;
            for (int corner = 0; corner < 8; ++corner) {
                const glm::vec3 p{corner & 1 ? prim.bounds.max.x : prim.bounds.min.x,
                                  corner & 2 ? prim.bounds.max.y : prim.bounds.min.y,
                                  corner & 4 ? prim.bounds.max.z : prim.bounds.min.z};
                bounds.extend(glm::vec3(node.world * glm::vec4(p, 1.0f)));
            }
        }
    });
    return bounds;
}

std::size_t Scene::triangle_count() const {
    std::size_t count = 0;
    for_each_drawn_node(*this, [&](int, const Node& node) {
        for (const Primitive& prim : meshes[static_cast<size_t>(node.mesh)].primitives)
            count += prim.triangle_count();
    });
    return count;
}

std::vector<WorldTriangle> Scene::world_triangles() const {
    std::vector<WorldTriangle> out;
    out.reserve(triangle_count());
    for_each_drawn_node(*this, [&](int node_index, const Node& node) {
        const glm::mat3 normal_matrix = glm::inverseTranspose(glm::mat3(node.world));
        const bool flip = node.mirrored();
        for (const Primitive& prim : meshes[static_cast<size_t>(node.mesh)].primitives) {
            for (size_t t = 0; t + 2 < prim.indices.size(); t += 3) {
                WorldTriangle tri;
                tri.material = prim.material;
                tri.node = node_index;
                for (int k = 0; k < 3; ++k) {
                    const int src = flip ? (k == 0 ? 0 : 3 - k) : k;  // 0,2,1 when mirrored
                    const Vertex& v = prim.vertices[prim.indices[t + static_cast<size_t>(src)]];
                    tri.p[static_cast<size_t>(k)] = glm::vec3(node.world * glm::vec4(v.position, 1.0f));
                    const glm::vec3 n = normal_matrix * v.normal;
                    const float len = glm::length(n);
                    tri.n[static_cast<size_t>(k)] = len > 0.0f ? n / len : glm::vec3(0, 0, 1);
                    const glm::vec3 t = glm::mat3(node.world) * glm::vec3(v.tangent);
                    const float tl = glm::length(t);
                    tri.tangent[static_cast<size_t>(k)] =
                        glm::vec4(tl > 0.0f ? t / tl : glm::vec3(1, 0, 0), (v.tangent.w < 0.0f ? -1.0f : 1.0f) * (flip ? -1.0f : 1.0f));
                    tri.uv0[static_cast<size_t>(k)] = v.uv0;
                    tri.uv1[static_cast<size_t>(k)] = v.uv1;
                }
                out.push_back(tri);
            }
        }
    });
    return out;
}

std::vector<Scene::PlacedLight> Scene::placed_lights() const {
    std::vector<PlacedLight> out;
    for (const Node& node : nodes) {
        if (node.light < 0) continue;
        const glm::vec3 position = glm::vec3(node.world[3]);
        glm::vec3 direction = -glm::vec3(node.world[2]);
        const float len = glm::length(direction);
        direction = len > 0.0f ? direction / len : glm::vec3(0, 0, -1);
        out.push_back({&lights[static_cast<size_t>(node.light)], position, direction});
    }
    return out;
}

Camera framing_camera(const Bounds& bounds) {
    Camera camera;
    camera.name = "framing";
    const glm::vec3 center = bounds.empty() ? glm::vec3(0.0f) : bounds.center();
    const float radius = bounds.empty() ? 1.0f : std::max(0.5f * glm::length(bounds.extent()), 1e-6f);
    camera.yfov = 0.8f;
    const float distance = radius / std::sin(camera.yfov * 0.5f);
    const glm::vec3 dir = glm::normalize(glm::vec3(0.0f, 0.35f, 1.0f));
    const glm::vec3 eye = center + dir * distance;
    camera.znear = std::max(distance - radius, distance * 1e-3f) * 0.5f;
    camera.world = glm::inverse(glm::lookAt(eye, center, glm::vec3(0, 1, 0)));
    return camera;
}

Camera Scene::select_camera(const std::string& selector, float image_aspect) const {
    (void)image_aspect;
    if (selector.empty()) return cameras.empty() ? framing_camera(world_bounds()) : cameras.front();
    // "auto" always means the framing camera, even in a file that has cameras (a file's own
    // camera can cut the model off).
    if (selector == "auto") return framing_camera(world_bounds());
    const bool numeric = std::all_of(selector.begin(), selector.end(), [](char c) { return c >= '0' && c <= '9'; });
    if (numeric && selector.size() < 9) {
        const size_t index = std::stoul(selector);
        if (index < cameras.size()) return cameras[index];
    }
    for (const Camera& camera : cameras)
        if (camera.name == selector) return camera;
    std::string names;
    for (size_t i = 0; i < cameras.size(); ++i)
        names += (i ? ", " : "") + std::to_string(i) + " '" + cameras[i].name + "'";
    throw bad_input(source.string() + ": no camera '" + selector + "' (the scene has " +
                    (cameras.empty() ? std::string("no cameras") : names) + "; 'auto' frames the bounds)");
}

glm::mat4 projection_matrix(const Camera& camera, float image_aspect) {
    glm::mat4 p(0.0f);
    const float n = camera.znear;
    if (camera.orthographic) {
        const float f = camera.zfar > n ? camera.zfar : n + 1000.0f;
        const float xmag = camera.ymag * image_aspect;  // keep the image undistorted
        p[0][0] = 1.0f / xmag;
        p[1][1] = 1.0f / camera.ymag;
        // Reversed depth: z = -n -> 1, z = -f -> 0.
        p[2][2] = 1.0f / (f - n);
        p[3][2] = f / (f - n);
        p[3][3] = 1.0f;
        return p;
    }
    const float aspect = image_aspect;  // the image decides; glTF's aspectRatio only hints
    const float t = 1.0f / std::tan(camera.yfov * 0.5f);
    p[0][0] = t / aspect;
    p[1][1] = t;
    p[2][3] = -1.0f;
    if (camera.zfar > n) {
        const float f = camera.zfar;
        p[2][2] = n / (f - n);
        p[3][2] = n * f / (f - n);
    } else {
        p[3][2] = n;  // infinite far plane: depth = n / -z
    }
    return p;
}

bool has_thin_lens(const Camera& camera) { return camera.aperture > 0.0f && !camera.orthographic; }

float focus_distance_or_auto(const Camera& camera, const Bounds& scene_bounds) {
    if (camera.focus_distance > 0.0f) return camera.focus_distance;
    const float znear = std::max(camera.znear, 0.0f);
    if (scene_bounds.empty()) return std::max(znear, 1.0f);
    const glm::vec3 axis = glm::normalize(-glm::vec3(camera.world[2]));
    const float along = glm::dot(scene_bounds.center() - glm::vec3(camera.world[3]), axis);
    return std::isfinite(along) ? std::max(along, znear) : std::max(znear, 1.0f);
}

int find_variant(const Scene& scene, const std::string& selector) {
    const int n = static_cast<int>(scene.variants.size());
    auto available = [&] {
        if (n == 0) return std::string("the scene has no material variants");
        std::string s = "the scene has " + std::to_string(n) + ": ";
        for (int i = 0; i < n; ++i) s += (i ? ", " : "") + std::to_string(i) + " '" + scene.variants[static_cast<size_t>(i)] + "'";
        return s + "; or default";
    };
    if (selector == "default" || selector == "none") return -1;
    if (!selector.empty() && std::all_of(selector.begin(), selector.end(), [](char c) { return c >= '0' && c <= '9'; })) {
        const long i = selector.size() > 9 ? -1 : std::stol(selector);
        if (i >= 0 && i < n) return static_cast<int>(i);
        throw bad_input("--variant " + selector + ": no such material variant (" + available() + ")");
    }
    for (int i = 0; i < n; ++i)
        if (scene.variants[static_cast<size_t>(i)] == selector) return i;
    throw bad_input("--variant '" + selector + "': no such material variant (" + available() + ")");
}

void select_variant(Scene& scene, int variant) {
    if (variant >= static_cast<int>(scene.variants.size()) || variant < -1)
        throw bad_input(scene.source.string() + ": material variant " + std::to_string(variant) + " does not exist (the scene has " +
                        std::to_string(scene.variants.size()) + ")");
    for (Mesh& mesh : scene.meshes)
        for (Primitive& p : mesh.primitives)
            if (!p.variants.by_variant.empty()) p.material = p.variants.material(variant);
    scene.active_variant = variant;
}

int variant_changes(const Scene& scene, int variant) {
    int n = 0;
    for (const Mesh& mesh : scene.meshes)
        for (const Primitive& p : mesh.primitives) n += p.variants.material(variant) != p.variants.default_material;
    return n;
}

}  // namespace candela
