// A program of a project that uses an installed Candela (find_package(Candela), Candela::engine):
// loads a glTF scene with the engine's loader and prints its triangle count and bounds, then reads
// one of the engine's effect shaders, with its #includes, from the package's data directory.
//   scene_info SCENE.gltf     exit 0, or Candela's exit code (2: a broken scene) with its message
#include <cstdio>
#include <filesystem>
#include <string>

#include "core/error.hpp"
#include "scene/gltf_loader.hpp"
#include "shader/shader_library.hpp"

int main(int argc, char** argv) {
    if (argc != 2) {
        std::fprintf(stderr, "usage: scene_info SCENE.gltf\n");
        return 2;
    }
    try {
        const candela::Scene scene = candela::load_gltf(argv[1]);
        const candela::Bounds b = scene.world_bounds();
        std::printf("triangles: %zu\n", scene.triangle_count());
        std::printf("bounds: (%.3g, %.3g, %.3g) to (%.3g, %.3g, %.3g)\n", b.min.x, b.min.y, b.min.z, b.max.x, b.max.y,
                    b.max.z);
        // CANDELA_DATA_DIR: Candela_DATA_DIR from the package (CMakeLists.txt), i.e. <prefix>/share/candela.
        const std::filesystem::path data = CANDELA_DATA_DIR;
        const candela::ShaderLibrary shaders(data / "shaders", data);
        const candela::PreprocessedSource ssao = shaders.preprocess("effects/ssao/ssao.frag", {});
        std::printf("effects/ssao/ssao.frag: %zu files after #include\n", ssao.files.size());
        return 0;
    } catch (const candela::Error& e) {
        std::fprintf(stderr, "scene_info: %s\n", e.what());
        return static_cast<int>(e.code());
    }
}
