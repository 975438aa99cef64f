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
#include "gpu/bindings.h"
#include "image/image.hpp"
#include "platform/context.hpp"
#include "render/features.hpp"
#include "render/renderer.hpp"
#include "render/view_lighting.hpp"
#include "rt/ray_tracer.hpp"
#include "rt/tracer_options.hpp"
#include "scene/animation.hpp"
#include "script.hpp"
#include "shader/program_catalog.hpp"
#include "shader/file_watcher.hpp"

namespace candela::viewer {
namespace {
namespace fs = std::filesystem;
using Clock = std::chrono::steady_clock;

// The panel is docked to the window's right edge and the scene is drawn only left of it, so the
// panel never hides the scene. Widths are in window coordinates (ImGui's); the user can drag the
// panel's left edge. `candela view --size WxH` is the scene's size: the window adds the panel.
constexpr float kPanelWidth = 440.0f;
constexpr float kMinPanelWidth = 240.0f;
constexpr float kMinSceneWidth = 64.0f;

double ms_since(Clock::time_point t) { return std::chrono::duration<double, std::milli>(Clock::now() - t).count(); }

// Reads the window's back buffer (after the UI is drawn), top row first.
std::vector<unsigned char> read_window(int w, int h) {
    std::vector<unsigned char> rgba(static_cast<size_t>(w) * static_cast<size_t>(h) * 4);
    glBindFramebuffer(GL_READ_FRAMEBUFFER, 0);
    glReadBuffer(GL_BACK);
    glPixelStorei(GL_PACK_ALIGNMENT, 1);
    glReadPixels(0, 0, w, h, GL_RGBA, GL_UNSIGNED_BYTE, rgba.data());
    const size_t row = static_cast<size_t>(w) * 4;
    for (int y = 0; y < h / 2; ++y)
        std::swap_ranges(rgba.begin() + static_cast<std::ptrdiff_t>(y * row), rgba.begin() + static_cast<std::ptrdiff_t>((y + 1) * row),
                         rgba.begin() + static_cast<std::ptrdiff_t>((h - 1 - y) * row));
    return rgba;
}

// An RGBA8 texture holding display values (top row first in `img`, [0,1]).
void upload_display(gl::Texture& tex, const ImageF& img) {
    if (!tex || tex.width() != img.width || tex.height() != img.height) tex = gl::Texture::create_2d(GL_RGBA8, img.width, img.height, 1);
    std::vector<unsigned char> bytes(static_cast<size_t>(img.width) * static_cast<size_t>(img.height) * 4);
    for (int y = 0; y < img.height; ++y)
        for (int x = 0; x < img.width; ++x) {
            const float* p = img.at(x, img.height - 1 - y);  // GL's first row is the bottom one
            unsigned char* o = bytes.data() + (static_cast<size_t>(y) * static_cast<size_t>(img.width) + static_cast<size_t>(x)) * 4;
            for (int c = 0; c < 3; ++c) o[c] = static_cast<unsigned char>(std::clamp(p[c], 0.0f, 1.0f) * 255.0f + 0.5f);
            o[3] = 255;
        }
    glPixelStorei(GL_UNPACK_ALIGNMENT, 1);
    glTextureSubImage2D(tex.id(), 0, 0, 0, img.width, img.height, GL_RGBA, GL_UNSIGNED_BYTE, bytes.data());
}

// The reference mode: the ray tracer refines the current view between frames.
struct Reference {
    static constexpr const char* kModes[] = {"path", "direct", "whitted", "ao"};
    static constexpr const char* kViews[] = {"raster", "reference", "split", "flip", "difference"};
    bool on = false;
    int mode = 0, built_mode = -1;
    int view = 2;
    float budget_ms = 40.0f;
    std::unique_ptr<rt::RayTracer> tracer;
    glm::mat4 camera{0.0f};
    glm::vec2 lens{-1.0f};  // the traced camera's aperture and focus distance (with_lens)
    int width = 0, height = 0;
    int shown_samples = -1;
    // The pose the tracer's geometry was made from (Viewer::pose_serial_), and whether it was
    // built with the shutter open (Options::pose_at: motion blur), and the time slices posed
    // since the last restart (pose_within_shutter).
    std::uint64_t pose_serial = 0;
    bool built_motion = false;
    std::uint32_t motion_slices = 0;
    double rmse = -1.0, rmse_display = -1.0;  // linear radiance; display values
    gl::Texture image, diff;
    gl::Framebuffer fbo;
};

class Viewer {
public:
    Viewer(Scene& scene, const ViewerOptions& o, Context& ctx, std::vector<ScriptCommand> script, int animation)
        : scene_(scene), o_(o), ctx_(ctx), shaders_(o.shader_dir), gpu_(scene), settings_(o.settings),
          renderer_(shaders_, scene, gpu_, settings_), watcher_(shaders_.root()), effects_watcher_(shaders_.effects_root() / "effects"), bounds_(scene.world_bounds()),
          script_(std::move(script)) {
        select_camera(o.camera);
        deformable_ = has_deformation(scene_);
        if (animation >= 0) {
            anim_.select(animation, scene_.animations[static_cast<size_t>(animation)].end);
            anim_.playing = o.time < 0.0f;  // --time T: paused at T, the pose `render --time T` draws
            if (o.time >= 0.0f) anim_.set_time(o.time);
            log_animation("start");
        }
        IMGUI_CHECKVERSION();
        ImGui::CreateContext();
        ImGui::GetIO().IniFilename = nullptr;  // no imgui.ini next to the user's files
        ImGui::StyleColorsDark();
        ImGui_ImplGlfw_InitForOpenGL(ctx.window(), true);
        ImGui_ImplOpenGL3_Init("#version 450 core");
        blit_ = gl::Framebuffer::create();
        log::info(std::string("viewer: watching ") + shaders_.root().string() + " and " + (shaders_.effects_root() / "effects").string() +
                  (watcher_.uses_inotify() ? " (inotify)" : " (polling)"));
    }
    ~Viewer() {
        ImGui_ImplOpenGL3_Shutdown();
        ImGui_ImplGlfw_Shutdown();
        ImGui::DestroyContext();
    }
    int run();

private:
    void select_camera(const std::string& selector) {
        const auto [w, h] = scene_viewport();
        const Camera c = scene_.select_camera(selector, h > 0 ? static_cast<float>(w) / static_cast<float>(h) : 1.0f);
        const float d = bounds_.empty() ? 1.0f : glm::length(bounds_.center() - glm::vec3(c.world[3]));
        controller_.reset(c, std::max(d, 1e-3f));
    }
    void apply_settings(const RenderSettings& s) {
        try {
            renderer_.set_settings(s);
            settings_ = s;
            settings_error_.clear();
        } catch (const Error& e) {
            settings_error_ = e.what();
            log::warn(settings_error_);
        }
    }
    // The panel's width this frame (window coordinates): what the user left it at, narrowed so
    // that a narrow window keeps kMinSceneWidth for the scene.
    float panel_width(float window_width) const {
        return std::clamp(panel_width_, 0.0f, std::max(0.0f, window_width - kMinSceneWidth));
    }
    // The scene's part of the window in framebuffer pixels: the left part, full height (GL's
    // origin is the bottom-left corner, so the scene's viewport starts at 0,0). All of the window
    // when the panel is hidden (H).
    std::pair<int, int> scene_viewport() const {
        int fw = 0, fh = 0, ww = 0, wh = 0;
        glfwGetFramebufferSize(ctx_.window(), &fw, &fh);
        glfwGetWindowSize(ctx_.window(), &ww, &wh);
        if (!show_ui_ || ww <= 0 || fw <= 0) return {fw, fh};
        const float pixels_per_unit = static_cast<float>(fw) / static_cast<float>(ww);  // HiDPI
        const int panel = static_cast<int>(std::lround(panel_width(static_cast<float>(ww)) * pixels_per_unit));
        return {std::max(fw - panel, 1), fh};
    }
    void run_script(int frame);
    void handle_input(float dt);
    // Animation: poses the scene when the animation, its time or the shutter changed
    // since the last pose (paused: no work), then the GPU copy and the shutter's motion.
    void update_pose();
    // The reference tracer's Options::pose_at: the scene at time u in [0, 1) of the shutter.
    void pose_within_shutter(float u);
    std::string animation_label(int index) const {
        if (index < 0) return "none (rest pose)";
        const std::string& n = scene_.animations[static_cast<size_t>(index)].name;
        return n.empty() ? "animation " + std::to_string(index) : n;
    }
    void log_animation(const std::string& why) const;
    void animation_ui();
    void reload_shaders();
    void draw_ui(double frame_ms);
    void knob_widgets(const std::string& prefix_filter, bool exclude);
    void update_reference(const Camera& camera, int w, int h);
    void draw_inspected(int w, int h);
    struct Inspect {
        std::string name;  // "" = off
        int channel = 0, layer = 0;
        float scale = 1.0f, lod = 0.0f;
        gl::Program program;
    } inspect_;
    void draw_reference(int w, int h);
    // The GI probes' progress (effects/gi/gi.hpp); the log gets its line when the probes start
    // over, and when they converge, so a scripted run shows it too.
    GiStatus gi_status() const {
        const GiStatusView* v = renderer_.effect_runtime<GiStatusView>();
        return v ? v->gi_status() : GiStatus{};
    }
    void log_gi_progress(int frame);
    int gi_logged_phase_ = 0, gi_logged_updates_ = 0;  // 0 not planned, 1 converging, 2 converged
    Reference ref_;
    gl::VertexArray empty_vao_;

    Scene& scene_;  // posed by update_pose() as the animation plays
    ViewerOptions o_;
    Context& ctx_;
    ShaderLibrary shaders_;
    GpuScene gpu_;
    RenderSettings settings_;
    Renderer renderer_;
    FileWatcher watcher_;          // shaders/
    FileWatcher effects_watcher_;  // engine/effects/: each effect's GLSL beside its C++
    Bounds bounds_;
    std::vector<ScriptCommand> script_;
    CameraController controller_;
    gl::Framebuffer blit_;
    std::string shader_errors_, settings_error_, status_;
    std::deque<double> frame_times_;
    bool quit_ = false;
    std::vector<fs::path> pending_screenshots_;
    bool show_ui_ = true;
    float panel_width_ = kPanelWidth;
    // Animation: the clock, the shutter interval of the current pose, and a serial that changes
    // with every pose (the reference restarts on it; the Renderer watches GpuScene::pose_version).
    Playback anim_;
    bool deformable_ = false;  // has_deformation(scene): animations, skins or morph targets
    ShutterInterval shutter_{};
    std::uint64_t pose_serial_ = 0;
    std::vector<double> pose_ms_;  // CPU pose + GPU upload + motion, per pose (the log's median)
};

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

void Viewer::update_reference(const Camera& camera, int w, int h) {
    Reference& r = ref_;
    if (!r.on) return;
    // Motion blur in the reference: the shutter is open and something is animated. The tracer
    // then poses the scene itself per time slice (Options::pose_at) and rebuilds on restart.
    const bool motion = anim_.animation >= 0 && !shutter_.instant();
    if (!r.tracer || r.built_mode != r.mode || r.built_motion != motion) {
        rt::Options o = rt::tracer_options(settings_);
        o.mode = *rt::parse_mode(Reference::kModes[r.mode]);
        o.spp = 1 << 16;
        o.tile_rows = 16;
        if (motion) {
            // A time per sample (rt.shutter_slices is for `render`: with N slices over the
            // reference's 65536 samples its first slice would last 65536 / N samples).
            o.pose_at = [this](float u) { pose_within_shutter(u); };
            o.shutter_slices = 0;
        }
        try {
            r.tracer = std::make_unique<rt::RayTracer>(shaders_, scene_, gpu_, o);
        } catch (const Error& e) {
            settings_error_ = e.what();
            r.on = false;
            return;
        }
        r.built_mode = r.mode;
        r.built_motion = motion;
        r.pose_serial = pose_serial_;  // made from the scene as it is posed now
        if (motion) {
            char line[200];
            std::snprintf(line, sizeof line, "viewer: reference: motion blur, the tracer poses the scene over the shutter %.4f..%.4f s (a time per sample)",
                          shutter_.open, shutter_.close);
            log::info(line);
        }
        r.width = 0;  // restart below
    }
    if (r.pose_serial != pose_serial_) {
        // The pose changed: the accumulation starts over on the new geometry. With motion the
        // restart rebuilds at the frame's time itself; without, the tree is rebuilt here (a
        // refit would degrade over a long playback; a rebuild on Fox is well under a millisecond).
        if (!motion) r.tracer->update_geometry(rt::RtUpdate::rebuild);
        r.pose_serial = pose_serial_;
        r.width = 0;
        if (!anim_.playing) {  // a scrub or a new animation (while playing this is every frame)
            char line[160];
            std::snprintf(line, sizeof line, "viewer: reference restarts: new pose at %.3f s%s", anim_.time,
                          motion ? ", motion blur over the shutter" : "");
            log::info(std::string(line) + (motion ? " " + std::to_string(shutter_.open) + ".." + std::to_string(shutter_.close) + " s" : ""));
        }
    }
    const Camera lensed = with_lens(camera, settings_);  // camera.aperture / camera.focus_distance
    if (camera.world != r.camera || glm::vec2(lensed.aperture, lensed.focus_distance) != r.lens || w != r.width || h != r.height) {
        r.motion_slices = 0;  // the shutter times start over (pose_within_shutter)
        r.tracer->progressive_restart(lensed, w, h);
        r.camera = camera.world;
        r.lens = glm::vec2(lensed.aperture, lensed.focus_distance);
        r.width = w;
        r.height = h;
        r.shown_samples = -1;
    }
    r.tracer->progressive_step(r.budget_ms);
    // Read back when a whole sample more is in (a readback costs as much as a few tiles), and
    // every frame while the first sample is still coming in (its rows appear as they finish).
    const int samples = r.tracer->progressive_samples();
    if (samples == r.shown_samples && samples > 0) return;
    r.shown_samples = samples;
    const ImageF reference = r.tracer->progressive_image();
    const ImageF raster = renderer_.read_radiance();
    const ImageF shown = to_display(reference, o_.exposure_ev);
    r.rmse = samples > 0 ? compare(raster, reference, 2.0 / 255.0).rmse : -1.0;
    r.rmse_display = samples > 0 ? compare(to_display(raster, o_.exposure_ev), shown, 2.0 / 255.0).rmse : -1.0;
    upload_display(r.image, shown);
    upload_display(r.diff, heatmap(raster, reference, 0.1));
}

void Viewer::draw_inspected(int w, int h) {
    const gl::Texture* t = renderer_.inspected();
    if (inspect_.name.empty() || !t) return;
    if (!inspect_.program) {
        ShaderLibrary::BuildResult r = shaders_.build(program_desc("debug_view"));
        if (!r.ok()) {
            shader_errors_ = r.log;
            inspect_.name.clear();
            return;
        }
        inspect_.program = std::move(r.program);
    }
    GLint target = 0;
    glGetTextureParameteriv(t->id(), GL_TEXTURE_TARGET, &target);
    const int kind = target == GL_TEXTURE_2D_ARRAY ? 1 : target == GL_TEXTURE_CUBE_MAP_ARRAY ? 2 : 0;
    const GLuint p = inspect_.program.id();
    glBindFramebuffer(GL_FRAMEBUFFER, 0);
    glViewport(0, 0, w, h);
    glDisable(GL_DEPTH_TEST);
    glDisable(GL_BLEND);
    glDisable(GL_CULL_FACE);
    glUseProgram(p);
    glProgramUniform1i(p, 0, kind);
    glProgramUniform1i(p, 1, inspect_.channel);
    glProgramUniform1f(p, 2, inspect_.scale);
    glProgramUniform1i(p, 3, inspect_.layer);
    glProgramUniform1f(p, 4, inspect_.lod);
    for (GLuint unit = DEBUG_2D_UNIT; unit <= DEBUG_CUBE_UNIT; ++unit) glBindSampler(unit, 0);
    glBindTextureUnit(static_cast<GLuint>(DEBUG_2D_UNIT + kind), t->id());  // kind 0 2D, 1 array, 2 cube
    if (!empty_vao_) empty_vao_ = gl::VertexArray::create();
    glBindVertexArray(empty_vao_.id());
    glDrawArrays(GL_TRIANGLES, 0, 3);
    glBindVertexArray(0);
    glUseProgram(0);
}

void Viewer::draw_reference(int w, int h) {
    Reference& r = ref_;
    if (!r.on || !r.image || r.image.width() != w || r.image.height() != h || r.view == 0) return;
    if (!r.fbo) r.fbo = gl::Framebuffer::create();
    const bool flip_shows_reference = std::fmod(glfwGetTime(), 1.0) < 0.5;
    const gl::Texture& src = r.view == 4 ? r.diff : r.image;
    if (r.view == 3 && !flip_shows_reference) return;
    glNamedFramebufferTexture(r.fbo.id(), GL_COLOR_ATTACHMENT0, src.id(), 0);
    const int x0 = r.view == 2 ? w / 2 : 0;  // split: reference on the right half
    glBlitNamedFramebuffer(r.fbo.id(), 0, x0, 0, w, h, x0, 0, w, h, GL_COLOR_BUFFER_BIT, GL_NEAREST);
}

void Viewer::run_script(int frame) {
    for (const ScriptCommand& c : script_) {
        if (c.frame != frame) continue;
        const auto num = [&](size_t i) { return std::stof(c.args[i]); };
        try {
            if (c.verb == "orbit") controller_.orbit(num(0), num(1));
            else if (c.verb == "zoom") controller_.zoom(num(0));
            else if (c.verb == "pan") controller_.pan(num(0), num(1));
            else if (c.verb == "camera") select_camera(c.args[0]);
            else if (c.verb == "frame") controller_.frame(bounds_);
            else if (c.verb == "screenshot") pending_screenshots_.push_back(c.args[0]);
            else if (c.verb == "quit") quit_ = true;
            else if (c.verb == "animation" || c.verb == "time" || c.verb == "play" || c.verb == "pause" || c.verb == "speed" ||
                     c.verb == "loop") {
                if (c.verb == "animation") {
                    const int index = c.args[0] == "none" ? -1 : find_animation(scene_, c.args[0]);
                    anim_.select(index, index >= 0 ? scene_.animations[static_cast<size_t>(index)].end : 0.0f);
                } else if (anim_.animation < 0 && c.verb != "loop" && c.verb != "speed") {
                    throw bad_input("'" + c.verb + "' needs an animation (the scene has " + std::to_string(scene_.animations.size()) +
                                    "; none is chosen)");
                } else if (c.verb == "time") anim_.set_time(num(0));
                else if (c.verb == "play") anim_.play();
                else if (c.verb == "pause") anim_.pause();
                else if (c.verb == "speed") anim_.set_speed(num(0));
                else anim_.loop = c.args[0] == "on";
                log_animation("frame " + std::to_string(frame) + ": " + c.verb);
            } else if (c.verb == "inspect") {
                inspect_.name = c.args[0] == "off" ? "" : c.args[0];
                static const std::vector<std::string> channels = {"rgb", "r", "g", "b", "a"};
                if (c.args.size() > 1) {
                    auto it = std::find(channels.begin(), channels.end(), c.args[1]);
                    if (it == channels.end()) throw bad_input("'" + c.args[1] + "' is not a channel (rgb, r, g, b, a)");
                    inspect_.channel = static_cast<int>(it - channels.begin());
                }
                if (c.args.size() > 2) inspect_.scale = std::stof(c.args[2]);
                if (c.args.size() > 3) inspect_.layer = std::max(0, std::stoi(c.args[3]));
                renderer_.set_inspect(inspect_.name);
            } else if (c.verb == "reference" || c.verb == "show") {
                const bool ref = c.verb == "reference";
                if (ref && c.args[0] == "off") {
                    ref_.on = false;
                    continue;
                }
                const auto& names = ref ? std::vector<std::string>(Reference::kModes, Reference::kModes + 4)
                                        : std::vector<std::string>(Reference::kViews, Reference::kViews + 5);
                auto it = std::find(names.begin(), names.end(), c.args[0]);
                if (it == names.end()) throw bad_input("'" + c.args[0] + "' is not one of the " + (ref ? "reference modes" : "views"));
                (ref ? ref_.mode : ref_.view) = static_cast<int>(it - names.begin());
                if (ref) ref_.on = true;
                if (ref && c.args.size() > 1) ref_.budget_ms = std::clamp(std::stof(c.args[1]), 1.0f, 10000.0f);
            }
            else {
                RenderSettings s = settings_;
                if (c.verb == "effects") apply_effects(s, c.args[0]);
                else if (c.verb == "set") apply_knobs(s, {c.args[0]});
                else if (c.verb == "path") apply_knob(s, "render.path=" + c.args[0]);
                apply_settings(s);
            }
        } catch (const Error& e) {
            // A bad value in a script line is the script's error: say where, stop the run.
            throw bad_input(o_.script.string() + ":" + std::to_string(c.line) + ": " + e.what());
        }
    }
}

void Viewer::handle_input(float dt) {
    ImGuiIO& io = ImGui::GetIO();
    GLFWwindow* w = ctx_.window();
    if (!io.WantCaptureMouse) {
        const ImVec2 d = io.MouseDelta;
        const bool shift = io.KeyShift;
        if (ImGui::IsMouseDown(ImGuiMouseButton_Left) && !shift) controller_.orbit(-d.x * 0.3f, -d.y * 0.3f);
        if (ImGui::IsMouseDown(ImGuiMouseButton_Middle) || (ImGui::IsMouseDown(ImGuiMouseButton_Left) && shift))
            controller_.pan(-d.x * 0.002f, d.y * 0.002f);
        if (io.MouseWheel != 0.0f) controller_.zoom(std::pow(0.9f, io.MouseWheel));
    }
    if (io.WantCaptureKeyboard) return;
    const float speed = controller_.distance() * 0.8f * dt * (io.KeyShift ? 4.0f : 1.0f);
    glm::vec3 m(0.0f);
    if (glfwGetKey(w, GLFW_KEY_W) == GLFW_PRESS) m.z -= speed;
    if (glfwGetKey(w, GLFW_KEY_S) == GLFW_PRESS) m.z += speed;
    if (glfwGetKey(w, GLFW_KEY_A) == GLFW_PRESS) m.x -= speed;
    if (glfwGetKey(w, GLFW_KEY_D) == GLFW_PRESS) m.x += speed;
    if (glfwGetKey(w, GLFW_KEY_Q) == GLFW_PRESS) m.y -= speed;
    if (glfwGetKey(w, GLFW_KEY_E) == GLFW_PRESS) m.y += speed;
    if (m != glm::vec3(0.0f)) controller_.fly(m);
    if (ImGui::IsKeyPressed(GLFW_KEY_F)) controller_.frame(bounds_);
    if (ImGui::IsKeyPressed(GLFW_KEY_TAB)) controller_.fly_mode = !controller_.fly_mode;
    if (ImGui::IsKeyPressed(GLFW_KEY_H)) show_ui_ = !show_ui_;
    if (anim_.animation >= 0) {
        if (ImGui::IsKeyPressed(GLFW_KEY_SPACE)) anim_.playing ? anim_.pause() : anim_.play();
        // Arrows: one frame (camera.fps) back or ahead, paused.
        const float step = 1.0f / std::max(settings_.camera.fps, 1.0f);
        if (ImGui::IsKeyPressed(GLFW_KEY_LEFT)) anim_.pause(), anim_.set_time(anim_.time - step);
        if (ImGui::IsKeyPressed(GLFW_KEY_RIGHT)) anim_.pause(), anim_.set_time(anim_.time + step);
    }
    if (ImGui::IsKeyPressed(GLFW_KEY_P) || ImGui::IsKeyPressed(GLFW_KEY_F12)) {
        char name[64];
        std::snprintf(name, sizeof name, "candela_%lld.png",
                      static_cast<long long>(std::chrono::system_clock::now().time_since_epoch() / std::chrono::seconds(1)));
        pending_screenshots_.push_back(name);
    }
    if (ImGui::IsKeyPressed(GLFW_KEY_ESCAPE)) quit_ = true;
}

void Viewer::reload_shaders() {
    std::vector<fs::path> changed = watcher_.poll();
    for (fs::path& f : effects_watcher_.poll()) changed.push_back(std::move(f));
    if (changed.empty()) return;
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

void Viewer::knob_widgets(const std::string& prefix, bool exclude) {
    const nlohmann::json values = to_json(settings_)["knobs"];
    for (const KnobInfo& k : knob_infos()) {
        const bool match = k.name.rfind(prefix, 0) == 0;
        if (match == exclude) continue;
        const nlohmann::json& v = values[k.name];
        std::string assignment;
        ImGui::PushID(k.name.c_str());
        if (k.type == "bool") {
            bool b = v.get<bool>();
            if (ImGui::Checkbox(k.name.c_str(), &b)) assignment = k.name + "=" + (b ? "1" : "0");
        } else if (k.type == "int") {
            int i = v.get<int>();
            if (ImGui::InputInt(k.name.c_str(), &i, 1, 8, ImGuiInputTextFlags_EnterReturnsTrue)) assignment = k.name + "=" + std::to_string(i);
        } else if (k.type == "float") {
            float f = v.get<float>();
            if (ImGui::InputFloat(k.name.c_str(), &f, 0.0f, 0.0f, "%.4g", ImGuiInputTextFlags_EnterReturnsTrue))
                assignment = k.name + "=" + std::to_string(f);
        } else {
            const std::string current = v.get<std::string>();
            if (ImGui::BeginCombo(k.name.c_str(), current.c_str())) {
                size_t start = 0;
                while (start <= k.range.size()) {
                    const size_t bar = k.range.find('|', start);
                    const std::string choice = k.range.substr(start, bar == std::string::npos ? std::string::npos : bar - start);
                    if (ImGui::Selectable(choice.c_str(), choice == current)) assignment = k.name + "=" + choice;
                    if (bar == std::string::npos) break;
                    start = bar + 1;
                }
                ImGui::EndCombo();
            }
        }
        if (ImGui::IsItemHovered()) ImGui::SetTooltip("%s\n%s %s", k.help.c_str(), k.type.c_str(), k.range.c_str());
        ImGui::PopID();
        if (!assignment.empty()) {
            RenderSettings s = settings_;
            try {
                apply_knob(s, assignment);
                apply_settings(s);
            } catch (const Error& e) {
                settings_error_ = e.what();
            }
        }
    }
}

// Dim text that wraps at the panel's edge (ImGui::TextDisabled does not wrap).
void wrapped_disabled(const std::string& text) {
    ImGui::PushStyleColor(ImGuiCol_Text, ImGui::GetStyleColorVec4(ImGuiCol_TextDisabled));
    ImGui::TextWrapped("%s", text.c_str());
    ImGui::PopStyleColor();
}

void Viewer::animation_ui() {
    Playback& a = anim_;
    char label[160];
    const auto item = [&](int i) {
        if (i < 0) return animation_label(i);
        std::snprintf(label, sizeof label, "%s (%.2f s)", animation_label(i).c_str(), scene_.animations[static_cast<size_t>(i)].end);
        return std::string(label);
    };
    if (ImGui::BeginCombo("animation", item(a.animation).c_str())) {
        for (int i = -1; i < static_cast<int>(scene_.animations.size()); ++i) {
            ImGui::PushID(i);
            if (ImGui::Selectable(item(i).c_str(), i == a.animation) && i != a.animation) {
                const bool was_playing = a.playing;
                a.select(i, i >= 0 ? scene_.animations[static_cast<size_t>(i)].end : 0.0f);
                if (i >= 0 && was_playing) a.play();
            }
            ImGui::PopID();
        }
        ImGui::EndCombo();
    }
    if (a.animation < 0) {
        wrapped_disabled("the rest pose: the file's node transforms, default morph weights, skins at their bind pose");
        return;
    }
    if (ImGui::Button(a.playing ? "pause" : "play", ImVec2(ImGui::GetFrameHeight() * 3.0f, 0.0f))) a.playing ? a.pause() : a.play();
    ImGui::SameLine();
    ImGui::Checkbox("loop", &a.loop);
    ImGui::SameLine();
    ImGui::Text("%.3f / %.3f s", a.time, a.duration);
    // Scrubbing: the slider sets the time; playing goes on from there (pause first to hold it).
    float t = a.time;
    std::snprintf(label, sizeof label, "%%.3f s of %.3f", a.duration);
    if (ImGui::SliderFloat("time", &t, 0.0f, a.duration, label)) a.set_time(t);
    float speed = a.speed;
    if (ImGui::SliderFloat("speed", &speed, Playback::kMinSpeed, Playback::kMaxSpeed, "%.2fx", ImGuiSliderFlags_Logarithmic))
        a.set_speed(speed);
    // The shutter (camera.shutter, also under Knobs): motion blur in the raster frame (when the
    // effect plans) and in the reference.
    float shutter = settings_.camera.shutter;
    if (ImGui::SliderFloat("shutter", &shutter, 0.0f, 1.0f, "%.2f frame")) {
        RenderSettings s = settings_;
        s.camera.shutter = shutter;
        apply_settings(s);
    }
    if (ImGui::IsItemHovered()) ImGui::SetTooltip("camera.shutter: the fraction of a frame (camera.fps) the shutter is open; 0: no motion blur");
    std::string info;
    if (!pose_ms_.empty()) {
        std::snprintf(label, sizeof label, "last pose %.2f ms (CPU pose, upload%s); %zu poses", pose_ms_.back(),
                      shutter_.instant() ? "" : ", shutter motion", pose_ms_.size());
        info = label;
    }
    if (!shutter_.instant()) {
        std::snprintf(label, sizeof label, "; shutter open %.4f..%.4f s at %.0f fps", shutter_.open, shutter_.close, settings_.camera.fps);
        info += label;
    }
    if (!info.empty()) wrapped_disabled(info);
}

void Viewer::draw_ui(double frame_ms) {
    // Docked: pinned to the right edge at full height, opaque (the scene is not behind it), and
    // resizable only by its left edge; the new width moves the scene's edge on the next frame.
    const ImVec2 display = ImGui::GetIO().DisplaySize;
    const float width = panel_width(display.x);
    ImGui::SetNextWindowPos(ImVec2(display.x - width, 0.0f), ImGuiCond_Always);
    ImGui::SetNextWindowSize(ImVec2(width, display.y), ImGuiCond_Always);
    ImGui::SetNextWindowSizeConstraints(ImVec2(std::min(kMinPanelWidth, width), display.y),
                                        ImVec2(std::max(width, display.x - kMinSceneWidth), display.y));
    ImGui::PushStyleColor(ImGuiCol_WindowBg, ImVec4(0.08f, 0.08f, 0.09f, 1.0f));
    ImGui::PushStyleVar(ImGuiStyleVar_WindowRounding, 0.0f);
    ImGui::Begin("Candela", nullptr, ImGuiWindowFlags_NoMove | ImGuiWindowFlags_NoCollapse | ImGuiWindowFlags_NoTitleBar);
    ImGui::PopStyleVar();
    ImGui::PopStyleColor();
    if (ImGui::GetWindowWidth() != width) panel_width_ = ImGui::GetWindowWidth();  // dragged by the user
    ImGui::TextWrapped("%s", ctx_.device_string().c_str());
    frame_times_.push_back(frame_ms);
    if (frame_times_.size() > 60) frame_times_.pop_front();
    std::vector<double> sorted(frame_times_.begin(), frame_times_.end());
    std::sort(sorted.begin(), sorted.end());
    ImGui::Text("frame %.1f ms (median of %zu)  %s", sorted[sorted.size() / 2], sorted.size(), controller_.fly_mode ? "fly" : "orbit");
    if (!o_.lighting.reason.empty()) ImGui::TextWrapped("lighting: %s", o_.lighting.reason.c_str());
    ImGui::PushStyleColor(ImGuiCol_Text, ImGui::GetStyleColorVec4(ImGuiCol_TextDisabled));
    ImGui::TextWrapped("drag: turn  shift/middle drag: pan  wheel: zoom  WASDQE: move  F: frame  Tab: fly  P: screenshot  "
                       "H: hide this panel%s", scene_.animations.empty() ? "" : "  Space: play/pause  arrows: step a frame");
    ImGui::PopStyleColor();
    if (!shader_errors_.empty()) {
        ImGui::PushStyleColor(ImGuiCol_Text, ImVec4(1.0f, 0.45f, 0.4f, 1.0f));
        ImGui::TextWrapped("Shader error (the last good program is in use):\n%s", shader_errors_.c_str());
        ImGui::PopStyleColor();
    }
    if (!settings_error_.empty()) {
        ImGui::PushStyleColor(ImGuiCol_Text, ImVec4(1.0f, 0.45f, 0.4f, 1.0f));
        ImGui::TextWrapped("%s", settings_error_.c_str());
        ImGui::PopStyleColor();
    }
    if (!status_.empty()) wrapped_disabled(status_);

    if (ImGui::CollapsingHeader("Camera")) {
        if (ImGui::Button("Frame scene (F)")) controller_.frame(bounds_);
        for (size_t i = 0; i < scene_.cameras.size(); ++i) {
            ImGui::SameLine();
            const std::string label = scene_.cameras[i].name.empty() ? "camera " + std::to_string(i) : scene_.cameras[i].name;
            if (ImGui::Button(label.c_str())) select_camera(std::to_string(i));
        }
        ImGui::SliderFloat("exposure (EV)", &o_.exposure_ev, -8.0f, 8.0f);
    }
    if (!scene_.animations.empty() && ImGui::CollapsingHeader("Animation", ImGuiTreeNodeFlags_DefaultOpen)) animation_ui();
    if (ImGui::CollapsingHeader("Effects", ImGuiTreeNodeFlags_DefaultOpen)) {
        const Features& f = renderer_.features();
        RenderSettings s = settings_;
        bool changed = false;
        // The checkbox is the user's switch (--effects); beside it, what the planner made of it,
        // and below it the planner's reason, wrapped to the panel. The status column starts
        // after the longest effect name.
        float name_width = 0.0f;
        for (const std::string& n : effect_names()) name_width = std::max(name_width, ImGui::CalcTextSize(n.c_str()).x);
        const ImGuiStyle& style = ImGui::GetStyle();
        const float status_x = style.WindowPadding.x + ImGui::GetFrameHeight() + style.ItemInnerSpacing.x + name_width + style.ItemSpacing.x * 2.0f;
        for (const std::string& name : effect_names()) {
            bool on = s.on(name);
            const EffectStatus status = effect_status(on, f.decision(name));
            if (ImGui::Checkbox(name.c_str(), &on)) {
                s.set_on(name, on);
                changed = true;
            }
            if (ImGui::IsItemHovered())
                ImGui::SetTooltip("switch %s on or off (--effects); the planner still skips it when the scene does not need it",
                                  name.c_str());
            ImGui::SameLine(status_x);
            const ImVec4 colour = status.state == EffectState::running   ? ImVec4(0.45f, 0.85f, 0.45f, 1.0f)
                                  : status.state == EffectState::skipped ? ImVec4(0.95f, 0.75f, 0.35f, 1.0f)
                                                                         : ImGui::GetStyleColorVec4(ImGuiCol_TextDisabled);
            ImGui::TextColored(colour, "%s", status.label.c_str());
            ImGui::Indent(ImGui::GetFrameHeightWithSpacing());
            wrapped_disabled(status.detail);
            if (name == "gi") {
                const GiStatus gi = gi_status();
                const std::string line = gi_status_line(gi, settings_.get<GiOptions>().budget);
                if (!line.empty()) {
                    const ImVec4 c = gi.converged() ? ImVec4(0.45f, 0.85f, 0.45f, 1.0f) : ImVec4(0.95f, 0.75f, 0.35f, 1.0f);
                    ImGui::PushStyleColor(ImGuiCol_Text, c);
                    ImGui::TextWrapped("%s", line.c_str());
                    ImGui::PopStyleColor();
                }
            }
            ImGui::Unindent(ImGui::GetFrameHeightWithSpacing());
        }
        if (changed) apply_settings(s);
    }
    if (ImGui::CollapsingHeader("Reference (ray tracer)", ref_.on ? ImGuiTreeNodeFlags_DefaultOpen : 0)) {
        Reference& r = ref_;
        ImGui::Checkbox("refine in the background", &r.on);
        ImGui::Combo("mode", &r.mode, Reference::kModes, 4);
        ImGui::Combo("show", &r.view, Reference::kViews, 5);
        ImGui::SliderFloat("ms per frame", &r.budget_ms, 5.0f, 500.0f, "%.0f");
        if (r.on && r.tracer) {
            ImGui::Text("%d spp", r.tracer->progressive_samples());
            if (r.rmse >= 0.0) {
                ImGui::SameLine();
                ImGui::Text("RMSE vs reference: %.4f linear, %.4f display", r.rmse, r.rmse_display);
            }
        }
    }
    if (ImGui::CollapsingHeader("Knobs")) knob_widgets("debug.", true);
    if (ImGui::CollapsingHeader("Debug views")) {
        knob_widgets("debug.", false);
        const std::string current = inspect_.name.empty() ? "(final image)" : inspect_.name;
        if (ImGui::BeginCombo("buffer", current.c_str())) {
            if (ImGui::Selectable("(final image)", inspect_.name.empty())) inspect_.name.clear();
            for (const std::string& n : renderer_.inspectable())
                if (ImGui::Selectable(n.c_str(), n == inspect_.name)) inspect_.name = n;
            ImGui::EndCombo();
        }
        if (!inspect_.name.empty()) {
            static const char* channels[] = {"rgb", "r", "g", "b", "a"};
            ImGui::Combo("channel", &inspect_.channel, channels, 5);
            ImGui::SliderFloat("scale", &inspect_.scale, 0.01f, 100.0f, "%.3g", ImGuiSliderFlags_Logarithmic);
            ImGui::InputInt("layer / probe", &inspect_.layer);
            inspect_.layer = std::max(inspect_.layer, 0);
            ImGui::SliderFloat("mip level", &inspect_.lod, 0.0f, 8.0f, "%.1f");
            ImGui::TextDisabled("depth is reversed-Z (near 1, far 0); cubes show longitude/latitude");
        }
        renderer_.set_inspect(inspect_.name);
    }
    if (ImGui::CollapsingHeader("Passes", ImGuiTreeNodeFlags_DefaultOpen)) {
        const FrameReport& r = renderer_.last_frame();
        if (ImGui::BeginTable("passes", 5, ImGuiTableFlags_RowBg | ImGuiTableFlags_SizingStretchProp)) {
            for (const char* h : {"pass", "GPU ms", "draws", "triangles", "dispatches"}) ImGui::TableSetupColumn(h);
            ImGui::TableHeadersRow();
            for (const PassStats& p : r.passes) {
                ImGui::TableNextRow();
                ImGui::TableNextColumn();
                ImGui::TextUnformatted(p.name.c_str());
                ImGui::TableNextColumn();
                if (p.gpu_ms >= 0.0) ImGui::Text("%.2f", p.gpu_ms);
                else ImGui::TextDisabled("-");
                ImGui::TableNextColumn();
                ImGui::Text("%d", p.counters.draw_calls);
                ImGui::TableNextColumn();
                ImGui::Text("%zu", p.counters.triangles);
                ImGui::TableNextColumn();
                ImGui::Text("%d", p.counters.dispatches);
            }
            ImGui::EndTable();
        }
        for (const auto& [name, why] : r.culled) wrapped_disabled("culled " + name + ": " + why);
        if (ImGui::TreeNode("planned passes and why")) {
            for (const PlannedPass& p : plan_passes(renderer_.features(), settings_)) {
                ImGui::Bullet();
                ImGui::TextWrapped("%s: %s", p.name.c_str(), p.why.c_str());
            }
            ImGui::TreePop();
        }
    }
    ImGui::End();
}

void Viewer::log_gi_progress(int frame) {
    const GiStatus st = gi_status();
    const int phase = !st.planned ? 0 : st.converged() ? 2 : 1;
    // A restart (scene, shaders or GI settings changed) sets updates_done back.
    if (phase == gi_logged_phase_ && !(phase == 1 && st.updates_done < gi_logged_updates_)) {
        gi_logged_updates_ = st.updates_done;
        return;
    }
    gi_logged_phase_ = phase;
    gi_logged_updates_ = st.updates_done;
    if (phase == 0) return;
    log::info("viewer: frame " + std::to_string(frame) + ": " + gi_status_line(st, settings_.get<GiOptions>().budget));
}

int Viewer::run() {
    GLFWwindow* window = ctx_.window();
    auto last = Clock::now();
    int frame = 0;
    int w = 0, h = 0;  // the scene's viewport (left of the panel)
    std::vector<double> whole_frames;
    std::vector<bool> gi_frames;  // whether the frame traced GI probe rays
    while (!glfwWindowShouldClose(window) && !quit_) {
        glfwPollEvents();
        int window_w = 0, window_h = 0;  // framebuffer pixels
        glfwGetFramebufferSize(window, &window_w, &window_h);
        if (window_w <= 0 || window_h <= 0) {  // minimized: nothing to draw, do not spin
            glfwWaitEventsTimeout(0.1);
            continue;
        }
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
        const Camera camera = controller_.camera();
        renderer_.render(camera, w, h, FrameOutput::display, o_.exposure_ev);
        renderer_.resolve_gpu_times();
        gi_frames.push_back(gi_status().rays_last_frame > 0);
        log_gi_progress(frame);
        update_reference(camera, w, h);
        // The panel is opaque, but the strip under it must not show stale frames either.
        const GLfloat backdrop[4] = {0.08f, 0.08f, 0.09f, 1.0f};
        glClearNamedFramebufferfv(0, GL_COLOR, 0, backdrop);
        glNamedFramebufferTexture(blit_.id(), GL_COLOR_ATTACHMENT0, renderer_.display().id(), 0);
        glBlitNamedFramebuffer(blit_.id(), 0, 0, 0, w, h, 0, 0, w, h, GL_COLOR_BUFFER_BIT, GL_NEAREST);
        draw_reference(w, h);
        draw_inspected(w, h);
        const bool last_frame = o_.frames > 0 && frame + 1 >= o_.frames;
        if (last_frame && !o_.screenshot.empty()) pending_screenshots_.push_back(o_.screenshot);
        for (const fs::path& p : pending_screenshots_) {
            write_display_rgba8(p, renderer_.read_display(), w, h);
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
            log::info("viewer: wrote " + p.string() + pose + ", " + std::to_string(nonfinite) + " non-finite radiance values");
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
        // The frames that updated GI probes against the others (the cost of gi.budget).
        std::vector<double> with, without;
        for (size_t i = 1; i < whole_frames.size(); ++i) (gi_frames[i] ? with : without).push_back(whole_frames[i]);
        const auto median = [](std::vector<double>& v) {
            std::sort(v.begin(), v.end());
            return std::to_string(v[v.size() / 2]).substr(0, 6) + " ms";
        };
        if (!with.empty())
            log::info("viewer: median frame while GI probes update " + median(with) + " (" + std::to_string(with.size()) + " frames), " +
                      (without.empty() ? std::string("no frame without") : "without " + median(without) + " (" + std::to_string(without.size()) + " frames)") +
                      "; gi.budget " + std::to_string(settings_.get<GiOptions>().budget) + " rays/frame");
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

}  // namespace

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
