#include "rt/view_light.hpp"

#include <algorithm>
#include <chrono>
#include <cmath>
#include <cstdio>
#include <vector>

#include <glm/glm.hpp>

#include "image/image.hpp"
#include "rt/ray_tracer.hpp"

namespace candela {

std::string ViewLight::text() const {
    char buf[480];
    std::snprintf(buf, sizeof buf,
                  "%dx%d px x %d spp: %.0f %% passive surface, %.0f %% emitter, %.0f %% background; %d surface px, %d lit, "
                  "%.0f %% unlit, %.0f %% open to the sky; first bounce / direct %.3f +- %.3f, each later bounce x %.3f, indirect "
                  "%.0f %%; %.0f ms",
                  width, height, spp, passive_share * 100.0, emitter_share * 100.0, background_share * 100.0, surface_pixels,
                  lit_pixels, unlit_share * 100.0, sky_visibility * 100.0, ratio, ratio_stderr, per_bounce, indirect_share * 100.0, ms);
    return buf;
}

double scattering_albedo_bound(const Scene& scene) {
    // A material's albedo bound: a metal's base colour; a dielectric's diffuse (its base colour,
    // less what it transmits) plus its specular lobe's hemispherical mean (Fresnel of ior 1.5:
    // about 0.09; 0.1, times KHR_materials_specular's factor, and its colour where that exceeds
    // 1: a bound, so never less). What glass transmits passes light on without scattering it,
    // and is not counted.
    double bound = 0.0;
    for (const Material& m : scene.materials) {
        const glm::vec3 c = glm::vec3(m.base_color);
        const double base = std::max({c.r, c.g, c.b});
        const double spec = 0.1 * m.specular_factor * std::max({m.specular_color.r, m.specular_color.g, m.specular_color.b, 1.0f});
        const double dielectric = base * (1.0 - std::clamp(static_cast<double>(m.transmission), 0.0, 1.0)) + spec;
        const double metallic = std::clamp(static_cast<double>(m.metallic), 0.0, 1.0);
        bound = std::max(bound, std::min(1.0, metallic * base + (1.0 - metallic) * dielectric));
    }
    for (const Mesh& mesh : scene.meshes)
        for (const Primitive& p : mesh.primitives)
            if (p.material < 0 || p.material >= static_cast<int>(scene.materials.size())) bound = 1.0;  // the default material: white
    return bound;
}

namespace {
// About `pixels` pixels at the aspect (clamped to 1/16..16; 1 when not finite), at least 4 each way.
glm::ivec2 measurement_size(float aspect, int pixels) {
    const double a = std::isfinite(aspect) && aspect > 0.0f ? std::clamp(static_cast<double>(aspect), 1.0 / 16.0, 16.0) : 1.0;
    const double target = std::max(16, pixels);
    const int width = std::max(4, static_cast<int>(std::lround(std::sqrt(target * a))));
    return {width, std::max(4, static_cast<int>(std::lround(target / static_cast<double>(width))))};
}
// Sets a measurement's size (measurement_size) and sample count; returns the size.
template <class Measurement>
glm::ivec2 size_measurement(Measurement& m, float aspect, int pixels, int spp) {
    const glm::ivec2 size = measurement_size(aspect, pixels);
    m.width = size.x;
    m.height = size.y;
    m.spp = spp;
    return size;
}

// The options of the planner's `direct` renders of `size`: the light the seen surfaces reflect,
// without what the camera sees itself and without the highlights on glass (ray_tracer.hpp: a
// highlight does not light the glass).
rt::Options seen_surfaces_direct(glm::ivec2 size, int spp) {
    rt::Options o;
    o.mode = rt::Mode::direct;
    o.spp = std::max(1, spp);
    o.tile_rows = size.y;
    o.camera_sees_emission = false;
    o.dielectric_highlights = false;
    return o;
}
}  // namespace

ViewLight measure_view_light(const ShaderLibrary& shaders, const Scene& scene, GpuScene& gpu, const Camera& camera, float aspect,
                             int spp, int pixels, std::shared_ptr<rt::RtScene>* shared) {
    const auto t0 = std::chrono::steady_clock::now();
    ViewLight v;
    const glm::ivec2 size = size_measurement(v, aspect, pixels, spp);
    rt::Options o = seen_surfaces_direct(size, spp);
    // Sky visibility: AO rays that leave the scene's bounds are open to the sky.
    const Bounds bounds = scene.world_bounds();
    o.ao_radius = bounds.empty() ? 1e6f : std::max(1e-3f, 100.0f * glm::length(bounds.extent()));
    // One tracer for every render: the BVH is built and uploaded once (or taken from `shared`).
    rt::RayTracer tracer(shaders, scene, gpu, o, shared ? *shared : nullptr);
    if (shared) *shared = tracer.shared_scene();
    const size_t n = static_cast<size_t>(v.width) * static_cast<size_t>(v.height);
    // channel < 0: luminance; else that channel.
    auto channel = [&](const ImageF& img, int c) {
        std::vector<double> out(n);
        for (size_t i = 0; i < n; ++i) {
            const float* p = img.pixels.data() + i * static_cast<size_t>(img.channels);
            out[i] = c < 0 ? 0.2126 * p[0] + 0.7152 * p[1] + 0.0722 * p[2] : p[c];
            if (!std::isfinite(out[i])) out[i] = 0.0;
        }
        return out;
    };
    auto luminance = [&] { return channel(tracer.render(camera, v.width, v.height).image, -1); };
    // `path` truncated after 1, 2, 3 and 4 vertices (no Russian roulette before the fourth): the
    // same random numbers trace the same paths, so the differences are exactly the first and
    // second bounce of light, every BRDF lobe (metals and glossy surfaces pass light on too).
    const std::vector<double> direct = luminance();
    tracer.set_max_depth(2);
    tracer.set_mode(rt::Mode::path);
    const std::vector<double> depth2 = luminance();
    tracer.set_max_depth(3);
    const std::vector<double> depth3 = luminance();
    tracer.set_max_depth(4);
    const std::vector<double> depth4 = luminance();
    tracer.set_mode(rt::Mode::hits);
    const ImageF hits = tracer.render(camera, v.width, v.height).image;
    const std::vector<double> passive = channel(hits, 0), emitter = channel(hits, 1), diffuse = channel(hits, 2);
    tracer.set_mode(rt::Mode::ao);
    const std::vector<double> open = channel(tracer.render(camera, v.width, v.height).image, 0);
    double d = 0.0, b1 = 0.0, b2 = 0.0, b3 = 0.0, wsum = 0.0, esum = 0.0, sky = 0.0;
    std::vector<double> bounce(n), diffuse_direct(n), diffuse_bounce(n);
    std::vector<double> surface_light, lit_direct, surface_direct, surface_indirect;
    for (size_t k = 0; k < n; ++k) {
        const double w = std::clamp(passive[k], 0.0, 1.0);
        wsum += w;
        esum += std::clamp(emitter[k], 0.0, 1.0);
        sky += w * std::clamp(open[k], 0.0, 1.0);
        // The renders are 0 where the camera sees no passive surface (no emission, no sky).
        bounce[k] = std::max(0.0, depth2[k] - direct[k]);
        // The bounce sums count the diffuse part of each pixel's surface: what a metal or glass
        // surface shows of its lit surroundings is a reflection, not interreflected light.
        const double wd = w > 0.0 ? std::clamp(diffuse[k] / w, 0.0, 1.0) : 0.0;
        diffuse_direct[k] = wd * direct[k];
        diffuse_bounce[k] = wd * bounce[k];
        d += diffuse_direct[k];
        b1 += diffuse_bounce[k];
        b2 += wd * std::max(0.0, depth3[k] - depth2[k]);
        b3 += wd * std::max(0.0, depth4[k] - depth3[k]);
        if (w >= 0.5) {
            surface_light.push_back(direct[k] + bounce[k]);
            // Only where the surface is mostly diffuse: what glass or a mirror shows beyond itself
            // is a later vertex of the camera path, not light that the probes would carry.
            if (wd >= 0.5) {
                surface_direct.push_back(direct[k]);
                surface_indirect.push_back(std::max(0.0, depth4[k] - direct[k]));
            }
            if (direct[k] > 0.0) lit_direct.push_back(direct[k]);
        }
    }
    const double nd = static_cast<double>(n);
    v.passive_share = wsum / nd;
    v.emitter_share = esum / nd;
    v.background_share = std::max(0.0, 1.0 - v.passive_share - v.emitter_share);
    v.sky_visibility = wsum > 0.0 ? sky / wsum : 0.0;
    v.direct_mean = d / nd;
    v.bounce_mean = b1 / nd;
    v.second_bounce_mean = b2 / nd;
    v.surface_pixels = static_cast<int>(surface_light.size());
    v.lit_pixels = static_cast<int>(lit_direct.size());
    if (d > 0.0) {
        v.ratio = b1 / d;
        double r2 = 0.0;
        for (size_t k = 0; k < n; ++k) {
            const double r = diffuse_bounce[k] - v.ratio * diffuse_direct[k];
            r2 += r * r;
        }
        v.ratio_stderr = std::sqrt(nd / std::max(nd - 1.0, 1.0) * r2) / d;
    }
    v.third_bounce_mean = b3 / nd;
    // Later bounces return about what the third returned of the second. Not the second of the
    // first: the first bounce leaves from where the lights shine, the later ones from the whole
    // room, so in a closed bright room lit where the camera does not look B2 / B1 is a fraction of
    // B3 / B2 (0.18 against 0.84 measured on one) and the bounces after the second were mostly
    // left out. Without a third bounce, the second's ratio.
    // And never more than a bounce can return of the one before: the largest albedo a surface
    // of the scene scatters with, times the share of the hemisphere over the surfaces in view
    // that is closed (light sent into the open sky, the share the AO rays find open, does not
    // come back). A glass vertex counts as a vertex in the truncated paths without scattering
    // anything (the sky seen through a glass wall is a "third bounce" there), and made
    // b3 / b2 ~ 1 in open scenes with dark surfaces: the extrapolation then multiplied b2 by 20
    // (random:10002: 46 % indirect where the tracer measures 0.5 %).
    v.albedo_bound = scattering_albedo_bound(scene);
    const double ratio_cap = std::min(0.95, v.albedo_bound * (1.0 - v.sky_visibility));
    v.per_bounce = b2 > 0.0 && b3 > 0.0 ? std::clamp(b3 / b2, 0.0, ratio_cap) : b1 > 0.0 ? std::clamp(b2 / b1, 0.0, ratio_cap) : 0.0;
    const double indirect = b1 + b2 / (1.0 - v.per_bounce);
    v.indirect_share = d + indirect > 0.0 ? indirect / (d + indirect) : 0.0;
    if (!surface_light.empty()) {
        double level = 0.0;
        if (!lit_direct.empty()) {
            std::nth_element(lit_direct.begin(), lit_direct.begin() + static_cast<std::ptrdiff_t>(lit_direct.size() / 2), lit_direct.end());
            level = lit_direct[lit_direct.size() / 2];
        }
        size_t unlit = 0;
        for (double l : surface_light) unlit += !(l > kUnlitLevel * level) || level <= 0.0;
        v.unlit_share = static_cast<double>(unlit) / static_cast<double>(surface_light.size());
        size_t indirect_only = 0;
        for (size_t i = 0; i < surface_direct.size(); ++i)
            indirect_only += (level <= 0.0 || !(surface_direct[i] > kUnlitLevel * level)) &&
                             display_transform(glm::vec3(static_cast<float>(surface_indirect[i])), 0.0f).x >= kVisibleIndirect;
        v.indirect_only_share = surface_direct.empty() ? 0.0 : static_cast<double>(indirect_only) / static_cast<double>(surface_direct.size());
    }
    v.ms = std::chrono::duration<double, std::milli>(std::chrono::steady_clock::now() - t0).count();
    return v;
}

std::string Caustics::text() const {
    char buf[400];
    std::snprintf(buf, sizeof buf,
                  "%.1f %% +- %.1f %% of the light on the image's surfaces comes through glass or off a mirror after the first "
                  "surface, %.4f of display over 4x4 blocks (%dx%d px x %d spp; %.0f ms)%s",
                  share * 100.0, stderr_share * 100.0, display_error, width, height, spp, ms,
                  share >= 0.005 ? ": the raster draws no caustics, so its image is darker there by about that share" : "");
    return buf;
}

bool can_have_caustics(const Scene& scene) {
    for (const Material& m : scene.materials)
        if (m.transmission > 0.0f || (m.metallic > 0.5f && m.roughness < rt::kCausticMirrorRoughness)) return true;
    return false;
}

Caustics measure_caustics(const ShaderLibrary& shaders, const Scene& scene, GpuScene& gpu, const Camera& camera, float aspect,
                          int spp, int pixels, std::shared_ptr<rt::RtScene>* shared) {
    const auto t0 = std::chrono::steady_clock::now();
    Caustics c;
    size_measurement(c, aspect, pixels, spp);
    // kBatches independent batches (seeds) of spp / kBatches samples: the share of each, their
    // mean, and its standard error from their spread.
    constexpr int kBatches = 4;
    rt::Options o;
    o.mode = rt::Mode::path;
    o.spp = std::max(1, spp / kBatches);
    o.tile_rows = c.height;
    o.camera_sees_emission = false;  // the light the surfaces reflect, as measure_view_light
    rt::RayTracer tracer(shaders, scene, gpu, o, shared ? *shared : nullptr);
    if (shared) *shared = tracer.shared_scene();
    std::vector<double> shares;
    ImageF all_mean, caustic_mean;
    for (int b = 0; b < kBatches; ++b) {
        tracer.set_seed(static_cast<std::uint32_t>(1 + b));
        tracer.set_caustics_only(false);
        const ImageF all = tracer.render(camera, c.width, c.height).image;
        tracer.set_caustics_only(true);
        const ImageF caustic = tracer.render(camera, c.width, c.height).image;
        if (b == 0) all_mean = caustic_mean = ImageF(all.width, all.height, all.channels);
        for (size_t i = 0; i < all_mean.pixels.size(); ++i) {
            all_mean.pixels[i] += all.pixels[i] / kBatches;
            caustic_mean.pixels[i] += caustic.pixels[i] / kBatches;
        }
        const double la = mean_luminance(all), lc = mean_luminance(caustic);
        shares.push_back(la > 0.0 ? std::clamp(lc / la, 0.0, 1.0) : 0.0);
    }
    // The budget's metric (block_agreement, `compare --blocks 4`) between the tracer's image and
    // that image less its caustic light.
    ImageF without = all_mean;
    for (size_t i = 0; i < without.pixels.size(); ++i) without.pixels[i] = std::max(0.0f, all_mean.pixels[i] - caustic_mean.pixels[i]);
    c.display_error = block_agreement(without, all_mean, std::min({4, c.width, c.height})).mean_abs;
    double mean = 0.0, var = 0.0;
    for (double x : shares) mean += x / kBatches;
    for (double x : shares) var += (x - mean) * (x - mean) / (kBatches - 1);
    c.spp = o.spp * kBatches;
    c.share = mean;
    c.stderr_share = std::sqrt(var / kBatches);
    c.ms = std::chrono::duration<double, std::milli>(std::chrono::steady_clock::now() - t0).count();
    return c;
}

std::string EmitterLight::text() const {
    char buf[320];
    std::snprintf(buf, sizeof buf,
                  "the emitters give %.1f %% of the direct light on the image's surfaces, %.4f of display over 4x4 blocks at the "
                  "99th percentile (mean %.4f; %dx%d px x %d spp; %.0f ms)",
                  share * 100.0, display_p99, display_mean, width, height, spp, ms);
    return buf;
}

EmitterLight measure_emitter_light(const ShaderLibrary& shaders, const Scene& scene, GpuScene& gpu, const Camera& camera,
                                   float aspect, int spp, int pixels, std::shared_ptr<rt::RtScene>* shared) {
    const auto t0 = std::chrono::steady_clock::now();
    EmitterLight e;
    const glm::ivec2 size = size_measurement(e, aspect, pixels, spp);
    const rt::Options o = seen_surfaces_direct(size, spp);
    rt::RayTracer tracer(shaders, scene, gpu, o, shared ? *shared : nullptr);
    if (shared) *shared = tracer.shared_scene();
    const ImageF all = tracer.render(camera, e.width, e.height).image;
    tracer.set_emitters_only(true);
    const ImageF emitted = tracer.render(camera, e.width, e.height).image;
    ImageF without = all;
    for (size_t i = 0; i < without.pixels.size(); ++i)
        if (i % static_cast<size_t>(all.channels) < 3) without.pixels[i] = std::max(0.0f, all.pixels[i] - emitted.pixels[i]);
    const BlockAgreement b = block_agreement(without, all, std::min({4, e.width, e.height}));
    e.display_mean = b.mean_abs;
    e.display_p99 = b.p99_abs;
    const double la = mean_luminance(all), le = mean_luminance(emitted);
    e.share = la > 0.0 ? std::clamp(le / la, 0.0, 1.0) : 0.0;
    e.ms = std::chrono::duration<double, std::milli>(std::chrono::steady_clock::now() - t0).count();
    return e;
}

}  // namespace candela
