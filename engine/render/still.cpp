#include "render/still.hpp"

#include <algorithm>
#include <chrono>
#include <map>

#include "core/error.hpp"

namespace candela {
namespace {
double ms_since(std::chrono::steady_clock::time_point t0) {
    return std::chrono::duration<double, std::milli>(std::chrono::steady_clock::now() - t0).count();
}
double percentile(std::vector<double> v, double q) {
    if (v.empty()) return 0.0;
    std::sort(v.begin(), v.end());
    const double pos = q * static_cast<double>(v.size() - 1);
    const size_t i = static_cast<size_t>(pos);
    const double f = pos - static_cast<double>(i);
    return i + 1 < v.size() ? v[i] * (1.0 - f) + v[i + 1] * f : v[i];
}
}  // namespace

double median(std::vector<double> values) { return percentile(std::move(values), 0.5); }
std::pair<double, double> quartiles(std::vector<double> values) { return {percentile(values, 0.25), percentile(values, 0.75)}; }
double StillResult::median_frame_ms() const { return median(frame_ms); }

FrameLoop::FrameLoop(const Scene& scene, const ShaderLibrary& shaders, const StillOptions& options) : options_(options) {
    if (options.width < 1 || options.height < 1 || options.width > 16384 || options.height > 16384)
        throw bad_input("--size " + std::to_string(options.width) + "x" + std::to_string(options.height) +
                        " is out of range (1..16384 per side)");
    if (options.frames < 1 || options.frames > 100000) throw bad_input("--frames must be in [1, 100000]");
    if (options.warmup < 0 || options.warmup > 100000) throw bad_input("--warmup must be in [0, 100000]");
    camera_ = scene.select_camera(options.camera, static_cast<float>(options.width) / static_cast<float>(options.height));
    auto t0 = std::chrono::steady_clock::now();
    gpu_ = std::make_unique<GpuScene>(scene, options.mip_worker, &shaders);
    result_.upload_ms = ms_since(t0);
    t0 = std::chrono::steady_clock::now();
    update_motion(scene, *gpu_, options.animation, options.time, options.settings);
    renderer_ = std::make_unique<Renderer>(shaders, scene, *gpu_, options.settings, options.programs);
    renderer_->set_view(camera_, options.width, options.height);
    renderer_->set_verify_state(options.verify_state);
    result_.shader_ms = ms_since(t0);
    result_.features = renderer_->features();
}

void FrameLoop::warmup(int frames) {
    for (int i = 0; i < frames; ++i) renderer_->render(camera_, options_.width, options_.height, options_.output, options_.exposure_ev);
    glFinish();
}

double FrameLoop::measure_frame() {
    const auto t0 = std::chrono::steady_clock::now();
    renderer_->render(camera_, options_.width, options_.height, options_.output, options_.exposure_ev);
    glFinish();
    const double ms = ms_since(t0);
    result_.frame_ms.push_back(ms);
    renderer_->resolve_gpu_times();
    for (const auto& p : renderer_->last_frame().passes)
        if (p.gpu_ms >= 0.0) gpu_ms_[p.name].push_back(p.gpu_ms);  // -1: the driver's answer was impossible
    return ms;
}

StillResult FrameLoop::finish() {
    result_.report = renderer_->last_frame();
    result_.features = renderer_->features();  // as the frames planned (motion in view is counted per frame)
    for (auto& p : result_.report.passes) p.gpu_ms = gpu_ms_[p.name].empty() ? -1.0 : median(gpu_ms_[p.name]);
    // The images go straight into the returned result (result_ never holds them: copying a
    // 1280x720 float image cost about 7 ms of a 0.4 s render).
    StillResult out = result_;
    const auto t0 = std::chrono::steady_clock::now();
    out.radiance = renderer_->read_radiance();
    if (options_.output == FrameOutput::display) out.display = renderer_->read_display();
    out.readback_ms = ms_since(t0);
    return out;
}

void update_motion(const Scene& scene, GpuScene& gpu, int animation, float time, const RenderSettings& settings) {
    const ShutterInterval shutter = shutter_interval(time, settings.camera.shutter, settings.camera.fps);
    if (animation < 0 || shutter.instant()) return gpu.clear_motion();
    gpu.set_motion(evaluate_pose(scene, animation, shutter.open), evaluate_pose(scene, animation, shutter.close));
}

void FrameLoop::set_pose(Scene& scene, int animation, float time) {
    pose_scene(scene, animation, time);
    gpu_->update_pose();
    update_motion(scene, *gpu_, animation, time, options_.settings);
    options_.animation = animation;
    options_.time = time;
    // A glTF camera follows its (maybe animated) node; the framing camera stays where the first
    // frame put it, so a sequence does not zoom with the pose's bounds.
    const Camera c = scene.select_camera(options_.camera, static_cast<float>(options_.width) / static_cast<float>(options_.height));
    if (c.node >= 0) camera_ = c;
}

StillResult render_still(const Scene& scene, const ShaderLibrary& shaders, const StillOptions& options) {
    FrameLoop loop(scene, shaders, options);
    loop.warmup(options.warmup);
    for (int i = 0; i < options.frames; ++i) loop.measure_frame();
    return loop.finish();
}

}  // namespace candela
