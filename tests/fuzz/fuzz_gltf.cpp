// libFuzzer target: the glTF loader, the scene builder (world transforms, world triangles, scene
// features), posing (animations, skins, morph targets) and the ray tracer's geometry + BVH
// builder, on arbitrary bytes.
// A bad file must end in candela::Error (a clean "FILE: problem" message); anything else escaping,
// a sanitizer report, a hang or a loaded Scene that breaks one of its promises
// (scene_invariants.hpp) is a finding. Build: tests/fuzz/CMakeLists.txt (clang); run by ctest as
// fuzz.gltf; every finding is kept in tests/fuzz/regressions and replayed by the unit tests.
#include <cstdint>
#include <cstdio>
#include <cstdlib>
#include <filesystem>
#include <string_view>

#include "core/error.hpp"
#include "core/log.hpp"
#include "scene/animation.hpp"
#include "scene/gltf_loader.hpp"
#include "scene_invariants.hpp"

namespace {
// The input is loaded as if it were a file in samples/scenes, so relative URIs of mutated inputs
// still reach the sample buffers and textures.
const std::filesystem::path kInput = std::filesystem::path(CANDELA_SCENE_DIR) / "fuzz_input.gltf";
}  // namespace

extern "C" int LLVMFuzzerInitialize(int*, char***) {
    candela::log::set_level(candela::log::Level::quiet);
    return 0;
}

extern "C" int LLVMFuzzerTestOneInput(const std::uint8_t* data, std::size_t size) {
    using namespace candela;
    try {
        const Scene scene = load_gltf_from_memory(kInput, std::string_view(reinterpret_cast<const char*>(data), size));
        const std::string broken = fuzz::built_scene_violation(scene);
        if (!broken.empty()) {
            std::fprintf(stderr, "fuzz_gltf: the loaded scene breaks a promise: %s\n", broken.c_str());
            std::abort();
        }
        // Posing reads what the loader built: each animation at its start, middle and
        // end must not read out of bounds (the sanitizers watch; extreme keyframes may overflow).
        for (std::size_t a = 0; a < scene.animations.size() && a < 4; ++a) {
            const Animation& anim = scene.animations[a];
            for (float t : {anim.start, 0.5f * (anim.start + anim.end), anim.end}) (void)evaluate_pose(scene, static_cast<int>(a), t);
        }
    } catch (const Error&) {
        // The expected outcome for a broken file: a message naming the file and the problem.
    }
    return 0;
}
