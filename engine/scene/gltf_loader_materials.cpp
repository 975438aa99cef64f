// glTF loading of images (decoded on every core), textures and materials.
#include "scene/gltf_loader_internal.hpp"

#include <atomic>
#include <thread>

#include <stb/stb_image.h>

namespace candela::gltf_loading {
namespace {

// One image; `problem` empty on success. stb_image's failure reason is a global in some builds,
// so the message of a failed decode is taken again on the calling thread (decode_images).
void decode_one(ImageDecodeLog::Entry& e, bool with_reason) {
    const auto reason = [&](const char* fallback) {
        return std::string("cannot decode: ") + (with_reason && stbi_failure_reason() ? stbi_failure_reason() : fallback);
    };
    const int size = static_cast<int>(std::min<size_t>(e.bytes.size(), static_cast<size_t>(std::numeric_limits<int>::max())));
    int w = 0, h = 0, comp = 0;
    if (!stbi_info_from_memory(e.bytes.data(), size, &w, &h, &comp)) {
        e.problem = reason("unknown format");
        return;
    }
    if (w <= 0 || h <= 0 || w > kMaxImageSide || h > kMaxImageSide) {
        e.problem = "unsupported size " + std::to_string(w) + "x" + std::to_string(h);
        return;
    }
    unsigned char* pixels = stbi_load_from_memory(e.bytes.data(), size, &w, &h, &comp, 4);
    if (!pixels) {
        e.problem = reason("?");
        return;
    }
    e.width = w;
    e.height = h;
    e.rgba8.assign(pixels, pixels + static_cast<size_t>(w) * static_cast<size_t>(h) * 4);
    stbi_image_free(pixels);
}

}  // namespace

bool keep_image_bytes(tinygltf::Image*, const int image_index, std::string*, std::string*, int, int, const unsigned char* bytes, int size,
                      void* user) {
    auto* log = static_cast<ImageDecodeLog*>(user);
    log->images[image_index].bytes.assign(bytes, bytes + std::max(size, 0));
    return true;
}

void decode_images(ImageDecodeLog& log) {
    std::vector<ImageDecodeLog::Entry*> todo;
    for (auto& [index, e] : log.images) todo.push_back(&e);
    const size_t threads = std::min<size_t>(todo.size(), std::max(1u, std::thread::hardware_concurrency()));
    std::atomic<size_t> next{0};
    const auto work = [&] {
        for (size_t k; (k = next.fetch_add(1)) < todo.size();) decode_one(*todo[k], false);
    };
    std::vector<std::thread> pool;
    for (size_t t = 1; t < threads; ++t) pool.emplace_back(work);
    work();
    for (std::thread& t : pool) t.join();
    for (auto& [index, e] : log.images) {
        if (!e.problem.empty()) {
            e.problem.clear();
            decode_one(e, true);  // again, alone, for stb_image's reason
            if (!e.problem.empty()) log.problems[index] = e.problem;
        }
        e.bytes = {};
    }
}

TextureRef Loader::texture_ref(int index, int texcoord, const tinygltf::ExtensionMap& ext, const std::string& path,
                               double scale) const {
    TextureRef ref;
    if (index < 0) return ref;
    if (static_cast<size_t>(index) >= m_.textures.size())
        fail(path + ".index", "texture " + std::to_string(index) + " does not exist (the file has " +
                                  std::to_string(m_.textures.size()) + ")");
    const tinygltf::Texture& tex = m_.textures[static_cast<size_t>(index)];
    const std::string tpath = idx("textures", static_cast<size_t>(index));
    if (tex.source < 0) {
        warn(tpath, "has no image source this loader understands; using the fallback texture");
        ref.image = -2;  // resolved to the fallback
    } else if (static_cast<size_t>(tex.source) >= m_.images.size()) {
        fail(tpath + ".source", "image " + std::to_string(tex.source) + " does not exist (the file has " +
                                    std::to_string(m_.images.size()) + ")");
    } else {
        ref.image = tex.source;
    }
    if (tex.sampler >= 0) {
        if (static_cast<size_t>(tex.sampler) >= m_.samplers.size())
            fail(tpath + ".sampler", "sampler " + std::to_string(tex.sampler) + " does not exist");
        const tinygltf::Sampler& s = m_.samplers[static_cast<size_t>(tex.sampler)];
        // Values outside glTF's lists were warned about by the validation; they keep the defaults
        // rather than reach OpenGL as invalid enums.
        auto one_of = [](int v, std::initializer_list<int> ok) { return std::find(ok.begin(), ok.end(), v) != ok.end(); };
        if (one_of(s.magFilter, {9728, 9729})) ref.sampler.mag_filter = s.magFilter;
        if (one_of(s.minFilter, {9728, 9729, 9984, 9985, 9986, 9987})) ref.sampler.min_filter = s.minFilter;
        if (one_of(s.wrapS, {33071, 33648, 10497})) ref.sampler.wrap_s = s.wrapS;
        if (one_of(s.wrapT, {33071, 33648, 10497})) ref.sampler.wrap_t = s.wrapT;
    }
    ref.texcoord = texcoord;
    ref.scale = static_cast<float>(scale);
    if (const Value* t = extension(ext, "KHR_texture_transform")) {
        // uv' = T * R * S * uv, with R = [[cos, sin], [-sin, cos]] (the extension's definition).
        const glm::vec2 offset = vec<2>(*t, "offset", glm::vec2(0.0f));
        const float r = static_cast<float>(number(*t, "rotation", 0.0));
        const glm::vec2 s = vec<2>(*t, "scale", glm::vec2(1.0f));
        const glm::mat3 T(1, 0, 0, 0, 1, 0, offset.x, offset.y, 1);  // column-major
        const glm::mat3 R(std::cos(r), -std::sin(r), 0, std::sin(r), std::cos(r), 0, 0, 0, 1);
        const glm::mat3 S(s.x, 0, 0, 0, s.y, 0, 0, 0, 1);
        ref.transform = T * R * S;
        ref.texcoord = static_cast<int>(number(*t, "texCoord", texcoord));
    }
    // Sets above 1 are named once among the ignored features (gltf::ignored_features).
    if (ref.texcoord < 0 || ref.texcoord > 1) ref.texcoord = 0;
    return ref;
}

TextureRef Loader::texture_ref(const tinygltf::TextureInfo& info, const std::string& path, double scale) const {
    return texture_ref(info.index, info.texCoord, info.extensions, path, scale);
}

// A textureInfo inside an extension's object (tinygltf leaves those as JSON values).
TextureRef Loader::texture_ref(const Value& ext, const char* key, const std::string& path, const char* scale_key) const {
    if (!ext.IsObject() || !ext.Has(key)) return {};
    const Value& info = ext.Get(key);
    const std::string p = path + "." + key;
    if (!info.IsObject()) fail(p, "must be an object");
    const Value& index = info.Get("index");
    if (!index.IsNumber()) fail(p + ".index", "must be a texture index");
    tinygltf::ExtensionMap extensions;
    if (info.Has("extensions") && info.Get("extensions").IsObject()) {
        const Value& e = info.Get("extensions");
        for (const std::string& k : e.Keys()) extensions[k] = e.Get(k);
    }
    return texture_ref(static_cast<int>(index.GetNumberAsInt()), static_cast<int>(number(info, "texCoord", 0.0)), extensions, p,
                       scale_key ? number(info, scale_key, 1.0) : 1.0);
}

// KHR_materials_pbrSpecularGlossiness, converted to metallic-roughness with KHR_materials_specular:
// the extension's model is f = (1 - F) c_diff / pi + F D G / (4 n.l n.v) with F0 = specular,
// F90 = 1, c_diff = diffuse (1 - max(specular)) and alpha = (1 - glossiness)^2. Metallic 0,
// ior 1.5 (F0 0.04) with specular colour specular / 0.04 and roughness 1 - glossiness give
// exactly that. The glossiness texture (alpha of specularGlossinessTexture) becomes a generated
// metallic-roughness image, its specular (RGB) the specular colour texture. Not exact: where the
// specular comes from a texture, the diffuse is dimmed by its factor only (said in a warning).
void Loader::convert_specular_glossiness(Material& mat, const Value& e, const std::string& path, Scene& scene) {
    const glm::vec4 diffuse = factors<4>(path, e, "diffuseFactor", glm::vec4(1.0f), 0.0f, 1.0f);
    const glm::vec3 specular = factors<3>(path, e, "specularFactor", glm::vec3(1.0f), 0.0f, 1.0f);
    const float glossiness = factor(path, e, "glossinessFactor", 1.0, 0.0f, 1.0f);
    const float max_specular = std::max({specular.r, specular.g, specular.b});
    mat.base_color = glm::vec4(glm::vec3(diffuse) * (1.0f - max_specular), diffuse.a);
    mat.base_color_texture = texture_ref(e, "diffuseTexture", path, nullptr);
    mat.metallic = 0.0f;
    mat.ior = 1.5f;
    mat.specular_factor = 1.0f;
    mat.specular_color = specular / 0.04f;
    mat.roughness = 1.0f - glossiness;
    const TextureRef sg = texture_ref(e, "specularGlossinessTexture", path, nullptr);
    if (!sg.present()) return;
    mat.ext_textures[Material::ext_specular_color] = sg;  // RGB, sRGB: specular / 0.04 times the factor's
    if (sg.image < 0 || static_cast<size_t>(sg.image) >= scene.images.size() || !scene.images[static_cast<size_t>(sg.image)].valid) return;
    // roughness = 1 - glossiness * alpha: a new image in the metallic-roughness layout (G roughness,
    // B metallic 0), sampled like the source.
    const Image& src = scene.images[static_cast<size_t>(sg.image)];
    Image rough;
    rough.name = src.name + " (roughness from glossiness)";
    rough.uri = src.uri;
    rough.width = src.width;
    rough.height = src.height;
    rough.valid = true;
    rough.rgba8.resize(src.rgba8.size());
    for (size_t t = 0; t + 3 < src.rgba8.size(); t += 4) {
        const float g = glossiness * static_cast<float>(src.rgba8[t + 3]) / 255.0f;
        rough.rgba8[t] = 0;
        rough.rgba8[t + 1] = static_cast<std::uint8_t>(std::lround(255.0f * (1.0f - g)));
        rough.rgba8[t + 2] = 0;
        rough.rgba8[t + 3] = 255;
    }
    scene.images.push_back(std::move(rough));
    mat.metallic_roughness_texture = sg;
    mat.metallic_roughness_texture.image = static_cast<int>(scene.images.size() - 1);
    mat.roughness = 1.0f;
    if (max_specular < 1.0f)
        warn(path + ".specularGlossinessTexture",
             "the diffuse colour is dimmed by the specular factor, not by the specular texture (approximate conversion "
             "to metallic-roughness)");
}

Material Loader::build_material(size_t i, Scene& scene) {
    const tinygltf::Material& src = m_.materials[i];
    const std::string path = idx("materials", i);
    Material mat;
    mat.name = src.name.empty() ? path : src.name;
    const auto& pbr = src.pbrMetallicRoughness;
    if (pbr.baseColorFactor.size() == 4)
        mat.base_color = factors<4>(path + ".pbrMetallicRoughness.baseColorFactor", pbr.baseColorFactor, 0.0f, 1.0f);
    mat.metallic = factor(path + ".pbrMetallicRoughness.metallicFactor", pbr.metallicFactor, 0.0f, 1.0f);
    mat.roughness = factor(path + ".pbrMetallicRoughness.roughnessFactor", pbr.roughnessFactor, 0.0f, 1.0f);
    // glTF caps emissiveFactor at 1 (KHR_materials_emissive_strength goes beyond); several
    // exporters and Candela's own generated scenes write more, which is accepted up to 1e6.
    if (src.emissiveFactor.size() == 3) mat.emissive = factors<3>(path + ".emissiveFactor", src.emissiveFactor, 0.0f, 1e6f);
    mat.base_color_texture = texture_ref(pbr.baseColorTexture, path + ".pbrMetallicRoughness.baseColorTexture", 1.0);
    mat.metallic_roughness_texture =
        texture_ref(pbr.metallicRoughnessTexture, path + ".pbrMetallicRoughness.metallicRoughnessTexture", 1.0);
    mat.normal_texture = texture_ref(src.normalTexture.index, src.normalTexture.texCoord, src.normalTexture.extensions,
                                     path + ".normalTexture", src.normalTexture.scale);
    mat.occlusion_texture = texture_ref(src.occlusionTexture.index, src.occlusionTexture.texCoord,
                                        src.occlusionTexture.extensions, path + ".occlusionTexture",
                                        src.occlusionTexture.strength);
    mat.emissive_texture = texture_ref(src.emissiveTexture, path + ".emissiveTexture", 1.0);
    if (src.alphaMode == "MASK") mat.alpha_mode = AlphaMode::mask;
    else if (src.alphaMode == "BLEND") mat.alpha_mode = AlphaMode::blend;
    else if (src.alphaMode != "OPAQUE") warn(path + ".alphaMode", "unknown mode '" + src.alphaMode + "'; using OPAQUE");
    mat.alpha_cutoff = factor(path + ".alphaCutoff", src.alphaCutoff, 0.0f, 1.0f);
    mat.double_sided = src.doubleSided;
    // Limits where glTF has none: emission up to 1e6 (the hard cases use 1e4), specular colour up
    // to 100, IOR up to 10 (diamond is 2.42), thickness and attenuation distance up to 1e30.
    const std::string ext = path + ".extensions.";
    if (const Value* e = extension(src.extensions, "KHR_materials_emissive_strength"))
        mat.emissive_strength = factor(ext + "KHR_materials_emissive_strength", *e, "emissiveStrength", 1.0, 0.0f, 1e6f);
    if (const Value* e = extension(src.extensions, "KHR_materials_specular")) {
        mat.specular_factor = factor(ext + "KHR_materials_specular", *e, "specularFactor", 1.0, 0.0f, 1.0f);
        mat.specular_color = factors<3>(ext + "KHR_materials_specular", *e, "specularColorFactor", glm::vec3(1.0f), 0.0f, 100.0f);
    }
    if (const Value* e = extension(src.extensions, "KHR_materials_ior")) {
        mat.ior = f32(ext + "KHR_materials_ior.ior", number(*e, "ior", 1.5));
        if (mat.ior < 1.0f && mat.ior != 0.0f) {
            warn(ext + "KHR_materials_ior.ior", "must be >= 1 (or 0); using 1.5");
            mat.ior = 1.5f;
        }
        mat.ior = factor(ext + "KHR_materials_ior.ior", mat.ior, 0.0f, 10.0f);
    }
    if (const Value* e = extension(src.extensions, "KHR_materials_transmission"))
        mat.transmission = factor(ext + "KHR_materials_transmission", *e, "transmissionFactor", 0.0, 0.0f, 1.0f);
    if (const Value* e = extension(src.extensions, "KHR_materials_volume")) {
        mat.thickness = factor(ext + "KHR_materials_volume", *e, "thicknessFactor", 0.0, 0.0f, 1e30f);
        mat.attenuation_color = factors<3>(ext + "KHR_materials_volume", *e, "attenuationColor", glm::vec3(1.0f), 0.0f, 1.0f);
        const Value& ad = e->IsObject() && e->Has("attenuationDistance") ? e->Get("attenuationDistance") : Value();
        if (ad.IsNumber()) mat.attenuation_distance = factor(ext + "KHR_materials_volume.attenuationDistance", ad.GetNumberAsDouble(), 1e-30f, 1e30f);
        mat.ext_textures[Material::ext_thickness] = texture_ref(*e, "thicknessTexture", ext + "KHR_materials_volume", nullptr);
    }
    if (const Value* e = extension(src.extensions, "KHR_materials_specular")) {
        const std::string p = ext + "KHR_materials_specular";
        mat.ext_textures[Material::ext_specular] = texture_ref(*e, "specularTexture", p, nullptr);
        mat.ext_textures[Material::ext_specular_color] = texture_ref(*e, "specularColorTexture", p, nullptr);
    }
    if (const Value* e = extension(src.extensions, "KHR_materials_transmission"))
        mat.ext_textures[Material::ext_transmission] = texture_ref(*e, "transmissionTexture", ext + "KHR_materials_transmission", nullptr);
    if (extension(src.extensions, "KHR_materials_unlit")) mat.unlit = true;
    if (const Value* e = extension(src.extensions, "KHR_materials_clearcoat")) {
        const std::string p = ext + "KHR_materials_clearcoat";
        mat.clearcoat = factor(p, *e, "clearcoatFactor", 0.0, 0.0f, 1.0f);
        mat.clearcoat_roughness = factor(p, *e, "clearcoatRoughnessFactor", 0.0, 0.0f, 1.0f);
        mat.ext_textures[Material::ext_clearcoat] = texture_ref(*e, "clearcoatTexture", p, nullptr);
        mat.ext_textures[Material::ext_clearcoat_roughness] = texture_ref(*e, "clearcoatRoughnessTexture", p, nullptr);
        mat.ext_textures[Material::ext_clearcoat_normal] = texture_ref(*e, "clearcoatNormalTexture", p, "scale");
    }
    if (const Value* e = extension(src.extensions, "KHR_materials_sheen")) {
        const std::string p = ext + "KHR_materials_sheen";
        mat.sheen_color = factors<3>(p, *e, "sheenColorFactor", glm::vec3(0.0f), 0.0f, 1.0f);
        mat.sheen_roughness = factor(p, *e, "sheenRoughnessFactor", 0.0, 0.0f, 1.0f);
        mat.ext_textures[Material::ext_sheen_color] = texture_ref(*e, "sheenColorTexture", p, nullptr);
        mat.ext_textures[Material::ext_sheen_roughness] = texture_ref(*e, "sheenRoughnessTexture", p, nullptr);
    }
    if (const Value* e = extension(src.extensions, "KHR_materials_anisotropy")) {
        const std::string p = ext + "KHR_materials_anisotropy";
        mat.anisotropy = factor(p, *e, "anisotropyStrength", 0.0, 0.0f, 1.0f);
        mat.anisotropy_rotation = factor(p, *e, "anisotropyRotation", 0.0, -1e6f, 1e6f);
        mat.ext_textures[Material::ext_anisotropy] = texture_ref(*e, "anisotropyTexture", p, nullptr);
    }
    if (const Value* e = extension(src.extensions, "KHR_materials_iridescence")) {
        const std::string p = ext + "KHR_materials_iridescence";
        mat.iridescence = factor(p, *e, "iridescenceFactor", 0.0, 0.0f, 1.0f);
        mat.iridescence_ior = factor(p, *e, "iridescenceIor", 1.3, 1.0f, 10.0f);
        mat.iridescence_thickness_min = factor(p, *e, "iridescenceThicknessMinimum", 100.0, 0.0f, 1e5f);
        mat.iridescence_thickness_max = factor(p, *e, "iridescenceThicknessMaximum", 400.0, 0.0f, 1e5f);
        mat.ext_textures[Material::ext_iridescence] = texture_ref(*e, "iridescenceTexture", p, nullptr);
        mat.ext_textures[Material::ext_iridescence_thickness] = texture_ref(*e, "iridescenceThicknessTexture", p, nullptr);
    }
    // The older workflow replaces pbrMetallicRoughness (the extension's spec: a file may carry
    // both, for viewers without it; then the extension is the authored look).
    if (const Value* e = extension(src.extensions, "KHR_materials_pbrSpecularGlossiness"))
        convert_specular_glossiness(mat, *e, ext + "KHR_materials_pbrSpecularGlossiness", scene);
    return mat;
}

void Loader::build_images(Scene& scene) {
    scene.images.resize(m_.images.size());
    for (size_t i = 0; i < m_.images.size(); ++i) {
        const tinygltf::Image& src = m_.images[i];
        Image& img = scene.images[i];
        img.name = src.name;
        img.uri = src.uri.rfind("data:", 0) == 0 ? "(embedded)" : src.uri;
        if (auto d = image_log_.images.find(static_cast<int>(i)); d != image_log_.images.end() && !d->second.rgba8.empty()) {
            img.width = d->second.width;
            img.height = d->second.height;
            img.rgba8 = std::move(d->second.rgba8);
            img.valid = true;
            continue;
        }
        auto it = image_log_.problems.find(static_cast<int>(i));
        std::string why = it != image_log_.problems.end() ? it->second
                          : !src.uri.empty() && src.uri.rfind("data:", 0) != 0
                              ? "cannot read '" + (dir_ / src.uri).string() + "'"
                              : "no image data";
        warn(idx("images", i) + (img.uri.empty() ? "" : " ('" + img.uri + "')"), why + "; using the fallback texture");
        ++scene.sanitized.missing_textures;
    }
}

}  // namespace candela::gltf_loading
