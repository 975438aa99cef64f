#pragma once
// Still images of a scene with the current GL context: what `candela render`, the golden tests
// and `candela bench frame` all do, so that they cannot drift apart.
#include <map>
#include <memory>
#include <string>
#include <vector>

#include "image/image.hpp"
#include "render/renderer.hpp"
#include "scene/scene.hpp"
#include "shader/shader_library.hpp"

namespace candela {

struct StillOptions {
    int width = 512;   // pixels, 1..16384
    int height = 512;
    std::string camera;  // glTF camera index or name; empty: first camera, else framing camera
    RenderSettings settings;
    int frames = 1;   // measured frames [1, 100000]; the image is the last one
    int warmup = 0;   // frames rendered first and not measured [0, 100000]
    bool verify_state = false;
    FrameOutput output = FrameOutput::hdr;  // display: also run the GPU tonemap pass
    float exposure_ev = 0.0f;
    // Animation: the scene is already posed at `time` of `animation` (-1: none); with
    // settings.camera.shutter > 0 the loop adds the motion over the shutter (raster motion blur).
    int animation = -1;
    float time = 0.0f;
    // Programs shared by the renderers of a batch (built from the same ShaderLibrary in this
    // context; must outlive the loop); nullptr: the renderer builds its own.
    ProgramCache* programs = nullptr;
    // A worker context that makes the textures' mipmaps beside the main thread (GpuScene); must
    // outlive the loop. nullptr: made on the main thread at first use. The image is the same.
    GlWorker* mip_worker = nullptr;
};

struct StillResult {
    ImageF radiance;  // linear, RGBA32F, top row first
    std::vector<std::uint8_t> display;  // RGBA8 display values when FrameOutput::display
    FrameReport report;  // the last frame; pass gpu_ms = median over the measured frames
    Features features;
    std::vector<double> frame_ms;  // wall time of each measured frame (render + glFinish)
    double upload_ms = 0, shader_ms = 0, readback_ms = 0;
    double median_frame_ms() const;
};

double median(std::vector<double> values);
// {25th, 75th} percentiles (linear interpolation).
std::pair<double, double> quartiles(std::vector<double> values);

// One renderer kept across frames: warm-up, measured frames, and the result with per-pass medians.
// Throws candela::Error: bad_input for an unknown camera or an option out of range, internal
// for shader/framebuffer failures.
class FrameLoop {
public:
    FrameLoop(const Scene& scene, const ShaderLibrary& shaders, const StillOptions& options);
    void warmup(int frames);
    double measure_frame();  // render + glFinish; returns the wall time in ms
    StillResult finish();    // reads the image back; pass gpu_ms are medians over measured frames
    // Poses `scene` (the scene this loop was made with) at `time` of `animation` (-1: the rest
    // pose), updates the GPU copy, the motion over the shutter and the camera (it may be animated).
    void set_pose(Scene& scene, int animation, float time);
    GpuScene& gpu() { return *gpu_; }
    Renderer& renderer() { return *renderer_; }

private:
    StillOptions options_;
    Camera camera_;
    StillResult result_;
    std::unique_ptr<GpuScene> gpu_;
    std::unique_ptr<Renderer> renderer_;
    std::map<std::string, std::vector<double>> gpu_ms_;
};

// The motion over the shutter around `time` (shutter_interval with camera.shutter and camera.fps)
// into gpu.set_motion, or clear_motion when the shutter is closed or nothing is animated.
void update_motion(const Scene& scene, GpuScene& gpu, int animation, float time, const RenderSettings& settings);

StillResult render_still(const Scene& scene, const ShaderLibrary& shaders, const StillOptions& options);

}  // namespace candela
