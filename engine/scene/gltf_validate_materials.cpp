// glTF validation of images, samplers, textures and materials (spec 3.8, 3.9).
#include "scene/gltf_validate_internal.hpp"

#include <cmath>

namespace candela::gltf::validation {

void Validator::check_images() {
    for (auto [i, im] : items("images")) {
        const std::string p = at("images", i);
        Soft soft(*this);  // an unusable image gets the loader's fallback texture and a warning
        const bool has_uri = get(*im, "uri"), has_view = get(*im, "bufferView");
        if (has_uri == has_view) problem(p, "must have exactly one of 'uri' and 'bufferView'");
        const std::string* mime = string(*im, "mimeType", p, false);
        const std::string* uri = string(*im, "uri", p, false);
        if (has_view) {
            int64_t view;
            --soft_;  // a dangling bufferView is an error like any other reference
            view = ref(*im, "bufferView", p, "bufferViews", false);
            ++soft_;
            if (!mime) problem(p, "an image in a bufferView needs a mimeType");
            if (view >= 0 && views_[static_cast<size_t>(view)].stride)
                problem(at(p, "bufferView"), "bufferView " + std::to_string(view) + " of an image cannot have a byteStride");
            if (view >= 0 && views_[static_cast<size_t>(view)].unavailable)
                warn(at(p, "bufferView"), "bufferView " + std::to_string(view) + " lies in a buffer whose data is not available");
        }
        std::string type = mime ? *mime : "";
        if (uri) {
            if (auto data = parse_data_uri(*uri)) {
                size_t decoded = 0;
                if (!data->base64 || !valid_base64(data->payload, &decoded)) problem(at(p, "uri"), "is not a valid base64 data URI");
                else if (!starts_with(data->media_type, "image/"))
                    problem(at(p, "uri"), "data URI media type '" + data->media_type + "' is not an image type");
                type = data->media_type;
            } else if (const std::string why = uri_problem(*uri); !why.empty()) {
                problem(at(p, "uri"), why);
            }
        }
        if (!type.empty()) {
            const bool core = type == "image/png" || type == "image/jpeg";
            const bool by_ext = (type == "image/webp" && used("EXT_texture_webp")) || (type == "image/ktx2" && used("KHR_texture_basisu")) ||
                                (type == "image/avif" && used("EXT_texture_avif"));
            if (!core && !by_ext) problem(mime ? at(p, "mimeType") : at(p, "uri"), "media type '" + type + "' is not image/png or image/jpeg");
        }
        image_type_.push_back(type);
    }
}

void Validator::check_samplers() {
    for (const auto& [index, sampler] : items("samplers")) {
        const json* s = sampler;  // a lambda cannot capture a structured binding before C++20's clang 16
        const std::string p = at("samplers", index);
        auto in = [&](const char* key, std::initializer_list<int64_t> values) {
            const auto v = integer(*s, key, p, false, 0);
            if (v && std::find(values.begin(), values.end(), *v) == values.end())
                warn(at(p, key), std::to_string(*v) + " is not a valid value; the default is used");
        };
        in("magFilter", {9728, 9729});
        in("minFilter", {9728, 9729, 9984, 9985, 9986, 9987});
        in("wrapS", {33071, 33648, 10497});
        in("wrapT", {33071, 33648, 10497});
    }
}

void Validator::check_textures() {
    static const char* source_exts[] = {"EXT_texture_webp", "KHR_texture_basisu", "EXT_texture_avif", "MSFT_texture_dds"};
    for (auto [i, t] : items("textures")) {
        const std::string p = at("textures", i);
        ref(*t, "sampler", p, "samplers", false);
        const int64_t source = ref(*t, "source", p, "images", false);
        if (source >= 0 && static_cast<size_t>(source) < image_type_.size()) {
            const std::string& type = image_type_[static_cast<size_t>(source)];
            if (!type.empty() && type != "image/png" && type != "image/jpeg")
                warn(at(p, "source"), "image " + std::to_string(source) + " is '" + type +
                                          "', which a texture's source cannot be (only PNG or JPEG); the fallback texture is used");
        }
        if (const json* ext = get(*t, "extensions"))
            for (const char* e : source_exts)
                if (const json* o = get(*ext, e)) {
                    Soft soft(*this);
                    ref(*o, "source", at(at(p, "extensions"), e), "images", true, "image");
                }
    }
}

// A textureInfo (baseColorTexture, normalTexture, ..., and those of material extensions).
void Validator::check_texture_info(const json& ti, const std::string& p) {
    if (!ti.is_object()) return problem(p, "must be an object");
    ref(ti, "index", p, "textures", true, "texture");
    integer(ti, "texCoord", p, false, 0);
    if (const auto s = number(ti, "strength", p, false); s && (*s < 0 || *s > 1))
        warn(at(p, "strength"), num(*s) + " is outside [0, 1]");
    number(ti, "scale", p, false);
    if (const json* e = get(ti, "extensions"))
        if (const json* tt = get(*e, "KHR_texture_transform"); tt && tt->is_object()) {
            const std::string tp = at(at(p, "extensions"), "KHR_texture_transform");
            numbers(*tt, "offset", tp, 2);
            numbers(*tt, "scale", tp, 2);
            number(*tt, "rotation", tp, false);
            integer(*tt, "texCoord", tp, false, 0);
        }
}

void Validator::check_materials() {
    for (auto [i, m] : items("materials")) {
        const std::string p = at("materials", i);
        walk(*m, p, "material", [&](const json& obj, const std::string& path, const std::string& kind) {
            if (kind == "textureInfo") {
                std::optional<Soft> soft;
                if (path.find(".extensions.") != std::string::npos) {
                    const size_t s = path.find(".extensions.") + 12;
                    if (!extension_implemented(path.substr(s, path.find('.', s) - s))) soft.emplace(*this);
                }
                check_texture_info(obj, path);
            }
        });
        if (const json* pbr = get(*m, "pbrMetallicRoughness"); pbr && !pbr->is_object())
            problem(at(p, "pbrMetallicRoughness"), "must be an object");
        else if (pbr) {
            const std::string pp = at(p, "pbrMetallicRoughness");
            numbers(*pbr, "baseColorFactor", pp, 4);
            number(*pbr, "metallicFactor", pp, false);
            number(*pbr, "roughnessFactor", pp, false);
        }
        numbers(*m, "emissiveFactor", p, 3);
        string(*m, "alphaMode", p, false);
        number(*m, "alphaCutoff", p, false);
        if (const json* ds = get(*m, "doubleSided"); ds && !ds->is_boolean()) problem(at(p, "doubleSided"), "must be true or false");
    }
}

}  // namespace candela::gltf::validation
