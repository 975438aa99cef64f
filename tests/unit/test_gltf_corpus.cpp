// glTF-Validator's own test files (tests/data/gltf-validator-corpus, with the validator's report
// beside each file): an invalid file (report issues.numErrors > 0) is either rejected
// (bad_input) or warned about, never loaded in silence; a valid file loads. Warnings that only
// name ignored features (Scene::ignored, one each) do not count as warning about the problem.
#include <gtest/gtest.h>

#include <algorithm>
#include <filesystem>
#include <fstream>
#include <iostream>

#include <nlohmann/json.hpp>

#include "core/error.hpp"
#include "core/log.hpp"
#include "scene/gltf_loader.hpp"

namespace candela {
namespace {

namespace fs = std::filesystem;
const fs::path kCorpus = fs::path(CANDELA_SOURCE_DIR) / "tests" / "data" / "gltf-validator-corpus";

std::vector<fs::path> corpus_files() {
    std::vector<fs::path> out;
    for (const auto& e : fs::recursive_directory_iterator(kCorpus / "test"))
        if (e.is_regular_file() && (e.path().extension() == ".gltf" || e.path().extension() == ".glb")) out.push_back(e.path());
    std::sort(out.begin(), out.end());
    return out;
}

int validator_errors(const fs::path& file) {
    std::ifstream in(file.string() + ".report.json");
    return nlohmann::json::parse(in)["issues"]["numErrors"].get<int>();
}

enum class Outcome { loaded, warned, rejected, rejected_required_extension };

struct Result {
    Outcome outcome;
    std::string message;  // the bad_input message when rejected
};

Result load_counting_warnings(const fs::path& file) {
    const int before = log::warning_count();
    try {
        const Scene scene = load_gltf(file);
        const int problems = log::warning_count() - before - static_cast<int>(scene.ignored.size());
        return {problems > 0 ? Outcome::warned : Outcome::loaded, {}};
    } catch (const Error& e) {
        EXPECT_EQ(e.code(), ExitCode::bad_input) << file << ": " << e.what();
        const std::string m = e.what();
        EXPECT_NE(m.find(file.string()), std::string::npos) << "the message names the file: " << m;
        const bool required = m.find("extensionsRequired: '") != std::string::npos && m.find("is not supported") != std::string::npos;
        return {required ? Outcome::rejected_required_extension : Outcome::rejected, m};
    }
}

struct QuietLog {
    QuietLog() : saved(log::level()) { log::set_level(log::Level::quiet); }
    ~QuietLog() { log::set_level(saved); }
    log::Level saved;
};

TEST(GltfCorpus, InvalidFilesAreNeverSilentAndValidFilesLoad) {
    ASSERT_TRUE(fs::is_directory(kCorpus)) << kCorpus;
    const QuietLog quiet;
    int invalid = 0, rejected = 0, warned = 0, valid = 0, loaded = 0, required_ext = 0;
    std::vector<std::string> silent, wrongly_rejected;
    for (const fs::path& f : corpus_files()) {
        const std::string name = fs::relative(f, kCorpus).string();
        const Result r = load_counting_warnings(f);
        if (validator_errors(f) > 0) {
            ++invalid;
            if (r.outcome == Outcome::rejected || r.outcome == Outcome::rejected_required_extension) ++rejected;
            else if (r.outcome == Outcome::warned) ++warned;
            else silent.push_back(name);
        } else {
            ++valid;
            if (r.outcome == Outcome::loaded || r.outcome == Outcome::warned) ++loaded;
            else if (r.outcome == Outcome::rejected_required_extension) ++required_ext;  // exit 2 by design (glTF 3.12)
            else wrongly_rejected.push_back(name + ": " + r.message);
        }
    }
    std::cout << "glTF-Validator corpus: invalid: " << invalid << " = " << rejected << " rejected + " << warned << " warned + "
              << silent.size() << " silent; valid: " << valid << " = " << loaded << " loaded + " << wrongly_rejected.size()
              << " rejected + " << required_ext << " requiring an unimplemented extension\n";
    for (const std::string& s : silent) std::cout << "  silent invalid file: " << s << "\n";
    for (const std::string& s : wrongly_rejected) std::cout << "  rejected valid file: " << s << "\n";
    EXPECT_EQ(invalid, 243);
    EXPECT_EQ(valid, 129);
    EXPECT_TRUE(silent.empty()) << silent.size() << " invalid files load without a word";
    EXPECT_TRUE(wrongly_rejected.empty()) << wrongly_rejected.size() << " valid files are rejected";
}

// The message names the problem and its JSON path (a few files the issue named).
std::string rejection(const char* file) {
    const QuietLog quiet;
    const Result r = load_counting_warnings(kCorpus / "test" / "base" / "data" / file);
    EXPECT_EQ(r.outcome, Outcome::rejected) << file;
    return r.message;
}

std::string warnings_of(const char* file) {
    const log::Level saved = log::level();
    log::set_level(log::Level::warn);
    testing::internal::CaptureStderr();
    const Result r = load_counting_warnings(kCorpus / "test" / "base" / "data" / file);
    const std::string err = testing::internal::GetCapturedStderr();
    log::set_level(saved);
    EXPECT_EQ(r.outcome, Outcome::warned) << file;
    return err;
}

TEST(GltfCorpus, RejectionsNameTheJsonPath) {
    EXPECT_NE(rejection("asset/1_0_version.gltf").find("asset.version: glTF 1.0 is not supported"), std::string::npos);
    EXPECT_NE(rejection("accessor/unresolved_bufferviews.gltf").find("accessors[0].bufferView: bufferView 0 does not exist"), std::string::npos)
        << rejection("accessor/unresolved_bufferviews.gltf");
    EXPECT_NE(rejection("buffer_view/invalid_length.gltf").find("bufferViews[0].byteLength: byteOffset 0 + byteLength"), std::string::npos)
        << rejection("buffer_view/invalid_length.gltf");
    EXPECT_NE(rejection("camera/orthographic_z.gltf").find("cameras[0].orthographic: zfar"), std::string::npos)
        << rejection("camera/orthographic_z.gltf");
    EXPECT_NE(rejection("glb/invalid_magic.glb").find("GLB byte 0: the magic is not 'glTF'"), std::string::npos);
}

TEST(GltfCorpus, WarningsNameTheJsonPath) {
    EXPECT_NE(warnings_of("json/bom.gltf").find("byte order mark"), std::string::npos);
    const std::string anim = warnings_of("animation/unresolved_channel_sampler.gltf");
    EXPECT_NE(anim.find("animations[0].channels[0].sampler: sampler 1 does not exist"), std::string::npos) << anim;
    const std::string stride = warnings_of("animation/sampler_bufferview_bytestride.gltf");
    EXPECT_NE(stride.find("animations[0].samplers[0].input: bufferView"), std::string::npos) << stride;
}

}  // namespace
}  // namespace candela
