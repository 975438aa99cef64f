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
#include <cstdio>
#include <deque>

#include <nlohmann/json.hpp>

#include "camera_controller.hpp"
#include "core/error.hpp"
#include "core/log.hpp"
#include "image/image.hpp"
#include "platform/context.hpp"
#include "render/features.hpp"
#include "render/renderer.hpp"
#include "script.hpp"
#include "shader/file_watcher.hpp"

namespace candela::viewer {
namespace {
namespace fs = std::filesystem;
using Clock = std::chrono::steady_clock;

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

class Viewer {
public:
    Viewer(const Scene& scene, const ViewerOptions& o, Context& ctx)
        : scene_(scene), o_(o), ctx_(ctx), shaders_(o.shader_dir), gpu_(scene), settings_(o.settings),
          renderer_(shaders_, scene, gpu_, settings_), watcher_(shaders_.root()), bounds_(scene.world_bounds()) {
        if (!o.script.empty()) script_ = load_script(o.script);
        select_camera(o.camera);
        IMGUI_CHECKVERSION();
        ImGui::CreateContext();
        ImGui::GetIO().IniFilename = nullptr;  // no imgui.ini next to the user's files
        ImGui::StyleColorsDark();
        ImGui_ImplGlfw_InitForOpenGL(ctx.window(), true);
        ImGui_ImplOpenGL3_Init("#version 450 core");
        blit_ = gl::Framebuffer::create();
        log::info(std::string("viewer: watching ") + shaders_.root().string() + (watcher_.uses_inotify() ? " (inotify)" : " (polling)"));
    }
    ~Viewer() {
        ImGui_ImplOpenGL3_Shutdown();
        ImGui_ImplGlfw_Shutdown();
        ImGui::DestroyContext();
    }
    int run();

private:
    void select_camera(const std::string& selector) {
        int w = 0, h = 0;
        glfwGetFramebufferSize(ctx_.window(), &w, &h);
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
    void run_script(int frame);
    void handle_input(float dt);
    void reload_shaders();
    void draw_ui(double frame_ms);
    void knob_widgets(const std::string& prefix_filter, bool exclude);

    const Scene& scene_;
    ViewerOptions o_;
    Context& ctx_;
    ShaderLibrary shaders_;
    GpuScene gpu_;
    RenderSettings settings_;
    Renderer renderer_;
    FileWatcher watcher_;
    Bounds bounds_;
    CameraController controller_;
    std::vector<ScriptCommand> script_;
    gl::Framebuffer blit_;
    std::string shader_errors_, settings_error_, status_;
    std::deque<double> frame_times_;
    bool quit_ = false;
    std::vector<fs::path> pending_screenshots_;
    bool show_ui_ = true;
};

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
            else {
                RenderSettings s = settings_;
                if (c.verb == "effects") apply_effects(s, c.args[0]);
                else if (c.verb == "set") apply_knob(s, c.args[0]);
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
    if (ImGui::IsKeyPressed(GLFW_KEY_P) || ImGui::IsKeyPressed(GLFW_KEY_F12)) {
        char name[64];
        std::snprintf(name, sizeof name, "candela_%lld.png",
                      static_cast<long long>(std::chrono::system_clock::now().time_since_epoch() / std::chrono::seconds(1)));
        pending_screenshots_.push_back(name);
    }
    if (ImGui::IsKeyPressed(GLFW_KEY_ESCAPE)) quit_ = true;
}

void Viewer::reload_shaders() {
    const std::vector<fs::path> changed = watcher_.poll();
    if (changed.empty()) return;
    const auto t0 = Clock::now();
    const ShaderReload r = renderer_.reload_shaders(changed);
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

void Viewer::draw_ui(double frame_ms) {
    ImGui::SetNextWindowPos(ImVec2(8, 8), ImGuiCond_FirstUseEver);
    ImGui::SetNextWindowSize(ImVec2(430, 0), ImGuiCond_FirstUseEver);
    ImGui::Begin("Candela");
    ImGui::TextUnformatted(ctx_.device_string().c_str());
    frame_times_.push_back(frame_ms);
    if (frame_times_.size() > 60) frame_times_.pop_front();
    std::vector<double> sorted(frame_times_.begin(), frame_times_.end());
    std::sort(sorted.begin(), sorted.end());
    ImGui::Text("frame %.1f ms (median of %zu)  %s", sorted[sorted.size() / 2], sorted.size(), controller_.fly_mode ? "fly" : "orbit");
    ImGui::TextDisabled("drag: turn  shift/middle drag: pan  wheel: zoom  WASDQE: move  F: frame  Tab: fly  P: screenshot  H: hide");
    if (!shader_errors_.empty()) {
        ImGui::PushStyleColor(ImGuiCol_Text, ImVec4(1.0f, 0.45f, 0.4f, 1.0f));
        ImGui::TextWrapped("Shader error (the last good program is in use):\n%s", shader_errors_.c_str());
        ImGui::PopStyleColor();
    }
    if (!settings_error_.empty()) ImGui::TextColored(ImVec4(1.0f, 0.45f, 0.4f, 1.0f), "%s", settings_error_.c_str());
    if (!status_.empty()) ImGui::TextDisabled("%s", status_.c_str());

    if (ImGui::CollapsingHeader("Camera")) {
        if (ImGui::Button("Frame scene (F)")) controller_.frame(bounds_);
        for (size_t i = 0; i < scene_.cameras.size(); ++i) {
            ImGui::SameLine();
            const std::string label = scene_.cameras[i].name.empty() ? "camera " + std::to_string(i) : scene_.cameras[i].name;
            if (ImGui::Button(label.c_str())) select_camera(std::to_string(i));
        }
        ImGui::SliderFloat("exposure (EV)", &o_.exposure_ev, -8.0f, 8.0f);
    }
    if (ImGui::CollapsingHeader("Effects", ImGuiTreeNodeFlags_DefaultOpen)) {
        const Features& f = renderer_.features();
        RenderSettings s = settings_;
        bool* flags[] = {&s.shadows, &s.ssao, &s.rsm, &s.transparency, &s.reflections};
        const EffectDecision* decisions[] = {&f.shadows, &f.ssao, &f.rsm, &f.transparency, &f.reflections};
        bool changed = false;
        for (size_t i = 0; i < 5; ++i) {
            changed |= ImGui::Checkbox(effect_names()[i].c_str(), flags[i]);
            ImGui::SameLine(140);
            ImGui::TextDisabled("%s", decisions[i]->reason.c_str());
        }
        if (changed) apply_settings(s);
    }
    if (ImGui::CollapsingHeader("Knobs")) knob_widgets("debug.", true);
    if (ImGui::CollapsingHeader("Debug views")) knob_widgets("debug.", false);
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
        for (const auto& [name, why] : r.culled) ImGui::TextDisabled("culled %s: %s", name.c_str(), why.c_str());
        if (ImGui::TreeNode("planned passes and why")) {
            for (const PlannedPass& p : plan_passes(renderer_.features(), settings_)) ImGui::BulletText("%s: %s", p.name.c_str(), p.why.c_str());
            ImGui::TreePop();
        }
    }
    ImGui::End();
}

int Viewer::run() {
    GLFWwindow* window = ctx_.window();
    auto last = Clock::now();
    int frame = 0;
    int w = 0, h = 0;
    while (!glfwWindowShouldClose(window) && !quit_) {
        glfwPollEvents();
        glfwGetFramebufferSize(window, &w, &h);
        if (w <= 0 || h <= 0) {  // minimized: nothing to draw, do not spin
            glfwWaitEventsTimeout(0.1);
            continue;
        }
        const auto t0 = Clock::now();
        const float dt = static_cast<float>(std::chrono::duration<double>(t0 - last).count());
        last = t0;
        reload_shaders();
        run_script(frame);
        ImGui_ImplOpenGL3_NewFrame();
        ImGui_ImplGlfw_NewFrame();
        ImGui::NewFrame();
        handle_input(std::min(dt, 0.1f));
        renderer_.render(controller_.camera(), w, h, FrameOutput::display, o_.exposure_ev);
        renderer_.resolve_gpu_times();
        glNamedFramebufferTexture(blit_.id(), GL_COLOR_ATTACHMENT0, renderer_.display().id(), 0);
        glBlitNamedFramebuffer(blit_.id(), 0, 0, 0, w, h, 0, 0, w, h, GL_COLOR_BUFFER_BIT, GL_NEAREST);
        const bool last_frame = o_.frames > 0 && frame + 1 >= o_.frames;
        if (last_frame && !o_.screenshot.empty()) pending_screenshots_.push_back(o_.screenshot);
        for (const fs::path& p : pending_screenshots_) {
            write_display_rgba8(p, renderer_.read_display(), w, h);
            log::info("viewer: wrote " + p.string());
        }
        pending_screenshots_.clear();
        if (show_ui_) draw_ui(ms_since(t0));
        ImGui::Render();
        ImGui_ImplOpenGL3_RenderDrawData(ImGui::GetDrawData());
        if (last_frame && !o_.window_shot.empty()) {
            write_display_rgba8(o_.window_shot, read_window(w, h), w, h);
            log::info("viewer: wrote " + o_.window_shot.string());
        }
        ctx_.swap_buffers();
        ++frame;
        if (last_frame) break;
    }
    return 0;
}

}  // namespace

int run_viewer(const Scene& scene, const ViewerOptions& options) {
    ContextOptions co;
    co.width = options.width;
    co.height = options.height;
    co.vsync = options.vsync;
    co.title = "Candela - " + scene.source.filename().string();
    ContextResult ctx = create_context(Backend::glfw, co);
    if (!ctx.context) {
        std::fprintf(stderr, "candela: %s\n", ctx.error.c_str());
        return static_cast<int>(ExitCode::no_gl);
    }
    log::info("viewer: " + ctx.context->device_string());
    Viewer viewer(scene, options, *ctx.context);
    return viewer.run();
}

}  // namespace candela::viewer
