// glTF validation of animations: channels, samplers and their accessors (spec 3.11).
#include "scene/gltf_validate_internal.hpp"

#include <cmath>

namespace candela::gltf::validation {

// Errors: what sampling reads (input times as FLOAT SCALAR, an output whose format fits the
// path and whose count fits the input); the rest warns and the loader drops what it cannot use.
void Validator::check_animations() {
    static const std::set<std::string> paths = {"translation", "rotation", "scale", "weights"};
    Soft soft(*this);
    for (auto [i, anim] : items("animations")) {
        const std::string p = at("animations", i);
        const json* samplers = get(*anim, "samplers");
        const json* channels = get(*anim, "channels");
        if (!samplers || !samplers->is_array() || samplers->empty()) problem(p, "needs a non-empty 'samplers' array");
        if (!channels || !channels->is_array() || channels->empty()) problem(p, "needs a non-empty 'channels' array");
        const size_t ns = samplers && samplers->is_array() ? samplers->size() : 0;
        std::vector<std::pair<int64_t, int64_t>> io(ns, {-1, -1});
        std::vector<std::string> interp(ns, "LINEAR");
        for (size_t si = 0; si < ns; ++si) {
            const json& s = (*samplers)[si];
            const std::string sp = at(at(p, "samplers"), si);
            if (!s.is_object()) {
                problem(sp, "must be an object");
                continue;
            }
            io[si].first = ref(s, "input", sp, "accessors", true, "accessor");
            io[si].second = ref(s, "output", sp, "accessors", true, "accessor");
            if (const std::string* m = string(s, "interpolation", sp, false)) {
                if (*m != "LINEAR" && *m != "STEP" && *m != "CUBICSPLINE")
                    problem(at(sp, "interpolation"), "'" + *m + "' is not LINEAR, STEP or CUBICSPLINE");
                else interp[si] = *m;
            }
            for (auto [key, a] : {std::pair{"input", io[si].first}, std::pair{"output", io[si].second}}) {
                if (a < 0 || !accessors_[static_cast<size_t>(a)].ok) continue;
                const AccessorInfo& info = accessors_[static_cast<size_t>(a)];
                if (info.view >= 0 && views_[static_cast<size_t>(info.view)].stride)
                    problem(at(sp, key), "bufferView " + std::to_string(info.view) + " of animation data cannot have a byteStride");
            }
            if (io[si].first >= 0 && accessors_[static_cast<size_t>(io[si].first)].ok) {
                const AccessorInfo& in = accessors_[static_cast<size_t>(io[si].first)];
                if (in.type != "SCALAR" || in.component_type != kFloat)
                    error(at(sp, "input"), "accessor " + std::to_string(io[si].first) + " must be FLOAT SCALAR (times in seconds)");
                if (!in.has_min || !in.has_max) problem(at(sp, "input"), "accessor " + std::to_string(io[si].first) + " needs min and max");
                if (interp[si] == "CUBICSPLINE" && in.count < 2)
                    problem(at(sp, "input"), "CUBICSPLINE needs at least 2 keyframes, accessor has " + std::to_string(in.count));
            }
        }
        if (!channels || !channels->is_array()) continue;
        std::set<std::pair<int64_t, std::string>> targets;
        for (size_t ci = 0; ci < channels->size(); ++ci) {
            const json& c = (*channels)[ci];
            const std::string cp = at(at(p, "channels"), ci);
            if (!c.is_object()) {
                problem(cp, "must be an object");
                continue;
            }
            const json* sv = get(c, "sampler");
            const int64_t s = sv ? ref_value(*sv, at(cp, "sampler"), "sampler", ns) : -1;
            if (!sv) problem(cp, "'sampler' is required");
            const json* t = get(c, "target");
            if (!t || !t->is_object()) {
                problem(cp, "needs a 'target' object");
                continue;
            }
            const std::string tp = at(cp, "target");
            const json* te = get(*t, "extensions");
            const json* pointer = te ? get(*te, "KHR_animation_pointer") : nullptr;
            const std::string* path = string(*t, "path", tp, true);
            if (pointer && pointer->is_object()) {
                const std::string pp = at(at(tp, "extensions"), "KHR_animation_pointer");
                const std::string* ptr = string(*pointer, "pointer", pp, true);
                if (ptr && (ptr->empty() || (*ptr)[0] != '/')) problem(at(pp, "pointer"), "'" + *ptr + "' is not a JSON pointer");
                if (get(*t, "node")) problem(at(tp, "node"), "must not be set with KHR_animation_pointer");
                if (path && *path != "pointer") problem(at(tp, "path"), "must be 'pointer' with KHR_animation_pointer, not '" + *path + "'");
                continue;
            }
            if (path && !paths.count(*path)) {
                problem(at(tp, "path"), "'" + *path + "' is not translation, rotation, scale or weights");
                path = nullptr;
            }
            const int64_t node = ref(*t, "node", tp, "nodes", false, "node");
            if (node < 0 || !path) continue;
            if (!targets.insert({node, *path}).second) problem(tp, "node " + std::to_string(node) + " " + *path + " is animated twice");
            const json* nj = item("nodes", node);
            if (nj && get(*nj, "matrix") && *path != "weights")
                warn(tp, "node " + std::to_string(node) + " has a matrix; TRS animation needs translation/rotation/scale (the channel is ignored)");
            int64_t morphs = 0;
            if (*path == "weights") {
                const json* mesh = nj ? get(*nj, "mesh") : nullptr;
                if (mesh && mesh->is_number_integer() && mesh->get<int64_t>() >= 0 &&
                    static_cast<size_t>(mesh->get<int64_t>()) < morph_targets_.size())
                    morphs = static_cast<int64_t>(morph_targets_[static_cast<size_t>(mesh->get<int64_t>())]);
                if (morphs == 0) problem(tp, "node " + std::to_string(node) + " has no mesh with morph targets to animate");
            }
            if (s < 0 || io[static_cast<size_t>(s)].second < 0) continue;
            const int64_t out = io[static_cast<size_t>(s)].second;
            const AccessorInfo& o = accessors_[static_cast<size_t>(out)];
            if (!o.ok) continue;
            const int64_t ct = o.component_type;
            const bool normalized_ok = o.normalized && ct != kUInt && ct != kFloat;
            bool format_ok = true;
            if (*path == "translation" || *path == "scale") format_ok = o.type == "VEC3" && ct == kFloat;
            else if (*path == "rotation") format_ok = o.type == "VEC4" && (ct == kFloat || normalized_ok);
            else format_ok = o.type == "SCALAR" && (ct == kFloat || normalized_ok);
            if (!format_ok)
                error(at(cp, "sampler"), "output accessor " + std::to_string(out) + " (" + component_name(ct) + " " + o.type +
                                               ") does not fit path '" + *path + "'");
            const int64_t in = io[static_cast<size_t>(s)].first;
            if (in >= 0 && accessors_[static_cast<size_t>(in)].ok) {
                const int64_t expect = accessors_[static_cast<size_t>(in)].count * (interp[static_cast<size_t>(s)] == "CUBICSPLINE" ? 3 : 1) *
                                       (*path == "weights" ? std::max<int64_t>(morphs, 1) : 1);
                if (o.count != expect && (*path != "weights" || morphs > 0))
                    error(at(cp, "sampler"), "output accessor " + std::to_string(out) + " has " + std::to_string(o.count) + " elements, " +
                                                 std::to_string(expect) + " expected (input accessor " + std::to_string(in) + ": " +
                                                 std::to_string(accessors_[static_cast<size_t>(in)].count) + " keyframes" +
                                                 (interp[static_cast<size_t>(s)] == "CUBICSPLINE" ? " x 3 for CUBICSPLINE" : "") +
                                                 (*path == "weights" ? " x " + std::to_string(morphs) + " morph targets" : "") + ")");
            }
        }
    }
}

}  // namespace candela::gltf::validation
