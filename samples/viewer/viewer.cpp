#include "viewer.hpp"

#include <glad/gl.h>
// After glad: GLFW must not pull in the system's GL header.
#define GLFW_INCLUDE_NONE
#include <GLFW/glfw3.h>
#include <imgui.h>
#include <imgui_impl_glfw.h>
#include <imgui_impl_opengl3.h>

#include <algorithm>
#include <chrono>
#include <cmath>
#include <cstdio>
#include <deque>
#include <tuple>
#include <utility>

#include <nlohmann/json.hpp>

#include "camera_controller.hpp"
#include "effect_status.hpp"
#include "playback.hpp"
#include "core/error.hpp"
#include "core/log.hpp"
#include "scene/origin.hpp"
#include "image/image.hpp"
#include "platform/context.hpp"
#include "render/features.hpp"
#include "render/renderer.hpp"
#include "rt/view_lighting.hpp"
#include "rt/ray_tracer.hpp"
#include "rt/tracer_options.hpp"
#include "scene/animation.hpp"
#include "script.hpp"
#include "render/program_catalog.hpp"
#include "shader/file_watcher.hpp"

#include "viewer_internal.hpp"

namespace candela::viewer {
namespace {
namespace fs = std::filesystem;
}  // namespace

double ms_since(Clock::time_point t) { return std::chrono::duration<double, std::milli>(Clock::now() - t).count(); }

void Viewer::log_animation(const std::string& why) const {
    if (anim_.animation < 0) {
        log::info("viewer: " + why + ": animation none (rest pose)");
        return;
    }
    char line[256];
    std::snprintf(line, sizeof line, "viewer: %s: animation '%s' (%d of %zu), %.3f s of %.3f s, %s, speed %.2fx, loop %s", why.c_str(),
                  animation_label(anim_.animation).c_str(), anim_.animation, scene_.animations.size(), anim_.time, anim_.duration,
                  anim_.playing ? "playing" : "paused", anim_.speed, anim_.loop ? "on" : "off");
    log::info(line);
}

void Viewer::update_pose() {
    const float shutter = settings_.camera.shutter, fps = settings_.camera.fps;
    if (!deformable_ || !anim_.needs_pose(shutter, fps)) return;
    const auto t0 = Clock::now();
    pose_scene(scene_, anim_.animation, anim_.time);
    gpu_.update_pose();
    shutter_ = anim_.animation >= 0 ? shutter_interval(anim_.time, shutter, fps) : ShutterInterval{anim_.time, anim_.time};
    if (!shutter_.instant())
        gpu_.set_motion(evaluate_pose(scene_, anim_.animation, shutter_.open), evaluate_pose(scene_, anim_.animation, shutter_.close));
    else
        gpu_.clear_motion();
    anim_.mark_posed(shutter, fps);
    ++pose_serial_;
    pose_ms_.push_back(ms_since(t0));
}

void Viewer::anchor_at_the_camera(int frame) {
    const glm::dvec3 before = scene_.origin;
    const auto t0 = Clock::now();
    if (!anchor_at_camera(scene_, controller_.camera(), anim_.animation, anim_.time)) return;
    const glm::vec3 shift(scene_.origin - before);
    controller_.shift(shift);
    bounds_ = scene_.world_bounds();
    last_camera_.world[3] -= glm::vec4(shift, 0.0f);  // the same view, not a jump
    gpu_.update_pose();  // every draw moved: the renderer re-plans, probes re-capture, GI retraces
    if (!shutter_.instant())
        gpu_.set_motion(evaluate_pose(scene_, anim_.animation, shutter_.open), evaluate_pose(scene_, anim_.animation, shutter_.close));
    ref_.tracer.reset();  // the tracer's geometry is in the old frame
    ref_.built_mode = -1;
    ++view_generation_;
    ++pose_serial_;
    char line[256];
    std::snprintf(line, sizeof line, "viewer: frame %d: origin moved to the camera, (%.17g, %.17g, %.17g) (%.1f ms)", frame, scene_.origin.x,
                  scene_.origin.y, scene_.origin.z, ms_since(t0));
    log::info(line);
}

void Viewer::pose_within_shutter(float u) {
    // u = 0.5 is the frame's own time (the tracer leaves the scene there between steps): exactly
    // the pose the raster frame drew, not open + 0.5 * (close - open) rounded.
    if (u == 0.5f) {
        pose_scene(scene_, anim_.animation, anim_.time);
        return;
    }
    // Any other call starts a new time slice (one per sample: the viewer leaves
    // Options::shutter_slices at 0). The tracer stratifies its slice times over the whole render
    // (Options::spp, 65536 here) in sample order, which suits a render that finishes; a
    // progressive reference that shows its first few dozen samples would then show only the
    // shutter's opening instant. So the viewer takes the k-th slice since the restart at the
    // base-2 radical inverse of k, jittered within its 1/65536 stratum: every prefix of 2^n
    // samples covers the shutter evenly, and the times stay uniform over it.
    const std::uint32_t k = ref_.motion_slices++;
    std::uint32_t bits = k & 0xFFFFu, reversed = 0;
    for (int i = 0; i < 16; ++i, bits >>= 1) reversed = (reversed << 1) | (bits & 1u);
    std::uint32_t h = k * 0x9E3779B9u;  // a jitter in [0, 1) from k (a PCG-style hash)
    h ^= h >> 16;
    h *= 0x7FEB352Du;
    h ^= h >> 15;
    const float jitter = static_cast<float>(h >> 8) * (1.0f / 16777216.0f);
    const float v = std::min((static_cast<float>(reversed) + jitter) / 65536.0f, std::nextafter(1.0f, 0.0f));
    pose_scene(scene_, anim_.animation, shutter_.open + v * (shutter_.close - shutter_.open));
}

void Viewer::select_variant_live(int variant) {
    if (variant == scene_.active_variant) return;
    const auto t0 = Clock::now();
    select_variant(scene_, variant);
    gpu_.refresh_materials();  // the renderer re-plans, probes re-capture, GI retraces (a new pose version)
    ref_.tracer.reset();       // the tracer reads the primitives' materials when it is made
    ++view_generation_;
    ref_.built_mode = -1;
    char line[256];
    std::snprintf(line, sizeof line, "viewer: material variant %s (%.1f ms)",
                  variant < 0 ? "default" : ("[" + std::to_string(variant) + "] '" + scene_.variants[static_cast<size_t>(variant)] + "'").c_str(),
                  ms_since(t0));
    log::info(line);
}

void Viewer::reload_shaders() {
    std::vector<fs::path> changed = watcher_.poll();
    for (fs::path& f : effects_watcher_.poll()) changed.push_back(std::move(f));
    if (changed.empty()) return;
    ++view_generation_;
    const auto t0 = Clock::now();
    const ShaderReload r = renderer_.reload_shaders(changed);
    // The viewer's own programs are rebuilt on next use: the reference tracer (which then
    // starts over) and the buffer inspector.
    ref_.tracer.reset();
    ref_.built_mode = -1;
    inspect_.program = gl::Program();
    shader_errors_.clear();
    for (const std::string& e : r.errors) {
        shader_errors_ += e + "\n";
        std::fprintf(stderr, "candela: %s\n", e.c_str());
    }
    if (!r.rebuilt.empty()) {
        status_ = "reloaded " + std::to_string(r.rebuilt.size()) + " program(s) in " + std::to_string(static_cast<int>(ms_since(t0))) + " ms";
        log::info("viewer: " + status_);
    }
}

void Viewer::log_progress(int frame) {
    for (const std::string& name : effect_names()) {
        const EffectProgress p = renderer_.effect_progress(name);
        Logged& logged = progress_logged_[name];
        const int phase = !p.active ? 0 : p.converged ? 2 : 1;
        // A restart (scene, shaders or the effect's settings changed) sets the steps back.
        const bool restarted = phase == 1 && p.steps_done < logged.steps;
        logged.steps = p.steps_done;
        if (phase == logged.phase && !restarted) continue;
        logged.phase = phase;
        if (phase != 0 && !p.line.empty()) log::info("viewer: frame " + std::to_string(frame) + ": " + p.line);
    }
}

bool Viewer::progress_worked(std::string* pace) const {
    for (const std::string& name : effect_names()) {
        const EffectProgress p = renderer_.effect_progress(name);
        if (p.work_last_frame > 0) {
            if (pace) *pace = p.pace;
            return true;
        }
    }
    return false;
}

namespace {

// Whether two cameras show the same view (the name aside).
bool same_view(const Camera& a, const Camera& b) {
    return a.world == b.world && a.orthographic == b.orthographic && a.yfov == b.yfov && a.aspect_ratio == b.aspect_ratio &&
           a.znear == b.znear && a.zfar == b.zfar && a.xmag == b.xmag && a.ymag == b.ymag && a.aperture == b.aperture &&
           a.focus_distance == b.focus_distance;
}

}  // namespace

QualityState Viewer::choose_quality(const Camera& camera) {
    // The view moves: the camera changed since the last frame (mouse, keys, the script, a scene
    // camera), or the animation posed the scene again.
    const bool moved = (have_last_camera_ && !same_view(camera, last_camera_)) || (shown_.valid && shown_.pose != pose_serial_);
    last_camera_ = camera;
    have_last_camera_ = true;
    moved_ = moved;
    QualityState q = adaptive_.update(moved, std::chrono::duration<double>(Clock::now() - start_).count());
    if (force_reduced_) q = QualityState{QualityLevel::reduced, 1.0f, 0};
    return q;
}

void Viewer::use_settings_for(const QualityState& q) {
    const bool reduced = q.level != QualityLevel::full;
    if (reduced == renderer_reduced_) return;
    // Both were accepted by the renderer before (reduced_ lowers knobs within their ranges).
    renderer_.set_settings(reduced ? reduced_ : settings_);
    renderer_reduced_ = reduced;
}

bool Viewer::view_unchanged(const Camera& camera, int rw, int rh) const {
    // Only with adaptive quality on (off: every frame renders, as before), and never while an
    // effect still converges over frames (GI probes) or the reference refines against the raster.
    if (!adaptive_.enabled() || !shown_.valid || progress_worked(nullptr)) return false;
    return same_view(camera, shown_.camera) && rw == shown_.width && rh == shown_.height && quality_ == shown_.quality &&
           o_.exposure_ev == shown_.exposure && pose_serial_ == shown_.pose && view_generation_ == shown_.generation &&
           inspect_.name == shown_.inspect;
}

int Viewer::run() {
    GLFWwindow* window = ctx_.window();
    auto last = Clock::now();
    int frame = 0;
    int w = 0, h = 0;  // the scene's viewport (left of the panel)
    std::vector<double> whole_frames;
    std::vector<bool> converging_frames;  // whether the frame did work of a converging effect (GI probe rays)
    std::string pace;                     // the knob that paces that work
    std::vector<bool> moving_frames;      // whether the view moved in the frame (adaptive quality's input)
    std::map<std::string, int> level_frames;  // frames rendered at each quality level
    while (!glfwWindowShouldClose(window) && !quit_) {
        glfwPollEvents();
        int window_w = 0, window_h = 0;  // framebuffer pixels
        glfwGetFramebufferSize(window, &window_w, &window_h);
        if (window_w <= 0 || window_h <= 0) {  // minimized: nothing to draw, do not spin
            glfwWaitEventsTimeout(0.1);
            continue;
        }
        frame_ = frame;
        const auto t0 = Clock::now();
        const float dt = static_cast<float>(std::chrono::duration<double>(t0 - last).count());
        last = t0;
        reload_shaders();
        anim_.advance(std::min(dt, 0.1f));  // before the script: its `time T` is this frame's time
        run_script(frame);
        std::tie(w, h) = scene_viewport();  // after the script: it may hide or show the panel
        ImGui_ImplOpenGL3_NewFrame();
        ImGui_ImplGlfw_NewFrame();
        ImGui::NewFrame();
        handle_input(std::min(dt, 0.1f));
        update_pose();
        anchor_at_the_camera(frame);
        const Camera camera = controller_.camera();
        // The error budget chooses from this view's statistics when asked to (turned on, a new E,
        // a re-choice), before the frame renders at the choice; never because the camera moved.
        if (budget_pending_) choose_budget(camera, w, h);
        const bool last_frame = o_.frames > 0 && frame + 1 >= o_.frames;
        if (last_frame && !o_.screenshot.empty()) pending_screenshots_.push_back(o_.screenshot);
        const QualityState previous = quality_;
        quality_ = choose_quality(camera);
        if (!(quality_ == previous)) {
            char line[160], last[48] = "";
            if (last_render_frame_ms_ >= 0.0) std::snprintf(last, sizeof last, "last frame %.1f ms, ", last_render_frame_ms_);
            std::snprintf(line, sizeof line, "viewer: frame %d: quality %s, scale %.2f (%starget %.0f ms)", frame,
                          quality_level_name(quality_.level), quality_.scale, last, adaptive_.target_ms());
            log::info(line);
        }
        // The render size: the scene's, or a fraction of it upscaled below (the same aspect:
        // a camera that takes the image's aspect gets the scene's exactly).
        const int rw = std::max(1, static_cast<int>(std::lround(static_cast<float>(w) * quality_.scale)));
        const int rh = std::max(1, static_cast<int>(std::lround(static_cast<float>(h) * quality_.scale)));
        Camera render_camera = camera;
        if (quality_.scale != 1.0f && render_camera.aspect_ratio <= 0.0f) render_camera.aspect_ratio = static_cast<float>(w) / static_cast<float>(h);
        const bool rendered = !view_unchanged(camera, rw, rh);
        if (rendered) {
            use_settings_for(quality_);
            renderer_.render(render_camera, rw, rh, FrameOutput::display, o_.exposure_ev);
            renderer_.resolve_gpu_times();
            shown_ = Shown{true, camera, rw, rh, quality_, o_.exposure_ev, pose_serial_, view_generation_, inspect_.name};
            render_w_ = rw;
            render_h_ = rh;
        }
        converging_frames.push_back(rendered && progress_worked(&pace));
        log_progress(frame);
        update_reference(render_camera, render_w_, render_h_);
        // The panel is opaque, but the strip under it must not show stale frames either.
        const GLfloat backdrop[4] = {0.08f, 0.08f, 0.09f, 1.0f};
        glClearNamedFramebufferfv(0, GL_COLOR, 0, backdrop);
        glNamedFramebufferTexture(blit_.id(), GL_COLOR_ATTACHMENT0, renderer_.display().id(), 0);
        const bool upscaled = render_w_ != w || render_h_ != h;
        glBlitNamedFramebuffer(blit_.id(), 0, 0, 0, render_w_, render_h_, 0, 0, w, h, GL_COLOR_BUFFER_BIT, upscaled ? GL_LINEAR : GL_NEAREST);
        draw_reference(w, h);
        draw_inspected(w, h);
        for (const fs::path& p : pending_screenshots_) {
            // The image the frame rendered: at a reduced level (the view moving with adaptive
            // quality on) it is the reduced one, at its own size; the log says which.
            write_display_rgba8(p, renderer_.read_display(), render_w_, render_h_);
            // The display image cannot show a NaN: the log counts them in the radiance.
            const ImageF radiance = renderer_.read_radiance();
            size_t nonfinite = 0;
            for (float v : radiance.pixels) nonfinite += std::isfinite(v) ? 0 : 1;
            std::string pose;
            if (anim_.animation >= 0) {
                char t[96];
                std::snprintf(t, sizeof t, " (animation %d at %.3f s)", anim_.animation, anim_.time);
                pose = t;
            }
            char quality[96];
            std::snprintf(quality, sizeof quality, " at quality %s (%dx%d)", quality_level_name(shown_.quality.level), render_w_, render_h_);
            // The reference mode's image (not written: the screenshot is the raster frame) is
            // checked too, the frame the budget traces among them.
            std::string reference;
            if (ref_.on && ref_.tracer && ref_.shown_samples > 0)
                reference = " (reference " + std::string(Reference::kModes[ref_.mode]) + " at " + std::to_string(ref_.shown_samples) +
                            " spp: " + std::to_string(ref_.nonfinite) + " non-finite values)";
            log::info("viewer: wrote " + p.string() + pose + quality + ", " + std::to_string(nonfinite) + " non-finite radiance values" +
                      reference);
        }
        pending_screenshots_.clear();
        if (show_ui_) draw_ui(ms_since(t0));
        ImGui::Render();
        ImGui_ImplOpenGL3_RenderDrawData(ImGui::GetDrawData());
        if (last_frame && !o_.window_shot.empty()) {
            write_display_rgba8(o_.window_shot, read_window(window_w, window_h), window_w, window_h);
            log::info("viewer: wrote " + o_.window_shot.string());
        }
        ctx_.swap_buffers();
        whole_frames.push_back(ms_since(t0));
        if (rendered) {
            ++level_frames[quality_level_name(quality_.level)];
            last_render_frame_ms_ = whole_frames.back();
            adaptive_.measured(last_render_frame_ms_);
        }
        moving_frames.push_back(moved_);
        ++frame;
        if (last_frame) break;
    }
    if (!whole_frames.empty()) {
        // Without the first frame (shader compilation happens there on llvmpipe).
        std::vector<double> steady(whole_frames.begin() + (whole_frames.size() > 1 ? 1 : 0), whole_frames.end());
        std::sort(steady.begin(), steady.end());
        log::info("viewer: " + std::to_string(frame) + " frames; median frame (render, UI, swap; after the first) " +
                  std::to_string(steady[steady.size() / 2]).substr(0, 6) + " ms; scene " + std::to_string(w) + "x" + std::to_string(h) +
                  (show_ui_ ? " left of the panel" : ", panel hidden"));
        // The frames in which the view moved: what adaptive quality is for (on or off).
        std::vector<double> moving;
        for (size_t i = 1; i < whole_frames.size(); ++i)
            if (moving_frames[i]) moving.push_back(whole_frames[i]);
        std::string levels;
        for (const auto& [name, count] : level_frames) levels += (levels.empty() ? "" : ", ") + name + " " + std::to_string(count);
        if (!moving.empty()) {
            std::sort(moving.begin(), moving.end());
            const double m = moving[moving.size() / 2];
            char line[256];
            std::snprintf(line, sizeof line, "viewer: %zu frames with the view moving: median frame %.1f ms (%.2f fps); adaptive quality %s, target %.0f ms",
                          moving.size(), m, m > 0.0 ? 1000.0 / m : 0.0, adaptive_.enabled() ? "on" : "off", adaptive_.target_ms());
            log::info(line);
        }
        log::info("viewer: frames rendered by quality level: " + (levels.empty() ? std::string("none") : levels));
        // The frames that did converging work (GI probe updates) against the others: the cost of
        // the knob that paces it (gi.budget).
        std::vector<double> with, without;
        for (size_t i = 1; i < whole_frames.size(); ++i) (converging_frames[i] ? with : without).push_back(whole_frames[i]);
        const auto median = [](std::vector<double>& v) {
            std::sort(v.begin(), v.end());
            return std::to_string(v[v.size() / 2]).substr(0, 6) + " ms";
        };
        if (!with.empty())
            log::info("viewer: median frame while an effect converges " + median(with) + " (" + std::to_string(with.size()) + " frames), " +
                      (without.empty() ? std::string("no frame without") : "without " + median(without) + " (" + std::to_string(without.size()) + " frames)") +
                      "; " + pace);
    }
    if (ref_.on && ref_.tracer)
        log::info(std::string("viewer: reference ") + Reference::kModes[ref_.mode] + ": " + std::to_string(ref_.tracer->progressive_samples()) +
                  " samples per pixel at the end");
    if (!pose_ms_.empty()) {
        std::vector<double> sorted = pose_ms_;
        std::sort(sorted.begin(), sorted.end());
        log::info("viewer: posed the scene " + std::to_string(sorted.size()) + " times in " + std::to_string(frame) +
                  " frames; median pose (pose_scene, GpuScene::update_pose, shutter motion) " + std::to_string(sorted[sorted.size() / 2]).substr(0, 6) +
                  " ms, max " + std::to_string(sorted.back()).substr(0, 6) + " ms");
    }
    return 0;
}

int run_viewer(Scene& scene, const ViewerOptions& options) {
    // Bad input is reported before a window opens.
    std::vector<ScriptCommand> script;
    if (!options.script.empty()) script = load_script(options.script);
    for (const ScriptCommand& c : script)  // the script's animation names, before a window opens
        if (c.verb == "animation" && c.args[0] != "none") try {
                find_animation(scene, c.args[0]);
            } catch (const Error& e) {
                throw bad_input(options.script.string() + ":" + std::to_string(c.line) + ": " + e.what());
            }
    // The first animation plays unless --animation says otherwise (none: the rest pose).
    int animation = scene.animations.empty() ? -1 : 0;
    if (!options.animation.empty()) animation = options.animation == "none" ? -1 : find_animation(scene, options.animation);
    if (options.time >= 0.0f && animation < 0)
        throw bad_input("--time needs an animation (" + std::string(scene.animations.empty() ? "the scene has none" : "--animation none was given") + ")");
    ContextOptions co;
    // --size is the scene's size; the docked panel is added beside it.
    co.width = options.width + static_cast<int>(kPanelWidth);
    co.height = options.height;
    co.vsync = options.vsync;
    co.title = "Candela - " + scene.source.filename().string();
    ContextResult ctx = create_context(Backend::glfw, co);
    if (!ctx.context) {
        std::fprintf(stderr, "candela: %s\n", ctx.error.c_str());
        return static_cast<int>(ExitCode::no_gl);
    }
    log::info("viewer: " + ctx.context->device_string());
    ViewerOptions o = options;
    {
        const float aspect = static_cast<float>(o.width) / static_cast<float>(o.height);
        const ShaderLibrary shaders(o.shader_dir);
        complete_lighting(scene, o.lighting, shaders, scene.select_camera(o.camera, aspect), aspect);
    }
    apply_viewer_defaults(o.settings, o.set_knobs);
    Viewer viewer(scene, o, *ctx.context, std::move(script), animation);
    return viewer.run();
}

}  // namespace candela::viewer
