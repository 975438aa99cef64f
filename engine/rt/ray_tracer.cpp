#include "rt/ray_tracer.hpp"

#include <unistd.h>

#include <algorithm>
#include <chrono>
#include <cmath>
#include <cstdio>
#include <cstdlib>

#include "core/error.hpp"
#include "core/log.hpp"
#include "gpu/bindings.h"
#include "rt/environment_cdf.hpp"
#include "rt/intersect.hpp"
#include "rt/progress_bar.hpp"
#include "rt/sampling.hpp"

namespace candela::rt {

const char* to_string(Mode mode) {
    switch (mode) {
        case Mode::whitted: return "whitted";
        case Mode::path: return "path";
        case Mode::direct: return "direct";
        case Mode::indirect: return "indirect";
        case Mode::ao: return "ao";
        case Mode::primary: return "primary";
        case Mode::visibility: return "visibility";
        case Mode::bounce: return "bounce";
        case Mode::hits: return "hits";
    }
    return "?";
}

ModeProgram mode_program(Mode mode) {
    switch (mode) {
        case Mode::ao: return {"MODE_AO", "rt/modes/ao.comp"};
        case Mode::primary: return {"MODE_PRIMARY", "rt/modes/primary.comp"};
        case Mode::path:
        case Mode::direct: return {"MODE_PATH", "rt/modes/path.comp"};
        case Mode::indirect: return {"MODE_INDIRECT", "rt/modes/indirect.comp"};
        case Mode::whitted: return {"MODE_WHITTED", "rt/modes/whitted.comp"};
        case Mode::visibility: return {"MODE_VISIBILITY", "rt/modes/visibility.comp"};
        case Mode::bounce: return {"MODE_BOUNCE", "rt/modes/bounce.comp"};
        case Mode::hits: return {"MODE_HITS", "rt/modes/hits.comp"};
    }
    return {"MODE_PATH", "rt/modes/path.comp"};
}

std::optional<Mode> parse_mode(const std::string& name) {
    for (Mode m : {Mode::whitted, Mode::path, Mode::direct, Mode::indirect, Mode::ao, Mode::primary, Mode::visibility, Mode::bounce, Mode::hits})
        if (name == to_string(m)) return m;
    return std::nullopt;
}

RayTracer::RayTracer(const ShaderLibrary& shaders, const Scene& scene, GpuScene& gpu, const Options& options,
                     std::shared_ptr<RtScene> shared)
    : shaders_(shaders), scene_(scene), gpu_(gpu), options_(options), requested_max_depth_(options.max_depth),
      rt_scene_(shared ? std::move(shared) : std::make_shared<RtScene>(scene, static_cast<int>(scene.materials.size()))) {
    const Bounds b = scene.world_bounds();
    scene_diagonal_ = b.empty() ? 1.0f : glm::length(b.extent());
    if (options_.spp < 1 || options_.spp > (1 << 24)) throw bad_input("--spp must be in [1, 16777216]");
    if (options_.shard_count < 1 || options_.shard < 0 || options_.shard >= options_.shard_count)
        throw bad_input("--spp-shard K/N needs 0 <= K < N");
    // CANDELA_RT_SAMPLES_PER_DISPATCH=N overrides Options::samples_per_dispatch (A/B timing,
    // docs/raytracing.md "Path tracing speed"; 1 is the one-sample-per-dispatch schedule).
    if (const char* env = std::getenv("CANDELA_RT_SAMPLES_PER_DISPATCH"); env && std::atoi(env) > 0)
        options_.samples_per_dispatch = std::atoi(env);
    // A reference is the box-filtered pixel average: every mode jitters unless told not to.
    if (options_.jitter < 0) options_.jitter = 1;
    select_program(options_.mode);
    frame_ubo_ = gl::Buffer(sizeof(FrameGpu), nullptr, GL_DYNAMIC_STORAGE_BIT);
}

void RayTracer::set_mode(Mode mode) {
    select_program(mode);
    // The accumulation in progress was traced with the old program: progressive_restart starts anew.
    progressive_.frame.reset();
    progressive_.sample = 0;
    progressive_.row = 0;
}

void RayTracer::set_max_depth(int depth) {
    requested_max_depth_ = depth;
    options_.max_depth = depth;
}

void RayTracer::select_program(Mode mode) {
    // Unbiased by default (a reference must not be dark): path has no depth cap, only Russian roulette; an explicit
    // max_depth is a truncation the caller asked for.
    int depth = requested_max_depth_;
    if (depth < 0) depth = mode == Mode::whitted ? 5 : mode == Mode::direct ? 1 : kUnboundedDepth;
    if (mode == Mode::direct) depth = 1;
    // Whitted has no roulette: its recursion is bounded by the depth alone.
    const int depth_limit = mode == Mode::whitted ? 64 : kUnboundedDepth;
    if (depth > depth_limit) throw bad_input("--max-depth must be in [0, " + std::to_string(depth_limit) + "] in this mode");
    // One program per mode (shaders/rt/modes/), specialised: code for features the scene lacks
    // is never compiled or run.
    const ModeProgram program = mode_program(mode);
    std::vector<std::string> defines;
    if (!rt_scene_->geometry().emitters.empty()) defines.push_back("HAS_EMITTERS");
    if (rt_scene_->geometry().has_transmission) defines.push_back("HAS_TRANSMISSION");
    if (std::any_of(scene_.materials.begin(), scene_.materials.end(), [](const Material& m) { return m.has_layers(); })) defines.push_back("MATERIAL_LAYERS");
    if (rt_scene_->geometry().has_blend) defines.push_back("HAS_BLEND");
    if (rt_scene_->geometry().has_vertex_colors) defines.push_back("HAS_VERTEX_COLORS");
    if (rt_scene_->geometry().has_mask) defines.push_back("HAS_MASK");
    if (options_.traversal_stats) defines.push_back("RT_STATS");
    // What the scene lacks is compiled out too: llvmpipe executes both sides of a branch, masked.
    const auto textured = [](const Material& m) {
        return m.base_color_texture.present() || m.metallic_roughness_texture.present() || m.normal_texture.present() ||
               m.occlusion_texture.present() || m.emissive_texture.present();
    };
    if (std::none_of(scene_.materials.begin(), scene_.materials.end(), textured)) defines.push_back("RT_NO_TEXTURES");
    if (rt_scene_->geometry().spheres.empty()) defines.push_back("RT_NO_SPHERES");
    gl::Buffer env_distribution;
    int env_width = 0, env_height = 0;
    if (gpu_.has_environment_map() && options_.env_importance && (mode == Mode::path || mode == Mode::direct)) {
        defines.push_back("HAS_ENV_MAP_SAMPLING");
        const ImageF& map = gpu_.environment_image();
        const std::vector<float> dist = environment_distribution(map);
        env_distribution = gl::Buffer(static_cast<GLsizeiptr>(dist.size() * sizeof(float)), dist.data());
        env_width = map.width;
        env_height = map.height;
    }
    std::string names = program.name;
    for (const auto& d : defines) names += " " + d;
    gl::Program built = shaders_.build_or_throw({std::string("trace ") + names, {{ShaderStage::compute, program.file}}, defines});
    // Nothing changes unless the program built: a failed set_mode leaves the tracer as it was.
    program_ = std::move(built);
    defines_ = std::move(names);
    env_distribution_ = std::move(env_distribution);
    env_width_ = env_width;
    env_height_ = env_height;
    options_.mode = mode;
    options_.max_depth = depth;
}

RayTracer::~RayTracer() = default;

void RayTracer::set_shard(int shard, int count) {
    if (count < 1 || shard < 0 || shard >= count) throw bad_input("--spp-shard K/N needs 0 <= K < N");
    options_.shard = shard;
    options_.shard_count = count;
}

// --- motion blur ------------------------------------------------------------------------

int RayTracer::slice_count() const {
    if (!options_.pose_at) return 0;
    return options_.shutter_slices > 0 ? std::min(options_.shutter_slices, options_.spp) : options_.spp;
}

// Stratified in [0, 1), jittered by a hash of the seed and the slice index only: every shard gives
// a sample the time the single run gives it.
float RayTracer::slice_time(int slice) const {
    const std::uint32_t h = pcg_hash(options_.seed * 0x9E3779B9u ^ pcg_hash(static_cast<std::uint32_t>(slice) ^ 0x85EBCA6Bu));
    const double r = static_cast<double>(h >> 8) * (1.0 / 16777216.0);
    const double u = (static_cast<double>(slice) + r) / static_cast<double>(slice_count());
    return std::min(static_cast<float>(u), std::nextafter(1.0f, 0.0f));
}

int RayTracer::slice_of(int sample) const {
    return static_cast<int>(static_cast<std::int64_t>(sample) * slice_count() / options_.spp);
}

void RayTracer::refresh_counts(FrameGpu& f) const {
    const RtGeometry& g = rt_scene_->geometry();
    f.triangle_count = static_cast<int>(g.triangles.size());
    f.sphere_count = static_cast<int>(g.spheres.size());
    f.emitter_count = static_cast<int>(g.emitters.size());
    f.surface_count = static_cast<int>(g.surfaces.size());
    f.emitted_power = static_cast<float>(g.emitted_power);
}

RtUpdateStats RayTracer::update_geometry(RtUpdate how) {
    const RtUpdateStats stats = rt_scene_->update(scene_, how);
    posed_slice_ = -1;
    return stats;
}

bool RayTracer::pose_slice(int slice, FrameGpu& f, Result* result) {
    if (slice == posed_slice_) return false;
    const auto t0 = std::chrono::steady_clock::now();
    options_.pose_at(slice_time(slice));
    const auto t1 = std::chrono::steady_clock::now();
    rt_scene_->update(scene_, RtUpdate::refit);
    posed_slice_ = slice;
    refresh_counts(f);
    if (result) {
        result->pose_ms += std::chrono::duration<double, std::milli>(t1 - t0).count();
        result->geometry_ms += std::chrono::duration<double, std::milli>(std::chrono::steady_clock::now() - t1).count();
        ++result->shutter_slices;
    }
    return true;
}

FrameGpu scene_frame_block(const Scene& scene, const RtScene& rt_scene, const GpuScene& gpu) {
    FrameGpu f{};
    const Bounds b = scene.world_bounds();
    const float diagonal = b.empty() ? 1.0f : glm::length(b.extent());
    f.env_radiance = gpu.environment_radiance();
    f.env_map_bound = gpu.has_environment_map() ? 1.0f : 0.0f;
    const RtGeometry& g = rt_scene.geometry();
    f.triangle_count = static_cast<int>(g.triangles.size());
    f.sphere_count = static_cast<int>(g.spheres.size());
    f.emitter_count = static_cast<int>(g.emitters.size());
    f.punctual_light_count = static_cast<int>(scene.placed_lights().size());
    f.surface_count = static_cast<int>(g.surfaces.size());
    f.max_depth = 1;
    f.indirect_occlusion = 1;
    f.ao_radius = 1.0f;
    f.whitted_max_roughness = 0.05f;
    f.emitted_power = static_cast<float>(g.emitted_power);
    f.ray_offset = ray_offset_for_extent(diagonal);
    return f;
}

void bind_scene(const RtScene& rt_scene, GpuScene& gpu) {
    glBindBufferBase(GL_SHADER_STORAGE_BUFFER, MATERIALS_BINDING, gpu.materials().id());
    glBindBufferBase(GL_SHADER_STORAGE_BUFFER, LIGHTS_BINDING, gpu.lights().id());  // punctual lights come first
    rt_scene.bind();
    gl::bind_texture_unit(ENVIRONMENT_UNIT, gpu.environment_map());
    gl::bind_texture_unit(RT_IMAGES_UNIT, gpu.image_array());
    gl::bind_texture_unit(RT_IMAGES_SRGB_UNIT, gpu.image_array_srgb());
}

FrameGpu RayTracer::make_frame(const Camera& camera, int width, int height) const {
    FrameGpu f = scene_frame_block(scene_, *rt_scene_, gpu_);
    const float aspect = static_cast<float>(width) / static_cast<float>(height);
    // Camera-relative: the view without its translation, so that unprojected points stay near 0
    // and keep their precision when the camera is far from the origin (hard case
    // FarFromTheOrigin); camera_pos adds the position back.
    glm::mat4 rotation = camera.world;
    rotation[3] = glm::vec4(0.0f, 0.0f, 0.0f, 1.0f);
    f.inv_view_proj = glm::inverse(projection_matrix(camera, aspect) * glm::inverse(rotation));
    f.camera_pos = glm::vec4(glm::vec3(camera.world[3]), 1.0f);
    f.env_width = env_width_;
    f.env_height = env_height_;
    f.max_depth = options_.max_depth;
    f.jitter = options_.jitter;
    f.indirect_occlusion = options_.indirect_occlusion ? 1 : 0;
    f.tile_y = 0;
    f.ao_radius = options_.ao_radius;
    f.whitted_max_roughness = options_.whitted_max_roughness;
    f.visibility_light = static_cast<float>(options_.visibility_light);
    f.ray_offset = ray_offset_for_extent(scene_diagonal_);
    f.sample_stride = 0.0f;
    f.camera_hides_emission = options_.camera_sees_emission ? 0.0f : 1.0f;
    f.dielectric_highlights = options_.dielectric_highlights ? 1.0f : 0.0f;
    f.caustics_only = options_.caustics_only ? 1.0f : 0.0f;
    f.emitters_only = options_.emitters_only ? 1.0f : 0.0f;
    // The thin lens (docs/raytracing.md, "Depth of field"): an orthonormal frame of the camera
    // (its -Z the view axis), the disk's axes scaled by the radius. Orthographic cameras stay
    // pinholes (has_thin_lens).
    if (camera.orthographic && camera.aperture > 0.0f && !warned_orthographic_lens_) {
        char aperture[32];
        std::snprintf(aperture, sizeof(aperture), "%g", static_cast<double>(camera.aperture));
        log::warn("camera '" + camera.name + "': aperture " + aperture + " ignored, an orthographic camera has no depth of field");
        warned_orthographic_lens_ = true;
    }
    if (has_thin_lens(camera)) {
        const glm::vec3 axis = glm::normalize(-glm::vec3(camera.world[2]));
        const glm::vec3 y = glm::normalize(glm::vec3(camera.world[1]) - axis * glm::dot(glm::vec3(camera.world[1]), axis));
        const glm::vec3 x = glm::cross(axis, y);  // the camera's +X: right-handed with y and -axis
        const float radius = camera.aperture;
        f.lens_x = glm::vec4(x * radius, radius);
        f.lens_y = glm::vec4(y * radius, focus_distance_or_auto(camera, scene_.world_bounds()));
        f.lens_axis = glm::vec4(axis, 0.0f);
    }
    return f;
}

void RayTracer::bind(const gl::Buffer& accum, const gl::Buffer& diagnostics) const {
    glUseProgram(program_.id());
    bind_scene(*rt_scene_, gpu_);
    glBindBufferBase(GL_UNIFORM_BUFFER, RT_FRAME_BINDING, frame_ubo_.id());
    glBindBufferBase(GL_SHADER_STORAGE_BUFFER, RT_ACCUM_BINDING, accum.id());
    glBindBufferBase(GL_SHADER_STORAGE_BUFFER, RT_DIAGNOSTICS_BINDING, diagnostics.id());
    if (env_distribution_) glBindBufferBase(GL_SHADER_STORAGE_BUFFER, RT_ENV_DISTRIBUTION_BINDING, env_distribution_.id());
}

void RayTracer::progressive_restart(const Camera& camera, int width, int height) {
    if (width < 1 || height < 1 || width > 16384 || height > 16384) throw bad_input("reference size is out of range");
    if (options_.pose_at) {  // the tree for this frame's refits, built at its time
        options_.pose_at(0.5f);
        update_geometry(RtUpdate::rebuild);
    }
    Progressive& p = progressive_;
    const size_t pixels = static_cast<size_t>(width) * static_cast<size_t>(height);
    if (p.width != width || p.height != height || !p.accum) {
        p.accum = gl::Buffer(static_cast<GLsizeiptr>(pixels * sizeof(glm::vec4)), nullptr, GL_DYNAMIC_STORAGE_BIT);
        p.diagnostics = gl::Buffer(5 * sizeof(unsigned), nullptr, GL_DYNAMIC_STORAGE_BIT);
    }
    const float zero = 0.0f;
    glClearNamedBufferData(p.accum.id(), GL_R32F, GL_RED, GL_FLOAT, &zero);
    const unsigned zero_u = 0;
    glClearNamedBufferData(p.diagnostics.id(), GL_R32UI, GL_RED_INTEGER, GL_UNSIGNED_INT, &zero_u);
    p.frame = std::make_unique<FrameGpu>(make_frame(camera, width, height));
    p.width = width;
    p.height = height;
    p.sample = 0;
    p.row = 0;
}

void RayTracer::progressive_step(double budget_ms) {
    Progressive& p = progressive_;
    if (!p.frame || progressive_done()) return;
    bind(p.accum, p.diagnostics);
    const auto t0 = std::chrono::steady_clock::now();
    const int rows = std::max(1, options_.tile_rows);
    const bool motion = static_cast<bool>(options_.pose_at);
    do {
        if (motion && pose_slice(slice_of(p.sample), *p.frame, nullptr)) bind(p.accum, p.diagnostics);
        FrameGpu f = *p.frame;
        f.width = p.width;
        f.height = p.height;
        f.sample_index = p.sample;
        f.seed = static_cast<int>(options_.seed);
        f.tile_y = p.row;
        frame_ubo_.update(0, sizeof(FrameGpu), &f);
        glDispatchCompute(static_cast<GLuint>((p.width + 7) / 8), static_cast<GLuint>((std::min(rows, p.height - p.row) + 7) / 8), 1);
        glMemoryBarrier(GL_SHADER_STORAGE_BARRIER_BIT | GL_UNIFORM_BARRIER_BIT);
        glFinish();  // the budget is wall time of finished work
        p.row += rows;
        if (p.row >= p.height) {
            p.row = 0;
            ++p.sample;
        }
    } while (!progressive_done() &&
             std::chrono::duration<double, std::milli>(std::chrono::steady_clock::now() - t0).count() < budget_ms);
    glUseProgram(0);
    // The scene goes back to the frame's time between steps (the caller may draw it); the
    // geometry keeps the slice, so the next step continues without posing again.
    if (motion) options_.pose_at(0.5f);
}

ImageF RayTracer::progressive_image() const {
    const Progressive& p = progressive_;
    ImageF img(std::max(p.width, 1), std::max(p.height, 1), 4);
    if (!p.accum) return img;
    const size_t pixels = static_cast<size_t>(p.width) * static_cast<size_t>(p.height);
    std::vector<glm::vec4> sums(pixels);
    glGetNamedBufferSubData(p.accum.id(), 0, static_cast<GLsizeiptr>(pixels * sizeof(glm::vec4)), sums.data());
    for (size_t i = 0; i < pixels; ++i) {
        const glm::vec4 v = sums[i];
        const float n = v.w > 0.0f ? v.w : 1.0f;
        float* o = img.pixels.data() + i * 4;
        o[0] = v.x / n, o[1] = v.y / n, o[2] = v.z / n, o[3] = v.w;
    }
    return img;
}

Result RayTracer::render(const Camera& camera, int width, int height) {
    if (width < 1 || height < 1 || width > 16384 || height > 16384) throw bad_input("--size is out of range (1..16384 per side)");
    Result result;
    result.defines = defines_;
    const size_t pixels = static_cast<size_t>(width) * static_cast<size_t>(height);
    std::vector<glm::vec4> zeros(pixels, glm::vec4(0.0f));
    gl::Buffer accum(static_cast<GLsizeiptr>(pixels * sizeof(glm::vec4)), zeros.data(), GL_DYNAMIC_STORAGE_BIT);
    const unsigned zero_diag[5] = {0, 0, 0, 0, 0};
    gl::Buffer diagnostics(sizeof(zero_diag), zero_diag, GL_DYNAMIC_STORAGE_BIT);

    const bool motion = static_cast<bool>(options_.pose_at);
    const auto start = std::chrono::steady_clock::now();
    if (motion) {  // the tree every slice refits, built at the frame's time (the same for every shard)
        options_.pose_at(0.5f);
        const auto posed = std::chrono::steady_clock::now();
        update_geometry(RtUpdate::rebuild);
        result.pose_ms += std::chrono::duration<double, std::milli>(posed - start).count();
        result.geometry_ms += std::chrono::duration<double, std::milli>(std::chrono::steady_clock::now() - posed).count();
    }
    FrameGpu f = make_frame(camera, width, height);
    bind(accum, diagnostics);

    const bool show_progress = options_.progress && isatty(STDERR_FILENO);
    int mine = 0;
    for (int s = 0; s < options_.spp; ++s) mine += s % options_.shard_count == options_.shard;
    const auto t0 = start;
    auto elapsed = [&] { return std::chrono::duration<double>(std::chrono::steady_clock::now() - t0).count(); };
    const int rows = std::max(1, options_.tile_rows);
    const int stride = options_.shard_count;
    f.sample_stride = static_cast<float>(stride);  // exact: spp <= 2^24
    double sample_s = 0.0;  // measured seconds per sample (for --time-limit's chunk size)
    // This run's samples are s = shard, shard + N, ...; a dispatch traces `count` of them from
    // `s`, all in one motion-blur time slice.
    for (int s = options_.shard; s < options_.spp;) {
        if (options_.time_limit_s > 0.0 && result.samples > 0 && elapsed() >= options_.time_limit_s) {
            result.stopped_early = true;
            break;
        }
        int count = 1;
        const int most = std::max(1, options_.samples_per_dispatch);
        while (count < most && s + count * stride < options_.spp &&
               (!motion || slice_of(s + count * stride) == slice_of(s)))
            ++count;
        if (options_.time_limit_s > 0.0) {
            // Near the limit, fewer samples per dispatch: stop at about the limit, as one per dispatch did.
            const double left = options_.time_limit_s - elapsed();
            const int fit = sample_s > 0.0 ? static_cast<int>(left / sample_s) : 1;
            count = std::clamp(fit, 1, count);
        }
        if (motion && pose_slice(slice_of(s), f, &result)) bind(accum, diagnostics);
        const double chunk_start = elapsed();
        for (int y0 = 0; y0 < height; y0 += rows) {
            f.width = width;
            f.height = height;
            f.sample_index = s;
            f.seed = static_cast<int>(options_.seed);
            f.tile_y = y0;
            f.dispatch_samples = count;
            frame_ubo_.update(0, sizeof(FrameGpu), &f);
            glDispatchCompute(static_cast<GLuint>((width + 7) / 8), static_cast<GLuint>((std::min(rows, height - y0) + 7) / 8), 1);
            glMemoryBarrier(GL_SHADER_STORAGE_BARRIER_BIT | GL_UNIFORM_BARRIER_BIT);
        }
        glFinish();  // a sample boundary: time limit and progress are checked here
        sample_s = (elapsed() - chunk_start) / count;
        result.samples += count;
        s += count * stride;
        if (show_progress) progress_bar(result.samples, mine, elapsed());
    }
    if (show_progress && result.stopped_early) std::fprintf(stderr, "\n");
    if (motion) {
        const auto posing = std::chrono::steady_clock::now();
        options_.pose_at(0.5f);  // the scene back at the frame's time
        result.pose_ms += std::chrono::duration<double, std::milli>(std::chrono::steady_clock::now() - posing).count();
    }
    result.trace_ms = elapsed() * 1000.0;

    std::vector<glm::vec4> sums(pixels);
    glGetNamedBufferSubData(accum.id(), 0, static_cast<GLsizeiptr>(pixels * sizeof(glm::vec4)), sums.data());
    unsigned diag[5] = {0, 0, 0, 0, 0};
    glGetNamedBufferSubData(diagnostics.id(), 0, sizeof(diag), diag);
    result.nonfinite_samples = diag[0];
    if (diag[3] > 0) {
        result.nodes_per_ray = static_cast<double>(diag[1]) / diag[3];
        result.primitives_per_ray = static_cast<double>(diag[2]) / diag[3];
    }
    if (diag[4] > 0) result.lane_utilisation = static_cast<double>(diag[1]) / diag[4];
    result.traversal_rays = diag[3];
    result.traversal_steps = diag[1];
    result.traversal_primitives = diag[2];
    result.traversal_slots = diag[4];
    result.image = ImageF(width, height, 4);
    for (size_t i = 0; i < pixels; ++i) {
        const glm::vec4 v = sums[i];
        float* o = result.image.pixels.data() + i * 4;
        const float n = v.w > 0.0f ? v.w : 1.0f;
        o[0] = v.x / n, o[1] = v.y / n, o[2] = v.z / n, o[3] = v.w;
    }
    glUseProgram(0);
    return result;
}

}  // namespace candela::rt
