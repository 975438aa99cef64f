#include "render/gpu_scene.hpp"

#include "gl/mipmaps.hpp"
#include "render/environment.hpp"
#include "render/program_catalog.hpp"

#include <algorithm>
#include <cmath>
#include <cstring>
#include <limits>

#include <glm/gtc/constants.hpp>
#include <glm/gtc/matrix_inverse.hpp>

#include "core/error.hpp"
#include "core/log.hpp"

namespace candela {

std::array<glm::vec3, 9> project_irradiance_sh(const ImageF& equirect) {
    std::array<glm::vec3, 9> L{};
    const int w = equirect.width, h = equirect.height;
    const double pi = 3.14159265358979323846;
    for (int y = 0; y < h; ++y) {
        const double theta = (y + 0.5) / h * pi;  // from +Y
        const double d_omega = (2.0 * pi / w) * (pi / h) * std::sin(theta);
        for (int x = 0; x < w; ++x) {
            // Inverse of direction_to_equirect in shaders/common/math.glsl.
            const double phi = ((x + 0.5) / w - 0.5) * 2.0 * pi;
            const double dx = std::sin(theta) * std::sin(phi), dy = std::cos(theta), dz = -std::sin(theta) * std::cos(phi);
            const float* p = equirect.at(x, y);
            glm::vec3 c(p[0], p[1], p[2]);
            for (int k = 0; k < 3; ++k)
                if (!std::isfinite(c[k]) || c[k] < 0.0f) c[k] = 0.0f;
            const double basis[9] = {0.282095,
                                     0.488603 * dy,
                                     0.488603 * dz,
                                     0.488603 * dx,
                                     1.092548 * dx * dy,
                                     1.092548 * dy * dz,
                                     0.315392 * (3.0 * dz * dz - 1.0),
                                     1.092548 * dx * dz,
                                     0.546274 * (dx * dx - dy * dy)};
            for (int i = 0; i < 9; ++i) L[static_cast<size_t>(i)] += c * static_cast<float>(basis[i] * d_omega);
        }
    }
    return L;
}

MaterialData to_gpu(const Material& m) {
    MaterialData d{};
    d.base_color = m.base_color;
    d.emission = m.emission();
    d.metallic = m.metallic;
    d.roughness = m.roughness;
    d.alpha_cutoff = m.alpha_cutoff;
    d.alpha_mode = static_cast<float>(m.alpha_mode);
    d.double_sided = m.double_sided ? 1.0f : 0.0f;
    d.specular_color = m.specular_color;
    d.specular_factor = m.specular_factor;
    d.ior = m.ior;
    d.transmission = m.transmission;
    d.normal_scale = m.normal_texture.scale;
    d.occlusion_strength = m.occlusion_texture.scale;
    const TextureRef* slots[5] = {&m.base_color_texture, &m.metallic_roughness_texture, &m.normal_texture,
                                  &m.occlusion_texture, &m.emissive_texture};
    int tc[5];
    for (int s = 0; s < 5; ++s) {
        tc[s] = slots[s]->present() ? slots[s]->texcoord : -1;
        const glm::mat3& t = slots[s]->transform;  // column-major: t[col][row]
        d.uv_transform[s * 2] = glm::vec4(t[0][0], t[1][0], t[2][0], 0.0f);
        d.uv_transform[s * 2 + 1] = glm::vec4(t[0][1], t[1][1], t[2][1], 0.0f);
    }
    d.texcoord = glm::ivec4(tc[0], tc[1], tc[2], tc[3]);
    d.emissive_texcoord = tc[4];
    d.pad0 = d.pad1 = d.pad2 = -1;
    d.images = glm::ivec4(slots[0]->image, slots[1]->image, slots[2]->image, slots[3]->image);
    // Wrap modes for the ray tracer (it samples one repeating texture array): 4 bits per slot.
    auto wrap_code = [](int gl_wrap) { return gl_wrap == 33071 ? 1 : gl_wrap == 33648 ? 2 : 0; };  // CLAMP_TO_EDGE, MIRRORED_REPEAT
    // And the magnification filter, 1 bit per slot: the tracer fetches the nearest texel for NEAREST.
    int wraps = 0, nearest = 0;
    for (int s = 0; s < 5; ++s) {
        const SamplerDesc& sampler = slots[s]->sampler;
        wraps |= (wrap_code(sampler.wrap_s) | (wrap_code(sampler.wrap_t) << 2)) << (4 * s);
        if (sampler.mag_filter == 9728) nearest |= 1 << s;  // GL_NEAREST
    }
    d.emissive_image = slots[4]->image;
    d.wrap_modes = wraps;
    d.nearest_magnification = nearest;
    d.pad6 = -1;
    d.attenuation_color = m.attenuation_color;
    d.thickness = m.thickness;
    d.attenuation_distance = std::isfinite(m.attenuation_distance) ? m.attenuation_distance : 0.0f;
    d.clearcoat = glm::vec4(m.clearcoat, m.clearcoat_roughness, m.ext_textures[Material::ext_clearcoat_normal].scale,
                            m.unlit ? 1.0f : 0.0f);
    d.sheen = glm::vec4(m.sheen_color, m.sheen_roughness);
    d.anisotropy = glm::vec4(m.anisotropy, std::cos(m.anisotropy_rotation), std::sin(m.anisotropy_rotation), 0.0f);
    d.iridescence = glm::vec4(m.iridescence, m.iridescence_ior, m.iridescence_thickness_min, m.iridescence_thickness_max);
    static_assert(Material::ext_slot_count == EXT_SLOT_COUNT, "one extension slot list");
    for (int s = 0; s < EXT_SLOT_COUNT; ++s) {
        const TextureRef& t = m.ext_textures[s];
        // The image array holds every image; a missing one (-2) reads the array's white layer 0
        // fallback nowhere: it is drawn as if untextured.
        const bool on = t.image >= 0;
        d.ext_image[s / 4][s % 4] = on ? t.image : -1;
        d.ext_texcoord[s / 4][s % 4] = on ? t.texcoord : -1;
        d.ext_uv_transform[s * 2] = glm::vec4(t.transform[0][0], t.transform[1][0], t.transform[2][0], 0.0f);
        d.ext_uv_transform[s * 2 + 1] = glm::vec4(t.transform[0][1], t.transform[1][1], t.transform[2][1], 0.0f);
    }
    return d;
}

LightData to_gpu(const Scene::PlacedLight& pl) {
    const Light& l = *pl.light;
    LightData d{};
    const float type = l.type == LightType::directional ? 0.0f : l.type == LightType::point ? 1.0f : 2.0f;
    d.position = pl.position;
    d.type = type;
    d.direction = pl.direction;
    d.range = l.range;
    d.color = l.color * l.intensity;
    if (l.type == LightType::spot) {
        const float scale = 1.0f / std::max(1e-4f, std::cos(l.inner_cone) - std::cos(l.outer_cone));
        d.spot_scale = scale;
        d.spot_offset = -std::cos(l.outer_cone) * scale;
    }
    return d;
}

GpuScene::GpuScene(const Scene& scene, GlWorker* mips, const ShaderLibrary* shaders) : scene_(scene), mips_(mips && mips->running() ? mips : nullptr) {
    std::vector<Vertex> vertices;
    std::vector<std::uint32_t> indices;
    std::vector<std::vector<Range>>& ranges = ranges_;
    ranges.assign(scene.meshes.size(), {});
    uploaded_vertices_.assign(scene.meshes.size(), {});
    for (size_t mi = 0; mi < scene.meshes.size(); ++mi)
        for (const Primitive& p : scene.meshes[mi].primitives) {
            uploaded_vertices_[mi].push_back(p.deformable() ? p.vertices : std::vector<Vertex>{});
            ranges[mi].push_back({indices.size(), static_cast<GLint>(vertices.size())});
            vertices.insert(vertices.end(), p.vertices.begin(), p.vertices.end());
            indices.insert(indices.end(), p.indices.begin(), p.indices.end());
        }
    // Deformable primitives (skins, morph targets) are re-uploaded per pose: dynamic storage then.
    const bool deformable = has_deformation(scene);
    vertex_count_ = vertices.size();
    vertices_ = gl::Buffer(static_cast<GLsizeiptr>(std::max<size_t>(vertices.size(), 1) * sizeof(Vertex)), vertices.empty() ? nullptr : vertices.data(),
                           deformable ? GL_DYNAMIC_STORAGE_BIT : 0);
    indices_ = gl::Buffer(static_cast<GLsizeiptr>(indices.size() * sizeof(std::uint32_t)), indices.data());
    auto make_vao = [&](const gl::Buffer& elements) {
        gl::VertexArray vao = gl::VertexArray::create();
        glVertexArrayVertexBuffer(vao.id(), 0, vertices_.id(), 0, sizeof(Vertex));
        glVertexArrayElementBuffer(vao.id(), elements.id());
        const struct { GLuint loc; GLint size; GLuint offset; } attribs[] = {
            {0, 3, offsetof(Vertex, position)}, {1, 3, offsetof(Vertex, normal)}, {2, 4, offsetof(Vertex, tangent)},
            {3, 2, offsetof(Vertex, uv0)},      {4, 2, offsetof(Vertex, uv1)},    {5, 4, offsetof(Vertex, color)}};
        for (const auto& a : attribs) {
            glEnableVertexArrayAttrib(vao.id(), a.loc);
            glVertexArrayAttribFormat(vao.id(), a.loc, a.size, GL_FLOAT, GL_FALSE, a.offset);
            glVertexArrayAttribBinding(vao.id(), a.loc, 0);
        }
        return vao;
    };
    vao_ = make_vao(indices_);
    // A second index buffer for per-frame triangle orders (transparency.sort=triangle), as large
    // as all indices, with its own vertex array over the same vertices.
    sorted_indices_ = gl::Buffer(static_cast<GLsizeiptr>(std::max<size_t>(indices.size(), 1) * sizeof(std::uint32_t)), nullptr,
                                 GL_DYNAMIC_STORAGE_BIT);
    sorted_vao_ = make_vao(sorted_indices_);

    std::vector<MaterialData> mats;
    for (const Material& m : scene.materials) mats.push_back(to_gpu(m));
    mats.push_back(to_gpu(Material{}));  // the default material
    materials_ = gl::Buffer(static_cast<GLsizeiptr>(mats.size() * sizeof(MaterialData)), mats.data());
    // A slot without a texture has texcoord set -1 (material_uv.glsl).
    for (const MaterialData& m : mats)
        material_textures_ = material_textures_ || m.texcoord.x >= 0 || m.texcoord.y >= 0 || m.texcoord.z >= 0 ||
                             m.texcoord.w >= 0 || m.emissive_texcoord >= 0;
    material_layers_ = std::any_of(scene.materials.begin(), scene.materials.end(), [](const Material& m) { return m.has_layers(); });

    // Draws: every node reachable from the roots that has a mesh.
    std::vector<int> stack(scene.roots.begin(), scene.roots.end());
    while (!stack.empty()) {
        const int ni = stack.back();
        stack.pop_back();
        const Node& node = scene.nodes[static_cast<size_t>(ni)];
        stack.insert(stack.end(), node.children.begin(), node.children.end());
        if (node.mesh < 0) continue;
        const Mesh& mesh = scene.meshes[static_cast<size_t>(node.mesh)];
        for (size_t pi = 0; pi < mesh.primitives.size(); ++pi) {
            const Primitive& p = mesh.primitives[pi];
            if (p.indices.empty()) continue;
            Draw d{};
            d.node = ni;
            d.primitive = static_cast<int>(pi);
            d.index_count = static_cast<GLsizei>(p.indices.size());
            d.first_index = ranges[static_cast<size_t>(node.mesh)][pi].first_index;
            d.base_vertex = ranges[static_cast<size_t>(node.mesh)][pi].base_vertex;
            d.model = node.world;
            d.model_open = d.model_close = node.world;
            d.normal_matrix = glm::inverseTranspose(glm::mat3(node.world));
            d.mirrored = node.mirrored();
            set_material(d, p);
            {
                const Material& m = scene.material(p.material);
                if (m.transmission > 0.0f && m.thickness > 0.0f) {
                    d.solid_transmissive = true;
                    d.volume_shape = volume_shape(p);
                    d.volume_lo = p.bounds.min;
                    d.volume_hi = p.bounds.max;
                }
            }
            for (int corner = 0; corner < 8; ++corner)
                d.world_bounds.extend(glm::vec3(node.world * glm::vec4(corner & 1 ? p.bounds.max.x : p.bounds.min.x,
                                                                        corner & 2 ? p.bounds.max.y : p.bounds.min.y,
                                                                        corner & 4 ? p.bounds.max.z : p.bounds.min.z, 1.0f)));
            triangles_ += p.triangle_count();
            draws_.push_back(d);
        }
    }

    update_lights(0, nullptr, false, 1, 0);  // punctual lights only, until a renderer sets up its own

    white_ = gl::Texture::create_2d(GL_RGBA8, 1, 1, 1);
    const std::uint8_t white[4] = {255, 255, 255, 255};
    glTextureSubImage2D(white_.id(), 0, 0, 0, 1, 1, GL_RGBA, GL_UNSIGNED_BYTE, white);

    const Environment& env = scene.environment;
    env_radiance_ = env.radiance * env.intensity;
    if (env.has_map()) {
        const ImageF map = env.image ? *env.image : read_image(env.map);
        // Equirectangular: 360 by 180 degrees. Anything else (a cube cross, a photo) would be
        // stretched silently; say so instead.
        if (map.width != 2 * map.height)
            throw bad_input((env.image ? env.label : env.map.string()) + ": an environment map must be equirectangular (width = 2 x height); it is " +
                            std::to_string(map.width) + "x" + std::to_string(map.height));
        env_map_ = gl::Texture::create_2d(GL_RGBA32F, map.width, map.height, 0);
        glTextureSubImage2D(env_map_.id(), 0, 0, 0, map.width, map.height, GL_RGBA, GL_FLOAT, map.pixels.data());
        glTextureParameteri(env_map_.id(), GL_TEXTURE_MIN_FILTER, GL_LINEAR_MIPMAP_LINEAR);
        glTextureParameteri(env_map_.id(), GL_TEXTURE_WRAP_S, GL_REPEAT);
        glTextureParameteri(env_map_.id(), GL_TEXTURE_WRAP_T, GL_CLAMP_TO_EDGE);
        // On this thread even with a mip worker: the renderer needs the map first thing (the
        // reflection cube, the GI estimate), while the material textures' mipmaps on the worker
        // are needed only by the first frame.
        if (shaders) FloatMipmaps(*shaders).generate(env_map_, GL_TEXTURE_2D, map.width, map.height, 1, 0);
        else glGenerateTextureMipmap(env_map_.id());
        env_mips_ = gl::full_mip_levels(map.width, map.height);
        env_sh_ = project_irradiance_sh(map);
        for (auto& c : env_sh_) c *= env.intensity;
        env_radiance_ = glm::vec3(env.intensity);
        env_image_ = map;
    }
    // Every texture a draw uses, uploaded now so that its mipmaps are made beside the main
    // thread's work (program builds, the first frame's other passes) instead of at first use.
    if (mips_ && shaders) {
        mip_program_ = shaders->build_or_throw(program_desc("mip_downsample"));
        prefetching_ = true;
        for (const Draw& d : draws_)
            for (size_t s = 0; s < d.textures.size(); ++s)
                if (d.textures[s] >= 0) texture(d.textures[s], d.srgb[s]);
        prefetching_ = false;
    }
}

void GpuScene::set_material(Draw& d, const Primitive& p) const {
    d.primitive_material = p.material >= 0 ? p.material : static_cast<int>(scene_.materials.size());
    const Material& m = scene_.material(p.material);
    d.alpha_mode = m.alpha_mode;
    d.double_sided = m.double_sided;
    const TextureRef* slots[5] = {&m.base_color_texture, &m.metallic_roughness_texture, &m.normal_texture, &m.occlusion_texture,
                                  &m.emissive_texture};
    for (int s = 0; s < 5; ++s) {
        d.textures[static_cast<size_t>(s)] = slots[s]->image;
        d.srgb[static_cast<size_t>(s)] = s == 0 || s == 4;
        d.samplers[static_cast<size_t>(s)] = slots[s]->sampler;
    }
}

int GpuScene::volume_shape(const Primitive& p) {
    if (p.deformable() || p.vertices.size() < 4 || p.bounds.empty()) return 0;
    const glm::vec3 lo = p.bounds.min, hi = p.bounds.max, ext = hi - lo;
    if (!(std::min({ext.x, ext.y, ext.z}) > 0.0f)) return 0;
    const float eps = 1e-4f * std::max({ext.x, ext.y, ext.z});
    bool box = true;
    for (size_t t = 0; box && t + 2 < p.indices.size(); t += 3) {
        bool on_face = false;
        for (int a = 0; a < 3 && !on_face; ++a) {
            bool at_lo = true, at_hi = true;
            for (int c = 0; c < 3; ++c) {
                const float x = p.vertices[p.indices[t + static_cast<size_t>(c)]].position[a];
                at_lo = at_lo && std::abs(x - lo[a]) <= eps;
                at_hi = at_hi && std::abs(x - hi[a]) <= eps;
            }
            on_face = at_lo || at_hi;
        }
        box = on_face;
    }
    if (box) return 1;
    const glm::vec3 c = 0.5f * (lo + hi), r = 0.5f * ext;
    for (const Vertex& v : p.vertices)
        if (std::abs(glm::length((v.position - c) / r) - 1.0f) > 0.02f) return 0;
    return 2;
}

void GpuScene::refresh_materials() {
    for (Draw& d : draws_) {
        const Node& node = scene_.nodes[static_cast<size_t>(d.node)];
        set_material(d, scene_.meshes[static_cast<size_t>(node.mesh)].primitives[static_cast<size_t>(d.primitive)]);
    }
    ++pose_version_;  // what the renderer re-plans and re-captures on, as for a new pose
    ++material_version_;  // and what it measures the view's light again on
}

float light_cutoff_distance(float peak_intensity, float fraction, int lights) {
    if (!(fraction > 0.0f) || !(peak_intensity > 0.0f)) return 0.0f;
    return std::sqrt(peak_intensity * static_cast<float>(std::max(lights, 1)) / (glm::pi<float>() * fraction * kDisplayQuantum));
}

std::vector<float> unranged_light_cutoffs(const Scene& scene, float fraction) {
    const auto placed = scene.placed_lights();
    const auto unranged = [](const Scene::PlacedLight& pl) { return pl.light->type != LightType::directional && !(pl.light->range > 0.0f); };
    const int cut_lights = static_cast<int>(std::count_if(placed.begin(), placed.end(), unranged));
    std::vector<float> out(placed.size(), 0.0f);
    for (size_t i = 0; i < placed.size(); ++i)
        if (unranged(placed[i])) {
            const glm::vec3 c = placed[i].light->color * placed[i].light->intensity;  // to_gpu's colour
            out[i] = light_cutoff_distance(std::max({c.r, c.g, c.b}), fraction, cut_lights);
        }
    return out;
}

void GpuScene::update_lights(int area_samples, EmitterSplitter split, bool shadows, int cascades, int max_shadowed, float cutoff,
                             int shadow_resolution, double shadow_budget_mb, const glm::vec3* viewer) {
    if (!split) area_samples = 0;
    const std::tuple<int, bool, int, int, float, int, double, bool, glm::vec3> key{
        area_samples, shadows, cascades, max_shadowed, cutoff, shadow_resolution, shadow_budget_mb, viewer != nullptr, viewer ? *viewer : glm::vec3(0.0f)};
    if (key == light_key_) return;
    light_key_ = key;
    std::vector<LightData> lights;
    light_infos_.clear();
    const auto placed = scene_.placed_lights();
    const std::vector<float> cutoffs = unranged_light_cutoffs(scene_, cutoff);
    for (size_t i = 0; i < placed.size(); ++i) {
        const Scene::PlacedLight& pl = placed[i];
        lights.push_back(to_gpu(pl));
        lights.back().cutoff = cutoffs[i];
        LightInfo info;
        info.kind = pl.light->type == LightType::directional ? LightInfo::Kind::directional
                    : pl.light->type == LightType::point     ? LightInfo::Kind::point
                                                             : LightInfo::Kind::spot;
        info.position = pl.position;
        info.direction = pl.direction;
        info.outer_cone = pl.light->outer_cone;
        light_infos_.push_back(info);
    }
    punctual_count_ = static_cast<int>(lights.size());
    const std::vector<AreaPiece> pieces = area_samples > 0 ? split(scene_, *this, area_samples) : std::vector<AreaPiece>{};
    for (const AreaPiece& piece : pieces) {
        LightData d{};
        d.position = piece.centroid;
        d.type = 3.0f;  // LIGHT_AREA_PATCH
        d.direction = piece.normal;
        d.patch_two_sided = piece.double_sided ? 1.0f : 0.0f;
        d.color = piece.power_per_sr;
        d.patch_area = piece.area;
        lights.push_back(d);
        LightInfo info;
        info.kind = LightInfo::Kind::area;
        info.position = piece.centroid;
        info.direction = piece.normal;
        info.size = std::sqrt(piece.area);
        info.own_draw = piece.draw;
        info.double_sided = piece.double_sided;
        light_infos_.push_back(info);
    }
    // The shadow budget: directional lights first, then by what they add to the view (rgb sum of
    // the intensity over the squared distance from the viewer; without one, the brightest). The
    // distance is kept from zero by a thousandth of the scene's size, so it scales with the scene.
    const Bounds wb = scene_.world_bounds();
    const float eps = wb.empty() ? 1e-3f : std::max(1e-3f * glm::length(wb.max - wb.min), 1e-30f);
    auto priority = [&](size_t i) {
        if (light_infos_[i].kind == LightInfo::Kind::directional) return std::numeric_limits<float>::max();
        const float intensity = lights[i].color.r + lights[i].color.g + lights[i].color.b;
        if (!viewer) return intensity;
        const glm::vec3 d = light_infos_[i].position - *viewer;
        return intensity / (glm::dot(d, d) + eps * eps);
    };
    std::vector<size_t> order(lights.size());
    for (size_t i = 0; i < order.size(); ++i) order[i] = i;
    std::stable_sort(order.begin(), order.end(), [&](size_t a, size_t b) { return priority(a) > priority(b); });
    std::vector<ShadowRequest> requests(lights.size());
    for (size_t k = 0; k < order.size() && k < static_cast<size_t>(std::max(max_shadowed, 0)); ++k) {
        const size_t i = order[k];
        const LightInfo& info = light_infos_[i];
        requests[i].views = !shadows ? 0
                            : info.kind == LightInfo::Kind::directional ? cascades
                            : info.kind == LightInfo::Kind::spot        ? 1
                                                                        : 6;
        requests[i].priority = priority(i);
    }
    // The layers the budget and the context allow.
    GLint max_layers = 256;
    glGetIntegerv(GL_MAX_ARRAY_TEXTURE_LAYERS, &max_layers);
    const double budget_layers = std::floor(shadow_budget_mb * 1024.0 * 1024.0 / shadow_layer_bytes(shadow_resolution));
    const int layers = static_cast<int>(std::clamp(budget_layers, 1.0, static_cast<double>(std::max(max_layers, 1))));
    shadow_atlas_ = allocate_shadow_atlas(requests, shadow_resolution, layers);
    for (size_t i = 0; i < lights.size(); ++i) {
        LightInfo& info = light_infos_[i];
        info.first_view = shadow_atlas_.first_view[i];
        info.view_count = info.first_view >= 0 ? requests[i].views : 0;
        lights[i].first_shadow_view = static_cast<float>(info.first_view);
        lights[i].shadow_view_count = static_cast<float>(info.view_count);
    }
    light_count_ = static_cast<int>(lights.size());
    if (lights.empty()) lights.push_back(LightData{});
    lights_ = gl::Buffer(static_cast<GLsizeiptr>(lights.size() * sizeof(LightData)), lights.data());
}

const gl::Texture& GpuScene::image_array() const {
    if (image_array_) return image_array_;
    int side = 1;
    for (const Image& img : scene_.images)
        if (img.valid) side = std::max({side, img.width, img.height});
    side = std::min(side, 2048);
    const int layers = std::max<int>(1, static_cast<int>(scene_.images.size()));
    GLuint id = 0;
    glCreateTextures(GL_TEXTURE_2D_ARRAY, 1, &id);
    // One level: the tracer reads level 0 only (texelFetch and textureLod 0 in shaders/rt/scene.glsl),
    // and mipmaps cost 60-110 ms of FlightHelmet's load for nothing.
    glTextureStorage3D(id, 1, GL_RGBA8, side, side, layers);
    std::vector<std::uint8_t> layer(static_cast<size_t>(side) * static_cast<size_t>(side) * 4, 255);
    std::vector<size_t> column(static_cast<size_t>(side));
    for (size_t i = 0; i < scene_.images.size(); ++i) {
        const Image& img = scene_.images[i];
        const std::uint8_t* pixels = layer.data();
        if (img.valid && img.width == side && img.height == side) {
            pixels = img.rgba8.data();  // already the common size (FlightHelmet: every image): as it is
        } else if (img.valid) {
            // Nearest-neighbour resampling to the common size (exact when sizes divide evenly):
            // texel (x, y) takes source texel (x w / side, y h / side).
            for (int x = 0; x < side; ++x)
                column[static_cast<size_t>(x)] = static_cast<size_t>(x) * static_cast<size_t>(img.width) / static_cast<size_t>(side);
            for (int y = 0; y < side; ++y) {
                const size_t sy = static_cast<size_t>(y) * static_cast<size_t>(img.height) / static_cast<size_t>(side);
                const std::uint8_t* src = &img.rgba8[sy * static_cast<size_t>(img.width) * 4];
                std::uint8_t* dst = &layer[static_cast<size_t>(y) * static_cast<size_t>(side) * 4];
                for (int x = 0; x < side; ++x) std::memcpy(dst + static_cast<size_t>(x) * 4, src + column[static_cast<size_t>(x)] * 4, 4);
            }
        } else {
            std::fill(layer.begin(), layer.end(), std::uint8_t{255});  // missing: white, as before
        }
        glTextureSubImage3D(id, 0, 0, 0, static_cast<GLint>(i), side, side, 1, GL_RGBA, GL_UNSIGNED_BYTE, pixels);
    }
    glTextureParameteri(id, GL_TEXTURE_MIN_FILTER, GL_LINEAR);
    glTextureParameteri(id, GL_TEXTURE_WRAP_S, GL_REPEAT);
    glTextureParameteri(id, GL_TEXTURE_WRAP_T, GL_REPEAT);
    image_array_ = gl::Texture::adopt(id, side, side, GL_RGBA8);
    return image_array_;
}

const gl::Texture& GpuScene::image_array_srgb() const {
    if (image_array_srgb_) return image_array_srgb_;
    const gl::Texture& linear = image_array();
    GLint levels = 0, layers = 0;
    glGetTextureParameteriv(linear.id(), GL_TEXTURE_IMMUTABLE_LEVELS, &levels);
    glGetTextureLevelParameteriv(linear.id(), 0, GL_TEXTURE_DEPTH, &layers);
    GLuint id = 0;
    glGenTextures(1, &id);  // a view needs a name that has never been bound
    glTextureView(id, GL_TEXTURE_2D_ARRAY, linear.id(), GL_SRGB8_ALPHA8, 0, static_cast<GLuint>(levels), 0,
                  static_cast<GLuint>(layers));
    glTextureParameteri(id, GL_TEXTURE_MIN_FILTER, GL_LINEAR);
    glTextureParameteri(id, GL_TEXTURE_WRAP_S, GL_REPEAT);
    glTextureParameteri(id, GL_TEXTURE_WRAP_T, GL_REPEAT);
    image_array_srgb_ = gl::Texture::adopt(id, linear.width(), linear.height(), GL_SRGB8_ALPHA8);
    return image_array_srgb_;
}

const gl::Texture& GpuScene::texture(int image, bool srgb) {
    if (image < 0 || image >= static_cast<int>(scene_.images.size())) return white_;
    auto key = std::make_pair(image, srgb);
    auto it = textures_.find(key);
    if (it != textures_.end()) {
        auto pending = prefetching_ ? pending_.textures.end() : pending_.textures.find(key);
        if (pending != pending_.textures.end()) {
            GlWorker::Ticket ticket = std::move(pending->second);
            pending_.textures.erase(pending);
            GlWorker::wait(ticket);
        }
        return it->second;
    }
    const Image& img = scene_.images[static_cast<size_t>(image)];
    if (!img.valid) return white_;
    gl::Texture tex = gl::Texture::create_2d(srgb ? GL_SRGB8_ALPHA8 : GL_RGBA8, img.width, img.height, 0);
    glTextureSubImage2D(tex.id(), 0, 0, 0, img.width, img.height, GL_RGBA, GL_UNSIGNED_BYTE, img.rgba8.data());
    // From the constructor's prefetch: queued; texture() waits for it at the first draw.
    // gl::draw_mipmaps, not glGenerateTextureMipmap: the same texels, without holding Mesa's
    // texture mutex (which this thread's draws need), and without a blit shader compiled anew.
    if (prefetching_) {
        const int levels = gl::full_mip_levels(img.width, img.height);
        const GLenum format = srgb ? GL_SRGB8_ALPHA8 : GL_RGBA8;
        pending_.textures[key] = mips_->submit([program = mip_program_.id(), id = tex.id(), format, w = img.width, h = img.height, levels] {
            gl::draw_mipmaps(program, id, format, w, h, levels);
        });
    }
    else glGenerateTextureMipmap(tex.id());
    return textures_.emplace(key, std::move(tex)).first->second;
}

const gl::Sampler& GpuScene::sampler(const SamplerDesc& d) {
    auto key = std::make_tuple(d.min_filter, d.mag_filter, d.wrap_s, d.wrap_t);
    auto it = samplers_.find(key);
    if (it != samplers_.end()) return it->second;
    auto valid = [](int v, std::initializer_list<int> ok, int fallback) {
        for (int o : ok)
            if (o == v) return static_cast<GLenum>(v);
        return static_cast<GLenum>(fallback);
    };
    const GLenum min = valid(d.min_filter, {GL_NEAREST, GL_LINEAR, GL_NEAREST_MIPMAP_NEAREST, GL_LINEAR_MIPMAP_NEAREST,
                                            GL_NEAREST_MIPMAP_LINEAR, GL_LINEAR_MIPMAP_LINEAR}, GL_LINEAR_MIPMAP_LINEAR);
    const GLenum mag = valid(d.mag_filter, {GL_NEAREST, GL_LINEAR}, GL_LINEAR);
    const GLenum ws = valid(d.wrap_s, {GL_REPEAT, GL_CLAMP_TO_EDGE, GL_MIRRORED_REPEAT}, GL_REPEAT);
    const GLenum wt = valid(d.wrap_t, {GL_REPEAT, GL_CLAMP_TO_EDGE, GL_MIRRORED_REPEAT}, GL_REPEAT);
    return samplers_.emplace(key, gl::Sampler::create(min, mag, ws, wt)).first->second;
}


namespace {
Bounds transformed(const Bounds& b, const glm::mat4& m) {
    Bounds out;
    if (b.empty()) return out;
    for (int corner = 0; corner < 8; ++corner)
        out.extend(glm::vec3(m * glm::vec4(corner & 1 ? b.max.x : b.min.x, corner & 2 ? b.max.y : b.min.y, corner & 4 ? b.max.z : b.min.z, 1.0f)));
    return out;
}
}  // namespace

bool GpuScene::update_pose() {
    bool changed = false;
    for (size_t mi = 0; mi < scene_.meshes.size() && mi < ranges_.size(); ++mi)
        for (size_t pi = 0; pi < scene_.meshes[mi].primitives.size() && pi < ranges_[mi].size(); ++pi) {
            const Primitive& p = scene_.meshes[mi].primitives[pi];
            if (!p.deformable() || p.vertices.empty()) continue;
            // A pose that leaves the vertices as they were (an animation holding still, the same
            // time again) changes nothing: the captures and caches that follow pose_version stay.
            std::vector<Vertex>& last = uploaded_vertices_[mi][pi];
            if (last.size() == p.vertices.size() && std::memcmp(last.data(), p.vertices.data(), p.vertices.size() * sizeof(Vertex)) == 0)
                continue;
            last = p.vertices;
            vertices_.update(static_cast<GLintptr>(static_cast<size_t>(ranges_[mi][pi].base_vertex) * sizeof(Vertex)),
                             static_cast<GLsizeiptr>(p.vertices.size() * sizeof(Vertex)), p.vertices.data());
            changed = true;
        }
    for (Draw& d : draws_) {
        const Node& node = scene_.nodes[static_cast<size_t>(d.node)];
        const Primitive& p = scene_.meshes[static_cast<size_t>(node.mesh)].primitives[static_cast<size_t>(d.primitive)];
        if (node.world != d.model) changed = true;
        d.model = node.world;
        d.normal_matrix = glm::inverseTranspose(glm::mat3(node.world));
        d.mirrored = node.mirrored();
        d.world_bounds = transformed(p.bounds, node.world);
        if (!has_motion_) d.model_open = d.model_close = d.model;
    }
    // Lights on animated nodes and moving emitters: rebuild the light buffer at the next update_lights.
    if (changed) {
        std::get<0>(light_key_) = -1;
        ++pose_version_;
    }
    return changed;
}

void GpuScene::clear_motion() {
    has_motion_ = false;
    for (Draw& d : draws_) {
        d.model_open = d.model_close = d.model;
        d.moves = false;
    }
}

void GpuScene::set_motion(const Pose& open, const Pose& close) {
    // Object-space positions at open and close for every vertex of the main vertex buffer:
    // deformed primitives from the poses, rigid ones from the scene (they do not change).
    std::vector<glm::vec4> motion(std::max<size_t>(vertex_count_, 1) * 2, glm::vec4(0.0f));
    std::vector<std::vector<bool>> deforms(scene_.meshes.size());
    for (size_t mi = 0; mi < scene_.meshes.size() && mi < ranges_.size(); ++mi) {
        deforms[mi].assign(scene_.meshes[mi].primitives.size(), false);
        for (size_t pi = 0; pi < scene_.meshes[mi].primitives.size() && pi < ranges_[mi].size(); ++pi) {
            const Primitive& p = scene_.meshes[mi].primitives[pi];
            const size_t base = static_cast<size_t>(ranges_[mi][pi].base_vertex);
            auto from = [&](const Pose& pose, size_t v) {
                if (mi < pose.vertices.size() && pi < pose.vertices[mi].size() && pose.vertices[mi][pi].size() == p.vertices.size())
                    return pose.vertices[mi][pi][v].position;
                return p.vertices[v].position;
            };
            for (size_t v = 0; v < p.vertices.size(); ++v) {
                const glm::vec3 a = from(open, v), b = from(close, v);
                motion[2 * (base + v)] = glm::vec4(a, 1.0f);
                motion[2 * (base + v) + 1] = glm::vec4(b, 1.0f);
                if (a != b) deforms[mi][pi] = true;
            }
        }
    }
    has_motion_ = false;
    for (Draw& d : draws_) {
        const size_t ni = static_cast<size_t>(d.node);
        d.model_open = ni < open.world.size() ? open.world[ni] : d.model;
        d.model_close = ni < close.world.size() ? close.world[ni] : d.model;
        const int mesh = scene_.nodes[ni].mesh;
        d.moves = d.model_open != d.model_close || deforms[static_cast<size_t>(mesh)][static_cast<size_t>(d.primitive)];
        has_motion_ = has_motion_ || d.moves;
    }
    const GLsizeiptr bytes = static_cast<GLsizeiptr>(motion.size() * sizeof(glm::vec4));
    if (!motion_ || motion_.size() != bytes) {
        motion_ = gl::Buffer(bytes, motion.data(), GL_DYNAMIC_STORAGE_BIT);
        motion_vao_ = gl::VertexArray::create();
        glVertexArrayVertexBuffer(motion_vao_.id(), 0, vertices_.id(), 0, sizeof(Vertex));
        glVertexArrayVertexBuffer(motion_vao_.id(), 1, motion_.id(), 0, 2 * sizeof(glm::vec4));
        glVertexArrayElementBuffer(motion_vao_.id(), indices_.id());
        const struct { GLuint loc, binding, offset; } attribs[] = {
            {0, 0, offsetof(Vertex, position)}, {1, 1, 0}, {2, 1, sizeof(glm::vec4)}};
        for (const auto& a : attribs) {
            glEnableVertexArrayAttrib(motion_vao_.id(), a.loc);
            glVertexArrayAttribFormat(motion_vao_.id(), a.loc, 3, GL_FLOAT, GL_FALSE, a.offset);
            glVertexArrayAttribBinding(motion_vao_.id(), a.loc, a.binding);
        }
    } else {
        motion_.update(0, bytes, motion.data());
    }
}

}  // namespace candela
