#include "shards.hpp"

#include <algorithm>
#include <cmath>
#include <cstdio>
#include <fstream>
#include <set>

#include "core/error.hpp"
#include "core/log.hpp"

namespace candela::cli {
namespace fs = std::filesystem;

namespace {

// FNV-1a 64 of a file's bytes, in hex ("" if it cannot be read: generated scenes have no file).
std::string file_hash(const std::string& path) {
    std::ifstream in(path, std::ios::binary);
    if (!in) return "";
    std::uint64_t h = 1469598103934665603ull;
    char buf[65536];
    while (in.read(buf, sizeof buf) || in.gcount() > 0) {
        for (std::streamsize i = 0; i < in.gcount(); ++i) h = (h ^ static_cast<unsigned char>(buf[i])) * 1099511628211ull;
        if (!in) break;
    }
    char out[17];
    std::snprintf(out, sizeof out, "%016llx", static_cast<unsigned long long>(h));
    return out;
}

// Options that do not change the tracer's image (where it goes, how it reports, which driver
// runs it), and those with their own tag.
const std::set<std::string> kNotInArgs = {"-o", "--output", "--spp-shard", "--timings", "--quiet", "--stats", "--debug-gl",
                                          "--verify-state", "--backend", "--raytrace", "--spp", "--seed", "--size"};

}  // namespace

int shard_samples(int spp, int shard, int shard_count) {
    return spp > shard ? (spp - shard + shard_count - 1) / shard_count : 0;
}

std::string shard_tag(const std::vector<int>& shards, int count) {
    std::string s;
    for (int k : shards) {
        if (!s.empty()) s += ',';
        s += std::to_string(k);
    }
    s += '/';
    s += std::to_string(count);
    return s;
}

void parse_shard_tag(const std::string& text, const std::string& file, std::vector<int>& shards, int& count) {
    shards.clear();
    const size_t slash = text.find('/');
    const auto bad = [&] { return bad_input(file + ": candela:shard '" + text + "' is not K/N or K1,K2,.../N"); };
    if (slash == std::string::npos) throw bad();
    try {
        size_t used = 0;
        count = std::stoi(text.substr(slash + 1), &used);
        if (used != text.size() - slash - 1 || count < 1) throw bad();
        for (size_t at = 0; at < slash;) {
            const size_t comma = std::min(text.find(',', at), slash);
            const int k = std::stoi(text.substr(at, comma - at), &used);
            if (used != comma - at || k < 0 || k >= count) throw bad();
            shards.push_back(k);
            at = comma + 1;
        }
    } catch (const std::logic_error&) {  // stoi: not a number
        throw bad();
    }
    if (shards.empty()) throw bad();
}

Tags shard_tags(const Parsed& p, const std::string& mode, std::uint32_t seed, int spp, int shard, int shard_count, int width, int height) {
    Tags t;
    const std::string scene = p.positional.empty() ? "" : p.positional.front();
    t["candela:scene"] = fs::path(scene).filename().string();
    const std::string hash = file_hash(scene);
    t["candela:scene_hash"] = hash.empty() ? scene : hash;  // generated:N: its name is its content
    t["candela:mode"] = mode;
    t["candela:seed"] = std::to_string(seed);
    t["candela:spp"] = std::to_string(spp);
    t["candela:shard"] = shard_tag({shard}, shard_count);
    t["candela:size"] = std::to_string(width) + "x" + std::to_string(height);
    std::string args;
    for (const auto& [name, values] : p.values) {  // std::map: a fixed order whatever the command line's
        if (kNotInArgs.count(name)) continue;
        for (const std::string& v : values) args += (args.empty() ? "" : " ") + name + " " + v;
    }
    for (const auto& [name, on] : p.flags)
        if (on && !kNotInArgs.count(name)) args += (args.empty() ? "" : " ") + name;
    t["candela:args"] = args.empty() ? "-" : args;  // EXR headers drop empty strings
    return t;
}

Tags check_shards(const std::vector<fs::path>& files, const std::vector<ImageF>& images) {
    Tags merged;
    size_t first = files.size();  // the first tagged image
    std::vector<int> seen;        // shard index -> position in files + 1
    int count = 0;
    for (size_t i = 0; i < files.size(); ++i) {
        const Tags& t = images[i].tags;
        if (!t.count("candela:shard")) {
            log::warn(files[i].string() + ": no candela:shard tags (not written by render --spp-shard of this version): "
                      "cannot check that it is a shard of the same render");
            continue;
        }
        std::vector<int> shards;
        int n = 0;
        parse_shard_tag(t.at("candela:shard"), files[i].string(), shards, n);
        if (first == files.size()) {
            first = i;
            merged = t;
            count = n;
            seen.assign(static_cast<size_t>(n), 0);
        } else {
            // Every tag but the shard must agree: the files are parts of one render.
            std::set<std::string> names;
            for (const auto& kv : t) names.insert(kv.first);
            for (const auto& kv : merged) names.insert(kv.first);
            for (const std::string& name : names) {
                if (name == "candela:shard") continue;
                const Tags::const_iterator a = merged.find(name), b = t.find(name);
                const std::string va = a == merged.cend() ? "(none)" : a->second, vb = b == t.end() ? "(none)" : b->second;
                if (va != vb)
                    throw bad_input(files[i].string() + " is a shard of another render than " + files[first].string() + ": " + name +
                                    " is '" + vb + "' in the first and '" + va + "' in the second");
            }
            if (n != count)
                throw bad_input(files[i].string() + " is shard " + t.at("candela:shard") + " but " + files[first].string() +
                                " is one of " + std::to_string(count) + " shards");
        }
        for (int k : shards) {
            if (seen[static_cast<size_t>(k)])
                throw bad_input(files[i].string() + ": shard " + std::to_string(k) + "/" + std::to_string(count) + " is also in " +
                                files[static_cast<size_t>(seen[static_cast<size_t>(k)] - 1)].string() +
                                " (its samples would count twice)");
            seen[static_cast<size_t>(k)] = static_cast<int>(i) + 1;
        }
    }
    if (first == files.size()) return {};
    std::vector<int> all;
    for (int k = 0; k < count; ++k)
        if (seen[static_cast<size_t>(k)]) all.push_back(k);
    merged["candela:shard"] = shard_tag(all, count);
    return merged;
}

bool shard_complete(const fs::path& path, const Tags& expected, int samples, std::string& why) {
    if (!fs::exists(path)) return why = "no output yet", false;
    ImageF img;
    try {
        img = read_image(path);
    } catch (const Error& e) {
        return why = std::string("unreadable (") + e.what() + ")", false;
    }
    for (const auto& [name, value] : expected) {
        const auto it = img.tags.find(name);
        if (it == img.tags.end() || it->second != value)
            return why = name + " is '" + (it == img.tags.end() ? std::string("(none)") : it->second) + "', not '" + value + "'", false;
    }
    if (img.channels != 4) return why = "no sample-count channel", false;
    for (size_t i = 0; i < img.pixels.size(); i += 4) {
        if (!std::isfinite(img.pixels[i]) || !std::isfinite(img.pixels[i + 1]) || !std::isfinite(img.pixels[i + 2]))
            return why = "non-finite pixels", false;
        if (img.pixels[i + 3] != static_cast<float>(samples))
            return why = "a pixel holds " + std::to_string(static_cast<long long>(img.pixels[i + 3])) + " samples, not " + std::to_string(samples),
                   false;
    }
    return true;
}

}  // namespace candela::cli
