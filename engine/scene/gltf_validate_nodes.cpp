// glTF validation of cameras, nodes, scenes and skins (spec 3.5, 3.10, 3.7.3).
#include "scene/gltf_validate_internal.hpp"

#include <algorithm>
#include <cmath>

namespace candela::gltf::validation {

void Validator::check_cameras() {
    for (auto [i, c] : items("cameras")) {
        const std::string p = at("cameras", i);
        const std::string* type = string(*c, "type", p, true);
        if (!type) continue;
        if (*type != "perspective" && *type != "orthographic") {
            problem(at(p, "type"), "'" + *type + "' is neither perspective nor orthographic");
            continue;
        }
        const char* other = *type == "perspective" ? "orthographic" : "perspective";
        if (get(*c, other)) problem(p, "has a '" + std::string(other) + "' object but its type is " + *type);
        const json* o = get(*c, type->c_str());
        const std::string op = at(p, *type);
        if (!o || !o->is_object()) {
            problem(p, "needs a '" + *type + "' object");
            continue;
        }
        if (*type == "perspective") {
            const auto yfov = number(*o, "yfov", op, true);
            const auto znear = number(*o, "znear", op, true);
            const auto zfar = number(*o, "zfar", op, false);
            const auto aspect = number(*o, "aspectRatio", op, false);
            if (yfov && !(*yfov > 0)) problem(at(op, "yfov"), num(*yfov) + " must be positive");
            else if (yfov && *yfov >= kPi) warn(at(op, "yfov"), num(*yfov) + " should be less than pi");
            if (znear && !(*znear > 0)) problem(at(op, "znear"), num(*znear) + " must be positive");
            if (zfar && !(*zfar > 0)) problem(at(op, "zfar"), num(*zfar) + " must be positive");
            else if (zfar && znear && *zfar <= *znear) problem(op, "zfar " + num(*zfar) + " must be greater than znear " + num(*znear));
            if (aspect && !(*aspect > 0)) problem(at(op, "aspectRatio"), num(*aspect) + " must be positive");
        } else {
            const auto xmag = number(*o, "xmag", op, true);
            const auto ymag = number(*o, "ymag", op, true);
            const auto znear = number(*o, "znear", op, true);
            const auto zfar = number(*o, "zfar", op, true);
            for (auto [key, v] : {std::pair{"xmag", xmag}, std::pair{"ymag", ymag}}) {
                if (v && *v == 0) problem(at(op, key), "must not be zero");
                else if (v && *v < 0) warn(at(op, key), num(*v) + " should not be negative");
            }
            if (znear && *znear < 0) problem(at(op, "znear"), num(*znear) + " must not be negative");
            if (zfar && !(*zfar > 0)) problem(at(op, "zfar"), num(*zfar) + " must be positive");
            else if (zfar && znear && *zfar <= *znear) problem(op, "zfar " + num(*zfar) + " must be greater than znear " + num(*znear));
        }
    }
}

void Validator::check_nodes() {
    const size_t n = count("nodes");
    parent_.assign(n, -1);
    for (auto [i, node] : items("nodes")) {
        const std::string p = at("nodes", i);
        ref(*node, "camera", p, "cameras", false);
        const int64_t mesh = ref(*node, "mesh", p, "meshes", false);
        {
            const int64_t skin = ref(*node, "skin", p, "skins", false);
            Soft soft(*this);
            if (get(*node, "skin") && !get(*node, "mesh")) problem(at(p, "skin"), "a skin needs a mesh on the same node");
            if (skin >= 0 && mesh >= 0) {
                bool skinned = false;
                const json* m = item("meshes", mesh);
                if (const json* prims = m ? get(*m, "primitives") : nullptr; prims && prims->is_array())
                    for (const auto& pr : *prims)
                        if (const json* at = get(pr, "attributes"); at && at->is_object() && at->contains("JOINTS_0") && at->contains("WEIGHTS_0"))
                            skinned = true;
                if (!skinned) problem(at(p, "skin"), "mesh " + std::to_string(mesh) + " has no JOINTS_0 and WEIGHTS_0 to skin");
            }
            if (const json* w = numbers(*node, "weights", p, 0)) {
                if (mesh < 0) problem(at(p, "weights"), "morph weights need a mesh on the same node");
                else if (static_cast<size_t>(mesh) < morph_targets_.size() && w->size() != morph_targets_[static_cast<size_t>(mesh)])
                    error(at(p, "weights"), "has " + std::to_string(w->size()) + " weights, mesh " + std::to_string(mesh) + " has " +
                                                  std::to_string(morph_targets_[static_cast<size_t>(mesh)]) + " morph targets");
            }
        }
        // EXT_mesh_gpu_instancing (its specification): per-instance TRANSLATION, ROTATION and SCALE
        // accessors of one count; custom attributes (_ID...) are allowed and ignored.
        if (const json* e = get(*node, "extensions"); e && e->is_object())
            if (const json* gi = get(*e, "EXT_mesh_gpu_instancing"); gi && gi->is_object()) {
                const std::string ip = at(at(p, "extensions"), "EXT_mesh_gpu_instancing");
                if (!get(*node, "mesh")) warn(ip, "the node has no mesh to instance; ignored");
                const json* attrs = get(*gi, "attributes");
                if (!attrs || !attrs->is_object() || attrs->empty()) {
                    problem(ip, "needs a non-empty 'attributes' object (TRANSLATION, ROTATION, SCALE)");
                } else {
                    int64_t instances = -1;
                    std::string first;
                    for (auto it = attrs->begin(); it != attrs->end(); ++it) {
                        const std::string& name = it.key();
                        const std::string ap = at(at(ip, "attributes"), name);
                        const bool trs = name == "TRANSLATION" || name == "ROTATION" || name == "SCALE";
                        if (!trs && !starts_with(name, "_")) warn(ap, "'" + name + "' is not TRANSLATION, ROTATION, SCALE or a custom _NAME; ignored");
                        const int64_t a = ref_value(*it, ap, "accessor", count("accessors"));
                        if (a < 0 || (trs && unusable(a, ap))) continue;
                        const AccessorInfo& info = accessors_[static_cast<size_t>(a)];
                        if (!info.ok) continue;
                        const int64_t ct = info.component_type;
                        const bool f = ct == kFloat, snorm = (ct == kByte || ct == kShort) && info.normalized;
                        if ((name == "TRANSLATION" || name == "SCALE") && !(info.type == "VEC3" && (f || ct == kByte || ct == kShort)))
                            problem(ap, "accessor " + std::to_string(a) + " is " + component_name(ct) + " " + info.type + "; " + name +
                                            " must be VEC3 FLOAT (or BYTE/SHORT, normalized or not)");
                        if (name == "ROTATION" && !(info.type == "VEC4" && (f || snorm)))
                            problem(ap, "accessor " + std::to_string(a) + " is " + component_name(ct) + (info.normalized ? " normalized " : " ") +
                                            info.type + "; ROTATION must be VEC4 FLOAT or normalized BYTE/SHORT");
                        if (instances < 0) {
                            instances = info.count;
                            first = name;
                        } else if (info.count != instances) {
                            problem(ap, "accessor " + std::to_string(a) + " has " + std::to_string(info.count) + " elements, " + first + " has " +
                                            std::to_string(instances) + " (one per instance)");
                        }
                    }
                }
            }
        const json* matrix = numbers(*node, "matrix", p, 16);
        if (matrix) {
            const json& mm = *matrix;
            if (mm[3].get<double>() != 0 || mm[7].get<double>() != 0 || mm[11].get<double>() != 0 || mm[15].get<double>() != 1)
                problem(at(p, "matrix"), "is not an affine transform (its last row must be 0 0 0 1), so it is not a TRS");
            if (get(*node, "translation") || get(*node, "rotation") || get(*node, "scale"))
                warn(p, "has both a matrix and translation/rotation/scale; the matrix is used");
        }
        numbers(*node, "translation", p, 3);
        numbers(*node, "scale", p, 3);
        if (const json* r = numbers(*node, "rotation", p, 4)) {
            // A component outside [-1, 1] (the schema's range) makes the length exceed 1, so it
            // is this warning too; float rounding of a unit quaternion (1.0000001) stays silent.
            double len2 = 0;
            for (const auto& c : *r) len2 += c.get<double>() * c.get<double>();
            if (std::fabs(std::sqrt(len2) - 1.0) > 1e-4)
                warn(at(p, "rotation"), "is not a unit quaternion (length " + num(std::sqrt(len2)) + "); normalised");
        }
        for (int64_t c : ref_array(*node, "children", p, "nodes", "node", false)) {
            const std::string cp = at(p, "children");
            if (static_cast<size_t>(c) == i) problem(cp, "node " + std::to_string(c) + " is its own child");
            else if (parent_[static_cast<size_t>(c)] >= 0)
                problem(cp, "node " + std::to_string(c) + " already has parent " + std::to_string(parent_[static_cast<size_t>(c)]) +
                                " (the hierarchy must be a tree)");
            else parent_[static_cast<size_t>(c)] = static_cast<int64_t>(i);
        }
    }
}

// A loop: following parents from a node comes back to it. After check_scenes, whose message
// (a root that is also a child) is the clearer one when a scene lists a node of the loop.
void Validator::check_node_loops() {
    const size_t n = parent_.size();
    for (size_t i = 0; i < n; ++i) {
        int64_t k = parent_[i];
        for (size_t steps = 0; k >= 0 && steps <= n; ++steps) {
            if (static_cast<size_t>(k) == i) {
                problem(at("nodes", i), "is its own ancestor (the children form a loop)");
                return;
            }
            k = parent_[static_cast<size_t>(k)];
        }
    }
}

void Validator::check_scenes() {
    for (auto [i, s] : items("scenes")) {
        const std::string p = at("scenes", i);
        for (int64_t r : ref_array(*s, "nodes", p, "nodes", "node", false))
            if (parent_[static_cast<size_t>(r)] >= 0)
                problem(at(p, "nodes"), "node " + std::to_string(r) + " is a root and also a child (of node " +
                                            std::to_string(parent_[static_cast<size_t>(r)]) + ")");
    }
}

// A skinned node drawn by a scene needs its joints in that scene too (spec 3.7.3).
void Validator::check_skinned_nodes_in_scenes() {
    for (auto [si, s] : items("scenes")) {
        const json* roots = get(*s, "nodes");
        if (!roots || !roots->is_array()) continue;
        std::set<int64_t> in_scene;
        for (const auto& r : *roots)
            if (r.is_number_integer() && r.get<int64_t>() >= 0 && static_cast<size_t>(r.get<int64_t>()) < parent_.size())
                in_scene.insert(r.get<int64_t>());
        for (size_t i = 0; i < parent_.size(); ++i)  // add descendants: a node is in if its root is
            if (in_scene.count(root_of(static_cast<int64_t>(i)))) in_scene.insert(static_cast<int64_t>(i));
        for (int64_t n : in_scene) {
            const json* node = item("nodes", n);
            const json* skin_ref = node ? get(*node, "skin") : nullptr;
            if (!skin_ref || !skin_ref->is_number_integer()) continue;
            const json* skin = item("skins", skin_ref->get<int64_t>());
            const json* joints = skin ? get(*skin, "joints") : nullptr;
            if (!joints || !joints->is_array()) continue;
            for (const auto& j : *joints)
                if (j.is_number_integer() && !in_scene.count(j.get<int64_t>())) {
                    problem(at("nodes", static_cast<size_t>(n)), "is skinned in scene " + std::to_string(si) + ", which does not contain its joint " +
                                                                  std::to_string(j.get<int64_t>()));
                    break;
                }
        }
    }
}

int64_t Validator::root_of(int64_t n) const {
    for (size_t steps = 0; parent_[static_cast<size_t>(n)] >= 0 && steps < parent_.size(); ++steps) n = parent_[static_cast<size_t>(n)];
    return n;
}

bool Validator::is_ancestor_or_self(int64_t a, int64_t n) const {
    for (size_t steps = 0; n >= 0 && steps <= parent_.size(); ++steps, n = parent_[static_cast<size_t>(n)])
        if (n == a) return true;
    return false;
}

void Validator::check_skins() {
    for (auto [i, s] : items("skins")) {
        const std::string p = at("skins", i);
        const std::vector<int64_t> joints = ref_array(*s, "joints", p, "nodes", "node", true);
        const int64_t ibm = ref(*s, "inverseBindMatrices", p, "accessors", false, "accessor");
        if (ibm >= 0 && accessors_[static_cast<size_t>(ibm)].ok) {
            const AccessorInfo& a = accessors_[static_cast<size_t>(ibm)];
            if (a.type != "MAT4" || a.component_type != kFloat)
                problem(at(p, "inverseBindMatrices"), "accessor " + std::to_string(ibm) + " must be FLOAT MAT4");
            if (a.count < static_cast<int64_t>(joints.size()))
                problem(at(p, "inverseBindMatrices"), "accessor " + std::to_string(ibm) + " has " + std::to_string(a.count) +
                                                          " matrices for " + std::to_string(joints.size()) + " joints");
            if (a.view >= 0 && views_[static_cast<size_t>(a.view)].stride)
                warn(at(p, "inverseBindMatrices"), "bufferView " + std::to_string(a.view) + " cannot have a byteStride");
        }
        Soft soft(*this);  // informative for posing (which uses the joints' world matrices)
        const int64_t skeleton = ref(*s, "skeleton", p, "nodes", false, "node");
        if (get(*s, "joints") && joints.empty()) continue;
        bool common = true;
        for (int64_t j : joints) common = common && root_of(j) == root_of(joints[0]);
        if (!common) problem(at(p, "joints"), "the joints do not have a common root");
        if (skeleton >= 0)
            for (int64_t j : joints)
                if (!is_ancestor_or_self(skeleton, j)) {
                    problem(at(p, "skeleton"), "node " + std::to_string(skeleton) + " is not an ancestor of joint " + std::to_string(j));
                    break;
                }
    }
}

}  // namespace candela::gltf::validation
