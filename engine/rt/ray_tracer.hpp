#pragma once
// The compute-shader ray tracer: the reference every raster effect is judged against. Modes:
// whitted, path, direct (path with one bounce), indirect (one diffuse bounce only), ao.
#include <cstdint>
#include <functional>
#include <optional>
#include <memory>
#include <string>

#include "gpu/rt_frame.h"
#include "image/image.hpp"
#include "render/gpu_scene.hpp"
#include "rt/rt_scene.hpp"
#include "shader/shader_library.hpp"

namespace candela::rt {

// visibility: the fraction of one light reaching each visible point (the ground truth of the
// raster visibility buffer, debug.view=visibility).
// bounce: camera rays plus one cosine-distributed closest-hit ray (ray-rate benchmark).
// hits: the share of each pixel's camera rays that see a passive surface (r), an emitter (g), and
// the diffuse part of the passive surfaces seen (b; nothing hit is 1 - r - g): what the planner's
// view measurements weight pixels with.
enum class Mode { whitted, path, direct, indirect, ao, primary, visibility, bounce, hits };
const char* to_string(Mode mode);
std::optional<Mode> parse_mode(const std::string& name);

// The compute program of a mode: one file per mode under shaders/rt/modes/ (direct is path with
// one bounce), over the shared includes in shaders/rt/. `name` identifies the program in program
// names and in Result::defines ("MODE_PATH HAS_EMITTERS"); it is not a define.
struct ModeProgram {
    const char* name;
    const char* file;  // relative to the shader root
};
ModeProgram mode_program(Mode mode);

// The default depth of `path`: no cap in practice. Russian roulette survives with probability at
// most 0.95 from the fourth bounce, so a path reaches this depth with probability < 0.95^(2^20).
inline constexpr int kUnboundedDepth = 1 << 20;
// Options::caustics_only: a metal smoother than this is a mirror (shaders/rt/modes/path.comp has
// the same constant). It is the reflection effect's default reflections.max_roughness: the raster
// shows such a metal's surroundings with reflection probes, and its GI probes cannot carry the
// light it throws onto other surfaces (a probe ray meets a mirror's light only along one line).
inline constexpr float kCausticMirrorRoughness = 0.3f;

struct Options {
    Mode mode = Mode::path;
    int spp = 16;          // [1, 1 << 24] samples per pixel (the whole render, before sharding)
    // Bounces. -1: the mode's default: whitted 5, direct 1, path unbounded (Russian roulette ends
    // every path; kUnboundedDepth is only a safety net, its truncation bias is below 1e-300 for albedos up to 0.999). A
    // set value N truncates path: light after more than N reflections is dropped, a bias of
    // -a^(N+1) in a closed box of albedo a (docs/raytracing.md), for speed only.
    int max_depth = -1;
    std::uint32_t seed = 1;
    int shard = 0;         // --spp-shard K/N: this run computes samples s with s % N == K
    int shard_count = 1;
    double time_limit_s = 0.0;  // > 0: stop at the first sample boundary past it
    float ao_radius = 1.0f;     // world units (ao.radius, shared with SSAO)
    // Camera rays at uniformly random points of the pixel (on: the box-filtered pixel average, what
    // a reference renderer computes) or through its centre (off: the point sample a rasterizer
    // takes; partly covered pixels then come out 0 or 1). -1: on, in every mode.
    int jitter = -1;
    float whitted_max_roughness = 0.05f;  // smoother surfaces reflect as mirrors in whitted mode
    // indirect mode: with false, the bounce points y are sampled over all surfaces by area and the
    // visibility between x and y is ignored (RSM's own model), so RSM's sampling error can be
    // told apart from its missing occlusion. Light visibility at y is kept in both.
    bool indirect_occlusion = true;
    // Environment maps: sample directions by the map's luminance and combine with BRDF sampling
    // by MIS (path and direct). Off: BRDF sampling only (for comparison).
    bool env_importance = true;
    // path and direct: false leaves out what camera rays see directly (emitters' emission and the
    // environment), so that the image is the light the surfaces reflect alone (view_light.hpp).
    bool camera_sees_emission = true;
    // path and direct: punctual lights reflected by a dielectric interface's specular lobe (the
    // highlights on glass). The planner's view measurements leave them out: a surface is lit by
    // the light that reaches it or by the lit things it shows, and the faint tail of a highlight
    // over every glass pixel would count the glass as lit.
    bool dielectric_highlights = true;
    // path: count only caustic paths, those that leave the first diffuse or glossy surface the
    // camera sees through glass or off a mirror (a metal smoother than kCausticMirrorRoughness)
    // and reach a light with nothing else between: the light the raster has no way to carry
    // (view_light.hpp, measure_caustics).
    bool caustics_only = false;
    // path and direct: count only the light that left an emissive surface (no punctual light, no
    // environment): what the emitters add to the image, for the area lights' planner
    // (view_light.hpp, measure_emitter_light).
    bool emitters_only = false;
    // visibility mode: the light (debug.light); >= the punctual count: all emissive triangles.
    int visibility_light = 0;
    bool progress = false;      // progress bar with ETA on stderr
    int tile_rows = 64;         // rows per dispatch: short dispatches never trip a GPU watchdog
    // Samples per pixel in one dispatch (render(); the progressive mode traces one). Each lane of
    // the path program starts its next sample when its path ends (shaders/rt/modes/path.comp),
    // so more samples per dispatch keep more of llvmpipe's SIMD lanes busy. The samples are the
    // same whatever the grouping. With --time-limit the tracer takes fewer near the limit.
    int samples_per_dispatch = 16;
    bool traversal_stats = false;  // count BVH nodes and primitives per ray (slower; benchmarks)
    // Motion blur. With `pose_at` set, the shutter is open: before each time slice the
    // tracer calls pose_at(u) with the slice's time u in [0, 1) within the shutter (stratified and
    // jittered from the seed and the slice index only, so shards merge to the single run); the
    // callback poses the Scene this tracer was made with (the caller owns it, e.g.
    // pose_scene(scene, animation, open + u * (close - open))), and the tracer rebuilds its
    // geometry from it. `shutter_slices` slices per render (rt.shutter_slices; 0: one per sample,
    // each sample pass at its own time). The tracer calls pose_at(0.5) when it is done, so the
    // scene is left at the frame's time (the centre of the shutter).
    // How (ray_tracer.cpp, measured in tests/bench/bench_rt_motion.cpp): at the start of a render
    // (and at progressive_restart) pose_at(0.5) and a full BVH build at the frame's time; before
    // each slice pose_at(u) and a refit of that tree (same topology, boxes recomputed bottom-up),
    // the triangles re-uploaded in place. The slice of sample s is s * S / spp (S the slice count,
    // at most spp), its time (k + r(seed, k)) / S with r a hash in [0, 1).
    std::function<void(float u)> pose_at;
    int shutter_slices = 0;
};

// The tracer's frame block (`rt` in the GLSL), declared with the GLSL in gpu/rt_frame.h.
using FrameGpu = gpu::RtFrame;

// For other compute programs over shaders/rt/scene.glsl (the GI probes, engine/effects/gi/): the
// frame block with the scene's counts and ray offset (no camera), and the scene's bindings
// (materials, lights, the RtScene's, environment, image arrays: gpu/bindings.h). Environment-map
// importance sampling is not bound.
FrameGpu scene_frame_block(const Scene& scene, const RtScene& rt_scene, const GpuScene& gpu);
void bind_scene(const RtScene& rt_scene, GpuScene& gpu);

struct Result {
    ImageF image;  // rgb: mean radiance (ao: unoccluded fraction); a: samples accumulated
    int samples = 0;           // samples per pixel this run computed
    bool stopped_early = false;  // --time-limit
    unsigned nonfinite_samples = 0;  // replaced by 0 (should stay 0; tests assert it)
    // With Options::traversal_stats: mean BVH nodes visited and primitives tested per traced ray.
    double nodes_per_ray = 0.0, primitives_per_ray = 0.0;
    // With traversal_stats: the fraction of SIMD lanes that did a traversal step while their
    // subgroup ran one (the rest waited for the others); 0 without GL_ARB_shader_ballot.
    double lane_utilisation = 0.0;
    // The raw counts behind those means: rays traced, traversal steps (nodes and leaves),
    // primitives tested, lane slots.
    std::uint64_t traversal_rays = 0, traversal_steps = 0, traversal_primitives = 0, traversal_slots = 0;
    double trace_ms = 0.0;
    // Motion blur (Options::pose_at): time slices this run traced, and the time spent posing the
    // scene (pose_at) and updating the geometry (build/refit, pack, upload), part of trace_ms.
    int shutter_slices = 0;
    double pose_ms = 0.0, geometry_ms = 0.0;
    std::string defines;       // the program used: ModeProgram::name, then the feature defines
};

class RayTracer {
public:
    // Builds the BVH, uploads the scene, compiles the program specialised to the mode and the
    // scene's features. Throws candela::Error (internal) if the shader does not build. `shaders`,
    // `scene` and `gpu` must outlive the tracer (set_mode builds from `shaders`). `shared`: the
    // BVH and geometry of another tracer of this scene in its present pose (shared_scene()), used
    // instead of building them again; null: built here.
    RayTracer(const ShaderLibrary& shaders, const Scene& scene, GpuScene& gpu, const Options& options,
              std::shared_ptr<RtScene> shared = nullptr);
    ~RayTracer();
    Result render(const Camera& camera, int width, int height);

    // Progressive accumulation (the viewer's reference mode): restart for a camera and size,
    // then each step traces tiles of further samples for about `budget_ms` of wall time (at
    // least one tile), so a frame loop stays responsive. Samples stop at Options::spp.
    void progressive_restart(const Camera& camera, int width, int height);
    void progressive_step(double budget_ms);
    // Per-pixel mean of the samples traced so far (alpha: their count; a pixel may be one ahead).
    ImageF progressive_image() const;
    int progressive_samples() const { return progressive_.sample; }  // complete samples per pixel
    bool progressive_done() const { return progressive_.sample >= options_.spp; }
    // Changes the sample count for the next render (benchmarks warm up with one sample first).
    void set_spp(int spp) { options_.spp = spp; }
    // Changes the seed for the next render: independent full renders from one tracer (the motion
    // blur test's batches, each a complete stratification of the shutter).
    void set_seed(std::uint32_t seed) { options_.seed = seed; }
    // Options::caustics_only for the next render (path mode).
    void set_caustics_only(bool on) { options_.caustics_only = on; }
    void set_emitters_only(bool on) { options_.emitters_only = on; }
    // Changes the bounce limit of path mode for the next render (1: direct light only); a later
    // set_mode applies the mode's rules to it as the constructor does to Options::max_depth.
    void set_max_depth(int depth);
    // Switches the next renders to another mode over the same BVH and uploaded scene: the
    // program (and the environment's sampling distribution) of a tracer constructed with that
    // mode and these options, so the images are those of such a tracer, bit for bit. What it
    // saves is the RtScene: the planner's indirect estimate traces `direct` then `indirect` with
    // one tracer (the BVH of FlightHelmet, 95k triangles, is 60-200 ms of build and upload). A
    // progressive accumulation in progress is dropped. Throws as the constructor does (a bad
    // max depth for the mode, a shader that does not build), leaving the tracer unchanged.
    void set_mode(Mode mode);
    Mode mode() const { return options_.mode; }
    // The next render computes the samples s with s % count == shard (--spp-shard K/N): independent
    // batches from one tracer (the statistical tests). Throws bad_input unless 0 <= shard < count.
    void set_shard(int shard, int count);
    const RtScene& scene() const { return *rt_scene_; }
    // The tracer's geometry, for another tracer of the same scene and pose (the planner's
    // measurements share one: building the BVH of a million triangles is most of their time).
    std::shared_ptr<RtScene> shared_scene() const { return rt_scene_; }
    // Rebuilds or refits the tracer's geometry from its Scene as it is now (after the caller posed
    // it), e.g. when the viewer's pose changes; render() does this itself with Options::pose_at.
    // The program stays (it was specialised to the features at construction). After a render with
    // motion, scene() holds the last slice's geometry.
    RtUpdateStats update_geometry(RtUpdate how);

private:
    const ShaderLibrary& shaders_;
    const Scene& scene_;
    GpuScene& gpu_;
    Options options_;
    int requested_max_depth_ = -1;  // Options::max_depth as asked (-1: the mode's default)
    std::shared_ptr<RtScene> rt_scene_;
    float scene_diagonal_ = 1.0f;  // of the world bounds: sets the smallest ray offset
    gl::Program program_;
    gl::Buffer frame_ubo_;
    gl::Buffer env_distribution_;
    int env_width_ = 0, env_height_ = 0;
    std::string defines_;
    struct Progressive {
        gl::Buffer accum, diagnostics;
        std::unique_ptr<FrameGpu> frame;
        int width = 0, height = 0;
        int sample = 0, row = 0;  // the next tile
    } progressive_;
    FrameGpu make_frame(const Camera& camera, int width, int height) const;
    // The mode's depth, program and environment distribution from requested_max_depth_ and the
    // scene's features; commits only once the program built (constructor and set_mode).
    void select_program(Mode mode);
    mutable bool warned_orthographic_lens_ = false;
    // Motion blur: the time slice the geometry holds (-1: the frame's time or unknown).
    int posed_slice_ = -1;
    int slice_count() const;
    float slice_time(int slice) const;
    int slice_of(int sample) const;
    void refresh_counts(FrameGpu& f) const;  // the geometry's counts and emitted power into f
    // Poses the scene at the slice and refits the geometry (unless it holds it already); adds the
    // times to `result` when given. Returns whether the geometry changed.
    bool pose_slice(int slice, FrameGpu& f, Result* result);
    void pose_frame_time(Result* result);  // pose_at(0.5), rebuild at the frame's time
    void bind(const gl::Buffer& accum, const gl::Buffer& diagnostics) const;
};

}  // namespace candela::rt
