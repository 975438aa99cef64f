// glTF loading of the node hierarchy, cameras, KHR_lights_punctual lights and the environment.
#include "scene/gltf_loader_internal.hpp"
#include "scene/origin.hpp"

#include <glm/gtc/matrix_inverse.hpp>
#include <glm/gtc/quaternion.hpp>
#include <glm/gtc/type_ptr.hpp>

namespace candela::gltf_loading {

void Loader::build_nodes(Scene& scene) {
    const size_t n = m_.nodes.size();
    scene.nodes.resize(n);
    dlocal_.assign(n, glm::dmat4(1.0));
    dtranslation_.assign(n, glm::dvec3(0.0));
    for (size_t i = 0; i < n; ++i) {
        const tinygltf::Node& src = m_.nodes[i];
        Node& node = scene.nodes[i];
        const std::string path = idx("nodes", i);
        node.name = src.name.empty() ? path : src.name;
        if (src.matrix.size() == 16) {
            for (int k = 0; k < 16; ++k)
                glm::value_ptr(node.local)[k] = f32(path + ".matrix[" + std::to_string(k) + "]", src.matrix[static_cast<size_t>(k)]);
            node.has_matrix = true;  // not animatable (glTF 3.7.2.1): channels on it are dropped
            for (int k = 0; k < 16; ++k) glm::value_ptr(dlocal_[i])[k] = src.matrix[static_cast<size_t>(k)];
            dtranslation_[i] = glm::dvec3(dlocal_[i][3]);
        } else {
            glm::vec3 t(0.0f), s(1.0f);
            glm::quat r(1.0f, 0.0f, 0.0f, 0.0f);
            for (size_t k = 0; k < 3 && src.translation.size() == 3; ++k)
                t[static_cast<int>(k)] = f32(path + ".translation[" + std::to_string(k) + "]", src.translation[k]);
            for (size_t k = 0; k < 3 && src.scale.size() == 3; ++k)
                s[static_cast<int>(k)] = f32(path + ".scale[" + std::to_string(k) + "]", src.scale[k]);
            if (src.rotation.size() == 4) {
                r = glm::quat(static_cast<float>(src.rotation[3]), static_cast<float>(src.rotation[0]),
                              static_cast<float>(src.rotation[1]), static_cast<float>(src.rotation[2]));
                const float len = glm::length(r);
                r = len > 0.0f && std::isfinite(len) ? r / len : glm::quat(1, 0, 0, 0);
            }
            node.local = glm::translate(glm::mat4(1.0f), t) * glm::mat4_cast(r) * glm::scale(glm::mat4(1.0f), s);
            if (src.translation.size() == 3) dtranslation_[i] = glm::dvec3(src.translation[0], src.translation[1], src.translation[2]);
            // In double from the file's numbers: a rotation rounded to float turns a translation
            // of 6.4e6 m below it by up to 0.4 m.
            glm::dquat dr(1.0, 0.0, 0.0, 0.0);
            if (src.rotation.size() == 4) {
                dr = glm::dquat(src.rotation[3], src.rotation[0], src.rotation[1], src.rotation[2]);
                const double len = glm::length(dr);
                dr = len > 0.0 && std::isfinite(len) ? dr / len : glm::dquat(1.0, 0.0, 0.0, 0.0);
            }
            glm::dvec3 ds(1.0);
            for (size_t k = 0; k < 3 && src.scale.size() == 3; ++k) ds[static_cast<int>(k)] = src.scale[k];
            dlocal_[i] = glm::translate(glm::dmat4(1.0), dtranslation_[i]) * glm::mat4_cast(dr) * glm::scale(glm::dmat4(1.0), ds);
            node.translation = t;
            node.rotation = r;
            node.scale = s;
        }
        for (int k = 0; k < 16; ++k)
            if (!std::isfinite(glm::value_ptr(node.local)[k])) fail(path, "transform has a non-finite value");
        if (src.mesh >= 0) {
            if (static_cast<size_t>(src.mesh) >= m_.meshes.size())
                fail(path + ".mesh", "mesh " + std::to_string(src.mesh) + " does not exist (the file has " +
                                         std::to_string(m_.meshes.size()) + ")");
            node.mesh = src.mesh;
        }
        if (src.skin >= 0) {
            if (static_cast<size_t>(src.skin) >= m_.skins.size())
                fail(path + ".skin", "skin " + std::to_string(src.skin) + " does not exist (the file has " + std::to_string(m_.skins.size()) + ")");
            node.skin = src.skin;
        }
        // Morph weights: the node's own, else its mesh's defaults (zeros when the file has none).
        own_weights_.resize(n, false);
        if (node.mesh >= 0) {
            const std::vector<float>& defaults = scene.meshes[static_cast<size_t>(node.mesh)].weights;
            node.rest_weights = defaults;
            if (!src.weights.empty()) {
                if (src.weights.size() != defaults.size())
                    fail(path + ".weights", "has " + std::to_string(src.weights.size()) + " weights, meshes[" + std::to_string(node.mesh) +
                                                "] has " + std::to_string(defaults.size()) + " morph targets");
                for (size_t k = 0; k < defaults.size(); ++k)
                    node.rest_weights[k] = f32(path + ".weights[" + std::to_string(k) + "]", src.weights[k]);
                own_weights_[i] = true;
            }
        }  // weights without a mesh: warned by the validation, nothing to morph
        node.weights = node.rest_weights;
        if (src.camera >= 0) {
            if (static_cast<size_t>(src.camera) >= m_.cameras.size())
                fail(path + ".camera", "camera " + std::to_string(src.camera) + " does not exist");
            node.camera = src.camera;
        }
        if (const Value* e = extension(src.extensions, "KHR_lights_punctual")) {
            const int light = static_cast<int>(number(*e, "light", -1));
            if (light < 0 || static_cast<size_t>(light) >= m_.lights.size())
                fail(path + ".extensions.KHR_lights_punctual.light", "light " + std::to_string(light) + " does not exist (the file has " +
                                                                         std::to_string(m_.lights.size()) + ")");
            node.light = light;
        }
        if (src.extras.IsObject() && src.extras.Has("sphere")) {
            const double r = number(src.extras.Get("sphere"), "radius", -1.0);
            if (!(r > 0.0) || !std::isfinite(r)) fail(path + ".extras.sphere.radius", "must be a positive number");
            node.sphere_radius = static_cast<float>(r);
        }
        if (src.extras.IsObject() && src.extras.Has("reflection_probe")) {
            const Value& e = src.extras.Get("reflection_probe");
            const std::string where = path + ".extras.reflection_probe";
            if (!e.IsObject()) fail(where, "must be an object {position, extent, center}");
            ReflectionProbe probe;
            const glm::vec3 bad(std::numeric_limits<float>::quiet_NaN());
            auto finite3 = [&](const char* key, glm::vec3 fallback) {
                const glm::vec3 v = vec<3>(e, key, bad);
                if (!e.Has(key)) return fallback;
                if (glm::any(glm::isnan(v)) || glm::any(glm::isinf(v))) fail(where + "." + key, "must be an array of 3 finite numbers");
                return v;
            };
            probe.position = finite3("position", glm::vec3(0.0f));
            probe.center = finite3("center", probe.position);
            if (e.Has("extent")) {
                probe.extent = finite3("extent", glm::vec3(0.0f));
                if (glm::any(glm::lessThanEqual(probe.extent, glm::vec3(0.0f))))
                    fail(where + ".extent", "half sizes must be positive");
                probe.has_extent = true;
                if (glm::any(glm::greaterThan(glm::abs(probe.position - probe.center), probe.extent)))
                    fail(where, "the position lies outside the box center +- extent");
            }
            node.reflection_probe = probe;
        }
        for (int c : src.children) {
            if (c < 0 || static_cast<size_t>(c) >= n) fail(path + ".children", "node " + std::to_string(c) + " does not exist");
            Node& child = scene.nodes[static_cast<size_t>(c)];
            if (child.parent >= 0 || static_cast<size_t>(c) == i)
                fail(path + ".children", "node " + std::to_string(c) + " has more than one parent (the hierarchy must be a tree)");
            child.parent = static_cast<int>(i);
            node.children.push_back(c);
        }
    }
    build_instances(scene);
    // Roots: the default scene's nodes, else every parentless node.
    if (!m_.scenes.empty()) {
        const size_t si = m_.defaultScene >= 0 && static_cast<size_t>(m_.defaultScene) < m_.scenes.size()
                              ? static_cast<size_t>(m_.defaultScene) : 0;
        for (int r : m_.scenes[si].nodes) {
            if (r < 0 || static_cast<size_t>(r) >= n) fail(idx("scenes", si) + ".nodes", "node " + std::to_string(r) + " does not exist");
            if (scene.nodes[static_cast<size_t>(r)].parent >= 0)
                fail(idx("scenes", si) + ".nodes", "node " + std::to_string(r) + " is a root and also a child");
            scene.roots.push_back(r);
        }
    } else {
        for (size_t i = 0; i < n; ++i)
            if (scene.nodes[i].parent < 0) scene.roots.push_back(static_cast<int>(i));
    }
    // With one parent per node and parentless roots, no cycle is reachable from a root.
    scene.update_world_transforms();
    // Instances whose world transform has no usable normal matrix (a SCALE of 0, or scales so
    // large or small that the inverse overflows) would give non-finite normals: not drawn.
    std::map<int, size_t> degenerate;  // instanced node -> instances dropped
    for (size_t i = n; i < scene.nodes.size(); ++i) {
        Node& inst = scene.nodes[i];
        const glm::mat3 m(inst.world);
        const float det = glm::determinant(m);
        const glm::mat3 normal = glm::inverseTranspose(m);
        bool finite = det != 0.0f && std::isfinite(det);
        // Entries up to 1e30 keep normal_matrix * normal finite for unit normals.
        for (int c = 0; c < 3 && finite; ++c)
            finite = !glm::any(glm::isnan(normal[c])) && glm::all(glm::lessThan(glm::abs(normal[c]), glm::vec3(1e30f)));
        if (finite) continue;
        inst.mesh = -1;
        ++degenerate[inst.parent];
    }
    for (const auto& [node, count] : degenerate)
        warn(idx("nodes", static_cast<size_t>(node)) + ".extensions.EXT_mesh_gpu_instancing",
             std::to_string(count) + " instances have a zero or extreme scale (no usable normals); not drawn");
}

// Far from the origin. Geospatial glTF (and 3D Tiles content) places a small scene with a large
// translation, e.g. a building at (3e6, 4e6, 3.5e6) m on the Earth's surface: in float its
// vertices would keep steps of 0.25-0.5 m, and every GPU computation after them (shadow
// views, probe grids, the tracer's rays) would run on those steps. So the loader composes the
// hierarchy from the file's numbers in double, finds the centre of the scene's bounds, and when
// that centre is far from the origin compared with the scene's size it moves the scene next to
// the origin: every root node's translation, and the keyframes that animate one, lose the
// centre in double before they become float. Scene::origin keeps the centre (the file's frame
// is Scene::origin + the scene's coordinates). A scene near the origin is left as written, so
// its numbers, and its images, are the file's.
void Loader::rebase_far_scene(Scene& scene) {
    // Rebased only when the centre is this many scene radii from the origin: there float keeps
    // steps of at least 2^-23 * 64 (7.6e-6) of the radius, below anything an image shows.
    constexpr double kFar = 64.0;
    const size_t n = scene.nodes.size();
    std::vector<glm::dmat4> world(n, glm::dmat4(1.0));
    std::vector<int> stack(scene.roots.rbegin(), scene.roots.rend());
    std::vector<bool> placed(n, false);
    for (int r : scene.roots) world[static_cast<size_t>(r)] = static_cast<size_t>(r) < dlocal_.size() ? dlocal_[static_cast<size_t>(r)] : glm::dmat4(scene.nodes[static_cast<size_t>(r)].local);
    while (!stack.empty()) {
        const size_t i = static_cast<size_t>(stack.back());
        stack.pop_back();
        if (placed[i]) continue;
        placed[i] = true;
        for (int c : scene.nodes[i].children) {
            const size_t ci = static_cast<size_t>(c);
            world[ci] = world[i] * (ci < dlocal_.size() ? dlocal_[ci] : glm::dmat4(scene.nodes[ci].local));
            stack.push_back(c);
        }
    }
    glm::dvec3 lo(std::numeric_limits<double>::max()), hi(-std::numeric_limits<double>::max());
    auto add = [&](const glm::dvec3& p) { lo = glm::min(lo, p), hi = glm::max(hi, p); };
    std::vector<bool> joint(n, false);
    for (const Skin& skin : scene.skins)
        for (int j : skin.joints)
            if (j >= 0 && static_cast<size_t>(j) < n) joint[static_cast<size_t>(j)] = true;
    for (size_t i = 0; i < n; ++i) {
        if (!placed[i]) continue;
        const Node& node = scene.nodes[i];
        // A skinned mesh is placed by its joints (glTF ignores its node's transform): the joints
        // stand for it, with the light and camera nodes.
        if (joint[i] || node.light >= 0 || node.camera >= 0) add(glm::dvec3(world[i][3]));
        if (node.mesh < 0 || node.skin >= 0) continue;
        for (const Primitive& prim : scene.meshes[static_cast<size_t>(node.mesh)].primitives)
            for (const Vertex& v : prim.vertices) add(glm::dvec3(world[i] * glm::dvec4(glm::dvec3(v.position), 1.0)));
    }
    const bool far = lo.x <= hi.x && glm::length(0.5 * (lo + hi)) > kFar * std::max(0.5 * glm::length(hi - lo), 1e-3);
    if (far) hoist_transform_roots(scene, joint);
    // The file's placement of the roots in double, kept so that the origin can move later too
    // (the camera's anchor, scene/origin.hpp).
    std::vector<bool> root(n, false);
    for (int r : scene.roots) {
        const size_t i = static_cast<size_t>(r);
        root[i] = true;
        scene.root_placements.push_back({r, i < dtranslation_.size() ? dtranslation_[i] : glm::dvec3(scene.nodes[i].local[3])});
    }
    for (size_t a = 0; a < scene.animations.size(); ++a) {
        const Animation& anim = scene.animations[a];
        for (size_t c = 0; c < anim.channels.size(); ++c) {
            const AnimationChannel& ch = anim.channels[c];
            if (ch.path == AnimationPath::translation && ch.node >= 0 && root[static_cast<size_t>(ch.node)] && ch.sampler >= 0 &&
                static_cast<size_t>(ch.sampler) < anim.samplers.size())
                scene.root_tracks.push_back({static_cast<int>(a), static_cast<int>(c), ch.sampler, -1});
        }
    }
    if (far) move_origin(scene, 0.5 * (lo + hi));
}

// A far scene placed by a node below its roots (an exporter's root that only turns Z-up into
// Y-up, with the building's Earth-centred translation on its child): moving the roots would leave
// that child's float translation at 6.4e6 m, in steps of 0.5 m. So a root that is only a
// transform (no mesh, camera, light or skin, not a joint, not animated) and whose children are
// not animated hands its transform to its children, composed in double, and they become the
// roots; again while such roots remain. (An animated node keeps its place in the hierarchy: its
// channels are relative to its parent.)
void Loader::hoist_transform_roots(Scene& scene, const std::vector<bool>& joint) {
    const size_t n = scene.nodes.size();
    std::vector<bool> animated(n, false);
    for (const Animation& anim : scene.animations)
        for (const AnimationChannel& c : anim.channels)
            if (c.node >= 0 && static_cast<size_t>(c.node) < n) animated[static_cast<size_t>(c.node)] = true;
    for (int round = 0; round < 64; ++round) {
        bool changed = false;
        std::vector<int> roots;
        for (int r : scene.roots) {
            const size_t i = static_cast<size_t>(r);
            Node& node = scene.nodes[i];
            bool movable = i < dlocal_.size() && node.mesh < 0 && node.camera < 0 && node.light < 0 && node.skin < 0 && !joint[i] &&
                           !animated[i] && !node.children.empty();
            for (int c : node.children) movable = movable && static_cast<size_t>(c) < dlocal_.size() && !animated[static_cast<size_t>(c)];
            if (!movable) {
                roots.push_back(r);
                continue;
            }
            for (int c : node.children) {
                const size_t ci = static_cast<size_t>(c);
                Node& child = scene.nodes[ci];
                dlocal_[ci] = dlocal_[i] * dlocal_[ci];
                dtranslation_[ci] = glm::dvec3(dlocal_[ci][3]);
                child.local = glm::mat4(dlocal_[ci]);
                child.has_matrix = true;  // not animated: a matrix holds any composition
                child.parent = -1;
                roots.push_back(c);
            }
            node.children.clear();
            changed = true;
        }
        scene.roots = std::move(roots);
        if (!changed) break;
    }
}

// EXT_mesh_gpu_instancing: a node's mesh is drawn once per instance, at the node's transform
// times the instance's TRANSLATION, ROTATION and SCALE (the extension's specification), and not at
// the node's own transform. Each instance becomes a child node of the instanced node that refers
// to the same Mesh: the vertex data is shared, and everything that draws or traces nodes (the
// raster passes, the tracer, bounds, `info`) sees the instances without knowing the extension.
// Instance nodes come after the file's nodes, so glTF node indices (animation targets) keep
// their meaning; animating the instanced node moves all its instances.
void Loader::build_instances(Scene& scene) {
    constexpr size_t kMaxInstances = size_t(1) << 20;
    const size_t n = m_.nodes.size();
    size_t total = 0;
    for (size_t i = 0; i < n; ++i) {
        const Value* e = extension(m_.nodes[i].extensions, "EXT_mesh_gpu_instancing");
        if (!e || scene.nodes[i].mesh < 0) continue;  // a node without a mesh: warned by the validation
        const std::string ip = idx("nodes", i) + ".extensions.EXT_mesh_gpu_instancing";
        if (scene.nodes[i].skin >= 0) {
            warn(ip, "ignored on a skinned node (its skin places the mesh, so every instance would coincide); the mesh is drawn once");
            continue;
        }
        if (!e->Has("attributes") || !e->Get("attributes").IsObject()) fail(ip + ".attributes", "must be an object");
        const Value& attrs = e->Get("attributes");
        size_t count = 0;
        std::string first;
        auto read = [&](const char* key, int components) -> std::vector<glm::vec4> {
            if (!attrs.Has(key)) return {};
            const Value& v = attrs.Get(key);
            const std::string where = ip + ".attributes." + key;
            if (!v.IsInt() || v.GetNumberAsInt() < 0) fail(where, "must be an accessor index");
            std::vector<glm::vec4> out = read_accessor(v.GetNumberAsInt(), where, components);
            if (first.empty()) first = key, count = out.size();
            else if (out.size() != count)
                fail(where, "has " + std::to_string(out.size()) + " elements, " + first + " has " + std::to_string(count) + " (one per instance)");
            return out;
        };
        const std::vector<glm::vec4> t = read("TRANSLATION", 3), r = read("ROTATION", 4), s = read("SCALE", 3);
        if (count == 0) {
            warn(ip, "has no TRANSLATION, ROTATION or SCALE; the mesh is drawn once");
            continue;
        }
        total += count;
        if (total > kMaxInstances)
            fail(ip, "the file has more than " + std::to_string(kMaxInstances) + " instances; Candela makes a scene node of each and stops there");
        const int mesh = scene.nodes[i].mesh;
        scene.nodes[i].mesh = -1;
        scene.nodes.reserve(scene.nodes.size() + count);
        for (size_t k = 0; k < count; ++k) {
            Node inst;
            inst.name = scene.nodes[i].name + " instance " + std::to_string(k);
            inst.parent = static_cast<int>(i);
            inst.mesh = mesh;
            inst.rest_weights = inst.weights = scene.nodes[i].rest_weights;
            if (!t.empty()) inst.translation = glm::vec3(t[k]);
            if (!s.empty()) inst.scale = glm::vec3(s[k]);
            if (!r.empty()) {
                const glm::quat q(r[k].w, r[k].x, r[k].y, r[k].z);
                const float len = glm::length(q);
                if (!(len > 0.0f) || !std::isfinite(len)) fail(ip + ".attributes.ROTATION", "instance " + std::to_string(k) + " has a zero or non-finite rotation");
                inst.rotation = q / len;
            }
            inst.local = glm::translate(glm::mat4(1.0f), inst.translation) * glm::mat4_cast(inst.rotation) * glm::scale(glm::mat4(1.0f), inst.scale);
            for (int c = 0; c < 16; ++c)
                if (!std::isfinite(glm::value_ptr(inst.local)[c])) fail(ip, "instance " + std::to_string(k) + " has a non-finite transform");
            scene.nodes[i].children.push_back(static_cast<int>(scene.nodes.size()));
            scene.nodes.push_back(std::move(inst));
            own_weights_.push_back(own_weights_[i]);
        }
    }
}

void Loader::build_environment(Scene& scene) {
    if (m_.scenes.empty()) return;
    const size_t si = m_.defaultScene >= 0 && static_cast<size_t>(m_.defaultScene) < m_.scenes.size()
                          ? static_cast<size_t>(m_.defaultScene) : 0;
    const Value& extras = m_.scenes[si].extras;
    if (!extras.IsObject()) return;
    const std::string path = idx("scenes", si) + ".extras";
    scene.environment.radiance = factors<3>(path, extras, "environment_radiance", glm::vec3(0.0f), 0.0f, 1e6f);
    scene.environment.intensity = factor(path, extras, "environment_intensity", 1.0, 0.0f, 1e6f);
    if (extras.Has("environment_map") && extras.Get("environment_map").IsString()) {
        const fs::path map = dir_ / extras.Get("environment_map").Get<std::string>();
        if (fs::exists(map)) scene.environment.map = map;
        else warn(path + ".environment_map", "cannot find '" + map.string() + "'; using environment_radiance instead");
    }
}

}  // namespace candela::gltf_loading
