#include "scene/animation.hpp"

#include <algorithm>
#include <cmath>
#include <thread>

#include <glm/gtc/matrix_transform.hpp>

#include "core/error.hpp"
#include "scene/mesh_utils.hpp"

namespace candela {
namespace {

glm::quat to_quat(const float* v) { return glm::quat(v[3], v[0], v[1], v[2]); }  // glTF xyzw

glm::quat normalized_or_identity(glm::quat q) {
    const float len = glm::length(q);
    return len > 0.0f && std::isfinite(len) ? q / len : glm::quat(1.0f, 0.0f, 0.0f, 0.0f);
}

// Spherical interpolation along the shorter arc (glTF 2.0 appendix C), falling back to a
// normalised lerp when the rotations are nearly equal.
glm::quat slerp_short(glm::quat a, glm::quat b, float s) {
    float d = glm::dot(a, b);
    if (d < 0.0f) b = -b, d = -d;
    if (d > 0.9995f) return normalized_or_identity(a * (1.0f - s) + b * s);
    const float theta = std::acos(std::min(d, 1.0f));
    const float sin_theta = std::sin(theta);
    return normalized_or_identity(a * (std::sin((1.0f - s) * theta) / sin_theta) + b * (std::sin(s * theta) / sin_theta));
}

glm::mat4 trs(const glm::vec3& t, const glm::quat& r, const glm::vec3& s) {
    return glm::translate(glm::mat4(1.0f), t) * glm::mat4_cast(r) * glm::scale(glm::mat4(1.0f), s);
}

// The cofactor matrix of m: det(m) * inverse(transpose(m)), the normal transform up to scale.
glm::mat3 cofactor(const glm::mat3& m) {
    return glm::mat3(glm::cross(m[1], m[2]), glm::cross(m[2], m[0]), glm::cross(m[0], m[1]));
}

// Runs body(begin, end) over [0, n) on up to the hardware's threads (skinning 1M vertices).
template <class F>
void parallel_for(std::size_t n, F&& body) {
    const unsigned hw = std::max(1u, std::thread::hardware_concurrency());
    const std::size_t chunks = n < 65536 ? 1 : std::min<std::size_t>(hw, 8);
    if (chunks == 1) return body(std::size_t{0}, n);
    std::vector<std::thread> threads;
    const std::size_t step = (n + chunks - 1) / chunks;
    for (std::size_t c = 1; c < chunks; ++c)
        threads.emplace_back([&, c] { body(std::min(n, c * step), std::min(n, (c + 1) * step)); });
    body(0, std::min(n, step));
    for (auto& t : threads) t.join();
}

}  // namespace

void sample_animation(const AnimationSampler& sampler, AnimationPath path, float t, float* out) {
    const int w = sampler.width;
    const std::size_t keys = sampler.times.size();
    const bool cubic = sampler.interpolation == Interpolation::cubic_spline;
    const std::size_t per_key = static_cast<std::size_t>(w) * (cubic ? 3 : 1);
    const bool rotation = path == AnimationPath::rotation;
    if (keys == 0 || sampler.values.size() < keys * per_key) {  // the loader rejects this; stay safe
        for (int i = 0; i < w; ++i) out[i] = rotation && i == 3 ? 1.0f : 0.0f;
        return;
    }
    // The value of keyframe k (the middle element for CUBICSPLINE).
    auto value = [&](std::size_t k) { return sampler.values.data() + k * per_key + (cubic ? static_cast<std::size_t>(w) : 0); };
    auto copy = [&](const float* v) {
        std::copy(v, v + w, out);
        if (rotation && w == 4) {
            const glm::quat q = normalized_or_identity(to_quat(out));
            out[0] = q.x, out[1] = q.y, out[2] = q.z, out[3] = q.w;
        }
    };
    if (!(t > sampler.times.front()) || keys == 1) return copy(value(0));
    if (t >= sampler.times.back()) return copy(value(keys - 1));
    // The interval [times[k], times[k+1]) holding t.
    const std::size_t k = static_cast<std::size_t>(std::upper_bound(sampler.times.begin(), sampler.times.end(), t) - sampler.times.begin()) - 1;
    const float t0 = sampler.times[k], t1 = sampler.times[k + 1];
    const float td = t1 - t0;
    const float s = td > 0.0f ? std::clamp((t - t0) / td, 0.0f, 1.0f) : 0.0f;
    switch (sampler.interpolation) {
    case Interpolation::step:
        return copy(value(k));
    case Interpolation::linear:
        if (rotation && w == 4) {
            const glm::quat q = slerp_short(normalized_or_identity(to_quat(value(k))), normalized_or_identity(to_quat(value(k + 1))), s);
            out[0] = q.x, out[1] = q.y, out[2] = q.z, out[3] = q.w;
            return;
        }
        for (int i = 0; i < w; ++i) out[i] = value(k)[i] * (1.0f - s) + value(k + 1)[i] * s;
        return;
    case Interpolation::cubic_spline: {
        // Hermite spline with the tangents scaled by the keyframe interval (glTF 2.0 appendix C):
        // p(s) = (2s^3 - 3s^2 + 1) v_k + td (s^3 - 2s^2 + s) b_k + (-2s^3 + 3s^2) v_k+1 + td (s^3 - s^2) a_k+1
        const float* vk = value(k);
        const float* bk = sampler.values.data() + k * per_key + 2 * static_cast<std::size_t>(w);        // out-tangent of k
        const float* vk1 = value(k + 1);
        const float* ak1 = sampler.values.data() + (k + 1) * per_key;                                   // in-tangent of k+1
        const float s2 = s * s, s3 = s2 * s;
        const float h00 = 2 * s3 - 3 * s2 + 1, h10 = s3 - 2 * s2 + s, h01 = -2 * s3 + 3 * s2, h11 = s3 - s2;
        for (int i = 0; i < w; ++i) out[i] = h00 * vk[i] + h10 * td * bk[i] + h01 * vk1[i] + h11 * td * ak1[i];
        if (rotation && w == 4) {
            const glm::quat q = normalized_or_identity(to_quat(out));
            out[0] = q.x, out[1] = q.y, out[2] = q.z, out[3] = q.w;
        }
        return;
    }
    }
}

int find_animation(const Scene& scene, const std::string& selector) {
    const int n = static_cast<int>(scene.animations.size());
    auto available = [&] {
        if (n == 0) return std::string("the scene has no animations");
        std::string s = "the scene has " + std::to_string(n) + ": ";
        for (int i = 0; i < n; ++i) s += (i ? ", " : "") + std::to_string(i) + " '" + scene.animations[static_cast<size_t>(i)].name + "'";
        return s;
    };
    if (!selector.empty() && std::all_of(selector.begin(), selector.end(), [](char c) { return c >= '0' && c <= '9'; })) {
        const long i = selector.size() > 9 ? -1 : std::stol(selector);
        if (i >= 0 && i < n) return static_cast<int>(i);
        throw bad_input("--animation " + selector + ": no such animation (" + available() + ")");
    }
    for (int i = 0; i < n; ++i)
        if (scene.animations[static_cast<size_t>(i)].name == selector) return i;
    throw bad_input("--animation '" + selector + "': no such animation (" + available() + ")");
}

bool has_deformation(const Scene& scene) {
    if (!scene.animations.empty() || !scene.skins.empty()) return true;
    for (const Mesh& m : scene.meshes)
        for (const Primitive& p : m.primitives)
            if (p.deformable()) return true;
    return false;
}

Pose evaluate_pose(const Scene& scene, int animation, float time) {
    const std::size_t n = scene.nodes.size();
    Pose pose;
    pose.local.resize(n);
    pose.world.resize(n);
    pose.weights.resize(n);
    std::vector<glm::vec3> t(n), s(n);
    std::vector<glm::quat> r(n);
    for (std::size_t i = 0; i < n; ++i) {
        const Node& node = scene.nodes[i];
        t[i] = node.translation, r[i] = node.rotation, s[i] = node.scale;
        pose.weights[i] = node.rest_weights;
    }
    std::vector<bool> animated(n, false);
    if (animation >= 0 && static_cast<std::size_t>(animation) < scene.animations.size()) {
        const Animation& a = scene.animations[static_cast<std::size_t>(animation)];
        std::vector<float> buf;
        for (const AnimationChannel& c : a.channels) {
            if (c.node < 0 || static_cast<std::size_t>(c.node) >= n || c.sampler < 0 || static_cast<std::size_t>(c.sampler) >= a.samplers.size())
                continue;
            const std::size_t ni = static_cast<std::size_t>(c.node);
            const AnimationSampler& smp = a.samplers[static_cast<std::size_t>(c.sampler)];
            buf.assign(static_cast<std::size_t>(std::max(smp.width, 4)), 0.0f);
            sample_animation(smp, c.path, time, buf.data());
            switch (c.path) {
            case AnimationPath::translation: t[ni] = glm::vec3(buf[0], buf[1], buf[2]); break;
            case AnimationPath::scale: s[ni] = glm::vec3(buf[0], buf[1], buf[2]); break;
            case AnimationPath::rotation: r[ni] = normalized_or_identity(to_quat(buf.data())); break;
            case AnimationPath::weights: {
                std::vector<float>& wts = pose.weights[ni];
                wts.resize(static_cast<std::size_t>(smp.width), 0.0f);
                std::copy(buf.begin(), buf.begin() + smp.width, wts.begin());
                break;
            }
            }
            if (c.path != AnimationPath::weights) animated[ni] = true;
        }
    }
    for (std::size_t i = 0; i < n; ++i) {
        const Node& node = scene.nodes[i];
        // Animated TRS nodes from their channels over the rest TRS; every other node keeps its rest
        // transform (also nodes that scenes built in code placed through `local` alone).
        pose.local[i] = animated[i] && !node.has_matrix ? trs(t[i], r[i], s[i]) : node.rest_local.value_or(node.local);
    }
    // World matrices, parents first (the loader guarantees a tree).
    std::vector<char> done(n, 0);
    std::vector<std::size_t> chain;
    for (std::size_t i = 0; i < n; ++i) {
        std::size_t j = i;
        chain.clear();
        while (!done[j]) {
            chain.push_back(j);
            const int p = scene.nodes[j].parent;
            if (p < 0 || static_cast<std::size_t>(p) >= n || chain.size() > n) break;
            j = static_cast<std::size_t>(p);
        }
        for (auto it = chain.rbegin(); it != chain.rend(); ++it) {
            const int p = scene.nodes[*it].parent;
            pose.world[*it] = p >= 0 && static_cast<std::size_t>(p) < n && done[static_cast<std::size_t>(p)]
                                  ? pose.world[static_cast<std::size_t>(p)] * pose.local[*it]
                                  : pose.local[*it];
            done[*it] = 1;
        }
    }

    // Deformed primitives: morph, then skin, into the node's own space.
    pose.vertices.resize(scene.meshes.size());
    std::vector<int> owner(scene.meshes.size(), -1);  // the node that draws each mesh (the first one)
    for (std::size_t i = 0; i < n; ++i) {
        const int m = scene.nodes[i].mesh;
        if (m >= 0 && static_cast<std::size_t>(m) < owner.size() && owner[static_cast<std::size_t>(m)] < 0) owner[static_cast<std::size_t>(m)] = static_cast<int>(i);
    }
    for (std::size_t mi = 0; mi < scene.meshes.size(); ++mi) {
        const Mesh& mesh = scene.meshes[mi];
        pose.vertices[mi].resize(mesh.primitives.size());
        const int ni = owner[mi];
        const Node* node = ni >= 0 ? &scene.nodes[static_cast<std::size_t>(ni)] : nullptr;
        for (std::size_t pi = 0; pi < mesh.primitives.size(); ++pi) {
            const Primitive& prim = mesh.primitives[pi];
            if (!prim.deformable()) continue;
            std::vector<Vertex>& out = pose.vertices[mi][pi];
            out = prim.rest;
            // Morph targets: the node's weights, else the mesh's.
            const std::vector<float>& wts = node && !pose.weights[static_cast<std::size_t>(ni)].empty()
                                                ? pose.weights[static_cast<std::size_t>(ni)] : mesh.weights;
            const std::size_t targets = std::min(prim.targets.size(), wts.size());
            bool morphed_normals = false;
            for (std::size_t k = 0; k < targets; ++k) {
                const float w = wts[k];
                if (w == 0.0f || !std::isfinite(w)) continue;
                const MorphTarget& mt = prim.targets[k];
                for (std::size_t v = 0; v < out.size(); ++v) {
                    if (v < mt.position.size()) out[v].position += w * mt.position[v];
                    if (v < mt.normal.size()) out[v].normal += w * mt.normal[v];
                    if (v < mt.tangent.size()) out[v].tangent += glm::vec4(w * mt.tangent[v], 0.0f);
                }
                morphed_normals = morphed_normals || !mt.normal.empty() || !mt.tangent.empty();
            }
            if (morphed_normals)
                for (std::size_t i = 0; i < out.size(); ++i) {
                    // Deltas that cancel a normal or tangent (or overflow): the rest one, so that
                    // normals stay unit (a valid file can morph a normal to zero at weight 1).
                    Vertex& v = out[i];
                    const float ln = glm::length(v.normal);
                    v.normal = ln > 1e-20f && std::isfinite(ln) ? v.normal / ln : prim.rest[i].normal;
                    const glm::vec3 tan(v.tangent);
                    const float lt = glm::length(tan);
                    v.tangent = glm::vec4(lt > 1e-20f && std::isfinite(lt) ? tan / lt : glm::vec3(prim.rest[i].tangent), v.tangent.w);
                }
            // Skin: joint matrices in the node's space.
            if (!node || node->skin < 0 || static_cast<std::size_t>(node->skin) >= scene.skins.size() || !prim.skinned()) continue;
            const Skin& skin = scene.skins[static_cast<std::size_t>(node->skin)];
            const glm::mat4& node_world = pose.world[static_cast<std::size_t>(ni)];
            const float det = glm::determinant(glm::mat3(node_world));
            const glm::mat4 to_node = std::fabs(det) > 1e-30f && std::isfinite(det) ? glm::inverse(node_world) : glm::mat4(1.0f);
            std::vector<glm::mat4> joint(skin.joints.size());
            for (std::size_t j = 0; j < skin.joints.size(); ++j) {
                const int jn = skin.joints[j];
                const glm::mat4 jw = jn >= 0 && static_cast<std::size_t>(jn) < n ? pose.world[static_cast<std::size_t>(jn)] : glm::mat4(1.0f);
                joint[j] = to_node * jw * (j < skin.inverse_bind.size() ? skin.inverse_bind[j] : glm::mat4(1.0f));
            }
            const int sets = prim.influence_sets;
            const std::size_t nv = std::min(out.size(), prim.joints.size() / static_cast<std::size_t>(sets));
            parallel_for(nv, [&](std::size_t begin, std::size_t end) {
                for (std::size_t v = begin; v < end; ++v) {
                    glm::mat4 m(0.0f);
                    float total = 0.0f;
                    for (int k = 0; k < sets; ++k) {
                        const std::size_t at = v * static_cast<std::size_t>(sets) + static_cast<std::size_t>(k);
                        const glm::u16vec4 jv = prim.joints[at];
                        const glm::vec4 wv = at < prim.weights.size() ? prim.weights[at] : glm::vec4(0.0f);
                        for (int c = 0; c < 4; ++c) {
                            if (wv[c] == 0.0f || jv[c] >= joint.size()) continue;
                            m += wv[c] * joint[jv[c]];
                            total += wv[c];
                        }
                    }
                    if (!(total > 0.0f)) continue;  // no influence: the vertex stays in the node's space
                    Vertex& x = out[v];
                    x.position = glm::vec3(m * glm::vec4(x.position, 1.0f));
                    const glm::mat3 m3(m);
                    const glm::mat3 cof = cofactor(m3);
                    const float d = glm::determinant(m3);
                    glm::vec3 nn = cof * x.normal * (d < 0.0f ? -1.0f : 1.0f);
                    const float ln = glm::length(nn);
                    if (ln > 1e-20f && std::isfinite(ln)) x.normal = nn / ln;
                    glm::vec3 tt = m3 * glm::vec3(x.tangent);
                    const float lt = glm::length(tt);
                    if (lt > 1e-20f && std::isfinite(lt)) x.tangent = glm::vec4(tt / lt, x.tangent.w);
                }
            });
        }
    }
    return pose;
}

void apply_pose(Scene& scene, Pose&& pose) {
    const std::size_t n = std::min(scene.nodes.size(), pose.world.size());
    for (std::size_t i = 0; i < n; ++i) {
        Node& node = scene.nodes[i];
        if (!node.rest_local) node.rest_local = node.local;
        node.local = pose.local[i];
        node.world = pose.world[i];
        node.weights = std::move(pose.weights[i]);
    }
    for (std::size_t mi = 0; mi < scene.meshes.size() && mi < pose.vertices.size(); ++mi)
        for (std::size_t pi = 0; pi < scene.meshes[mi].primitives.size() && pi < pose.vertices[mi].size(); ++pi) {
            std::vector<Vertex>& v = pose.vertices[mi][pi];
            Primitive& prim = scene.meshes[mi].primitives[pi];
            if (v.empty() || v.size() != prim.vertices.size()) continue;
            prim.vertices = std::move(v);
            compute_bounds(prim);
        }
    for (Camera& cam : scene.cameras)
        if (cam.node >= 0 && static_cast<std::size_t>(cam.node) < scene.nodes.size()) cam.world = scene.nodes[static_cast<std::size_t>(cam.node)].world;
}

ShutterInterval shutter_interval(float time, float shutter, float fps) {
    if (!(shutter > 0.0f) || !(fps > 0.0f)) return {time, time};
    const float half = 0.5f * shutter / fps;
    return {time - half, time + half};
}

}  // namespace candela
