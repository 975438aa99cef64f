#include "scene/gltf_loader.hpp"

#include <tiny_gltf.h>

#include <algorithm>
#include <atomic>
#include <cmath>
#include <limits>
#include <cstdio>
#include <cstring>
#include <fstream>
#include <functional>
#include <map>
#include <new>
#include <set>
#include <sstream>
#include <thread>

#include <glm/gtc/quaternion.hpp>
#include <glm/gtc/type_ptr.hpp>
#include <nlohmann/json.hpp>
#include <stb/stb_image.h>

#include "core/error.hpp"
#include "core/log.hpp"
#include "scene/animation.hpp"
#include "scene/gltf_decode.hpp"
#include "scene/gltf_loader_internal.hpp"
#include "scene/gltf_validate.hpp"
#include "scene/gltf_validate_internal.hpp"
#include "scene/mesh_utils.hpp"

namespace candela {
namespace gltf_loading {

std::string trim(std::string s) {
    while (!s.empty() && (s.back() == '\n' || s.back() == ' ' || s.back() == '\r')) s.pop_back();
    return s;
}

std::string idx(const char* array, size_t i) { return std::string(array) + "[" + std::to_string(i) + "]"; }

// A number as a person would write it in a message: 2.2e+98, 4, 0.5.
std::string num(double v) {
    char buf[32];
    std::snprintf(buf, sizeof buf, "%g", v);
    return buf;
}

double number(const Value& object, const char* key, double fallback) {
    if (!object.IsObject() || !object.Has(key)) return fallback;
    const Value& v = object.Get(key);
    return v.IsNumber() ? v.GetNumberAsDouble() : fallback;
}

const Value* extension(const tinygltf::ExtensionMap& map, const char* name) {
    auto it = map.find(name);
    return it == map.end() || !it->second.IsObject() ? nullptr : &it->second;
}

Scene Loader::build() {
    Scene scene;
    scene.source = file_;
    build_images(scene);
    scene.materials.reserve(m_.materials.size());
    for (size_t i = 0; i < m_.materials.size(); ++i) scene.materials.push_back(build_material(i, scene));
    // The fallback image is appended so that texture refs with image -2 resolve to it.
    int fallback = -1;
    auto resolve = [&](TextureRef& ref) {
        if (ref.image >= 0 && !scene.images[static_cast<size_t>(ref.image)].valid) ref.image = -2;
        if (ref.image == -2) {
            if (fallback < 0) {
                Image img;
                img.name = "fallback";
                img.width = img.height = 8;
                img.valid = true;
                for (int y = 0; y < 8; ++y)
                    for (int x = 0; x < 8; ++x) {
                        const bool on = ((x / 2) + (y / 2)) % 2 == 0;  // magenta/black checker
                        img.rgba8.insert(img.rgba8.end(), {static_cast<uint8_t>(on ? 255 : 0), 0, static_cast<uint8_t>(on ? 255 : 0), 255});
                    }
                scene.images.push_back(std::move(img));
                fallback = static_cast<int>(scene.images.size()) - 1;
            }
            ref.image = fallback;
        }
    };
    for (Material& m : scene.materials)
        for (TextureRef* r : {&m.base_color_texture, &m.metallic_roughness_texture, &m.normal_texture,
                              &m.occlusion_texture, &m.emissive_texture})
            resolve(*r);
    std::vector<int> unknown_lights;
    for (size_t i = 0; i < m_.lights.size(); ++i) {
        const tinygltf::Light& src = m_.lights[i];
        Light light;
        light.name = src.name.empty() ? idx("lights", i) : src.name;
        if (src.type == "directional") light.type = LightType::directional;
        else if (src.type == "spot") light.type = LightType::spot;
        else if (src.type == "point") light.type = LightType::point;
        else unknown_lights.push_back(static_cast<int>(i));  // warned by the validation; its nodes lose it below
        const std::string lpath = "extensions.KHR_lights_punctual." + idx("lights", i);
        if (src.color.size() == 3) light.color = factors<3>(lpath + ".color", src.color, 0.0f, 1.0f);
        light.intensity = factor(lpath + ".intensity", src.intensity, 0.0f, 1e12f);
        light.range = factor(lpath + ".range", src.range, 0.0f, std::numeric_limits<float>::max());
        light.inner_cone = f32(lpath + ".spot.innerConeAngle", src.spot.innerConeAngle);
        light.outer_cone = f32(lpath + ".spot.outerConeAngle", src.spot.outerConeAngle);
        if (light.type == LightType::spot) {
            light.outer_cone = std::clamp(light.outer_cone, 1e-4f, 1.5707963f);
            light.inner_cone = std::clamp(light.inner_cone, 0.0f, light.outer_cone * 0.9999f);
        }
        scene.lights.push_back(light);
    }
    for (size_t i = 0; i < m_.meshes.size(); ++i) scene.meshes.push_back(build_mesh(i, scene));
    build_nodes(scene);
    build_skins(scene);
    build_animations(scene);
    build_deformation(scene);
    rebase_far_scene(scene);
    // The rest pose (no animation), so that every consumer sees skinned and morphed geometry.
    pose_scene(scene, -1, 0.0f);
    check_posed(scene);
    for (Node& node : scene.nodes)
        if (std::find(unknown_lights.begin(), unknown_lights.end(), node.light) != unknown_lights.end()) node.light = -1;
    for (size_t i = 0; i < scene.nodes.size(); ++i)
        for (int k = 0; k < 16; ++k)
            if (!std::isfinite(glm::value_ptr(scene.nodes[i].world)[k]))
                fail(idx("nodes", i), "the world transform overflows a 32-bit float (large scales or translations along the hierarchy)");
    if (const Bounds b = scene.world_bounds(); !b.empty() && !(std::isfinite(b.max.x - b.min.x) && std::isfinite(b.max.y - b.min.y) &&
                                                               std::isfinite(b.max.z - b.min.z)))
        fail("nodes", "the scene's world-space extent overflows a 32-bit float");
    for (size_t i = 0; i < scene.nodes.size(); ++i) {
        const Node& node = scene.nodes[i];
        if (node.camera < 0) continue;
        const tinygltf::Camera& src = m_.cameras[static_cast<size_t>(node.camera)];
        Camera cam;
        cam.name = src.name.empty() ? node.name : src.name;
        cam.node = static_cast<int>(i);
        cam.world = node.world;
        if (src.type == "orthographic") {
            cam.orthographic = true;
            const std::string cpath = idx("cameras", static_cast<size_t>(node.camera)) + ".orthographic";
            cam.xmag = std::fabs(f32(cpath + ".xmag", src.orthographic.xmag));
            cam.ymag = std::fabs(f32(cpath + ".ymag", src.orthographic.ymag));
            cam.znear = f32(cpath + ".znear", src.orthographic.znear);
            cam.zfar = f32(cpath + ".zfar", src.orthographic.zfar);
            if (!(cam.ymag > 0.0f)) fail(idx("cameras", static_cast<size_t>(node.camera)) + ".orthographic.ymag", "must be positive");
        } else {
            const std::string cpath = idx("cameras", static_cast<size_t>(node.camera)) + ".perspective";
            cam.yfov = f32(cpath + ".yfov", src.perspective.yfov);
            cam.aspect_ratio = std::max(0.0f, f32(cpath + ".aspectRatio", src.perspective.aspectRatio));
            cam.znear = f32(cpath + ".znear", src.perspective.znear);
            cam.zfar = f32(cpath + ".zfar", src.perspective.zfar);
            if (!(cam.yfov > 0.0f && cam.yfov < 3.14f))
                fail(idx("cameras", static_cast<size_t>(node.camera)) + ".perspective.yfov", "must be in (0, pi)");
            if (!(cam.znear > 0.0f))
                fail(idx("cameras", static_cast<size_t>(node.camera)) + ".perspective.znear", "must be positive");
        }
        const std::string cpath = idx("cameras", static_cast<size_t>(node.camera));
        if (cam.orthographic && !(cam.znear >= 0.0f)) fail(cpath + ".orthographic.znear", "must not be negative");
        if (cam.zfar != 0.0f && !(cam.zfar > cam.znear)) fail(cpath + (cam.orthographic ? ".orthographic" : ".perspective") + ".zfar", "must be greater than znear");
        // The thin lens (depth of field): extras.aperture is the lens radius, extras.focus_distance the
        // distance in focus along the view axis, both in scene units (0 or absent: a pinhole;
        // auto focus, focus_distance_or_auto).
        auto lens_number = [&](const char* key) {
            if (!src.extras.IsObject() || !src.extras.Has(key)) return 0.0f;
            const Value& v = src.extras.Get(key);
            const std::string where = cpath + ".extras." + key;
            if (!v.IsNumber()) fail(where, "must be a number >= 0 (scene units)");
            const double d = v.GetNumberAsDouble();
            if (!(d >= 0.0)) fail(where, num(d) + " is negative; must be >= 0 (scene units)");
            return f32(where, d);
        };
        cam.aperture = lens_number("aperture");
        cam.focus_distance = lens_number("focus_distance");
        if (cam.orthographic && cam.aperture > 0.0f)
            warn(cpath + ".extras.aperture", "ignored: an orthographic camera has no depth of field");
        scene.cameras.push_back(cam);
    }
    build_environment(scene);
    const SanitizeReport& s = scene.sanitized;
    if (s.nonfinite_positions) log::warn(file_ + ": " + std::to_string(s.nonfinite_positions) + " non-finite vertex positions replaced by 0");
    if (s.bad_normals) log::warn(file_ + ": " + std::to_string(s.bad_normals) + " zero-length or non-finite normals replaced by face normals");
    return scene;
}

namespace {

std::string read_file(const fs::path& path) {
    std::ifstream in(path, std::ios::binary);
    if (!in) throw bad_input(path.string() + ": cannot open (" + std::strerror(errno) + ")");
    std::ostringstream ss;
    ss << in.rdbuf();
    return ss.str();
}

// Checks what tinygltf reports only vaguely: JSON syntax (with line and column) and external
// buffer files that are missing or shorter than their byteLength.
nlohmann::json precheck_gltf_json(const fs::path& path, std::string_view text) {
    nlohmann::json j;
    // RFC 8259 and the glTF spec (3.2) forbid a byte order mark; nlohmann::json would skip it.
    if (text.substr(0, 3) == "\xEF\xBB\xBF") {
        log::warn(path.string() + ": the JSON starts with a UTF-8 byte order mark, which glTF does not allow; ignored");
        text.remove_prefix(3);
    }
    try {
        j = nlohmann::json::parse(text);
    } catch (const nlohmann::json::exception& e) {
        // parse_error, and out_of_range for a number beyond double (e.g. 1e400; found by fuzzing).
        std::string what = e.what();
        const auto pos = what.find("] ");
        throw bad_input(path.string() + ": invalid JSON: " + (pos == std::string::npos ? what : what.substr(pos + 2)));
    }
    if (!j.is_object()) throw bad_input(path.string() + ": the top level is not a JSON object");
    if (!j.contains("asset")) throw bad_input(path.string() + ": asset: missing (not a glTF 2.0 file?)");
    if (!j.contains("buffers")) return j;
    if (!j["buffers"].is_array()) throw bad_input(path.string() + ": buffers: not an array");
    const auto& buffers = j["buffers"];
    for (size_t i = 0; i < buffers.size(); ++i) {
        const auto& b = buffers[i];
        const std::string bpath = path.string() + ": " + idx("buffers", i);
        if (!b.is_object() || !b.contains("byteLength") || !b["byteLength"].is_number_unsigned())
            throw bad_input(bpath + ".byteLength: missing or not a non-negative integer");
        if (!b.contains("uri") || !b["uri"].is_string()) continue;
        const std::string uri = b["uri"].get<std::string>();
        if (uri.rfind("data:", 0) == 0 || !gltf::buffer_available(b, false, i)) continue;
        const fs::path file = path.parent_path() / uri;
        std::error_code ec;
        const auto size = fs::file_size(file, ec);
        if (ec) throw bad_input(bpath + ".uri: cannot open '" + file.string() + "' (" + ec.message() + ")");
        const auto need = b["byteLength"].get<std::uint64_t>();
        if (size < need)
            throw bad_input(bpath + ": '" + uri + "' has " + std::to_string(size) + " bytes but byteLength is " +
                            std::to_string(need) + " (truncated buffer)");
    }
    return j;
}

// A buffer marked as EXT_meshopt_compression's fallback (its bufferViews are all compressed).
bool meshopt_fallback(const nlohmann::json& buffer) {
    auto e = buffer.find("extensions");
    if (e == buffer.end() || !e->is_object()) return false;
    auto m = e->find("EXT_meshopt_compression");
    if (m == e->end() || !m->is_object()) return false;
    auto f = m->find("fallback");
    return f != m->end() && f->is_boolean() && f->get<bool>();
}

// tinygltf refuses some valid files: buffers without data (no uri, http://), data URIs that are
// not base64, accessors of unknown type (that nothing reads, or validation would have failed),
// and indices accessors without a bufferView (all zeros). It gets a rewritten document; the
// stand-in buffers are marked unavailable (nothing Candela reads lies in them) and the indices
// are restored in its model. Returns the rewritten .gltf/.glb bytes, or "" when none is needed.
std::string for_tinygltf(const std::string& file, const nlohmann::json& doc, bool glb, std::string_view bytes, std::vector<bool>* unavailable,
                         std::vector<std::pair<std::pair<size_t, size_t>, int>>* indices_without_view) {
    nlohmann::json out = doc;
    bool changed = false;
    if (auto b = out.find("buffers"); b != out.end() && b->is_array()) {
        unavailable->assign(b->size(), false);
        for (size_t i = 0; i < b->size(); ++i) {
            nlohmann::json& buf = (*b)[i];
            const uint64_t len = buf.value("byteLength", uint64_t(0));
            auto uri = buf.find("uri");
            if (!gltf::buffer_available(buf, glb, i)) {
                // An EXT_meshopt_compression fallback buffer: what lies in it comes from decoding
                // (decode_meshopt), so a few bytes stand in for any size.
                const bool fallback = meshopt_fallback(buf);
                constexpr uint64_t kMaxStandIn = uint64_t(1) << 26;
                if (len > kMaxStandIn && !fallback)
                    throw bad_input(file + ": " + idx("buffers", i) + ": has no data Candela can read and is too large to stand in for");
                const uint64_t stand_in = fallback ? 4 : len;
                buf["uri"] = "data:application/octet-stream;base64," + gltf::validation::base64_encode(std::string(stand_in, '\0'));
                buf["byteLength"] = stand_in;
                (*unavailable)[i] = changed = true;
            } else if (uri != buf.end() && uri->is_string() && uri->get<std::string>().rfind("data:", 0) == 0) {
                const std::string u = uri->get<std::string>();
                const size_t comma = u.find(',');
                if (comma == std::string::npos || u.substr(0, comma).find(";base64") != std::string::npos) continue;
                std::string decoded;
                for (size_t k = comma + 1; k < u.size(); ++k) {
                    if (u[k] == '%' && k + 2 < u.size()) {
                        decoded += static_cast<char>(std::stoi(u.substr(k + 1, 2), nullptr, 16));
                        k += 2;
                    } else {
                        decoded += u[k];
                    }
                }
                *uri = "data:application/octet-stream;base64," + gltf::validation::base64_encode(decoded);
                changed = true;
            }
        }
    }
    // KTX2 images that only KHR_texture_basisu refers to are never drawn (the textures use their
    // PNG/JPEG `source`): a 1x1 PNG stands in, so that they are neither decoded nor reported.
    if (auto t = out.find("textures"), im = out.find("images"); t != out.end() && t->is_array() && im != out.end() && im->is_array()) {
        std::set<int64_t> basisu_only, drawn;
        for (const auto& tex : *t) {
            if (!tex.is_object()) continue;
            if (auto s = tex.find("source"); s != tex.end() && s->is_number_integer()) drawn.insert(s->get<int64_t>());
            if (auto e = tex.find("extensions"); e != tex.end() && e->is_object())
                for (auto it = e->begin(); it != e->end(); ++it)
                    if (it->is_object())
                        if (auto s = it->find("source"); s != it->end() && s->is_number_integer())
                            (it.key() == "KHR_texture_basisu" ? basisu_only : drawn).insert(s->get<int64_t>());
        }
        for (int64_t i : basisu_only)
            if (!drawn.count(i) && i >= 0 && static_cast<size_t>(i) < im->size()) {
                (*im)[static_cast<size_t>(i)] = {{"uri", "data:image/png;base64,iVBORw0KGgoAAAANSUhEUgAAAAEAAAABCAYAAAAfFcSJAAAADUlEQVR42mNkYPhfDwAChwGA60e6kgAAAABJRU5ErkJggg=="},
                                                 {"name", "KTX2 image (not decoded)"}};
                changed = true;
            }
    }
    if (auto a = out.find("accessors"); a != out.end() && a->is_array())
        for (auto& acc : *a) {
            if (!acc.is_object()) continue;
            const std::string type = acc.value("type", std::string("SCALAR"));
            if (type != "SCALAR" && type != "VEC2" && type != "VEC3" && type != "VEC4" && type != "MAT2" && type != "MAT3" && type != "MAT4")
                acc["type"] = "SCALAR", changed = true;
            const int ct = acc.value("componentType", 5126);
            if (ct < 5120 || ct > 5126 || ct == 5124) acc["componentType"] = 5126, changed = true;
        }
    if (auto m = out.find("meshes"); m != out.end() && m->is_array())
        for (size_t mi = 0; mi < m->size(); ++mi) {
            auto prims = (*m)[mi].find("primitives");
            if (prims == (*m)[mi].end() || !prims->is_array()) continue;
            for (size_t pi = 0; pi < prims->size(); ++pi) {
                nlohmann::json& prim = (*prims)[pi];
                auto ind = prim.find("indices");
                if (ind == prim.end() || !ind->is_number_integer()) continue;
                const size_t a = ind->get<size_t>();
                if (!out.contains("accessors") || a >= out["accessors"].size()) continue;
                const nlohmann::json& acc = out["accessors"][a];
                if (acc.contains("bufferView") || acc.contains("sparse")) continue;
                indices_without_view->push_back({{mi, pi}, static_cast<int>(a)});
                prim.erase("indices");
                changed = true;
            }
        }
    // Integers written as floats (1.0): tinygltf wants integers where glTF has them; it reads any
    // JSON number where glTF has a float, so every integral float becomes an integer.
    std::function<void(nlohmann::json&)> integers = [&](nlohmann::json& v) {
        if (v.is_number_float()) {
            const double d = v.get<double>();
            if (std::isfinite(d) && std::floor(d) == d && std::fabs(d) < 9e15) v = static_cast<int64_t>(d), changed = true;
        } else if (v.is_structured()) {
            for (auto& child : v) integers(child);
        }
    };
    for (const char* key : {"buffers", "bufferViews", "accessors", "meshes", "nodes", "scenes", "textures", "images", "samplers",
                            "skins", "animations", "scene"})
        if (auto it = out.find(key); it != out.end()) {
            // Only where integers live: floats inside material factors etc. stay untouched.
            if (std::strcmp(key, "meshes") == 0 || std::strcmp(key, "nodes") == 0) {
                for (auto& item : *it) {
                    if (!item.is_object()) continue;
                    for (const char* k : {"mesh", "camera", "skin", "children", "primitives"})
                        if (auto c = item.find(k); c != item.end()) {
                            if (std::strcmp(k, "primitives") != 0) integers(*c);
                            else
                                for (auto& prim : *c)
                                    if (prim.is_object())
                                        for (const char* pk : {"attributes", "indices", "material", "mode", "targets"})
                                            if (auto pc = prim.find(pk); pc != prim.end()) integers(*pc);
                        }
                }
            } else if (std::strcmp(key, "accessors") == 0) {
                for (auto& acc : *it)
                    if (acc.is_object())
                        for (auto f = acc.begin(); f != acc.end(); ++f)
                            if (f.key() != "min" && f.key() != "max") integers(f.value());
            } else {
                integers(*it);
            }
        }
    if (!changed) return {};
    const std::string text = out.dump();
    if (!glb) return text;
    // The same .glb with the new JSON chunk (padded with spaces to 4 bytes) and the old chunks after it.
    uint32_t old_json = 0;
    std::memcpy(&old_json, bytes.data() + 12, 4);
    const std::string_view rest = bytes.substr(20 + old_json);
    const uint32_t json_len = static_cast<uint32_t>((text.size() + 3) / 4 * 4);
    const uint32_t total = static_cast<uint32_t>(20 + json_len + rest.size());
    std::string glb_out = std::string(bytes.substr(0, 8));
    glb_out.append(reinterpret_cast<const char*>(&total), 4);
    glb_out.append(reinterpret_cast<const char*>(&json_len), 4);
    glb_out.append("JSON", 4);
    glb_out += text;
    glb_out.append(json_len - text.size(), ' ');
    glb_out += rest;
    return glb_out;
}

// KHR_texture_basisu: no Debian package decodes KTX2 / Basis Universal, so a texture is drawn
// from its `source` (the PNG/JPEG fallback the extension allows) when it has one. Without one,
// the file is refused when it requires the extension; otherwise the texture gets the fallback
// checker like any texture without an image.
void check_basisu(const std::string& file, const nlohmann::json& doc) {
    bool required = false;
    if (auto req = doc.find("extensionsRequired"); req != doc.end() && req->is_array())
        for (const auto& e : *req) required = required || (e.is_string() && e.get<std::string>() == "KHR_texture_basisu");
    auto textures = doc.find("textures");
    if (textures == doc.end() || !textures->is_array()) return;
    size_t with_fallback = 0;
    for (size_t i = 0; i < textures->size(); ++i) {
        const nlohmann::json& t = (*textures)[i];
        if (!t.is_object() || !t.contains("extensions") || !t["extensions"].is_object() || !t["extensions"].contains("KHR_texture_basisu")) continue;
        // A `source` is a fallback unless it is the KTX2 image itself (some exporters put it there
        // when the extension is required).
        bool fallback = false;
        if (auto src = t.find("source"); src != t.end() && src->is_number_integer()) {
            fallback = true;
            auto images = doc.find("images");
            const int64_t si = src->get<int64_t>();
            if (images != doc.end() && images->is_array() && si >= 0 && static_cast<size_t>(si) < images->size() &&
                (*images)[static_cast<size_t>(si)].is_object()) {
                const nlohmann::json& img = (*images)[static_cast<size_t>(si)];
                const std::string mime = img.contains("mimeType") && img["mimeType"].is_string() ? img["mimeType"].get<std::string>() : "";
                const std::string uri = img.contains("uri") && img["uri"].is_string() ? img["uri"].get<std::string>() : "";
                fallback = mime != "image/ktx2" && !(uri.size() >= 5 && uri.compare(uri.size() - 5, 5, ".ktx2") == 0);
            }
        }
        if (fallback) {
            ++with_fallback;
            continue;
        }
        const std::string what = idx("textures", i) + ".extensions.KHR_texture_basisu: KTX2/Basis Universal textures are not supported "
                                 "and the texture has no PNG/JPEG 'source' to fall back to; re-exporting the file with PNG or JPEG textures works";
        if (required) throw bad_input(file + ": " + what);
        log::warn(file + ": " + what + " (the texture is drawn as a checker)");
    }
    if (with_fallback)
        log::info(file + ": KHR_texture_basisu: " + std::to_string(with_fallback) + (with_fallback == 1 ? " texture uses its" : " textures use their") +
                  " PNG/JPEG fallback image (KTX2/Basis Universal is not decoded)");
}

// The first error of a validation pass is bad input; warnings go to the log, at most
// kMaxValidationWarnings of them (a file with a million bad normals says so once per accessor).
void report(const std::string& file, const std::vector<gltf::Issue>& issues) {
    constexpr size_t kMaxValidationWarnings = 20;
    size_t errors = 0;
    for (const gltf::Issue& i : issues) errors += i.error;
    for (const gltf::Issue& i : issues)
        if (i.error)
            throw bad_input(file + ": " + (i.path.empty() ? "" : i.path + ": ") + i.what +
                            (errors > 1 ? " (and " + std::to_string(errors - 1) + " more problems)" : ""));
    for (size_t k = 0; k < issues.size() && k < kMaxValidationWarnings; ++k)
        log::warn(file + ": " + (issues[k].path.empty() ? "" : issues[k].path + ": ") + issues[k].what);
    if (issues.size() > kMaxValidationWarnings)
        log::warn(file + ": " + std::to_string(issues.size() - kMaxValidationWarnings) + " more problems not shown");
}

}  // namespace
}  // namespace gltf_loading

namespace {
namespace fs = std::filesystem;
}  // namespace

Scene load_gltf(const fs::path& path) {
    using namespace gltf_loading;
    std::error_code ec;
    if (!fs::exists(path, ec)) throw bad_input(path.string() + ": no such file");
    if (fs::is_directory(path, ec)) throw bad_input(path.string() + ": is a directory, not a glTF file");
    return load_gltf_from_memory(path, read_file(path));
}

Scene load_gltf_from_memory(const fs::path& path, std::string_view bytes) {
    using namespace gltf_loading;
    const std::string file = path.string();
    // A .glb by its magic, or by its name (then a wrong magic is reported as such).
    const bool binary = (bytes.size() >= 4 && bytes.compare(0, 4, "glTF") == 0) || path.extension() == ".glb";
    int64_t bin_size = -1;
    std::vector<gltf::Issue> container;
    const std::string_view json_text = binary ? gltf::glb_json_chunk(file, bytes, &bin_size, &container) : bytes;
    report(file, container);
    const nlohmann::json doc = precheck_gltf_json(path, json_text);
    // The glTF spec (3.12): a file whose required extension a loader does not implement must
    // not load. Checked first, so that such a file is refused for that reason.
    if (auto req = doc.find("extensionsRequired"); req != doc.end() && req->is_array())
        for (const auto& ext : *req)
            if (ext.is_string() && !gltf::extension_implemented(ext.get<std::string>()))
                throw bad_input(file + ": extensionsRequired: '" + ext.get<std::string>() + "' is not supported");
    check_basisu(file, doc);
    report(file, gltf::validate_document(doc, binary, bin_size));

    std::vector<bool> unavailable;
    std::vector<std::pair<std::pair<size_t, size_t>, int>> indices_without_view;
    const std::string rewritten = for_tinygltf(file, doc, binary, bytes, &unavailable, &indices_without_view);
    if (!rewritten.empty()) bytes = rewritten;

    tinygltf::TinyGLTF gltf;
    ImageDecodeLog image_log;
    gltf.SetImageLoader(keep_image_bytes, &image_log);
    tinygltf::Model model;
    std::string err, warn;
    const std::string base_dir = path.parent_path().string();
    const bool ok = binary
        ? gltf.LoadBinaryFromMemory(&model, &err, &warn, reinterpret_cast<const unsigned char*>(bytes.data()),
                                    static_cast<unsigned>(bytes.size()), base_dir)
        : gltf.LoadASCIIFromString(&model, &err, &warn, bytes.data(), static_cast<unsigned>(bytes.size()), base_dir);
    if (!ok) throw bad_input(file + ": " + (err.empty() ? "not a valid glTF 2.0 file" : trim(err)));
    decode_images(image_log);
    // tinygltf's image warnings are restated by the loader with the JSON path; pass on the rest.
    std::istringstream lines(warn);
    for (std::string line; std::getline(lines, line);)
        if (!line.empty() && line.find("image") == std::string::npos && line.rfind("File not found", 0) != 0)
            log::warn(file + ": " + line);
    for (const auto& [where, accessor] : indices_without_view)
        if (where.first < model.meshes.size() && where.second < model.meshes[where.first].primitives.size())
            model.meshes[where.first].primitives[where.second].indices = accessor;
    // Compressed geometry becomes plain data: `plain` is the document as if it had never been
    // compressed, which the data checks and the Loader read.
    nlohmann::json plain = doc;
    try {
        decode_meshopt(file, plain, model);
        decode_draco(file, plain, model);
    } catch (const nlohmann::json::exception& e) {
        throw bad_input(file + ": a compressed bufferView or primitive has a member of the wrong type (" + std::string(e.what()) + ")");
    } catch (const std::bad_alloc&) {
        // A stream whose header promises more data than memory holds (Draco sizes its arrays from it).
        throw bad_input(file + ": compressed geometry decodes to more data than fits in memory");
    }
    std::vector<std::string_view> buffers;
    for (size_t i = 0; i < model.buffers.size(); ++i)
        buffers.emplace_back(i < unavailable.size() && unavailable[i] ? std::string_view()
                                 : std::string_view(reinterpret_cast<const char*>(model.buffers[i].data.data()), model.buffers[i].data.size()));
    report(file, gltf::validate_data(plain, buffers));
    Scene scene = Loader(path, model, image_log, unavailable).build();
    // What Candela does not implement is named once per kind, in the Scene and on stderr.
    for (const gltf::IgnoredFeature& f : gltf::ignored_features(doc)) {
        log::warn(file + ": " + f.first_path + ": " + f.phrase + " ignored (not implemented)");
        scene.ignored.push_back(f.phrase);
    }
    return scene;
}

}  // namespace candela
