#include "effects/area_lights/area_lights.hpp"

#include <algorithm>
#include <array>
#include <cmath>
#include <cstdio>
#include <cstring>
#include <map>
#include <unordered_map>

#include <nlohmann/json.hpp>

#include "effects/area_lights/area_lights_data.h"
#include "effects/area_lights/area_lights_sweep.hpp"
#include "effects/area_lights/ltc.hpp"
#include "effects/area_lights/ltc_table.hpp"
#include "render/features.hpp"
#include "core/error.hpp"
#include "render/gpu_scene.hpp"
#include "rt/view_light.hpp"
#include "scene/features.hpp"
#include "scene/scene.hpp"

namespace candela {
namespace {

float srgb_to_linear(float c) { return c <= 0.04045f ? c / 12.92f : std::pow((c + 0.055f) / 1.055f, 2.4f); }

// The emissive texture's mean over a triangle: 16 points (the centroids of a 4x4 barycentric
// subdivision), nearest texel, repeat wrapping, sRGB decoded. 1 without a (valid) texture.
glm::vec3 emissive_texture_average(const Scene& scene, const Material& m, const Primitive& prim, size_t tri) {
    const TextureRef& t = m.emissive_texture;
    if (!t.present() || t.image >= static_cast<int>(scene.images.size())) return glm::vec3(1.0f);
    const Image& img = scene.images[static_cast<size_t>(t.image)];
    if (!img.valid || img.width < 1 || img.height < 1) return glm::vec3(1.0f);
    glm::vec2 uv[3];
    for (int c = 0; c < 3; ++c) {
        const Vertex& v = prim.vertices[prim.indices[tri * 3 + static_cast<size_t>(c)]];
        uv[c] = glm::vec2(t.transform * glm::vec3(t.texcoord == 1 ? v.uv1 : v.uv0, 1.0f));
    }
    constexpr int k = 4;
    glm::vec3 sum(0.0f);
    int count = 0;
    for (int i = 0; i < k; ++i)
        for (int j = 0; j < k - i; ++j)
            for (int inverted = 0; inverted < (j < k - i - 1 ? 2 : 1); ++inverted) {
                const float a = (static_cast<float>(i) + (inverted ? 2.0f : 1.0f) / 3.0f) / k;
                const float b = (static_cast<float>(j) + (inverted ? 2.0f : 1.0f) / 3.0f) / k;
                const glm::vec2 q = uv[0] + a * (uv[1] - uv[0]) + b * (uv[2] - uv[0]);
                const float fx = q.x - std::floor(q.x), fy = q.y - std::floor(q.y);
                const int x = std::min(img.width - 1, static_cast<int>(fx * static_cast<float>(img.width)));
                const int y = std::min(img.height - 1, static_cast<int>(fy * static_cast<float>(img.height)));
                const std::uint8_t* px = &img.rgba8[(static_cast<size_t>(y) * static_cast<size_t>(img.width) + static_cast<size_t>(x)) * 4];
                sum += glm::vec3(srgb_to_linear(px[0] / 255.0f), srgb_to_linear(px[1] / 255.0f), srgb_to_linear(px[2] / 255.0f));
                ++count;
            }
    return sum / static_cast<float>(count);
}

// Two triangles of one emitter that share an edge (walked in opposite directions), lie in one
// plane, have the same radiance and together form a convex quad are one polygon to the LTC
// integral: the integral over the union is the sum of the two integrals, and the quad has four
// edges where the pair had six (and one horizon edge where they had two). `shared` is the corner
// of A that starts the shared edge, `b_third` B's corner off it. False when the pair does not
// qualify; else `out` is the quad in A's winding order.
bool merge_into_quad(const PolygonLightGpu& A, const PolygonLightGpu& B, int shared, int b_third, PolygonLightGpu& out) {
    const glm::vec3 a[3] = {A.p0, A.p1, A.p2}, b[3] = {B.p0, B.p1, B.p2};
    for (int c = 0; c < 3; ++c)
        if (std::abs(A.radiance[c] - B.radiance[c]) > 1e-4f * std::max(A.radiance[c], B.radiance[c])) return false;
    // A = (x, y, z) with the shared edge x -> y; B = (y, x, w): the union is x, w, y, z.
    const glm::vec3 x = a[shared], y = a[(shared + 1) % 3], z = a[(shared + 2) % 3], w = b[b_third];
    const glm::vec3 n = glm::cross(y - x, z - x);
    const float n_len = glm::length(n);
    const float scale = std::max({glm::length(y - x), glm::length(z - x), glm::length(w - x)});
    if (!(n_len > 0.0f) || !(scale > 0.0f)) return false;
    if (std::abs(glm::dot(n / n_len, w - x)) > 1e-5f * scale) return false;  // not coplanar
    const glm::vec3 q[4] = {x, w, y, z};
    for (int k = 0; k < 4; ++k)  // convex: every corner turns the way of the normal
        if (!(glm::dot(glm::cross(q[(k + 1) % 4] - q[k], q[(k + 2) % 4] - q[(k + 1) % 4]), n) > 1e-12f * n_len * scale)) return false;
    out = A;
    out.p0 = x;
    out.p1 = w;
    out.p2 = y;
    out.p3 = z;
    out.corners = 4.0f;
    return true;
}

// Pairs of one emitter's triangles merged into quads where merge_into_quad allows; the others stay.
std::vector<PolygonLightGpu> merge_coplanar_pairs(const std::vector<PolygonLightGpu>& tris) {
    // Directed edge (from, to), by the bits of its corners' coordinates -> triangle index.
    using Key = std::array<std::uint32_t, 6>;
    struct KeyHash {
        size_t operator()(const Key& k) const {
            size_t h = 1469598103934665603ull;
            for (std::uint32_t v : k) h = (h ^ v) * 1099511628211ull;
            return h;
        }
    };
    const auto key = [](const glm::vec3& from, const glm::vec3& to) {
        Key k;
        std::memcpy(k.data(), &from, sizeof from);
        std::memcpy(k.data() + 3, &to, sizeof to);
        return k;
    };
    std::unordered_map<Key, size_t, KeyHash> open_edges;
    std::vector<bool> used(tris.size(), false);
    std::vector<PolygonLightGpu> out;
    for (size_t i = 0; i < tris.size(); ++i) {
        const glm::vec3 a[3] = {tris[i].p0, tris[i].p1, tris[i].p2};
        bool merged = false;
        for (int e = 0; e < 3 && !merged; ++e) {
            const auto it = open_edges.find(key(a[(e + 1) % 3], a[e]));  // the same edge, the other way
            if (it == open_edges.end() || used[it->second]) continue;
            const PolygonLightGpu& other = tris[it->second];
            const glm::vec3 b[3] = {other.p0, other.p1, other.p2};
            int third = 0;
            while (third < 3 && (b[third] == a[e] || b[third] == a[(e + 1) % 3])) ++third;
            PolygonLightGpu quad{};
            if (third < 3 && merge_into_quad(tris[i], other, e, third, quad)) {
                used[it->second] = used[i] = true;
                out.push_back(quad);
                merged = true;
            }
        }
        if (!merged)
            for (int e = 0; e < 3; ++e) open_edges.emplace(key(a[e], a[(e + 1) % 3]), i);
    }
    for (size_t i = 0; i < tris.size(); ++i)
        if (!used[i]) out.push_back(tris[i]);
    return out;
}


// Emitters whose share of the direct light on the view's surfaces is at least this stay lights,
// whatever the display difference: a quarter of the random-scene suite's 8 % promise on the
// image's mean.
constexpr double kNegligibleShare = 0.02;

// The most emissive triangles shaded as LTC polygons; more: the pieces shade (see prepare).
constexpr int kMaxPolygons = 64;

class AreaLightsRuntime final : public EffectRuntime {
public:
    void prepare(const FramePrep& p) override {
        const AreaLightsOptions& o = p.settings.get<AreaLightsOptions>();
        gpu::AreaLightsData d{};
        d.method = o.method == AreaLightMethod::ltc ? 1 : 0;
        d.ltc_size = ltc::kTableSize;
        d.residual = o.residual ? 1 : 0;
        d.far_field = o.far_field;
        if (!p.decision.planned) {
            d.method = 0;  // emission only: no piece in the light buffer, no polygon
        } else if (d.method == 1) {
            // Built again when the emitters move (an animated emitter, the scene's origin moved).
            if (built_for_ != &p.gpu || built_samples_ != o.samples || built_pose_ != p.gpu.pose_version()) {
                const std::vector<PolygonLightGpu> polys = polygon_lights(p.gpu.scene(), p.gpu, o.samples);
                polygon_count_ = static_cast<int>(polys.size());
                const PolygonLightGpu none{};
                polygons_ = gl::Buffer(static_cast<GLsizeiptr>(std::max<size_t>(polys.size(), 1) * sizeof(PolygonLightGpu)),
                                       polys.empty() ? &none : polys.data());
                built_for_ = &p.gpu;
                built_samples_ = o.samples;
                built_pose_ = p.gpu.pose_version();
            }
            if (!ltc_matrix_) upload_tables();
            d.polygon_count = polygon_count_;
            // Every pixel integrates every polygon: beyond kMaxPolygons emissive triangles the
            // pieces shade instead (a mesh with thousands of emissive triangles would take
            // minutes per frame on llvmpipe).
            if (polygon_count_ > kMaxPolygons) d.method = 0;
        }
        if (!block_) block_ = gl::Buffer(sizeof d, nullptr, GL_DYNAMIC_STORAGE_BIT);
        block_.update(0, sizeof d, &d);
        method_ = d.method;
        // No polygon to integrate: the lighting leaves the LTC code out.
        defines_.clear();
        if (d.method != 1 || d.polygon_count <= 0) defines_.push_back("AREA_LIGHTS_OFF");
    }
    std::vector<std::string> shading_defines() const override { return defines_; }
    void bind_shading_inputs(const PassEnv&, FrameGraph::Context*) const override {
        glBindBufferBase(GL_UNIFORM_BUFFER, AREA_LIGHTS_BINDING, block_.id());
        if (method_ != 1) return;
        glBindBufferBase(GL_SHADER_STORAGE_BUFFER, AREA_POLYGONS_BINDING, polygons_.id());
        gl::bind_texture_unit(LTC_MATRIX_UNIT, ltc_matrix_);
        gl::bind_texture_unit(LTC_AMPLITUDE_UNIT, ltc_amplitude_);
    }
    void inspectables(std::vector<std::pair<std::string, const gl::Texture*>>& out) const override {
        if (ltc_matrix_) {
            out.emplace_back("ltc_matrix", &ltc_matrix_);
            out.emplace_back("ltc_amplitude", &ltc_amplitude_);
        }
    }

private:
    // The fitted table (ltc_table.inc) as two linearly filtered textures, row j = view angle.
    void upload_tables() {
        const int n = ltc::kTableSize;
        const std::vector<glm::vec4> m = ltc::table_matrices();
        const std::vector<glm::vec2> a = ltc::table_amplitudes();
        ltc_matrix_ = gl::Texture::create_2d(GL_RGBA32F, n, n, 1);
        glTextureSubImage2D(ltc_matrix_.id(), 0, 0, 0, n, n, GL_RGBA, GL_FLOAT, m.data());
        ltc_amplitude_ = gl::Texture::create_2d(GL_RG32F, n, n, 1);
        glTextureSubImage2D(ltc_amplitude_.id(), 0, 0, 0, n, n, GL_RG, GL_FLOAT, a.data());
        for (const gl::Texture* t : {&ltc_matrix_, &ltc_amplitude_}) {
            glTextureParameteri(t->id(), GL_TEXTURE_MIN_FILTER, GL_LINEAR);
            glTextureParameteri(t->id(), GL_TEXTURE_MAG_FILTER, GL_LINEAR);
            glTextureParameteri(t->id(), GL_TEXTURE_WRAP_S, GL_CLAMP_TO_EDGE);
            glTextureParameteri(t->id(), GL_TEXTURE_WRAP_T, GL_CLAMP_TO_EDGE);
        }
    }
    gl::Buffer block_, polygons_;
    gl::Texture ltc_matrix_, ltc_amplitude_;
    const GpuScene* built_for_ = nullptr;
    int built_samples_ = -1;
    std::uint64_t built_pose_ = 0;
    int polygon_count_ = 0;
    int method_ = 0;
    std::vector<std::string> defines_;  // shading_defines: from the block
};

class AreaLights final : public Effect {
public:
    const char* name() const override { return "area_lights"; }
    bool switchable() const override { return false; }
    std::any default_options() const override { return AreaLightsOptions{}; }
    std::vector<Knob> knobs() const override {
        return KnobRows<AreaLightsOptions>("arealight", [](RenderSettings& s) -> AreaLightsOptions& { return s.get<AreaLightsOptions>(); })
            .integer("samples", &AreaLightsOptions::samples, 1, 64,
                     "pieces per emissive mesh: its shadow maps (ltc) or its Lambertian point lights (pieces)")
            .choice("method", &AreaLightsOptions::method, kAreaLightMethods,
                    "ltc: emissive triangles as polygon lights (exact unshadowed, LTC specular), pieces: point lights")
            .boolean("residual", &AreaLightsOptions::residual,
                     "ltc: add the specular the fitted lobe misses (tails, grazing views), measured on 3x3 cells of each polygon")
            .real("far_field", &AreaLightsOptions::far_field, 0.0f, 64.0f,
                  "ltc: polygons farther than this many of their radii (and narrower than the specular lobe) shade as points; "
                  "0: all by LTC")
            .real("negligible", &AreaLightsOptions::negligible, 0.0f, 1.0f,
                  "emitters whose measured light changes the display by less (99th percentile of 4x4 blocks) are emission only; "
                  "0: always lights")
            .rows;
    }
    std::vector<std::string> knob_groups() const override { return {"arealight"}; }
    // The planner measures the emitters' light unless arealight.negligible is 0.
    const char* view_estimate(const RenderSettings& s) const override {
        return s.get<AreaLightsOptions>().negligible > 0.0f ? "emitter light" : nullptr;
    }
    ViewEstimate estimate_view(const ViewEstimateInput& in) const override {
        if (analyze_features(in.scene).emissive_primitives == 0) return {std::any(), "none: no emissive material"};  // nothing to measure
        try {
            const EmitterLight e = measure_emitter_light(in.shaders, in.scene, in.gpu, in.camera, in.aspect, 16, kViewLightPixels,
                                                         in.tracer_scene);
            return {e, e.text()};
        } catch (const Error& error) {
            if (error.code() == ExitCode::internal) throw;
            return {std::any(), std::string("not measured (") + error.what() + "): the emitters stay lights"};
        }
    }
    void estimate_json(const ViewEstimate& v, nlohmann::json& j) const override {
        if (const auto* e = std::any_cast<EmitterLight>(&v.value))
            j["emitter_light"] = {{"display_p99", e->display_p99}, {"display_mean", e->display_mean}, {"share", e->share},
                                  {"ms", e->ms}, {"width", e->width}, {"height", e->height}, {"spp", e->spp}};
    }
    EffectDecision decide(const Features& f, const RenderSettings& s) const override {
        const Feature& emitters = f.scene.emissive_area_lights;
        const float negligible = s.get<AreaLightsOptions>().negligible;
        const ViewEstimate* v = f.estimate(name());
        const EmitterLight* e = v ? std::any_cast<EmitterLight>(&v->value) : nullptr;
        if (!emitters.needed || negligible <= 0.0f || !e)
            return decide_effect(name(), true, emitters.needed,
                                 emitters.reason + (!emitters.needed     ? ""
                                                    : negligible <= 0.0f ? "; arealight.negligible=0: always lights"
                                                                         : "; their light is not measured (no tracer): lights"),
                                 s.gating);
        char limit[128];
        std::snprintf(limit, sizeof limit, " arealight.negligible %.4f or %.0f %% of the light", static_cast<double>(negligible),
                      kNegligibleShare * 100.0);
        // Both measures must be small: the display difference at exposure 0, and the emitters'
        // share of the light, which no exposure changes (a dark scene lit by its emitters alone is
        // black at exposure 0, and its user raises the exposure).
        // Always gated, as GI: emitters whose light is small but not zero would change the image
        // if render.gating=off forced them to be lights.
        const bool needed = e->display_p99 >= negligible || e->share >= kNegligibleShare;
        return decide_effect(name(), true, needed,
                             needed ? emitters.reason + ": " + e->text() + ", at least" + limit
                                    : "emitters drawn as emission only: " + e->text() + ", below" + limit,
                             true);
    }
    void plan(Stage, const Features&, const RenderSettings&, std::vector<PlannedPass>&) const override {}
    // The pieces are in the light buffer while the emitters are lights (none without emitters).
    void light_setup(const RenderSettings& s, const EffectDecision& d, LightSetup& out) const override {
        out.area_samples = d.planned ? s.get<AreaLightsOptions>().samples : 0;
        out.split_emitters = &area_light_pieces;
    }
    std::vector<GpuBlockInfo> gpu_blocks() const override {
        return {{"AreaLightsData", AREA_LIGHTS_BINDING, sizeof(gpu::AreaLightsData), "forward"}};
    }
    const char* shading_include() const override { return "effects/area_lights/area_lights_shading.glsl"; }
    std::vector<ShadingHook> shading_hooks() const override { return {ShadingHook::direct_light, ShadingHook::shaded_light_count}; }
    std::unique_ptr<EffectRuntime> create_runtime() const override { return std::make_unique<AreaLightsRuntime>(); }
    std::vector<AccuracySweep> accuracy_sweeps(bool quick) const override { return area_lights_accuracy_sweeps(quick); }
};

}  // namespace

std::vector<PolygonLightGpu> polygon_lights(const Scene& scene, const GpuScene& gpu, int samples) {
    // Each emissive draw's pieces, in the light buffer's order: punctual lights, then the pieces.
    std::map<int, std::pair<int, int>> pieces_of;  // draw -> (first light index, count)
    const std::vector<AreaPiece> pieces = area_light_pieces(scene, gpu, samples);
    for (size_t k = 0; k < pieces.size(); ++k) {
        auto [it, fresh] = pieces_of.try_emplace(pieces[k].draw, gpu.punctual_light_count() + static_cast<int>(k), 0);
        ++it->second.second;
    }
    std::vector<PolygonLightGpu> out;
    const auto& draws = gpu.draws();
    for (const auto& [di, range] : pieces_of) {
        const GpuScene::Draw& d = draws[static_cast<size_t>(di)];
        const Node& node = scene.nodes[static_cast<size_t>(d.node)];
        const Primitive& prim = scene.meshes[static_cast<size_t>(node.mesh)].primitives[static_cast<size_t>(d.primitive)];
        const Material& m = scene.material(prim.material);
        std::vector<PolygonLightGpu> tris;
        for (size_t t = 0; t < prim.triangle_count(); ++t) {
            glm::vec3 p[3];
            for (int c = 0; c < 3; ++c)
                p[c] = glm::vec3(d.model * glm::vec4(prim.vertices[prim.indices[t * 3 + static_cast<size_t>(c)]].position, 1.0f));
            if (d.mirrored) std::swap(p[1], p[2]);  // a mirroring transform reverses the winding
            const float area2 = glm::length(glm::cross(p[1] - p[0], p[2] - p[0]));
            if (!(area2 > 0.0f) || !std::isfinite(area2)) continue;
            const glm::vec3 radiance = m.emission() * emissive_texture_average(scene, m, prim, t);
            if (!(radiance.r + radiance.g + radiance.b > 0.0f)) continue;
            PolygonLightGpu g{};
            g.p0 = p[0];
            g.double_sided = m.double_sided ? 1.0f : 0.0f;
            g.p1 = p[1];
            g.first_piece = static_cast<float>(range.first);
            g.p2 = p[2];
            g.piece_count = static_cast<float>(range.second);
            g.radiance = radiance;
            g.corners = 3.0f;
            g.p3 = p[0];
            tris.push_back(g);
        }
        for (const PolygonLightGpu& g : merge_coplanar_pairs(tris)) out.push_back(g);
    }
    return out;
}

const Effect& area_lights_effect() {
    static const AreaLights effect;
    return effect;
}

}  // namespace candela
