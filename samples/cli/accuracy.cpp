#include "accuracy.hpp"

#include <unistd.h>

#include <algorithm>
#include <chrono>
#include <cmath>
#include <cstdio>
#include <ctime>
#include <fstream>
#include <functional>
#include <limits>
#include <map>
#include <optional>
#include <sstream>

#include "core/error.hpp"
#include "core/log.hpp"
#include "effects/accuracy_sweep.hpp"
#include "image/image.hpp"
#include "render/features.hpp"
#include "render/renderer.hpp"
#include "render/still.hpp"
#include "rt/ray_tracer.hpp"
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

Scene load(const Run& c, const std::string& name) {
    if (name.rfind("generated:lights:", 0) == 0) return make_many_lights_scene(std::stoi(name.substr(17)));
    if (name == "generated:dof") return make_dof_scene();
    if (name == "generated:edges") return make_edges_scene();
    if (name == "generated:motion") return make_motion_scene();
    const fs::path p = fs::path(name).has_parent_path() ? fs::path(name) : c.o.scene_dir / name;
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
    rt::Options o;
    if (motion && motion->moving()) {
        // The exact motion blur: each time slice of the shutter poses the scene (the tracer leaves
        // it at the shutter's centre, the sweep's time, when it is done).
        const SceneTime m = *motion;
        o.pose_at = [m](float u) { pose_scene(*m.scene, m.animation, m.shutter.open + u * (m.shutter.close - m.shutter.open)); };
        o.shutter_slices = settings.rt.shutter_slices;
    }
    o.mode = r.mode;
    o.spp = spp;
    o.max_depth = r.max_depth;
    o.jitter = r.jitter;
    o.seed = seed;
    o.indirect_occlusion = r.indirect_occlusion;
    o.ao_radius = settings.ao.radius;
    o.whitted_max_roughness = settings.rt.whitted_max_roughness;
    o.visibility_light = 0;
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
    for (const auto& k : v.knobs) apply_knob(rs, k);
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

}  // namespace

int run_accuracy(const AccuracyOptions& o) {
    fs::create_directories(o.out);
    ContextOptions co;
    ContextResult ctx = create_context(o.backend, co);
    if (!ctx.context) {
        std::fprintf(stderr, "candela: %s\n", ctx.error.c_str());
        return static_cast<int>(ExitCode::no_gl);
    }
    if (!ctx.notice.empty()) std::fprintf(stderr, "candela: warning: %s\n", ctx.notice.c_str());
    const std::string device = ctx.context->device_string();
    const ShaderLibrary shaders(o.shader_dir);
    Progress progress;
    Run c{o, shaders, o.quick ? 128 : 320, o.quick ? 96 : 240, o.quick ? 1 : 3, o.quick ? 3 : 10, progress};
    std::vector<AccuracySweep> sweeps = make_sweeps(o.quick);
    if (!o.effects.empty()) {
        std::vector<AccuracySweep> kept;
        for (AccuracySweep& s : sweeps)
            if (std::find(o.effects.begin(), o.effects.end(), s.effect) != o.effects.end()) kept.push_back(std::move(s));
        if (kept.empty()) throw bad_input("bench accuracy: no section named by --effect");
        sweeps = std::move(kept);
    }

    // Which scenes each sweep runs on: its own, or those given that call for the effect.
    struct Job {
        const AccuracySweep* sweep;
        std::string scene;
    };
    std::vector<Job> jobs;
    for (const AccuracySweep& s : sweeps) {
        if (s.effect == "forward_deferred" || s.effect == "ray_tracer" || s.effect == "ray_tracer_depth" || o.scenes.empty()) {
            jobs.push_back({&s, s.scene});
            continue;
        }
        for (const std::string& name : o.scenes) {
            const Scene scene = load(c, name);
            if (s.needed(analyze(scene, RenderSettings{}))) jobs.push_back({&s, name});
        }
    }
    const std::vector<int> light_counts = o.quick ? std::vector<int>{4, 16} : std::vector<int>{4, 16, 64};
    const std::vector<int> spps = o.quick ? std::vector<int>{1, 4, 16} : std::vector<int>{1, 4, 16, 64};
    const std::vector<int> depths = o.quick ? std::vector<int>{2, 8} : std::vector<int>{2, 4, 8, 16, 32};
    for (const Job& j : jobs) {
        if (j.sweep->effect == "forward_deferred") progress.total += 2 * static_cast<int>(light_counts.size());
        else if (j.sweep->effect == "ray_tracer") progress.total += static_cast<int>(spps.size()) + 1;
        else if (j.sweep->effect == "ray_tracer_depth") progress.total += static_cast<int>(depths.size()) + 1;
        else progress.total += static_cast<int>(j.sweep->variants.size()) + 1 + (j.sweep->split ? 1 : 0);
    }

    struct Section {
        const AccuracySweep* sweep;
        std::string scene;
        size_t first = 0, last = 0;  // rows
        double noise = 0, rt_ms = 0;
        int ref_spp = 0;
        double occlusion_rmse = kNaN;  // a split sweep: RMSE of the reference with vs without occlusion
        ImageF reference;
        std::string knee_name;
    };
    std::vector<Section> sections;
    std::vector<Row> rows;
    const fs::path report = o.report.empty() ? o.out / "report.md" : o.report;
    if (report.has_parent_path()) fs::create_directories(report.parent_path());
    // Links from the report to the plots and strips.
    const fs::path link_dir = fs::relative(fs::absolute(o.out), fs::absolute(report).parent_path());
    const auto link = [&](const std::string& file) { return (link_dir / file).generic_string(); };
    for (const Job& j : jobs) {
        const AccuracySweep& s = *j.sweep;
        Section sec{&s, j.scene, rows.size(), rows.size(), 0, 0, 0, kNaN, {}, {}};
        if (s.effect == "forward_deferred") {
            for (int n : light_counts) {
                const std::string name = "generated:lights:" + std::to_string(n);
                const Scene scene = load(c, name);
                GpuScene gpu(scene);
                AccuracySweep t = s;
                t.scene = name;
                // No effects: the shading itself (an effect's passes would cost the same on both paths).
                t.variants = {{"forward " + std::to_string(n) + " lights", "none", {"render.path=forward"}},
                              {"deferred " + std::to_string(n) + " lights", "none", {"render.path=deferred"}}};
                raster_rows(c, t, scene, gpu, rows);
            }
            sec.scene = "generated:lights:N";
        } else if (s.effect == "ray_tracer") {
            const Scene scene = load(c, j.scene);
            GpuScene gpu(scene);
            const AccuracySweep::Reference path{rt::Mode::path, o.quick ? 32 : 256};
            const Reference ref = make_reference(c, scene, gpu, path, RenderSettings{});
            progress.step("ray_tracer: reference");
            sec.noise = ref.noise;
            sec.ref_spp = ref.spp;
            sec.reference = ref.image;
            for (int spp : spps) {
                const rt::Result r = trace(c, scene, gpu, path, spp, 7, RenderSettings{});
                Row row;
                row.effect = s.effect;
                row.variant = std::to_string(spp) + " spp";
                row.settings = "--raytrace path --spp " + std::to_string(spp);
                row.scene = j.scene;
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
            const Scene scene = load(c, j.scene);
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
                row.scene = j.scene;
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
            for (int depth : depths) {
                Row row = row_for(depth);
                measure_errors(row, row.image, ref, Buffer::radiance);
                rows.push_back(std::move(row));
                progress.step("ray_tracer_depth: max depth " + std::to_string(depth));
            }
            measure_errors(unbounded, unbounded.image, ref, Buffer::radiance);
            rows.push_back(std::move(unbounded));
        } else {
            Scene scene = load(c, j.scene);
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
            t.scene = j.scene;
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
        sections.push_back(std::move(sec));
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
       << "- Device: `" << device << "` (" << to_string(ctx.context->backend()) << "). llvmpipe runs on the CPU: "
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
    for (Section& sec : sections) {
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
    std::printf("device: %s\nwrote %s, %s and %zu sections (%zu rows) in %.0f s\n", device.c_str(),
                (o.out / "results.csv").string().c_str(), report.string().c_str(), sections.size(), rows.size(),
                std::chrono::duration<double>(Clock::now() - progress.start).count());
    return 0;
}

}  // namespace candela::cli
