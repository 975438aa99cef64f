#include "accuracy.hpp"

#include <unistd.h>

#include <algorithm>
#include <chrono>
#include <cmath>
#include <cstdio>
#include <cstdlib>
#include <cstring>
#include <ctime>
#include <fstream>
#include <functional>
#include <limits>
#include <map>
#include <optional>
#include <sstream>

#include <nlohmann/json.hpp>

#include "core/error.hpp"
#include "core/log.hpp"
#include "effects/accuracy_sweep.hpp"
#include "image/image.hpp"
#include "render/features.hpp"
#include "render/renderer.hpp"
#include "render/still.hpp"
#include "rt/ray_tracer.hpp"
#include "rt/tracer_options.hpp"
#include "scene/animation.hpp"
#include "scene/generate.hpp"
#include "scene/gltf_loader.hpp"

namespace candela::cli {
namespace {
namespace fs = std::filesystem;
using Clock = std::chrono::steady_clock;
constexpr double kNaN = std::numeric_limits<double>::quiet_NaN();
using Buffer = AccuracySweep::Buffer;  // what a raster variant outputs, and how it is compared

struct Row {
    std::string effect, variant, settings, scene;
    int width = 0, height = 0;
    double ms = kNaN, iqr = kNaN, frame_ms = kNaN;
    double rmse = kNaN, relmse = kNaN, max_abs = kNaN, pct_over = kNaN, flip = kNaN;
    double rmse_no_occlusion = kNaN;
    int ref_spp = 0;
    double ref_noise = kNaN;
    bool pareto = false, at_noise_floor = false;
    ImageF image;  // raster output (kept for the strips)
};

std::string join(const std::vector<std::string>& v, const char* sep) {
    std::string s;
    for (const auto& x : v) s += (s.empty() ? "" : sep) + x;
    return s;
}

std::string num(double v, const char* f = "%.4g") {
    if (!std::isfinite(v)) return "";
    char b[64];
    std::snprintf(b, sizeof b, f, v);
    return b;
}

// The sweeps: every effect's own (effects/*/*_sweep.cpp), then the three that belong to no effect.
// Each reading says what the error is made of; the numbers come from the run.
std::vector<AccuracySweep> make_sweeps(bool quick) {
    std::vector<AccuracySweep> sweeps = effect_accuracy_sweeps(quick);
    {
        AccuracySweep s;
        s.effect = "forward_deferred";
        s.compared = "time only: the whole frame without effects, forward vs deferred, by light count (generated:lights:N)";
        s.reading = "Forward shading loops over every light per fragment (overdraw included); deferred pays the "
                    "G-buffer once and culls lights per 16x16 tile. The crossing point sets deferred.auto_lights.";
        sweeps.push_back(s);
    }
    {
        AccuracySweep s;
        s.effect = "ray_tracer";
        s.scene = "cornell_box.gltf";
        s.compared = "`--raytrace path` at rising spp vs a high-spp render of itself: the price of the truth";
        s.reading = "Monte Carlo error falls as 1/sqrt(spp) while time grows linearly: each halving of the error "
                    "costs four times the time.";
        sweeps.push_back(s);
    }
    {
        AccuracySweep s;
        s.effect = "ray_tracer_depth";
        s.scene = "cornell_box.gltf";
        s.compared = "`--raytrace path --max-depth N` vs the default (no cap: Russian roulette ends paths), same seed and "
                     "spp, so both follow the same paths up to the cap and the difference is the truncation bias alone";
        s.reading = "A cap of N drops the light that arrives after more than N bounces: -a^(N+1) of the radiance in a "
                    "closed box of albedo a, a bias no number of samples removes. It saves the time of the long paths; "
                    "the default pays it so that the reference is unbiased.";
        sweeps.push_back(s);
    }
    return sweeps;
}

struct Progress {
    int done = 0, total = 0;
    bool tty = isatty(STDERR_FILENO) != 0;
    Clock::time_point start = Clock::now();
    void step(const std::string& what) {
        ++done;
        if (!tty) return;
        const int width = 30, filled = total > 0 ? std::min(width, done * width / total) : width;
        const double s = std::chrono::duration<double>(Clock::now() - start).count();
        const double eta = done > 0 ? s / done * (total - done) : 0.0;
        std::fprintf(stderr, "\r[%.*s%.*s] %d/%d %-40.40s ETA %.0f s ", filled, "##############################", width - filled,
                     "                              ", done, total, what.c_str(), eta);
        if (done >= total) std::fprintf(stderr, "\n");
    }
};

struct Run {
    const AccuracyOptions& o;
    const ShaderLibrary& shaders;
    int width, height, warmup, frames;
    Progress& progress;
};

Scene load(const AccuracyOptions& o, const std::string& name) {
    if (name.rfind("generated:lights:", 0) == 0) return make_many_lights_scene(std::stoi(name.substr(17)));
    if (name == "generated:dof") return make_dof_scene();
    if (name == "generated:edges") return make_edges_scene();
    if (name == "generated:motion") return make_motion_scene();
    const fs::path p = fs::path(name).has_parent_path() ? fs::path(name) : o.scene_dir / name;
    return load_gltf(p);
}

// The time a sweep's scene is shown at, and its shutter. Animated scenes (motion blur) are posed
// at a fixed time: animation 0 at its midpoint, (start + end) / 2; the shutter (camera.shutter of
// the sweep's first variant, at camera.fps) is centred on it. The raster frame is the pose at that
// time with GpuScene::set_motion of the poses at open and close; the tracer poses the scene at
// its samples' times in the shutter (rt::Options::pose_at).
struct SceneTime {
    Scene* scene = nullptr;
    int animation = -1;  // -1: not animated
    float time = 0.0f;
    ShutterInterval shutter;
    bool moving() const { return scene && animation >= 0 && !shutter.instant(); }
};

SceneTime pose_for_sweep(Scene& scene, const RenderSettings& s) {
    SceneTime t;
    t.scene = &scene;
    if (scene.animations.empty()) return t;
    t.animation = 0;
    const Animation& a = scene.animations.front();
    t.time = 0.5f * (a.start + a.end);
    t.shutter = shutter_interval(t.time, s.camera.shutter, s.camera.fps);
    pose_scene(scene, t.animation, t.time);
    return t;
}

// The raster side: the poses at shutter open and close (the frame's pose is the scene's own).
void set_sweep_motion(GpuScene& gpu, const SceneTime& t) {
    if (t.moving()) gpu.set_motion(evaluate_pose(*t.scene, t.animation, t.shutter.open), evaluate_pose(*t.scene, t.animation, t.shutter.close));
}

rt::Result trace(const Run& c, const Scene& scene, GpuScene& gpu, const AccuracySweep::Reference& r, int spp, std::uint32_t seed,
                 const RenderSettings& settings, const SceneTime* motion = nullptr) {
    rt::Options o = rt::tracer_options(settings);
    if (motion && motion->moving()) {
        // The exact motion blur: each time slice of the shutter poses the scene (the tracer leaves
        // it at the shutter's centre, the sweep's time, when it is done).
        const SceneTime m = *motion;
        o.pose_at = [m](float u) { pose_scene(*m.scene, m.animation, m.shutter.open + u * (m.shutter.close - m.shutter.open)); };
    }
    o.mode = r.mode;
    o.spp = spp;
    o.max_depth = r.max_depth;
    o.jitter = r.jitter;
    o.seed = seed;
    o.indirect_occlusion = r.indirect_occlusion;
    o.visibility_light = 0;  // the references are radiance, whatever debug.light says
    rt::RayTracer tracer(c.shaders, scene, gpu, o);
    // The variant's lens (camera.aperture / camera.focus_distance) over the camera's own, as the
    // raster renderer applies it.
    const Camera camera = with_lens(scene.select_camera("", static_cast<float>(c.width) / static_cast<float>(c.height)), settings);
    return tracer.render(camera, c.width, c.height);
}

// The mean of two seeds, and its noise: RMSE(a, b) / 2 (each seed has sigma = RMSE / sqrt 2; the
// mean of two has sigma / sqrt 2).
struct Reference {
    ImageF image;
    ImageF half_diff;  // (seed 1 - seed 2) / 2: the mean's noise, per pixel
    double noise = 0.0;
    double ms = 0.0;  // the tracer's time for this reference (both seeds)
    int spp = 0;
};

Reference make_reference(const Run& c, const Scene& scene, GpuScene& gpu, const AccuracySweep::Reference& r, const RenderSettings& s,
                         const SceneTime* motion = nullptr) {
    const rt::Result a = trace(c, scene, gpu, r, r.spp, 1, s, motion);
    const rt::Result b = trace(c, scene, gpu, r, r.spp, 2, s, motion);
    if (count_nonfinite(a.image) || count_nonfinite(b.image) || a.nonfinite_samples || b.nonfinite_samples)
        throw Error(ExitCode::internal, std::string("accuracy: non-finite values in a ") + rt::to_string(r.mode) + " reference");
    Reference ref;
    ref.image = a.image;
    for (size_t i = 0; i < ref.image.pixels.size(); ++i) ref.image.pixels[i] = 0.5f * (a.image.pixels[i] + b.image.pixels[i]);
    ref.noise = compare(a.image, b.image, 2.0 / 255.0).rmse / 2.0;
    ref.half_diff = a.image;
    for (size_t i = 0; i < ref.half_diff.pixels.size(); ++i) ref.half_diff.pixels[i] = 0.5f * (a.image.pixels[i] - b.image.pixels[i]);
    ref.ms = a.trace_ms + b.trace_ms;
    ref.spp = 2 * r.spp;
    return ref;
}

// AccuracySweep::Region::edges: the pixels whose 3x3 neighbourhood in the reference spans more than
// a tenth of its largest luminance.
std::vector<bool> edge_mask(const ImageF& ref) {
    const int w = ref.width, h = ref.height;
    auto lum = [&](int x, int y) {
        const float* p = ref.at(std::clamp(x, 0, w - 1), std::clamp(y, 0, h - 1));
        return 0.2126 * p[0] + 0.7152 * p[1] + 0.0722 * p[2];
    };
    double top = 0.0;
    for (int y = 0; y < h; ++y)
        for (int x = 0; x < w; ++x) top = std::max(top, lum(x, y));
    std::vector<bool> mask(static_cast<size_t>(w) * static_cast<size_t>(h), false);
    for (int y = 0; y < h; ++y)
        for (int x = 0; x < w; ++x) {
            double lo = 1e30, hi = -1e30;
            for (int j = -1; j <= 1; ++j)
                for (int i = -1; i <= 1; ++i) lo = std::min(lo, lum(x + i, y + j)), hi = std::max(hi, lum(x + i, y + j));
            mask[static_cast<size_t>(y) * static_cast<size_t>(w) + static_cast<size_t>(x)] = hi - lo > 0.1 * top;
        }
    return mask;
}

// The errors over the edge pixels only (RMSE over RGB, relative MSE, max, share over 2/255 after
// tone mapping) and the reference's noise there.
void measure_edge_errors(Row& row, const ImageF& img, const Reference& ref) {
    const std::vector<bool> mask = edge_mask(ref.image);
    const ImageF a = to_display(img, 0.0f), b = to_display(ref.image, 0.0f);
    double se = 0, rel = 0, noise = 0, mx = 0;
    size_t n = 0, over = 0;
    for (int y = 0; y < img.height; ++y)
        for (int x = 0; x < img.width; ++x) {
            if (!mask[static_cast<size_t>(y) * static_cast<size_t>(img.width) + static_cast<size_t>(x)]) continue;
            ++n;
            bool failing = false;
            for (int c = 0; c < 3; ++c) {
                const double d = img.at(x, y)[c] - ref.image.at(x, y)[c];
                se += d * d;
                rel += d * d / (ref.image.at(x, y)[c] * ref.image.at(x, y)[c] + 1e-2);
                noise += static_cast<double>(ref.half_diff.at(x, y)[c]) * ref.half_diff.at(x, y)[c];
                mx = std::max(mx, std::abs(d));
                failing = failing || std::abs(a.at(x, y)[c] - b.at(x, y)[c]) > 2.0 / 255.0;
            }
            over += failing ? 1 : 0;
        }
    const double k = std::max<double>(1.0, 3.0 * static_cast<double>(n));
    row.rmse = std::sqrt(se / k);
    row.relmse = rel / k;
    row.max_abs = mx;
    row.pct_over = 100.0 * static_cast<double>(over) / std::max<double>(1.0, static_cast<double>(n));
    row.ref_spp = ref.spp;
    row.ref_noise = std::sqrt(noise / k);
    row.at_noise_floor = row.ref_noise > 0.0 && row.rmse <= 1.5 * row.ref_noise;
}

void measure_errors(Row& row, const ImageF& img, const Reference& ref, Buffer buffer) {
    const CompareResult m = compare(img, ref.image, 2.0 / 255.0);
    row.rmse = m.rmse;
    row.relmse = m.relative_mse;
    row.max_abs = m.max_abs;
    // Radiance is judged after tone mapping; AO and visibility are already in [0, 1].
    const bool display = buffer == Buffer::radiance || buffer == Buffer::indirect;
    row.pct_over = 100.0 * (display ? compare(to_display(img, 0.0f), to_display(ref.image, 0.0f), 2.0 / 255.0) : m).failing_fraction;
    row.ref_spp = ref.spp;
    row.ref_noise = ref.noise;
    row.at_noise_floor = ref.noise > 0.0 && row.rmse <= 1.5 * ref.noise;
}

RenderSettings variant_settings(const AccuracySweep& s, const AccuracySweep::Variant& v) {
    RenderSettings rs;
    apply_effects(rs, v.effects);
    apply_knobs(rs, v.knobs);
    if (s.buffer == Buffer::visibility) rs.debug.view = DebugView::visibility, rs.debug.light = 0;
    if (s.buffer == Buffer::ao) rs.debug.view = DebugView::ao;
    if (s.buffer == Buffer::indirect) rs.debug.view = DebugView::indirect;
    return rs;
}

// Times and images of the raster variants of one sweep on one scene (one renderer, so shader
// compilation is paid once per program).
void raster_rows(const Run& c, const AccuracySweep& s, const Scene& scene, GpuScene& gpu, std::vector<Row>& rows) {
    std::unique_ptr<Renderer> renderer;
    const Camera camera = scene.select_camera("", static_cast<float>(c.width) / static_cast<float>(c.height));
    for (const AccuracySweep::Variant& v : s.variants) {
        const RenderSettings rs = variant_settings(s, v);
        if (!renderer) {
            renderer = std::make_unique<Renderer>(c.shaders, scene, gpu, rs);
            renderer->set_synchronous_timing(true);
        } else {
            renderer->set_settings(rs);
        }
        for (int i = 0; i < c.warmup; ++i) renderer->render(camera, c.width, c.height);
        glFinish();
        std::vector<double> own, frame;
        for (int i = 0; i < c.frames; ++i) {
            const auto t0 = Clock::now();
            renderer->render(camera, c.width, c.height);
            glFinish();
            frame.push_back(std::chrono::duration<double, std::milli>(Clock::now() - t0).count());
            renderer->resolve_gpu_times();
            double sum = 0.0;
            bool valid = true;
            for (const PassStats& p : renderer->last_frame().passes) {
                const bool mine = s.own_passes.empty() || std::find(s.own_passes.begin(), s.own_passes.end(), p.name) != s.own_passes.end();
                if (!mine) continue;
                if (p.sync_ms < 0.0) valid = false;
                sum += p.sync_ms;
            }
            if (valid) own.push_back(sum);
        }
        Row row;
        row.effect = s.effect;
        row.variant = v.name;
        row.settings = "--effects " + v.effects + (v.knobs.empty() ? "" : " --set " + join(v.knobs, " --set "));
        row.scene = s.scene;
        row.width = c.width;
        row.height = c.height;
        if (!own.empty()) {
            row.ms = median(own);
            const auto [q1, q3] = quartiles(own);
            row.iqr = q3 - q1;
        }
        row.frame_ms = median(frame);
        row.image = renderer->read_radiance();
        if (count_nonfinite(row.image)) throw Error(ExitCode::internal, s.effect + " " + v.name + ": non-finite values in the raster image");
        rows.push_back(std::move(row));
        c.progress.step(s.effect + ": " + v.name);
    }
}

void mark_pareto(std::vector<Row>& rows, size_t first) {
    for (size_t i = first; i < rows.size(); ++i) {
        Row& r = rows[i];
        if (!std::isfinite(r.ms) || !std::isfinite(r.rmse)) continue;
        r.pareto = true;
        for (size_t j = first; j < rows.size(); ++j) {
            const Row& o = rows[j];
            if (j == i || !std::isfinite(o.ms) || !std::isfinite(o.rmse)) continue;
            if (o.ms <= r.ms && o.rmse <= r.rmse && (o.ms < r.ms || o.rmse < r.rmse)) {
                r.pareto = false;
                break;
            }
        }
    }
}

// The Pareto row nearest the utopia point (least time and least error) in log-log.
int knee(const std::vector<Row>& rows, size_t first, size_t last) {
    double min_ms = 1e30, min_e = 1e30;
    for (size_t i = first; i < last; ++i)
        if (rows[i].pareto) min_ms = std::min(min_ms, std::max(rows[i].ms, 1e-3)), min_e = std::min(min_e, std::max(rows[i].rmse, 1e-6));
    int best = -1;
    double best_d = 1e30;
    for (size_t i = first; i < last; ++i) {
        if (!rows[i].pareto) continue;
        const double dx = std::log10(std::max(rows[i].ms, 1e-3) / min_ms), dy = std::log10(std::max(rows[i].rmse, 1e-6) / min_e);
        if (dx * dx + dy * dy < best_d) best_d = dx * dx + dy * dy, best = static_cast<int>(i);
    }
    return best;
}

// log ms (x) against log RMSE (y): every row, the Pareto front, the reference's noise floor and
// the ray tracer's time.
void write_plot(const fs::path& path, const std::string& title, const std::vector<Row>& rows, double noise, double rt_ms) {
    const double W = 640, H = 400, L = 70, R = 20, T = 30, B = 50;
    double x0 = 1e30, x1 = -1e30, y0 = 1e30, y1 = -1e30;
    auto lx = [](double ms) { return std::log10(std::max(ms, 1e-3)); };
    auto ly = [](double e) { return std::log10(std::max(e, 1e-6)); };
    for (const Row& r : rows) {
        if (!std::isfinite(r.ms) || !std::isfinite(r.rmse)) continue;
        x0 = std::min(x0, lx(r.ms)), x1 = std::max(x1, lx(r.ms));
        y0 = std::min(y0, ly(r.rmse)), y1 = std::max(y1, ly(r.rmse));
    }
    if (x0 > x1) return;
    if (noise > 0) y0 = std::min(y0, ly(noise)), y1 = std::max(y1, ly(noise));
    if (rt_ms > 0) x0 = std::min(x0, lx(rt_ms)), x1 = std::max(x1, lx(rt_ms));
    x0 = std::floor(x0 - 0.05), x1 = std::ceil(x1 + 0.05), y0 = std::floor(y0 - 0.05), y1 = std::ceil(y1 + 0.05);
    auto px = [&](double v) { return L + (v - x0) / (x1 - x0) * (W - L - R); };
    auto py = [&](double v) { return H - B - (v - y0) / (y1 - y0) * (H - T - B); };
    std::ofstream f(path);
    f << "<svg xmlns=\"http://www.w3.org/2000/svg\" width=\"" << W << "\" height=\"" << H << "\" font-family=\"sans-serif\" font-size=\"11\">\n";
    f << "<rect width=\"100%\" height=\"100%\" fill=\"white\"/>\n";
    f << "<text x=\"" << W / 2 << "\" y=\"18\" text-anchor=\"middle\" font-size=\"14\">" << title << "</text>\n";
    for (double d = x0; d <= x1 + 1e-9; d += 1.0) {
        f << "<line x1=\"" << px(d) << "\" y1=\"" << T << "\" x2=\"" << px(d) << "\" y2=\"" << H - B << "\" stroke=\"#ddd\"/>\n";
        f << "<text x=\"" << px(d) << "\" y=\"" << H - B + 15 << "\" text-anchor=\"middle\">" << num(std::pow(10.0, d), "%g") << "</text>\n";
    }
    for (double d = y0; d <= y1 + 1e-9; d += 1.0) {
        f << "<line x1=\"" << L << "\" y1=\"" << py(d) << "\" x2=\"" << W - R << "\" y2=\"" << py(d) << "\" stroke=\"#ddd\"/>\n";
        f << "<text x=\"" << L - 5 << "\" y=\"" << py(d) + 4 << "\" text-anchor=\"end\">" << num(std::pow(10.0, d), "%g") << "</text>\n";
    }
    f << "<text x=\"" << W / 2 << "\" y=\"" << H - 12 << "\" text-anchor=\"middle\">ms of the effect's passes (log)</text>\n";
    f << "<text transform=\"translate(16," << (H - B + T) / 2 << ") rotate(-90)\" text-anchor=\"middle\">RMSE vs reference (log)</text>\n";
    if (noise > 0)
        f << "<line x1=\"" << L << "\" y1=\"" << py(ly(noise)) << "\" x2=\"" << W - R << "\" y2=\"" << py(ly(noise))
          << "\" stroke=\"#36c\" stroke-dasharray=\"6,4\"/><text x=\"" << W - R - 4 << "\" y=\"" << py(ly(noise)) - 4
          << "\" text-anchor=\"end\" fill=\"#36c\">reference noise</text>\n";
    if (rt_ms > 0)
        f << "<line x1=\"" << px(lx(rt_ms)) << "\" y1=\"" << T << "\" x2=\"" << px(lx(rt_ms)) << "\" y2=\"" << H - B
          << "\" stroke=\"#c63\" stroke-dasharray=\"6,4\"/><text x=\"" << px(lx(rt_ms)) - 4 << "\" y=\"" << T + 12
          << "\" text-anchor=\"end\" fill=\"#c63\">ray tracer</text>\n";
    std::vector<const Row*> front;
    for (const Row& r : rows)
        if (r.pareto) front.push_back(&r);
    std::sort(front.begin(), front.end(), [](const Row* a, const Row* b) { return a->ms < b->ms; });
    if (front.size() > 1) {
        f << "<polyline fill=\"none\" stroke=\"#d22\" stroke-width=\"1.5\" points=\"";
        for (const Row* r : front) f << px(lx(r->ms)) << "," << py(ly(r->rmse)) << " ";
        f << "\"/>\n";
    }
    for (const Row& r : rows) {
        if (!std::isfinite(r.ms) || !std::isfinite(r.rmse)) continue;
        f << "<circle cx=\"" << px(lx(r.ms)) << "\" cy=\"" << py(ly(r.rmse)) << "\" r=\"4\" fill=\"" << (r.pareto ? "#d22" : "#999")
          << "\"/><text x=\"" << px(lx(r.ms)) + 6 << "\" y=\"" << py(ly(r.rmse)) - 5 << "\" font-size=\"9\" fill=\"#555\">" << r.variant
          << "</text>\n";
    }
    f << "</svg>\n";
}

// raster | reference | difference (red at 0.1), display values.
void write_strip(const fs::path& path, const ImageF& raster, const ImageF& reference, Buffer buffer) {
    const bool tonemap = buffer == Buffer::radiance || buffer == Buffer::indirect;
    const ImageF a = tonemap ? to_display(raster, 0.0f) : raster;
    const ImageF b = tonemap ? to_display(reference, 0.0f) : reference;
    const ImageF d = heatmap(raster, reference, 0.1);
    const int w = a.width, h = a.height, gap = 4;
    ImageF strip(3 * w + 2 * gap, h, 4);
    for (int y = 0; y < h; ++y)
        for (int k = 0; k < 3; ++k) {
            const ImageF& src = k == 0 ? a : k == 1 ? b : d;
            for (int x = 0; x < w; ++x) {
                float* o = strip.at(k * (w + gap) + x, y);
                const float* p = src.at(x, y);
                for (int ch = 0; ch < 3; ++ch) o[ch] = std::clamp(p[ch], 0.0f, 1.0f);
                o[3] = 1.0f;
            }
        }
    write_display_image(path, strip);
}

std::string slug(std::string s) {
    for (char& ch : s)
        if (!std::isalnum(static_cast<unsigned char>(ch))) ch = '_';
    return s;
}

// The image size and frame counts of a run, and the steps of the three sweeps that belong to no
// effect.
struct Sizes {
    int width, height, warmup, frames;
};
Sizes sizes(bool quick) { return {quick ? 128 : 320, quick ? 96 : 240, quick ? 1 : 3, quick ? 3 : 10}; }
std::vector<int> light_counts(bool quick) { return quick ? std::vector<int>{4, 16} : std::vector<int>{4, 16, 64}; }
std::vector<int> spp_steps(bool quick) { return quick ? std::vector<int>{1, 4, 16} : std::vector<int>{1, 4, 16, 64}; }
std::vector<int> depth_steps(bool quick) { return quick ? std::vector<int>{2, 8} : std::vector<int>{2, 4, 8, 16, 32}; }

// One section of the report: a sweep on one scene.
struct Job {
    size_t sweep = 0;   // index in Plan::sweeps
    std::string scene;  // the sweep's own scene, or a given one that calls for the effect
};

struct Plan {
    std::vector<AccuracySweep> sweeps;
    std::vector<Job> jobs;
    const AccuracySweep& sweep(const Job& j) const { return sweeps[j.sweep]; }
};

// The sections in report order. Given scenes are loaded and analysed on the CPU (no GL context):
// a sweep runs on those that call for its effect.
Plan make_plan(const AccuracyOptions& o) {
    Plan plan;
    plan.sweeps = make_sweeps(o.quick);
    if (!o.effects.empty()) {
        std::vector<AccuracySweep> kept;
        for (AccuracySweep& s : plan.sweeps)
            if (std::find(o.effects.begin(), o.effects.end(), s.effect) != o.effects.end()) kept.push_back(std::move(s));
        if (kept.empty()) throw bad_input("bench accuracy: no section named by --effect");
        plan.sweeps = std::move(kept);
    }
    std::vector<Features> features;  // of each given scene, loaded once
    for (const std::string& name : o.scenes) features.push_back(analyze(load(o, name), RenderSettings{}));
    for (size_t i = 0; i < plan.sweeps.size(); ++i) {
        const AccuracySweep& s = plan.sweeps[i];
        if (s.effect == "forward_deferred" || s.effect == "ray_tracer" || s.effect == "ray_tracer_depth" || o.scenes.empty()) {
            plan.jobs.push_back({i, s.scene});
            continue;
        }
        for (size_t k = 0; k < o.scenes.size(); ++k)
            if (s.needed(features[k])) plan.jobs.push_back({i, o.scenes[k]});
    }
    return plan;
}

// The scene a section's heading names (forward_deferred runs on generated scenes of N lights).
std::string section_scene(const AccuracySweep& s, const std::string& scene) {
    return s.effect == "forward_deferred" ? "generated:lights:N" : scene;
}
std::string job_label(const Plan& plan, const Job& j) {
    const AccuracySweep& s = plan.sweep(j);
    return s.effect + " on " + section_scene(s, j.scene);
}

// The progress steps of a section (references and rows).
int job_steps(const AccuracySweep& s, bool quick) {
    if (s.effect == "forward_deferred") return 2 * static_cast<int>(light_counts(quick).size());
    if (s.effect == "ray_tracer") return static_cast<int>(spp_steps(quick).size()) + 1;
    if (s.effect == "ray_tracer_depth") return static_cast<int>(depth_steps(quick).size()) + 1;
    return static_cast<int>(s.variants.size()) + 1 + (s.split ? 1 : 0);
}

// A section's result: its rows are rows[first, last) of the run's row list.
struct Section {
    const AccuracySweep* sweep = nullptr;
    std::string scene;
    size_t first = 0, last = 0;
    double noise = 0, rt_ms = 0;
    int ref_spp = 0;
    double occlusion_rmse = kNaN;  // a split sweep: RMSE of the reference with vs without occlusion
    ImageF reference;
    std::string knee_name;         // the knee of the Pareto front (empty: none), for the saved section
    std::string device, backend;   // where it ran
    double seconds = 0;            // how long it took
};

// Runs one section, appending its rows to `rows`.
Section run_job(const Run& c, const AccuracySweep& s, const std::string& job_scene, std::vector<Row>& rows) {
    const AccuracyOptions& o = c.o;
    Progress& progress = c.progress;
    const auto start = Clock::now();
    Section sec;
    sec.sweep = &s;
    sec.scene = section_scene(s, job_scene);
    sec.first = rows.size();
    if (s.effect == "forward_deferred") {
        for (int n : light_counts(o.quick)) {
            const std::string name = "generated:lights:" + std::to_string(n);
            const Scene scene = load(o, name);
            GpuScene gpu(scene);
            AccuracySweep t = s;
            t.scene = name;
            // No effects: the shading itself (an effect's passes would cost the same on both paths).
            t.variants = {{"forward " + std::to_string(n) + " lights", "none", {"render.path=forward"}},
                          {"deferred " + std::to_string(n) + " lights", "none", {"render.path=deferred"}}};
            raster_rows(c, t, scene, gpu, rows);
        }
    } else if (s.effect == "ray_tracer") {
        const Scene scene = load(o, job_scene);
        GpuScene gpu(scene);
        const AccuracySweep::Reference path{rt::Mode::path, o.quick ? 32 : 256};
        const Reference ref = make_reference(c, scene, gpu, path, RenderSettings{});
        progress.step("ray_tracer: reference");
        sec.noise = ref.noise;
        sec.ref_spp = ref.spp;
        sec.reference = ref.image;
        for (int spp : spp_steps(o.quick)) {
            const rt::Result r = trace(c, scene, gpu, path, spp, 7, RenderSettings{});
            Row row;
            row.effect = s.effect;
            row.variant = std::to_string(spp) + " spp";
            row.settings = "--raytrace path --spp " + std::to_string(spp);
            row.scene = job_scene;
            row.width = c.width;
            row.height = c.height;
            row.ms = r.trace_ms;
            row.iqr = 0.0;
            row.frame_ms = r.trace_ms;
            row.image = r.image;
            measure_errors(row, r.image, ref, Buffer::radiance);
            rows.push_back(std::move(row));
            progress.step("ray_tracer: " + std::to_string(spp) + " spp");
        }
    } else if (s.effect == "ray_tracer_depth") {
        const Scene scene = load(o, job_scene);
        GpuScene gpu(scene);
        const int spp = o.quick ? 16 : 64;
        auto row_for = [&](int depth) {
            AccuracySweep::Reference r{rt::Mode::path, spp};
            r.max_depth = depth;
            const rt::Result res = trace(c, scene, gpu, r, spp, 7, RenderSettings{});
            Row row;
            row.effect = s.effect;
            row.variant = depth < 0 ? std::string("no cap (default)") : "max depth " + std::to_string(depth);
            row.settings = "--raytrace path --spp " + std::to_string(spp) + (depth < 0 ? "" : " --max-depth " + std::to_string(depth));
            row.scene = job_scene;
            row.width = c.width;
            row.height = c.height;
            row.ms = row.frame_ms = res.trace_ms;
            row.iqr = 0.0;
            row.image = res.image;
            return row;
        };
        Row unbounded = row_for(-1);
        progress.step("ray_tracer_depth: no cap");
        // The same paths up to the cap: no noise between the rows, only the dropped light.
        const Reference ref{unbounded.image, {}, 0.0, unbounded.ms, spp};
        sec.noise = 0.0;
        sec.ref_spp = spp;
        sec.reference = ref.image;
        for (int depth : depth_steps(o.quick)) {
            Row row = row_for(depth);
            measure_errors(row, row.image, ref, Buffer::radiance);
            rows.push_back(std::move(row));
            progress.step("ray_tracer_depth: max depth " + std::to_string(depth));
        }
        measure_errors(unbounded, unbounded.image, ref, Buffer::radiance);
        rows.push_back(std::move(unbounded));
    } else {
        Scene scene = load(o, job_scene);
        const RenderSettings base = variant_settings(s, s.variants.front());
        const SceneTime when = pose_for_sweep(scene, base);  // animated: animation 0 at its midpoint
        GpuScene gpu(scene);
        set_sweep_motion(gpu, when);
        const Reference ref = make_reference(c, scene, gpu, *s.reference, base, &when);
        progress.step(s.effect + ": reference");
        std::optional<Reference> split;
        if (s.split) {
            split = make_reference(c, scene, gpu, *s.split, base, &when);
            sec.occlusion_rmse = compare(ref.image, split->image, 2.0 / 255.0).rmse;
            progress.step(s.effect + ": reference without occlusion");
        }
        AccuracySweep t = s;
        t.scene = job_scene;
        raster_rows(c, t, scene, gpu, rows);
        for (size_t i = sec.first; i < rows.size(); ++i) {
            if (s.region == AccuracySweep::Region::edges) measure_edge_errors(rows[i], rows[i].image, ref);
            else measure_errors(rows[i], rows[i].image, ref, s.buffer);
            if (split) rows[i].rmse_no_occlusion = compare(rows[i].image, split->image, 2.0 / 255.0).rmse;
        }
        // On the edge pixels the noise is the reference's there (measure_edge_errors).
        sec.noise = s.region == AccuracySweep::Region::edges && rows.size() > sec.first ? rows[sec.first].ref_noise : ref.noise;
        sec.rt_ms = ref.ms;
        sec.ref_spp = ref.spp;
        sec.reference = ref.image;
    }
    sec.last = rows.size();
    mark_pareto(rows, sec.first);
    for (size_t i = sec.first; i < sec.last; ++i)
        if (!std::isfinite(rows[i].rmse)) rows[i].pareto = false;
    const int k = knee(rows, sec.first, sec.last);
    if (k >= 0) sec.knee_name = rows[static_cast<size_t>(k)].variant;
    sec.seconds = std::chrono::duration<double>(Clock::now() - start).count();
    return sec;
}

// OUT and the report's folder (made before a run, so that a bad path fails at once); the report.
fs::path make_output_dirs(const AccuracyOptions& o) {
    fs::create_directories(o.out);
    const fs::path report = o.report.empty() ? o.out / "report.md" : o.report;
    if (report.has_parent_path()) fs::create_directories(report.parent_path());
    return report;
}

struct Device {
    std::string device, backend;
    bool operator==(const Device&) const = default;
};

// results.csv, the plots, the strips and report.md from the sections and their rows: the one
// writer of `bench accuracy`, whether the sections ran in this process or were assembled from
// saved ones (so the two outputs cannot drift apart). Needs no GL context.
void write_outputs(const AccuracyOptions& o, const std::vector<Section>& sections, const std::vector<Row>& rows,
                   const std::vector<Device>& devices, Clock::time_point start) {
    const Sizes c = sizes(o.quick);
    const fs::path report = make_output_dirs(o);
    // Links from the report to the plots and strips.
    const fs::path link_dir = fs::relative(fs::absolute(o.out), fs::absolute(report).parent_path());
    const auto link = [&](const std::string& file) { return (link_dir / file).generic_string(); };
    // One device, as a single run has; assembled sections may have run on several.
    std::string device_md, device_text;
    for (const Device& d : devices) {
        device_md += (device_md.empty() ? "`" : ", `") + d.device + "` (" + d.backend + ")";
        device_text += (device_text.empty() ? "" : "; ") + d.device;
    }

    // results.csv
    {
        std::ofstream csv(o.out / "results.csv");
        csv << "effect,variant,settings,resolution,ms,iqr,rmse,relmse,max,pct_over,flip,ref_spp,ref_noise,pareto,scene,"
               "at_noise_floor,frame_ms,rmse_no_occlusion\n";
        for (const Row& r : rows)
            csv << r.effect << ",\"" << r.variant << "\",\"" << r.settings << "\"," << r.width << "x" << r.height << "," << num(r.ms)
                << "," << num(r.iqr) << "," << num(r.rmse) << "," << num(r.relmse) << "," << num(r.max_abs) << "," << num(r.pct_over)
                << "," << num(r.flip) << "," << r.ref_spp << "," << num(r.ref_noise) << "," << (r.pareto ? 1 : 0) << "," << r.scene
                << "," << (r.at_noise_floor ? 1 : 0) << "," << num(r.frame_ms) << "," << num(r.rmse_no_occlusion) << "\n";
    }
    // Plots, strips, report.md
    std::ostringstream md;
    const std::time_t now = std::time(nullptr);
    char date[32];
    std::strftime(date, sizeof date, "%Y-%m-%d", std::gmtime(&now));
    md << "# What accuracy costs in time\n\n"
       << "Generated by `" << o.command_line << "` on " << date << ".\n\n"
       << "- Device: " << device_md << ". llvmpipe runs on the CPU: "
       << "compare times within this report, not with a GPU.\n"
       << "- Images " << c.width << "x" << c.height << "; time = median ms of the effect's own passes over " << c.frames
       << " frames after " << c.warmup << " warm-up (IQR beside it); the sample scenes' first camera. On llvmpipe the "
          "GPU is the CPU and timer queries miss the vertex shading and binning done on the GL thread, so a pass's time "
          "here is its wall time between a glFinish before and one after it (Renderer::set_synchronous_timing).\n"
       << "- Error = RMSE in linear radiance (or in the AO/visibility buffer) against the ray tracer's reference, the mean "
          "of two seeds; `% > 2/255` counts pixels off by more than 2/255 after tone mapping. Each reference's own noise "
          "(RMSE of the two seeds / 2) is printed; an error within 1.5x of it is reported as *at noise floor*. "
          "Anti-aliasing (aa) is measured on the edge pixels only: those whose 3x3 neighbourhood in the reference "
          "spans more than a tenth of its largest luminance.\n"
       << "- Animated scenes (motion blur) are shown at a fixed time: animation 0 at its midpoint, (start + end) / 2, "
          "with the shutter (camera.shutter of the sweep's first variant, a fraction of a frame at camera.fps) centred on it; "
          "the reference traces every sample at its own time in the shutter on the scene posed then.\n"
       << "- Pareto rows (no other row is both faster and more accurate) are marked **P**; the plot's red line is the "
          "front, the dashed lines the reference noise and the ray tracer's time for the reference.\n\n";
    for (const Section& sec : sections) {
        const AccuracySweep& s = *sec.sweep;
        const std::vector<Row> part(rows.begin() + static_cast<std::ptrdiff_t>(sec.first), rows.begin() + static_cast<std::ptrdiff_t>(sec.last));
        const std::string base = slug(s.effect + "_" + fs::path(sec.scene).stem().string());
        md << "## " << s.effect << " (" << sec.scene << ")\n\n" << s.compared << ".\n\n" << s.reading << "\n\n";
        const bool has_error = std::any_of(part.begin(), part.end(), [](const Row& r) { return std::isfinite(r.rmse); });
        if (has_error) {
            write_plot(o.out / (base + ".svg"), s.effect + " on " + sec.scene, part, sec.noise, sec.rt_ms);
            md << "![" << s.effect << "](" << link(base + ".svg") << ")\n\n";
            md << "Reference: " << sec.ref_spp << " spp, noise " << num(sec.noise) << (sec.rt_ms > 0 ? ", " + num(sec.rt_ms, "%.0f") + " ms to trace" : "")
               << ".";
            if (std::isfinite(sec.occlusion_rmse))
                md << " Missing occlusion alone (the tracer with vs without visibility between bounce points): RMSE " << num(sec.occlusion_rmse) << ".";
            md << "\n\n| variant | ms | IQR | RMSE | rel. MSE | max | % > 2/255 |" << (std::isfinite(part[0].rmse_no_occlusion) ? " RMSE vs no-occlusion |" : "")
               << " P |\n|---|---|---|---|---|---|---|" << (std::isfinite(part[0].rmse_no_occlusion) ? "---|" : "") << "---|\n";
            for (const Row& r : part) {
                md << "| " << r.variant << (r.variant == s.shipped ? " (default)" : "") << " | " << num(r.ms, "%.2f") << " | " << num(r.iqr, "%.2f")
                   << " | " << (r.at_noise_floor ? "at noise floor" : num(r.rmse)) << " | " << num(r.relmse) << " | " << num(r.max_abs, "%.3g")
                   << " | " << num(r.pct_over, "%.1f") << " |";
                if (std::isfinite(r.rmse_no_occlusion)) md << " " << num(r.rmse_no_occlusion) << " |";
                md << " " << (r.pareto ? "**P**" : "") << " |\n";
            }
            const int k = knee(rows, sec.first, sec.last);
            int cheapest = -1;
            for (size_t i = sec.first; i < sec.last; ++i)
                if (rows[i].pareto && (cheapest < 0 || rows[i].ms < rows[static_cast<size_t>(cheapest)].ms)) cheapest = static_cast<int>(i);
            md << "\n";
            if (k >= 0) {
                const Row& kr = rows[static_cast<size_t>(k)];
                md << "Knee of the front (nearest the least time and least error, log-log): **" << kr.variant << "** ("
                   << num(kr.ms, "%.2f") << " ms, RMSE " << num(kr.rmse) << "). ";
                const auto shipped = std::find_if(part.begin(), part.end(), [&](const Row& r) { return r.variant == s.shipped; });
                if (shipped != part.end())
                    md << "The engine ships **" << s.shipped << "** (" << num(shipped->ms, "%.2f") << " ms, RMSE " << num(shipped->rmse) << ")"
                       << (shipped->pareto ? ", on the front." : ", off the front in this run.");
                md << "\n\n";
                for (const auto& [label, idx] : {std::pair<std::string, int>{"best trade-off", k}, {"cheapest", cheapest}}) {
                    if (idx < 0) continue;
                    const Row& r = rows[static_cast<size_t>(idx)];
                    const std::string file = base + "_" + slug(label) + ".png";
                    write_strip(o.out / file, r.image, sec.reference, s.buffer);
                    md << "*" << label << " (" << r.variant << "): raster | reference | difference (red = 0.1)*\n\n![" << label << "](" << link(file) << ")\n\n";
                }
            }
        } else {
            md << "| variant | frame ms (all passes) | IQR |\n|---|---|---|\n";
            for (const Row& r : part) md << "| " << r.variant << " | " << num(r.ms, "%.2f") << " | " << num(r.iqr, "%.2f") << " |\n";
            md << "\n";
        }
    }
    std::ofstream(report) << md.str();
    std::printf("device: %s\nwrote %s, %s and %zu sections (%zu rows) in %.0f s\n", device_text.c_str(),
                (o.out / "results.csv").string().c_str(), report.string().c_str(), sections.size(), rows.size(),
                std::chrono::duration<double>(Clock::now() - start).count());
}

// The GL context of a run (or of one section); prints why there is none.
struct Gl {
    ContextResult ctx;
    Device device;
};
std::optional<Gl> open_gl(const AccuracyOptions& o) {
    ContextOptions co;
    Gl gl{create_context(o.backend, co), {}};
    if (!gl.ctx.context) {
        std::fprintf(stderr, "candela: %s\n", gl.ctx.error.c_str());
        return std::nullopt;
    }
    if (!gl.ctx.notice.empty()) std::fprintf(stderr, "candela: warning: %s\n", gl.ctx.notice.c_str());
    gl.device = {gl.ctx.context->device_string(), to_string(gl.ctx.context->backend())};
    return gl;
}

// A saved section (run_accuracy_section, read by assemble_accuracy): DIR/section.json holds the
// section's fields and its rows' (every double as "%.17g" text, which reads back to the same
// bits, NaN included; JSON numbers have no NaN), DIR/reference.exr and DIR/row_NNN.exr the
// images as float32 EXR (lossless). section.json is written last, by a rename: a task that died
// leaves no section.json, and a directory with one is complete.
constexpr const char* kSectionFormat = "candela bench accuracy section 1";
constexpr const char* kSectionFile = "section.json";

std::string exact(double v) {
    char b[40];
    std::snprintf(b, sizeof b, "%.17g", v);
    return b;
}

double parse_exact(const nlohmann::json& j, const char* key) {
    if (!j.contains(key) || !j.at(key).is_string()) throw std::runtime_error(std::string("no number '") + key + "'");
    const std::string& t = j.at(key).get_ref<const std::string&>();
    char* end = nullptr;
    const double v = std::strtod(t.c_str(), &end);
    if (t.empty() || *end != '\0') throw std::runtime_error(std::string("'") + key + "' is not a number: " + t);
    return v;
}

std::string row_image_name(size_t i) {
    char b[32];
    std::snprintf(b, sizeof b, "row_%03zu.exr", i);
    return b;
}

nlohmann::ordered_json section_json(int index, const std::string& label, const AccuracyOptions& o, const Section& sec, const std::vector<Row>& rows) {
    const Sizes z = sizes(o.quick);
    nlohmann::ordered_json j;  // in the order written, for a reader
    j["format"] = kSectionFormat;
    j["index"] = index;
    j["label"] = label;
    j["effect"] = sec.sweep->effect;
    j["scene"] = sec.scene;
    j["quick"] = o.quick;
    j["width"] = z.width;
    j["height"] = z.height;
    j["device"] = sec.device;
    j["backend"] = sec.backend;
    j["seconds"] = exact(sec.seconds);
    j["noise"] = exact(sec.noise);
    j["rt_ms"] = exact(sec.rt_ms);
    j["ref_spp"] = sec.ref_spp;
    j["occlusion_rmse"] = exact(sec.occlusion_rmse);
    j["knee"] = sec.knee_name;
    j["reference"] = sec.reference.empty() ? nlohmann::ordered_json() : nlohmann::ordered_json{{"file", "reference.exr"}, {"channels", sec.reference.channels}};
    nlohmann::ordered_json list = nlohmann::ordered_json::array();
    for (size_t i = sec.first; i < sec.last; ++i) {
        const Row& r = rows[i];
        nlohmann::ordered_json row = {{"effect", r.effect}, {"variant", r.variant}, {"settings", r.settings}, {"scene", r.scene},
                              {"width", r.width}, {"height", r.height}, {"ms", exact(r.ms)}, {"iqr", exact(r.iqr)},
                              {"frame_ms", exact(r.frame_ms)}, {"rmse", exact(r.rmse)}, {"relmse", exact(r.relmse)},
                              {"max_abs", exact(r.max_abs)}, {"pct_over", exact(r.pct_over)}, {"flip", exact(r.flip)},
                              {"rmse_no_occlusion", exact(r.rmse_no_occlusion)}, {"ref_spp", r.ref_spp},
                              {"ref_noise", exact(r.ref_noise)}, {"pareto", r.pareto}, {"at_noise_floor", r.at_noise_floor}};
        row["image"] = r.image.empty() ? nlohmann::ordered_json()
                                       : nlohmann::ordered_json{{"file", row_image_name(i - sec.first)}, {"channels", r.image.channels}};
        list.push_back(std::move(row));
    }
    j["rows"] = std::move(list);
    return j;
}

void save_section(const fs::path& dir, const nlohmann::ordered_json& j, const Section& sec, const std::vector<Row>& rows) {
    fs::create_directories(dir);
    // Temporary names of this process, renamed into place once all is written.
    const std::string tmp = ".partial_" + std::to_string(::getpid()) + "_";
    std::vector<std::pair<fs::path, fs::path>> renames;
    const auto image = [&](const nlohmann::ordered_json& entry, const ImageF& img) {
        if (entry.is_null()) return;
        const std::string name = entry.at("file").get<std::string>();
        write_image(dir / (tmp + name), img);
        renames.emplace_back(dir / (tmp + name), dir / name);
    };
    image(j.at("reference"), sec.reference);
    for (size_t i = sec.first; i < sec.last; ++i) image(j.at("rows").at(i - sec.first).at("image"), rows[i].image);
    const fs::path json_tmp = dir / (tmp + kSectionFile);
    {
        std::ofstream f(json_tmp);
        f << j.dump(1) << "\n";
        if (!f.flush()) throw Error(ExitCode::internal, json_tmp.string() + ": cannot write");
    }
    for (const auto& [from, to] : renames) fs::rename(from, to);
    fs::rename(json_tmp, dir / kSectionFile);  // last: its presence means the section is complete
}

// complete_section's checks of a parsed section.json.
std::optional<nlohmann::json> check_section(const fs::path& dir, const nlohmann::json& j, const AccuracyOptions& o,
                                            const AccuracySweep& s, const std::string& scene, std::string& problem) {
    const fs::path file = dir / kSectionFile;
    const Sizes z = sizes(o.quick);
    const std::string expected = s.effect + " on " + section_scene(s, scene);
    const auto text = [&](const char* key) { return j.contains(key) && j.at(key).is_string() ? j.at(key).get<std::string>() : std::string("?"); };
    if (text("format") != kSectionFormat) problem = file.string() + ": not a '" + kSectionFormat + "' file";
    else if (text("effect") != s.effect || text("scene") != section_scene(s, scene))
        problem = file.string() + " holds '" + text("effect") + " on " + text("scene") + "', not '" + expected + "'";
    else if (j.value("quick", !o.quick) != o.quick || j.value("width", 0) != z.width || j.value("height", 0) != z.height)
        problem = file.string() + " was run " + (j.value("quick", false) ? "with" : "without") + " --quick, not as asked";
    else if (!j.contains("rows") || !j.at("rows").is_array() || !j.contains("reference"))
        problem = file.string() + ": no rows";
    if (!problem.empty()) return std::nullopt;
    std::vector<nlohmann::json> images = {j.at("reference")};
    for (const auto& r : j.at("rows")) images.push_back(r.value("image", nlohmann::json()));
    for (const auto& im : images)
        if (!im.is_null() && !(im.is_object() && im.contains("file") && im.at("file").is_string() &&
                               fs::is_regular_file(dir / im.at("file").get<std::string>()))) {
            problem = file.string() + " names an image that is missing (" + im.dump() + ")";
            return std::nullopt;
        }
    return j;
}

// DIR/section.json if DIR holds a complete result of this section; else why not (in `problem`).
std::optional<nlohmann::json> complete_section(const fs::path& dir, const AccuracyOptions& o, const AccuracySweep& s,
                                               const std::string& scene, std::string& problem) {
    problem.clear();
    const fs::path file = dir / kSectionFile;
    if (!fs::is_regular_file(file)) {
        problem = "no " + std::string(kSectionFile) + " (the section has not run, or did not finish)";
        return std::nullopt;
    }
    nlohmann::json j;
    try {
        std::ifstream f(file);
        j = nlohmann::json::parse(f);
    } catch (const std::exception& e) {
        problem = file.string() + " is not valid JSON (" + e.what() + ")";
        return std::nullopt;
    }
    try {
        return check_section(dir, j, o, s, scene, problem);
    } catch (const std::exception& e) {  // a field of the wrong type
        problem = file.string() + ": " + e.what();
        return std::nullopt;
    }
}

// write_image keeps 1-4 channels; read_image returns RGBA: back to the saved channel count.
ImageF load_image(const fs::path& dir, const nlohmann::json& entry, int width, int height) {
    if (entry.is_null()) return {};
    const fs::path path = dir / entry.at("file").get<std::string>();
    const int channels = entry.at("channels").get<int>();
    const ImageF rgba = read_image(path);
    if (rgba.width != width || rgba.height != height || channels < 1 || channels > 4)
        throw std::runtime_error(path.string() + ": not a " + std::to_string(width) + "x" + std::to_string(height) + " image of " +
                                 std::to_string(channels) + " channels");
    if (channels == 4) return rgba;
    ImageF img(width, height, channels);
    static const int from[4][4] = {{0}, {0, 3}, {0, 1, 2}, {0, 1, 2, 3}};
    for (size_t p = 0; p < static_cast<size_t>(width) * static_cast<size_t>(height); ++p)
        for (int ch = 0; ch < channels; ++ch) img.pixels[p * static_cast<size_t>(channels) + static_cast<size_t>(ch)] = rgba.pixels[p * 4 + static_cast<size_t>(from[channels - 1][ch])];
    return img;
}

// The section saved in DIR (its json from complete_section), its rows appended to `rows`.
Section load_section(const fs::path& dir, const nlohmann::json& j, const AccuracySweep& s, std::vector<Row>& rows) {
    const Sizes z = sizes(j.at("quick").get<bool>());
    Section sec;
    sec.sweep = &s;
    sec.scene = j.at("scene").get<std::string>();
    sec.noise = parse_exact(j, "noise");
    sec.rt_ms = parse_exact(j, "rt_ms");
    sec.ref_spp = j.at("ref_spp").get<int>();
    sec.occlusion_rmse = parse_exact(j, "occlusion_rmse");
    sec.knee_name = j.at("knee").get<std::string>();
    sec.device = j.at("device").get<std::string>();
    sec.backend = j.at("backend").get<std::string>();
    sec.seconds = parse_exact(j, "seconds");
    sec.reference = load_image(dir, j.at("reference"), z.width, z.height);
    sec.first = rows.size();
    for (const nlohmann::json& e : j.at("rows")) {
        Row r;
        r.effect = e.at("effect").get<std::string>();
        r.variant = e.at("variant").get<std::string>();
        r.settings = e.at("settings").get<std::string>();
        r.scene = e.at("scene").get<std::string>();
        r.width = e.at("width").get<int>();
        r.height = e.at("height").get<int>();
        r.ms = parse_exact(e, "ms");
        r.iqr = parse_exact(e, "iqr");
        r.frame_ms = parse_exact(e, "frame_ms");
        r.rmse = parse_exact(e, "rmse");
        r.relmse = parse_exact(e, "relmse");
        r.max_abs = parse_exact(e, "max_abs");
        r.pct_over = parse_exact(e, "pct_over");
        r.flip = parse_exact(e, "flip");
        r.rmse_no_occlusion = parse_exact(e, "rmse_no_occlusion");
        r.ref_spp = e.at("ref_spp").get<int>();
        r.ref_noise = parse_exact(e, "ref_noise");
        r.pareto = e.at("pareto").get<bool>();
        r.at_noise_floor = e.at("at_noise_floor").get<bool>();
        r.image = load_image(dir, e.value("image", nlohmann::json()), r.width, r.height);
        rows.push_back(std::move(r));
    }
    sec.last = rows.size();
    return sec;
}

// Bitwise equality (NaN equals NaN of the same bits): what a saved section must read back as.
bool same(double a, double b) { return std::memcmp(&a, &b, sizeof a) == 0 || (std::isnan(a) && std::isnan(b)); }
bool same(const ImageF& a, const ImageF& b) {
    return a.width == b.width && a.height == b.height && a.channels == b.channels && a.pixels.size() == b.pixels.size() &&
           std::equal(a.pixels.begin(), a.pixels.end(), b.pixels.begin(), [](float x, float y) {
               return std::memcmp(&x, &y, sizeof x) == 0 || (std::isnan(x) && std::isnan(y));
           });
}
// What differs between a section and its reloaded copy ("" when nothing).
std::string round_trip_difference(const Section& a, const std::vector<Row>& ar, const Section& b, const std::vector<Row>& br) {
    if (a.scene != b.scene || !same(a.noise, b.noise) || !same(a.rt_ms, b.rt_ms) || a.ref_spp != b.ref_spp ||
        !same(a.occlusion_rmse, b.occlusion_rmse) || a.knee_name != b.knee_name || a.device != b.device || a.backend != b.backend)
        return "the section's fields";
    if (!same(a.reference, b.reference)) return "the reference image";
    if (a.last - a.first != b.last - b.first) return "the row count";
    for (size_t i = 0; i < a.last - a.first; ++i) {
        const Row &x = ar[a.first + i], &y = br[b.first + i];
        const bool fields = x.effect == y.effect && x.variant == y.variant && x.settings == y.settings && x.scene == y.scene &&
                            x.width == y.width && x.height == y.height && same(x.ms, y.ms) && same(x.iqr, y.iqr) &&
                            same(x.frame_ms, y.frame_ms) && same(x.rmse, y.rmse) && same(x.relmse, y.relmse) &&
                            same(x.max_abs, y.max_abs) && same(x.pct_over, y.pct_over) && same(x.flip, y.flip) &&
                            same(x.rmse_no_occlusion, y.rmse_no_occlusion) && x.ref_spp == y.ref_spp &&
                            same(x.ref_noise, y.ref_noise) && x.pareto == y.pareto && x.at_noise_floor == y.at_noise_floor;
        if (!fields) return "row " + std::to_string(i) + " (" + x.variant + ")";
        if (!same(x.image, y.image)) return "row " + std::to_string(i) + "'s image (" + x.variant + ")";
    }
    return "";
}

}  // namespace

std::vector<AccuracyTask> plan_accuracy(const AccuracyOptions& o) {
    const Plan plan = make_plan(o);
    std::vector<AccuracyTask> tasks;
    for (const Job& j : plan.jobs) tasks.push_back({plan.sweep(j).effect, section_scene(plan.sweep(j), j.scene), job_label(plan, j)});
    return tasks;
}

int run_accuracy(const AccuracyOptions& o) {
    const Plan plan = make_plan(o);
    make_output_dirs(o);
    std::optional<Gl> gl = open_gl(o);
    if (!gl) return static_cast<int>(ExitCode::no_gl);
    const ShaderLibrary shaders(o.shader_dir);
    Progress progress;
    const Sizes z = sizes(o.quick);
    const Run c{o, shaders, z.width, z.height, z.warmup, z.frames, progress};
    for (const Job& j : plan.jobs) progress.total += job_steps(plan.sweep(j), o.quick);
    std::vector<Section> sections;
    std::vector<Row> rows;
    for (const Job& j : plan.jobs) {
        sections.push_back(run_job(c, plan.sweep(j), j.scene, rows));
        sections.back().device = gl->device.device;
        sections.back().backend = gl->device.backend;
    }
    write_outputs(o, sections, rows, {gl->device}, progress.start);
    return 0;
}

int run_accuracy_section(const AccuracyOptions& o, int index, const fs::path& section_dir) {
    const Plan plan = make_plan(o);
    const int count = static_cast<int>(plan.jobs.size());
    if (index < 0 || index >= count)
        throw bad_input("bench accuracy: --section " + std::to_string(index) + " is out of range: there are " + std::to_string(count) +
                        " sections (0 to " + std::to_string(count - 1) + ", see --list-sections)");
    const Job& j = plan.jobs[static_cast<size_t>(index)];
    const AccuracySweep& s = plan.sweep(j);
    const std::string label = job_label(plan, j);
    std::string problem;
    if (complete_section(section_dir, o, s, j.scene, problem)) {
        std::printf("section %d (%s): %s is complete, skipped\n", index, label.c_str(), section_dir.string().c_str());
        return 0;
    }
    // A stale result goes before any new file is written: a task that dies from here on leaves no
    // section.json, so the directory never looks complete.
    if (fs::exists(section_dir / kSectionFile)) {
        std::fprintf(stderr, "candela: note: %s; running section %d (%s) again\n", problem.c_str(), index, label.c_str());
        fs::remove(section_dir / kSectionFile);
    }
    std::optional<Gl> gl = open_gl(o);
    if (!gl) return static_cast<int>(ExitCode::no_gl);
    const ShaderLibrary shaders(o.shader_dir);
    Progress progress;
    progress.total = job_steps(s, o.quick);
    const Sizes z = sizes(o.quick);
    const Run c{o, shaders, z.width, z.height, z.warmup, z.frames, progress};
    std::vector<Row> rows;
    Section sec = run_job(c, s, j.scene, rows);
    sec.device = gl->device.device;
    sec.backend = gl->device.backend;
    const nlohmann::ordered_json saved = section_json(index, label, o, sec, rows);
    save_section(section_dir, saved, sec, rows);
    // Read back what assemble_accuracy will read: the save must be exact (a full file system or a
    // bad mount shows here, in the task that can be rerun, and not at assembly).
    std::vector<Row> reread_rows;
    const std::optional<nlohmann::json> reread = complete_section(section_dir, o, s, j.scene, problem);
    if (!reread) throw Error(ExitCode::internal, section_dir.string() + ": the saved section does not read back: " + problem);
    const Section copy = load_section(section_dir, *reread, s, reread_rows);
    if (const std::string d = round_trip_difference(sec, rows, copy, reread_rows); !d.empty()) {
        fs::remove(section_dir / kSectionFile);
        throw Error(ExitCode::internal, section_dir.string() + ": the saved section reads back different (" + d + ")");
    }
    std::printf("device: %s\nsection %d (%s): wrote %s (%zu rows) in %.1f s\n", sec.device.c_str(), index, label.c_str(),
                section_dir.string().c_str(), rows.size(), sec.seconds);
    return 0;
}

int assemble_accuracy(const AccuracyOptions& o, const std::vector<fs::path>& section_dirs) {
    const auto start = Clock::now();
    const Plan plan = make_plan(o);
    if (section_dirs.size() != plan.jobs.size())
        throw bad_input("bench accuracy: " + std::to_string(section_dirs.size()) + " section directories given for " +
                        std::to_string(plan.jobs.size()) + " sections (one per section, in --list-sections order)");
    std::vector<Section> sections;
    std::vector<Row> rows;
    int missing = 0;
    for (size_t i = 0; i < plan.jobs.size(); ++i) {
        const Job& j = plan.jobs[i];
        std::string problem;
        try {
            if (const std::optional<nlohmann::json> saved = complete_section(section_dirs[i], o, plan.sweep(j), j.scene, problem))
                sections.push_back(load_section(section_dirs[i], *saved, plan.sweep(j), rows));
        } catch (const std::exception& e) {
            problem = e.what();
        }
        if (!problem.empty()) {
            std::fprintf(stderr, "candela: %s: section %zu (%s) is missing or incomplete: %s\n", section_dirs[i].string().c_str(), i,
                         job_label(plan, j).c_str(), problem.c_str());
            ++missing;
        }
    }
    if (missing > 0)
        throw Error(ExitCode::internal, "bench accuracy: " + std::to_string(missing) + " of " + std::to_string(plan.jobs.size()) +
                                            " sections missing or incomplete; nothing written");
    std::vector<Device> devices;
    for (const Section& sec : sections)
        if (std::find(devices.begin(), devices.end(), Device{sec.device, sec.backend}) == devices.end())
            devices.push_back({sec.device, sec.backend});
    write_outputs(o, sections, rows, devices, start);
    return 0;
}

}  // namespace candela::cli
