#include "accuracy/section_file.hpp"

#include <unistd.h>

#include <algorithm>
#include <cmath>
#include <cstdio>
#include <cstdlib>
#include <cstring>
#include <fstream>
#include <stdexcept>
#include <utility>

#include "accuracy/plan.hpp"
#include "core/error.hpp"

namespace candela::accuracy {
namespace fs = std::filesystem;

namespace {

// The format named in every section.json (sections saved by earlier builds read back as long as
// it stays the same).
constexpr const char* kSectionFormat = "candela bench accuracy section 1";

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

// complete_section's checks of a parsed section.json.
std::optional<nlohmann::json> check_section(const fs::path& dir, const nlohmann::json& j, const Options& o,
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

// Bitwise equality (NaN equals NaN of the same bits): what a saved section must read back as.
bool same(double a, double b) { return std::memcmp(&a, &b, sizeof a) == 0 || (std::isnan(a) && std::isnan(b)); }
bool same(const ImageF& a, const ImageF& b) {
    return a.width == b.width && a.height == b.height && a.channels == b.channels && a.pixels.size() == b.pixels.size() &&
           std::equal(a.pixels.begin(), a.pixels.end(), b.pixels.begin(), [](float x, float y) {
               return std::memcmp(&x, &y, sizeof x) == 0 || (std::isnan(x) && std::isnan(y));
           });
}

}  // namespace

nlohmann::ordered_json section_json(int index, const std::string& label, const Options& o, const Section& sec, const std::vector<Row>& rows) {
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

std::optional<nlohmann::json> complete_section(const fs::path& dir, const Options& o, const AccuracySweep& s,
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

}  // namespace candela::accuracy
