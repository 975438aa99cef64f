#include "script.hpp"

#include <fstream>
#include <map>
#include <cmath>
#include <sstream>

#include "budget_mode.hpp"
#include "core/error.hpp"

namespace candela::viewer {

std::vector<ScriptCommand> load_script(const std::filesystem::path& file) {
    std::ifstream in(file);
    if (!in) throw bad_input(file.string() + ": cannot read the script");
    // verb -> (min, max) argument count
    static const std::map<std::string, std::pair<size_t, size_t>> verbs = {
        {"orbit", {2, 2}}, {"zoom", {1, 1}},    {"pan", {2, 2}}, {"fly", {3, 3}},        {"camera", {1, 1}}, {"frame", {0, 0}},
        {"effects", {1, 1}}, {"set", {1, 1}}, {"path", {1, 1}}, {"screenshot", {1, 1}}, {"quit", {0, 0}},
        {"reference", {1, 2}}, {"show", {1, 1}}, {"inspect", {1, 4}},
        {"animation", {1, 1}}, {"time", {1, 1}}, {"play", {0, 0}}, {"pause", {0, 0}}, {"speed", {1, 1}}, {"loop", {1, 1}},
        {"variant", {1, 1}}, {"adaptive", {1, 2}}, {"budget", {1, 1}}};
    std::vector<ScriptCommand> out;
    std::string text;
    int line_no = 0;
    while (std::getline(in, text)) {
        ++line_no;
        if (auto hash = text.find('#'); hash != std::string::npos) text.resize(hash);
        std::istringstream words(text);
        ScriptCommand c;
        c.line = line_no;
        std::string frame;
        if (!(words >> frame)) continue;
        const std::string where = file.string() + ":" + std::to_string(line_no) + ": ";
        try {
            size_t used = 0;
            c.frame = std::stoi(frame, &used);
            if (used != frame.size() || c.frame < 0) throw std::invalid_argument(frame);
        } catch (const std::exception&) {
            throw bad_input(where + "'" + frame + "' is not a frame number");
        }
        if (!(words >> c.verb)) throw bad_input(where + "a command is missing after the frame number");
        auto v = verbs.find(c.verb);
        if (v == verbs.end()) throw bad_input(where + "unknown command '" + c.verb + "'");
        for (std::string a; words >> a;) c.args.push_back(a);
        if (c.args.size() < v->second.first || c.args.size() > v->second.second)
            throw bad_input(where + "'" + c.verb + "' takes " + std::to_string(v->second.first) + " argument(s)");
        if (c.verb == "loop" && c.args[0] != "on" && c.args[0] != "off")
            throw bad_input(where + "'loop' takes on or off, not '" + c.args[0] + "'");
        if (c.verb == "adaptive") {
            if (c.args[0] != "on" && c.args[0] != "off" && c.args[0] != "reduced")
                throw bad_input(where + "'adaptive' takes on, off or reduced, not '" + c.args[0] + "'");
            if (c.args.size() > 1) {
                float ms = 0.0f;
                try {
                    size_t used = 0;
                    ms = std::stof(c.args[1], &used);
                    if (used != c.args[1].size()) throw std::invalid_argument(c.args[1]);
                } catch (const std::exception&) {
                    ms = -1.0f;
                }
                if (!std::isfinite(ms) || ms < 1.0f || ms > 10000.0f)
                    throw bad_input(where + "'adaptive' target '" + c.args[1] + "' is not a frame time in ms in [1, 10000]");
            }
        }
        if (c.verb == "budget") try {
                parse_budget_argument(c.args[0]);
            } catch (const Error& e) {
                throw bad_input(where + e.what());
            }
        for (const char* numeric : {"orbit", "zoom", "pan", "fly", "time", "speed"})
            if (c.verb == numeric)
                for (const auto& a : c.args) {
                    try {
                        size_t used = 0;
                        const float f = std::stof(a, &used);
                        if (used != a.size() || !std::isfinite(f)) throw std::invalid_argument(a);
                    } catch (const std::exception&) {
                        throw bad_input(where + "'" + a + "' is not a number");
                    }
                }
        out.push_back(std::move(c));
    }
    return out;
}

}  // namespace candela::viewer
