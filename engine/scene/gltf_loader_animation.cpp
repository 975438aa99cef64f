// glTF loading of skins and animations, and the deformation setup (skinned and morphed meshes).
#include "scene/gltf_loader_internal.hpp"

#include <glm/gtc/quaternion.hpp>
#include <glm/gtc/type_ptr.hpp>

#include "scene/animation.hpp"
#include "scene/mesh_utils.hpp"

namespace candela::gltf_loading {

void Loader::build_skins(Scene& scene) {
    const size_t nodes = scene.nodes.size();
    for (size_t i = 0; i < m_.skins.size(); ++i) {
        const tinygltf::Skin& src = m_.skins[i];
        const std::string path = idx("skins", i);
        Skin skin;
        skin.name = src.name.empty() ? path : src.name;
        if (src.joints.empty()) fail(path + ".joints", "a skin needs at least one joint");
        for (size_t k = 0; k < src.joints.size(); ++k) {
            const int j = src.joints[k];
            if (j < 0 || static_cast<size_t>(j) >= nodes)
                fail(path + ".joints[" + std::to_string(k) + "]", "node " + std::to_string(j) + " does not exist (the file has " +
                                                                      std::to_string(nodes) + ")");
            skin.joints.push_back(j);
        }
        skin.inverse_bind.assign(skin.joints.size(), glm::mat4(1.0f));
        const int ibm = src.inverseBindMatrices;
        if (ibm >= 0 && unavailable(ibm)) {
            warn(path + ".inverseBindMatrices", "the data is not available; identity matrices used");
        } else if (ibm >= 0) {
            const std::string ipath = path + ".inverseBindMatrices";
            int nc = 0;
            const std::vector<float> m = read_floats(ibm, ipath, 16, &nc);
            const tinygltf::Accessor& a = m_.accessors[static_cast<size_t>(ibm)];
            if (a.type != TINYGLTF_TYPE_MAT4 || a.componentType != TINYGLTF_COMPONENT_TYPE_FLOAT)
                fail(ipath, "accessor " + std::to_string(ibm) + " must be FLOAT MAT4");
            const size_t count = m.size() / 16;
            if (count < skin.joints.size())
                fail(ipath, "accessor " + std::to_string(ibm) + " has " + std::to_string(count) + " matrices for " +
                                std::to_string(skin.joints.size()) + " joints");
            for (size_t k = 0; k < skin.joints.size(); ++k) {
                for (size_t c = 0; c < 16; ++c)
                    if (!std::isfinite(m[k * 16 + c])) fail(ipath, "matrix " + std::to_string(k) + " is not finite");
                skin.inverse_bind[k] = glm::make_mat4(m.data() + k * 16);
            }
        }
        if (src.skeleton >= 0 && static_cast<size_t>(src.skeleton) < nodes) skin.skeleton = src.skeleton;
        scene.skins.push_back(std::move(skin));
    }
}

void Loader::build_animations(Scene& scene) {
    for (size_t ai = 0; ai < m_.animations.size(); ++ai) {
        const tinygltf::Animation& src = m_.animations[ai];
        const std::string path = idx("animations", ai);
        Animation anim;
        anim.name = src.name.empty() ? path : src.name;
        // Samplers: the input times (finite, strictly increasing) here; the output when a channel
        // says how wide its elements are. Samplers the validation warned about stay empty.
        anim.samplers.resize(src.samplers.size());
        std::vector<bool> usable(src.samplers.size(), false);
        std::vector<std::vector<float>> outputs(src.samplers.size());
        std::vector<int> output_components(src.samplers.size(), 0);
        bool any_times = false;
        for (size_t si = 0; si < src.samplers.size(); ++si) {
            const tinygltf::AnimationSampler& s = src.samplers[si];
            const std::string spath = path + "." + idx("samplers", si);
            auto exists = [&](int a) { return a >= 0 && static_cast<size_t>(a) < m_.accessors.size() && !unavailable(a); };
            if (!exists(s.input) || !exists(s.output)) continue;  // warned by the validation
            AnimationSampler& out = anim.samplers[si];
            if (s.interpolation == "STEP") out.interpolation = Interpolation::step;
            else if (s.interpolation == "CUBICSPLINE") out.interpolation = Interpolation::cubic_spline;
            const std::string ipath = spath + ".input";
            const tinygltf::Accessor& in = m_.accessors[static_cast<size_t>(s.input)];
            if (in.type != TINYGLTF_TYPE_SCALAR || in.componentType != TINYGLTF_COMPONENT_TYPE_FLOAT)
                fail(ipath, "accessor " + std::to_string(s.input) + " must be FLOAT SCALAR (times in seconds)");
            // An accessor without data is all zeros: valid glTF, but no keyframe times to sample.
            if (in.bufferView < 0 && !in.sparse.isSparse && in.count > 1) {
                warn(ipath, "accessor " + std::to_string(s.input) + " has no data (all times 0); the sampler is ignored");
                continue;
            }
            int nc = 0;
            out.times = read_floats(s.input, ipath, 1, &nc);
            if (out.times.empty()) fail(ipath, "accessor " + std::to_string(s.input) + " has no keyframes");
            for (size_t k = 0; k < out.times.size(); ++k) {
                if (!std::isfinite(out.times[k]))
                    fail(ipath, "keyframe " + std::to_string(k) + ": time " + num(out.times[k]) + " is not a finite number");
                if (k > 0 && !(out.times[k] > out.times[k - 1]))
                    fail(ipath, "keyframe times are not strictly increasing (keyframe " + std::to_string(k) + ": " + num(out.times[k]) +
                                    " after " + num(out.times[k - 1]) + ")");
            }
            const std::string opath = spath + ".output";
            outputs[si] = read_floats(s.output, opath, 4, &output_components[si]);
            for (size_t k = 0; k < outputs[si].size(); ++k)
                if (!std::isfinite(outputs[si][k]))
                    fail(opath, "element " + std::to_string(k / static_cast<size_t>(output_components[si])) + " is not a finite number");
            out.width = output_components[si];
            usable[si] = true;
            anim.start = any_times ? std::min(anim.start, out.times.front()) : out.times.front();
            anim.end = any_times ? std::max(anim.end, out.times.back()) : out.times.back();
            any_times = true;
        }
        std::vector<int> width(src.samplers.size(), 0);  // fixed by the first channel using the sampler
        for (size_t ci = 0; ci < src.channels.size(); ++ci) {
            const tinygltf::AnimationChannel& c = src.channels[ci];
            const std::string cpath = path + "." + idx("channels", ci);
            AnimationChannel channel;
            if (c.target_path == "translation") channel.path = AnimationPath::translation;
            else if (c.target_path == "rotation") channel.path = AnimationPath::rotation;
            else if (c.target_path == "scale") channel.path = AnimationPath::scale;
            else if (c.target_path == "weights") channel.path = AnimationPath::weights;
            else continue;  // KHR_animation_pointer ("pointer"): an ignored feature; others warned by the validation
            if (c.target_node < 0 || static_cast<size_t>(c.target_node) >= scene.nodes.size()) continue;  // warned by the validation
            if (c.sampler < 0 || static_cast<size_t>(c.sampler) >= src.samplers.size() || !usable[static_cast<size_t>(c.sampler)]) continue;
            const Node& node = scene.nodes[static_cast<size_t>(c.target_node)];
            // glTF 3.11: a node given by `matrix` is not animated (the validation warns: the channel is dropped).
            if (node.has_matrix && channel.path != AnimationPath::weights) continue;
            const size_t si = static_cast<size_t>(c.sampler);
            const int nc = output_components[si];
            const int need_components = channel.path == AnimationPath::rotation ? 4 : channel.path == AnimationPath::weights ? 1 : 3;
            if (nc != need_components)
                fail(cpath + ".sampler", "output accessor " + std::to_string(src.samplers[si].output) + " has " + std::to_string(nc) +
                                             " components per element; path '" + c.target_path + "' needs " + std::to_string(need_components));
            int w = need_components;
            if (channel.path == AnimationPath::weights) {
                w = node.mesh >= 0 ? static_cast<int>(scene.meshes[static_cast<size_t>(node.mesh)].weights.size()) : 0;
                if (w == 0) continue;  // no morph targets to animate: warned by the validation
            }
            AnimationSampler& smp = anim.samplers[si];
            const size_t per_key = static_cast<size_t>(w) * (smp.interpolation == Interpolation::cubic_spline ? 3 : 1);
            const size_t expect = smp.times.size() * per_key;  // floats
            if (outputs[si].size() != expect) {
                const size_t elements = outputs[si].size() / static_cast<size_t>(nc);
                fail(path + "." + idx("samplers", si) + ".output",
                     "has " + std::to_string(elements) + " elements for " + std::to_string(smp.times.size()) + " keyframes; " +
                         std::to_string(expect / static_cast<size_t>(nc)) + " expected (" + std::to_string(smp.times.size()) + " keyframes" +
                         (smp.interpolation == Interpolation::cubic_spline ? " x 3 for CUBICSPLINE" : "") +
                         (channel.path == AnimationPath::weights ? " x " + std::to_string(w) + " morph targets of nodes[" +
                                                                       std::to_string(c.target_node) + "]" : "") +
                         ", as " + cpath + " uses it)");
            }
            if (width[si] != 0 && width[si] != w)
                fail(cpath + ".sampler", "sampler " + std::to_string(si) + " is used with " + std::to_string(width[si]) + " and " +
                                             std::to_string(w) + " values per keyframe");
            width[si] = w;
            smp.width = w;
            if (smp.values.empty()) smp.values = outputs[si];
            channel.sampler = c.sampler;
            channel.node = c.target_node;
            anim.channels.push_back(channel);
        }
        scene.animations.push_back(std::move(anim));
    }
}

void Loader::build_deformation(Scene& scene) {
    const size_t file_meshes = scene.meshes.size();
    mesh_source_.resize(file_meshes);
    for (size_t m = 0; m < file_meshes; ++m) mesh_source_[m] = m;
    std::vector<std::vector<size_t>> users(file_meshes);
    for (size_t i = 0; i < scene.nodes.size(); ++i)
        if (scene.nodes[i].mesh >= 0) users[static_cast<size_t>(scene.nodes[i].mesh)].push_back(i);
    std::vector<bool> weights_animated(scene.nodes.size(), false);
    for (const Animation& a : scene.animations)
        for (const AnimationChannel& c : a.channels)
            if (c.path == AnimationPath::weights) weights_animated[static_cast<size_t>(c.node)] = true;
    // A mesh that deforms differently per node (a skin, own or animated weights) gets one copy per
    // node, so that each deformed primitive belongs to exactly one node. Instances that all deform
    // alike (the mesh's default weights, no skin) keep sharing it.
    for (size_t m = 0; m < file_meshes; ++m) {
        if (users[m].size() < 2) continue;
        bool has_joints = false, has_targets = false;
        for (const Primitive& p : scene.meshes[m].primitives) has_joints |= p.skinned(), has_targets |= !p.targets.empty();
        bool individual = false;
        for (size_t u : users[m]) {
            const Node& node = scene.nodes[u];
            individual |= (has_joints && node.skin >= 0) || (has_targets && (own_weights_[u] || weights_animated[u]));
        }
        if (!individual) continue;
        for (size_t k = 1; k < users[m].size(); ++k) {
            Mesh copy = scene.meshes[m];
            scene.meshes.push_back(std::move(copy));
            mesh_source_.push_back(m);
            scene.nodes[users[m][k]].mesh = static_cast<int>(scene.meshes.size()) - 1;
        }
    }
    std::vector<int> owner(scene.meshes.size(), -1);
    for (size_t i = 0; i < scene.nodes.size(); ++i)
        if (const int m = scene.nodes[i].mesh; m >= 0 && owner[static_cast<size_t>(m)] < 0) owner[static_cast<size_t>(m)] = static_cast<int>(i);
    for (size_t mi = 0; mi < scene.meshes.size(); ++mi) {
        const int skin_index = owner[mi] >= 0 ? scene.nodes[static_cast<size_t>(owner[mi])].skin : -1;
        for (size_t pi = 0; pi < scene.meshes[mi].primitives.size(); ++pi) {
            Primitive& prim = scene.meshes[mi].primitives[pi];
            if (prim.skinned() && skin_index >= 0) {
                const Skin& skin = scene.skins[static_cast<size_t>(skin_index)];
                const size_t sets = static_cast<size_t>(prim.influence_sets);
                const size_t nv = prim.vertices.size();
                for (size_t v = 0; v < nv; ++v)
                    for (size_t k = 0; k < sets; ++k)
                        for (int c = 0; c < 4; ++c)
                            if (const unsigned j = prim.joints[v * sets + k][c]; j >= skin.joints.size())
                                fail(primitive_path(mi, pi) + ".attributes.JOINTS_" + std::to_string(k),
                                     "vertex " + std::to_string(v) + ": joint " + std::to_string(j) + " is out of range (skins[" +
                                         std::to_string(skin_index) + "] of nodes[" + std::to_string(owner[mi]) + "] has " +
                                         std::to_string(skin.joints.size()) + " joints)");
                // Each vertex's weights sum to 1 (all zero: the vertex stays in the node's space).
                size_t off = 0;
                float worst = 0.0f;
                for (size_t v = 0; v < nv; ++v) {
                    float sum = 0.0f;
                    for (size_t k = 0; k < sets; ++k) sum += glm::dot(prim.weights[v * sets + k], glm::vec4(1.0f));
                    if (!(sum > 0.0f)) continue;
                    if (std::fabs(sum - 1.0f) > 1e-3f) ++off, worst = std::max(worst, std::fabs(sum - 1.0f));
                    if (!std::isfinite(sum)) fail(primitive_path(mi, pi) + ".attributes.WEIGHTS_0", "vertex " + std::to_string(v) + ": the weights overflow");
                    for (size_t k = 0; k < sets; ++k) prim.weights[v * sets + k] /= sum;
                }
                if (off && mesh_source_[mi] == mi)  // once per primitive of the file, not per copy
                    warn(primitive_path(mi, pi) + ".attributes.WEIGHTS_0",
                         "the skin weights of " + std::to_string(off) + " of " + std::to_string(nv) +
                             " vertices do not sum to 1 (off by up to " + num(worst) + "); normalised");
            } else if (prim.skinned()) {
                // Joints without a skin on the node that draws the mesh: drawn rigid (glTF 3.7.3).
                prim.joints.clear();
                prim.weights.clear();
                prim.influence_sets = 0;
            }
            if (prim.skinned() || !prim.targets.empty()) prim.rest = prim.vertices;
        }
    }
}

// The rest pose of skins and morph targets computed by pose_scene must be usable geometry.
void Loader::check_posed(const Scene& scene) const {
    auto finite = [](const glm::vec3& v) { return std::isfinite(v.x) && std::isfinite(v.y) && std::isfinite(v.z); };
    for (size_t mi = 0; mi < scene.meshes.size(); ++mi)
        for (size_t pi = 0; pi < scene.meshes[mi].primitives.size(); ++pi) {
            const Primitive& prim = scene.meshes[mi].primitives[pi];
            if (!prim.deformable()) continue;
            for (size_t v = 0; v < prim.vertices.size(); ++v)
                if (!finite(prim.vertices[v].position) || !finite(prim.vertices[v].normal) || !finite(glm::vec3(prim.vertices[v].tangent)))
                    fail(primitive_path(mi, pi), "vertex " + std::to_string(v) +
                                                     " is not finite after skinning and morphing (the joints' matrices or the morph deltas overflow a 32-bit float)");
        }
}

}  // namespace candela::gltf_loading
