// glTF validation of buffer contents (validate_data): what the document alone cannot tell.
#include "scene/gltf_validate_internal.hpp"

#include <cmath>
#include <cstring>
#include <map>

namespace candela::gltf {
namespace validation {
namespace {

class DataChecker {
public:
    DataChecker(const json& doc, const std::vector<std::string_view>& buffers) : d_(doc), buffers_(buffers) {}

    std::vector<Issue> run() {
        try {
            const json* accessors = d_.find("accessors") != d_.end() ? &d_["accessors"] : nullptr;
            if (accessors && accessors->is_array())
                for (size_t i = 0; i < accessors->size(); ++i) check_accessor(i);
            check_mesh_data();
            check_animation_data();
            check_skin_data();
        } catch (const json::exception&) {
            // A member of an unexpected type that the guards above missed (e.g. a numeric
            // "interpolation"): the structure checks name it; these checks only add warnings, so
            // they stop here rather than end the load with an internal error.
        }
        return std::move(issues_);
    }

private:
    void warn(const std::string& path, const std::string& what) { issues_.push_back({false, path, what}); }
    void error(const std::string& path, const std::string& what) { issues_.push_back({true, path, what}); }

    // Components of accessor `i` as doubles (raw values, not normalized), sparse applied; empty
    // when the accessor has no data this checker can read.
    const std::vector<double>& values(size_t i) {
        auto it = cache_.find(i);
        if (it != cache_.end()) return it->second;
        std::vector<double>& out = cache_[i];
        const json& a = d_["accessors"][i];
        const int64_t ct = a.value("componentType", 0);
        const int nc = type_components(a.value("type", std::string()));
        const int64_t n = a.value("count", int64_t(0));
        const int cs = component_size(ct);
        if (!cs || !nc || n <= 0 || n > (int64_t(1) << 26)) return out;
        const std::string type = a.value("type", std::string());
        if (type == "MAT2" || type == "MAT3") {
            if (cs < 4) return out;  // padded columns: not needed for any check here
        }
        out.assign(static_cast<size_t>(n) * static_cast<size_t>(nc), 0.0);
        auto read = [&](const unsigned char* p, int64_t t) -> double {
            switch (t) {
                case kFloat: { float f; std::memcpy(&f, p, 4); return f; }
                case kByte: return static_cast<int8_t>(*p);
                case kUByte: return *p;
                case kShort: { int16_t v; std::memcpy(&v, p, 2); return v; }
                case kUShort: { uint16_t v; std::memcpy(&v, p, 2); return v; }
                case kUInt: { uint32_t v; std::memcpy(&v, p, 4); return v; }
                default: return 0;
            }
        };
        auto view_bytes = [&](const json& holder, int64_t* stride) -> std::string_view {
            if (!holder.is_object()) return {};
            auto vj = holder.find("bufferView");
            auto views = d_.find("bufferViews");
            if (vj == holder.end() || !vj->is_number_integer() || vj->get<int64_t>() < 0 || views == d_.end() || !views->is_array() ||
                vj->get<size_t>() >= views->size() || !(*views)[vj->get<size_t>()].is_object())
                return {};
            const json& v = (*views)[vj->get<size_t>()];
            const size_t b = v.value("buffer", size_t(0));
            if (b >= buffers_.size()) return {};
            const size_t off = v.value("byteOffset", size_t(0)), len = v.value("byteLength", size_t(0));
            if (off > buffers_[b].size() || len > buffers_[b].size() - off) return {};
            *stride = v.value("byteStride", int64_t(0));
            return buffers_[b].substr(off, len);
        };
        if (!a.contains("bufferView") && !a.contains("sparse")) return out = {}, out;  // zeros by definition: nothing to check
        int64_t stride = 0;
        const std::string_view view = view_bytes(a, &stride);
        if (a.contains("bufferView")) {
            if (view.empty()) return out = {}, out;
            const int64_t s = stride ? stride : int64_t(cs) * nc;
            const size_t off = a.value("byteOffset", size_t(0));
            if (off + size_t(s) * size_t(n - 1) + size_t(cs) * size_t(nc) > view.size()) return out = {}, out;
            const auto* base = reinterpret_cast<const unsigned char*>(view.data()) + off;
            for (int64_t e = 0; e < n; ++e)
                for (int c = 0; c < nc; ++c) out[size_t(e) * size_t(nc) + size_t(c)] = read(base + e * s + c * cs, ct);
        }
        if (a.contains("sparse") && a["sparse"].is_object()) {
            const json& s = a["sparse"];
            const int64_t sn = s.value("count", int64_t(0));
            int64_t st = 0;
            if (!s.contains("indices") || !s.contains("values") || !s["indices"].is_object() || !s["values"].is_object()) return out = {}, out;
            const std::string_view iv = view_bytes(s["indices"], &st), vv = view_bytes(s["values"], &st);
            const int64_t ict = s["indices"].value("componentType", 0);
            const int ics = component_size(ict);
            const size_t ioff = s["indices"].value("byteOffset", size_t(0)), voff = s["values"].value("byteOffset", size_t(0));
            if (ics == 0 || ioff + size_t(sn) * size_t(ics) > iv.size() || voff + size_t(sn) * size_t(cs) * size_t(nc) > vv.size())
                return out = {}, out;
            for (int64_t k = 0; k < sn; ++k) {
                const auto target = static_cast<int64_t>(read(reinterpret_cast<const unsigned char*>(iv.data()) + ioff + size_t(k) * size_t(ics), ict));
                if (target < 0 || target >= n) return out = {}, out;
                for (int c = 0; c < nc; ++c)
                    out[size_t(target) * size_t(nc) + size_t(c)] =
                        read(reinterpret_cast<const unsigned char*>(vv.data()) + voff + size_t(k * nc + c) * size_t(cs), ct);
            }
        }
        return out;
    }

    void check_accessor(size_t i) {
        const json& a = d_["accessors"][i];
        if (!a.is_object()) return;  // the structure checks name it
        const std::string p = at("accessors", i);
        const std::vector<double>& v = values(i);
        if (v.empty()) return;
        const int nc = type_components(a.value("type", std::string()));
        const bool is_float = a.value("componentType", 0) == kFloat;
        if (is_float)
            for (size_t k = 0; k < v.size(); ++k)
                if (!std::isfinite(v[k])) {
                    warn(p, "element " + std::to_string(k / size_t(nc)) + " is not a finite number");
                    return;
                }
        for (const char* key : {"min", "max"}) {
            if (!a.contains(key) || !a[key].is_array() || a[key].size() != size_t(nc)) continue;
            const bool is_min = key[1] == 'i';
            for (int c = 0; c < nc; ++c) {
                double actual = is_min ? kInf : -kInf;
                for (size_t e = 0; e < v.size() / size_t(nc); ++e)
                    actual = is_min ? std::min(actual, v[e * size_t(nc) + size_t(c)]) : std::max(actual, v[e * size_t(nc) + size_t(c)]);
                double declared = a[key][size_t(c)].get<double>();
                if (is_float) declared = static_cast<float>(declared), actual = static_cast<float>(actual);
                if (declared != actual) {
                    const bool outside = is_min ? actual < declared : actual > declared;
                    warn(at(at(p, key), size_t(c)), "declared " + num(declared) + " but the data's " + (is_min ? "minimum" : "maximum") +
                                                         " is " + num(actual) + (outside ? " (elements lie outside the declared bounds)" : ""));
                    break;
                }
            }
        }
    }

    // The accessor an attribute/index refers to, if it is a valid index.
    const std::vector<double>* accessor_values(const json& v, int* nc, int64_t* ct, bool* normalized) {
        if (!v.is_number_integer() || v.get<int64_t>() < 0) return nullptr;
        const size_t a = v.get<size_t>();
        auto accessors = d_.find("accessors");
        if (accessors == d_.end() || !accessors->is_array() || a >= accessors->size() || !(*accessors)[a].is_object()) return nullptr;
        const json& acc = d_["accessors"][a];
        *nc = type_components(acc.value("type", std::string()));
        *ct = acc.value("componentType", 0);
        *normalized = acc.value("normalized", false);
        const std::vector<double>& out = values(a);
        return out.empty() ? nullptr : &out;
    }

    static double unorm(double v, int64_t ct, bool normalized) {
        if (!normalized) return v;
        switch (ct) {
            case kUByte: return v / 255.0;
            case kUShort: return v / 65535.0;
            case kByte: return std::max(v / 127.0, -1.0);
            case kShort: return std::max(v / 32767.0, -1.0);
            default: return v;
        }
    }

    void check_mesh_data() {
        // Only well-formed parts: a malformed one is the structure checks' error, and tinygltf may
        // still have read the file (a non-array "meshes" must not throw here).
        if (!d_.contains("meshes") || !d_["meshes"].is_array()) return;
        const json& meshes = d_["meshes"];
        for (size_t mi = 0; mi < meshes.size(); ++mi) {
            if (!meshes[mi].is_object() || !meshes[mi].contains("primitives") || !meshes[mi]["primitives"].is_array()) continue;
            const json& prims = meshes[mi]["primitives"];
            for (size_t pi = 0; pi < prims.size(); ++pi) {
                const json& prim = prims[pi];
                if (!prim.is_object() || !prim.contains("attributes") || !prim["attributes"].is_object()) continue;
                const std::string pp = at(at(at("meshes", mi), "primitives"), pi);
                const json& attrs = prim["attributes"];
                int nc = 0;
                int64_t ct = 0;
                bool norm = false;
                auto unit_check = [&](const char* name, int len) {
                    if (!attrs.contains(name)) return;
                    const auto* v = accessor_values(attrs[name], &nc, &ct, &norm);
                    if (!v || nc < len) return;
                    for (size_t e = 0; e < v->size() / size_t(nc); ++e) {
                        double l2 = 0;
                        for (int c = 0; c < 3; ++c) l2 += std::pow(unorm((*v)[e * size_t(nc) + size_t(c)], ct, norm), 2);
                        if (std::isfinite(l2) && std::fabs(std::sqrt(l2) - 1.0) > 5e-3) {
                            warn(at(at(pp, "attributes"), name), "element " + std::to_string(e) + " is not a unit vector (length " +
                                                                      num(std::sqrt(l2)) + "); normalised");
                            return;
                        }
                        if (len == 4 && std::fabs(std::fabs(unorm((*v)[e * size_t(nc) + 3], ct, norm)) - 1.0) > 1e-6) {
                            warn(at(at(pp, "attributes"), name), "element " + std::to_string(e) + " has w = " +
                                                                      num((*v)[e * size_t(nc) + 3]) + ", not 1 or -1; its sign is used");
                            return;
                        }
                    }
                };
                unit_check("NORMAL", 3);
                unit_check("TANGENT", 4);
                for (auto it = attrs.begin(); it != attrs.end(); ++it) {
                    const std::string& name = it.key();
                    const std::string ap = at(at(pp, "attributes"), name);
                    if (set_index(name, "COLOR_") >= 0) {
                        const auto* v = accessor_values(*it, &nc, &ct, &norm);
                        if (v && ct == kFloat)
                            for (double x : *v)
                                if (x < 0 || x > 1) {
                                    warn(ap, "colour component " + num(x) + " is outside [0, 1]");
                                    break;
                                }
                    }
                    if (const int w = set_index(name, "WEIGHTS_"); w >= 0) check_weights(attrs, w, ap);
                }
                if (prim.contains("indices")) {
                    const auto* v = accessor_values(prim["indices"], &nc, &ct, &norm);
                    const double restart = ct == kUByte ? 255 : ct == kUShort ? 65535 : 4294967295.0;
                    if (v)
                        for (double x : *v)
                            if (x == restart) {
                                warn(at(pp, "indices"), "contains the primitive restart value " + num(restart));
                                break;
                            }
                }
            }
        }
    }

    // Skin weights (spec 3.7.3.3): non-negative; a joint appears once per vertex with a non-zero
    // weight. Warnings: the loader clamps negative weights to 0 and normalises the sums.
    void check_weights(const json& attrs, int set, const std::string& path) {
        if (set != 0) return;  // all sets are summed together, once
        std::vector<const std::vector<double>*> ws, js;
        std::vector<std::pair<int64_t, bool>> wfmt;
        for (int s = 0;; ++s) {
            const std::string wn = "WEIGHTS_" + std::to_string(s), jn = "JOINTS_" + std::to_string(s);
            if (!attrs.contains(wn)) break;
            int nc = 0;
            int64_t ct = 0;
            bool norm = false;
            const auto* w = accessor_values(attrs[wn], &nc, &ct, &norm);
            if (!w || nc != 4) return;
            ws.push_back(w);
            wfmt.emplace_back(ct, norm);
            const auto* j = attrs.contains(jn) ? accessor_values(attrs[jn], &nc, &ct, &norm) : nullptr;
            js.push_back(j && nc == 4 && j->size() == w->size() ? j : nullptr);
        }
        if (ws.empty()) return;
        const size_t n = ws[0]->size() / 4;
        for (size_t e = 0; e < n; ++e) {
            double sum = 0;
            std::set<double> joints;
            for (size_t s = 0; s < ws.size(); ++s) {
                if (ws[s]->size() != ws[0]->size()) return;
                for (int c = 0; c < 4; ++c) {
                    const double w = unorm((*ws[s])[e * 4 + size_t(c)], wfmt[s].first, wfmt[s].second);
                    if (w < 0) {
                        warn(path, "vertex " + std::to_string(e) + " has a negative weight " + num(w));
                        return;
                    }
                    sum += w;
                    if (js[s] && w > 0 && !joints.insert((*js[s])[e * 4 + size_t(c)]).second) {
                        warn(path, "vertex " + std::to_string(e) + " lists joint " + num((*js[s])[e * 4 + size_t(c)]) + " twice");
                        return;
                    }
                }
            }
            (void)sum;  // not checked here: the loader normalises each vertex's weights (and warns once per primitive)
        }
    }

    void check_animation_data() {
        if (!d_.contains("animations") || !d_["animations"].is_array()) return;
        const json& anims = d_["animations"];
        for (size_t ai = 0; ai < anims.size(); ++ai) {
            const json& a = anims[ai];
            if (!a.is_object() || !a.contains("samplers") || !a["samplers"].is_array()) continue;
            const json& samplers = a["samplers"];
            for (size_t si = 0; si < samplers.size(); ++si) {
                const json& s = samplers[si];
                if (!s.is_object() || !s.contains("input")) continue;
                int nc = 0;
                int64_t ct = 0;
                bool norm = false;
                const auto* in = accessor_values(s["input"], &nc, &ct, &norm);
                const std::string sp = at(at(at("animations", ai), "samplers"), si);
                const std::string p = at(sp, "input");
                // Errors: the times must be finite and strictly increasing (sampling searches them),
                // the output values finite.
                bool negative = false;
                if (in && nc == 1)
                    for (size_t k = 0; k < in->size(); ++k) {
                        if (!std::isfinite((*in)[k])) {
                            error(p, "keyframe " + std::to_string(k) + ": time " + num((*in)[k]) + " is not a finite number");
                            break;
                        }
                        if (k > 0 && !((*in)[k] > (*in)[k - 1])) {
                            error(p, "keyframe times are not strictly increasing (keyframe " + std::to_string(k) + ": " + num((*in)[k]) +
                                         " after " + num((*in)[k - 1]) + ")");
                            break;
                        }
                        if ((*in)[k] < 0 && !negative) {
                            warn(p, "keyframe time " + num((*in)[k]) + " is negative");
                            negative = true;
                        }
                    }
                if (!s.contains("output")) continue;
                const auto* out = accessor_values(s["output"], &nc, &ct, &norm);
                if (out && ct == kFloat)
                    for (size_t k = 0; k < out->size(); ++k)
                        if (!std::isfinite((*out)[k])) {
                            error(at(sp, "output"), "element " + std::to_string(k / size_t(std::max(nc, 1))) + " is not a finite number");
                            break;
                        }
            }
            if (!a.contains("channels") || !a["channels"].is_array()) continue;
            for (size_t ci = 0; ci < a["channels"].size(); ++ci) {
                const json& c = a["channels"][ci];
                if (!c.is_object() || !c.contains("target") || !c["target"].is_object() || c["target"].value("path", "") != "rotation") continue;
                if (!c.contains("sampler") || !c["sampler"].is_number_integer() || c["sampler"].get<size_t>() >= samplers.size()) continue;
                const json& s = samplers[c["sampler"].get<size_t>()];
                if (!s.is_object() || !s.contains("output")) continue;
                int nc = 0;
                int64_t ct = 0;
                bool norm = false;
                const auto* out = accessor_values(s["output"], &nc, &ct, &norm);
                if (!out || nc != 4) continue;
                const bool cubic = s.value("interpolation", "") == "CUBICSPLINE";
                for (size_t e = 0; e < out->size() / 4; ++e) {
                    if (cubic && e % 3 != 1) continue;  // in- and out-tangents need not be unit
                    double l2 = 0;
                    for (int k = 0; k < 4; ++k) l2 += std::pow(unorm((*out)[e * 4 + size_t(k)], ct, norm), 2);
                    if (std::fabs(std::sqrt(l2) - 1.0) > 5e-3) {
                        warn(at(at(at("animations", ai), "channels"), ci) + ".sampler",
                             "rotation keyframe " + std::to_string(e) + " is not a unit quaternion (length " + num(std::sqrt(l2)) + ")");
                        break;
                    }
                }
            }
        }
    }

    void check_skin_data() {
        if (!d_.contains("skins") || !d_["skins"].is_array()) return;
        const json& skins = d_["skins"];
        for (size_t i = 0; i < skins.size(); ++i) {
            if (!skins[i].is_object() || !skins[i].contains("inverseBindMatrices")) continue;
            int nc = 0;
            int64_t ct = 0;
            bool norm = false;
            const auto* m = accessor_values(skins[i]["inverseBindMatrices"], &nc, &ct, &norm);
            if (!m || nc != 16) continue;
            for (size_t e = 0; e < m->size() / 16; ++e) {
                const double* x = m->data() + e * 16;
                if (x[3] != 0 || x[7] != 0 || x[11] != 0 || x[15] != 1) {
                    warn(at(at("skins", i), "inverseBindMatrices"), "matrix " + std::to_string(e) + " is not affine (last row 0 0 0 1)");
                    break;
                }
            }
        }
    }

    const json& d_;
    const std::vector<std::string_view>& buffers_;
    std::map<size_t, std::vector<double>> cache_;
    std::vector<Issue> issues_;
};

}  // namespace
}  // namespace validation

std::vector<Issue> validate_data(const nlohmann::json& doc, const std::vector<std::string_view>& buffers) {
    return validation::DataChecker(doc, buffers).run();
}

}  // namespace candela::gltf
