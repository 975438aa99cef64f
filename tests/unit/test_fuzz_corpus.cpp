// Replays the fuzz target's seeds and every finding it ever made (tests/fuzz/regressions) through
// the same checks as tests/fuzz/fuzz_gltf.cpp, with the normal compiler: the regressions stay
// fixed even on a machine without clang. A file either loads into a Scene that keeps every
// promise of scene_invariants.hpp or fails with candela::Error; nothing else may escape.
#include <gtest/gtest.h>

#include <filesystem>
#include <fstream>
#include <sstream>

#include "../fuzz/scene_invariants.hpp"
#include "core/error.hpp"
#include "scene/gltf_loader.hpp"

namespace fs = std::filesystem;
using namespace candela;

namespace {
const fs::path kSource = CANDELA_SOURCE_DIR;

std::string bytes_of(const fs::path& p) {
    std::ifstream in(p, std::ios::binary);
    std::ostringstream s;
    s << in.rdbuf();
    return s.str();
}

enum class Outcome { loaded, rejected };

// Loaded as if it sat in samples/scenes, like the fuzz target does.
Outcome replay(const fs::path& file, std::string* message) {
    const fs::path as = kSource / "samples" / "scenes" / file.filename();
    try {
        const Scene scene = load_gltf_from_memory(as, bytes_of(file));
        EXPECT_EQ(fuzz::built_scene_violation(scene), "") << file;
        return Outcome::loaded;
    } catch (const Error& e) {
        EXPECT_EQ(e.code(), ExitCode::bad_input) << file;
        EXPECT_NE(std::string(e.what()).find(as.string()), std::string::npos) << "the message names the file: " << e.what();
        if (message) *message = e.what();
        return Outcome::rejected;
    }
}

std::vector<fs::path> files_in(const fs::path& dir) {
    std::vector<fs::path> out;
    for (const auto& e : fs::directory_iterator(dir))
        if (e.is_regular_file()) out.push_back(e.path());
    std::sort(out.begin(), out.end());
    return out;
}
}  // namespace

TEST(FuzzCorpus, SeedsLoadAndKeepEveryPromise) {
    int n = 0;
    for (const fs::path& f : files_in(kSource / "samples" / "scenes"))
        if (f.extension() == ".gltf") {
            EXPECT_EQ(replay(f, nullptr), Outcome::loaded) << f;
            ++n;
        }
    for (const fs::path& f : files_in(kSource / "tests" / "fuzz" / "seeds")) {
        EXPECT_EQ(replay(f, nullptr), Outcome::loaded) << f;
        ++n;
    }
    EXPECT_GE(n, 9);
}

TEST(FuzzCorpus, EveryRegressionEndsInASceneOrACleanError) {
    const auto files = files_in(kSource / "tests" / "fuzz" / "regressions");
    ASSERT_FALSE(files.empty());
    for (const fs::path& f : files) {
        SCOPED_TRACE(f.string());
        std::string message;
        replay(f, &message);
    }
}

TEST(FuzzCorpus, NumberBeyondDoubleIsBadJsonNotACrash) {
    // Found by the fuzzer: "mesh": 1e381 made nlohmann::json throw out_of_range, which escaped the
    // loader as an internal error (exit 1) instead of bad input (exit 2).
    std::string message;
    ASSERT_EQ(replay(kSource / "tests" / "fuzz" / "regressions" / "json_number_overflow.gltf", &message), Outcome::rejected);
    EXPECT_NE(message.find("invalid JSON: number overflow parsing '1e381'"), std::string::npos) << message;
}

TEST(FuzzCorpus, NonArraySkinsIsBadInputNotAnInternalError) {
    // Found by the fuzzer: "skins": 0 passed tinygltf and the structure checks (a warning), and
    // the buffer-data checks then indexed it as an array: a json type_error escaped as an internal
    // error (exit 1). The data checks now look only at well-formed parts; since skins are
    // implemented a non-array is an error of the structure checks, like "meshes": 0.
    std::string message;
    EXPECT_EQ(replay(kSource / "tests" / "fuzz" / "regressions" / "skins_not_an_array.gltf", &message), Outcome::rejected) << message;
    EXPECT_NE(message.find("skins: must be an array of objects, not number"), std::string::npos) << message;
}

TEST(FuzzCorpus, FactorBeyondFloatIsBadInput) {
    // Found by the fuzzer: baseColorFactor 2.2e98 is a finite double but +Inf as a float; the
    // loaded material was not finite. Numbers that do not fit a float are now bad input, factors
    // outside their range are clamped with a warning.
    std::string message;
    ASSERT_EQ(replay(kSource / "tests" / "fuzz" / "regressions" / "factor_beyond_float.gltf", &message), Outcome::rejected);
    EXPECT_NE(message.find("materials[3].pbrMetallicRoughness.baseColorFactor[1]: "), std::string::npos) << message;
    EXPECT_NE(message.find("baseColorFactor[1]: 2.22222e+98 does not fit a 32-bit float"), std::string::npos) << message;
}
