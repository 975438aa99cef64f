// The viewer's input: mouse and keyboard (camera, toggles), the script's commands, and window
// screenshots.
#include "viewer_internal.hpp"

#include "rt/tracer_options.hpp"

namespace candela::viewer {

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

void Viewer::run_script(int frame) {
    for (const ScriptCommand& c : script_) {
        if (c.frame != frame) continue;
        const auto num = [&](size_t i) { return std::stof(c.args[i]); };
        try {
            if (c.verb == "orbit") controller_.orbit(num(0), num(1));
            else if (c.verb == "zoom") controller_.zoom(num(0));
            else if (c.verb == "pan") controller_.pan(num(0), num(1));
            else if (c.verb == "fly") controller_.fly(glm::vec3(num(0), num(1), num(2)));
            else if (c.verb == "camera") select_camera(c.args[0]);
            else if (c.verb == "frame") controller_.frame(bounds_);
            else if (c.verb == "screenshot") pending_screenshots_.push_back(c.args[0]);
            else if (c.verb == "quit") quit_ = true;
            else if (c.verb == "variant") select_variant_live(find_variant(scene_, c.args[0]));
            else if (c.verb == "adaptive") {
                adaptive_.set_enabled(c.args[0] != "off");
                force_reduced_ = c.args[0] == "reduced";
                if (c.args.size() > 1) adaptive_.set_target_ms(num(1));
                log::info("viewer: frame " + std::to_string(frame) + ": adaptive quality " + c.args[0] + ", target " +
                          std::to_string(static_cast<int>(adaptive_.target_ms())) + " ms; reduced: " + join_reductions());
            }
            else if (c.verb == "budget") {
                // `budget E`: chosen before this frame renders (from its view); `budget off`: now.
                if (const std::optional<double> e = parse_budget_argument(c.args[0])) {
                    budget_e_ = *e;
                    budget_pending_ = true;
                } else {
                    budget_off();
                }
            }
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

}  // namespace candela::viewer
