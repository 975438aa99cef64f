#pragma once
// Internal to the viewer (viewer*.cpp): the Viewer, i.e. the window's frame loop and its state,
// and the reference tracer's progressive state. Its members are defined by concern:
//   viewer.cpp            the frame loop (run), animation posing, shader reloads, run_viewer
//   viewer_panel.cpp      the ImGui panel
//   viewer_input.cpp      mouse and keyboard, the script's commands, window screenshots
//   viewer_reference.cpp  the reference tracer refining the view, and the texture inspector
//   viewer_budget.cpp     the error budget's choice, applied as the settings (and the reference)
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
#include <cstdint>
#include <deque>
#include <filesystem>
#include <map>
#include <memory>
#include <string>
#include <utility>
#include <vector>

#include "adaptive_quality.hpp"
#include "budget_mode.hpp"
#include "camera_controller.hpp"
#include "effect_status.hpp"
#include "playback.hpp"
#include "viewer.hpp"
#include "core/error.hpp"
#include "core/log.hpp"
#include "image/image.hpp"
#include "platform/context.hpp"
#include "render/features.hpp"
#include "render/renderer.hpp"
#include "rt/ray_tracer.hpp"
#include "scene/animation.hpp"
#include "script.hpp"
#include "shader/file_watcher.hpp"

namespace candela::viewer {

using Clock = std::chrono::steady_clock;

// The panel is docked to the window's right edge and the scene is drawn only left of it, so the
// panel never hides the scene. Widths are in window coordinates (ImGui's); the user can drag the
// panel's left edge. `candela view --size WxH` is the scene's size: the window adds the panel.
constexpr float kPanelWidth = 440.0f;
constexpr float kMinPanelWidth = 240.0f;
constexpr float kMinSceneWidth = 64.0f;

double ms_since(Clock::time_point t);

// Reads the window's back buffer (after the UI is drawn), top row first (viewer_input.cpp).
std::vector<unsigned char> read_window(int w, int h);

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
    std::size_t nonfinite = 0;  // non-finite values in the last image read back (shown_samples)
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
        reduced_ = reduced_settings(settings_);
        // Scripted runs replay the same images on any machine: adaptive quality starts off
        // there (the script's `adaptive on` turns it on).
        adaptive_.set_enabled(script_.empty());
        if (o.error_budget > 0.0) {  // --error-budget E: chosen before the first frame
            budget_e_ = o.error_budget;
            budget_pending_ = true;
        }
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
            reduced_ = reduced_settings(settings_);
            renderer_reduced_ = false;
            ++view_generation_;
            settings_error_.clear();
        } catch (const Error& e) {
            settings_error_ = e.what();
            log::warn(settings_error_);
        }
    }
    // Adaptive quality (adaptive_quality.hpp): the state this frame renders at, the renderer's
    // settings switched between the user's and the reduced ones, and whether the frame needs
    // rendering at all (a still view already shown at full quality is not rendered again).
    QualityState choose_quality(const Camera& camera);
    void use_settings_for(const QualityState& q);
    bool view_unchanged(const Camera& camera, int rw, int rh) const;
    void adaptive_ui();
    // The error budget (budget_mode.hpp). choose_budget measures the statistics of `camera` (a
    // small trace), chooses for budget_e_ and applies the choice; budget_off gives back what the
    // budget replaced. Both log what they did.
    void choose_budget(const Camera& camera, int w, int h);
    void budget_off();
    void budget_ui();
    ReferenceView reference_view() const { return {ref_.on, ref_.mode, ref_.view}; }
    void set_reference_view(const ReferenceView& v) {
        ref_.on = v.on;
        ref_.mode = v.mode;
        ref_.view = v.view;
    }
    // reductions(settings_) as "knob=value knob=value", for the log and the panel.
    std::string join_reductions() const {
        std::string out;
        for (const std::string& a : reductions(settings_)) out += (out.empty() ? "" : " ") + a;
        return out.empty() ? "nothing to lower" : out;
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
    // A scene large compared with what the camera sees close by: when the camera has moved
    // farther from Scene::origin than kAnchorDistances times its distance to the nearest geometry, the origin moves to
    // it (scene/origin.hpp) and the GPU copy, the view and the reference follow.
    void anchor_at_the_camera(int frame);
    // The reference tracer's Options::pose_at: the scene at time u in [0, 1) of the shutter.
    void pose_within_shutter(float u);
    std::string animation_label(int index) const {
        if (index < 0) return "none (rest pose)";
        const std::string& n = scene_.animations[static_cast<size_t>(index)].name;
        return n.empty() ? "animation " + std::to_string(index) : n;
    }
    void log_animation(const std::string& why) const;
    void animation_ui();
    // KHR_materials_variants: the scene's primitives take the variant's materials (-1: the
    // defaults), the draws follow (no reload: every material is on the GPU already), the
    // renderer re-plans (a variant may call for other effects), probes re-capture, GI retraces
    // and the reference starts over.
    void select_variant_live(int variant);
    void variant_ui();
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
    // Effects that converge over frames (EffectRuntime::progress): the log gets an effect's line
    // when it starts over and when it converges, so a scripted run shows it too.
    void log_progress(int frame);
    struct Logged {
        int phase = 0;  // 0 inactive, 1 converging, 2 converged
        int steps = 0;
    };
    std::map<std::string, Logged> progress_logged_;  // by effect name
    // Whether the last frame did work of an effect that converges over frames, and at what pace.
    bool progress_worked(std::string* pace) const;
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
    std::vector<std::filesystem::path> pending_screenshots_;
    bool show_ui_ = true;
    float panel_width_ = kPanelWidth;
    // Animation: the clock, the shutter interval of the current pose, and a serial that changes
    // with every pose (the reference restarts on it; the Renderer watches GpuScene::pose_version).
    Playback anim_;
    bool deformable_ = false;  // has_deformation(scene): animations, skins or morph targets
    ShutterInterval shutter_{};
    std::uint64_t pose_serial_ = 0;
    std::vector<double> pose_ms_;  // CPU pose + GPU upload + motion, per pose (the log's median)

    // Adaptive quality. The renderer holds reduced_ (the user's settings_ made cheaper) while
    // the view moves. What the last rendered frame showed decides whether a frame renders again.
    AdaptiveQuality adaptive_;
    QualityState quality_;          // this frame's
    bool force_reduced_ = false;    // the script's `adaptive reduced`: every frame at the reduced level
    RenderSettings reduced_;
    bool renderer_reduced_ = false;
    std::uint64_t view_generation_ = 0;  // settings, shaders, variants: anything else a frame shows
    Clock::time_point start_ = Clock::now();
    struct Shown {
        bool valid = false;
        Camera camera;
        int width = 0, height = 0;
        QualityState quality;
        float exposure = 0.0f;
        std::uint64_t pose = 0, generation = 0;
        std::string inspect;
    } shown_;
    Camera last_camera_;
    bool have_last_camera_ = false;
    bool moved_ = false;  // this frame's input to adaptive_
    int render_w_ = 0, render_h_ = 0;  // the last rendered frame's size (scaled: less than the scene's)
    double last_render_frame_ms_ = -1.0;

    // The error budget: the panel's E (the budget's while it is on), and whether to choose
    // before the next frame (turned on, a new E, the panel's re-choose button, the script).
    BudgetMode budget_;
    double budget_e_ = 0.03;
    bool budget_pending_ = false;
    std::string budget_stats_;  // the statistics of the last choice, for the panel
    int frame_ = 0;             // the frame being run (the log's "frame N")
};

}  // namespace candela::viewer
