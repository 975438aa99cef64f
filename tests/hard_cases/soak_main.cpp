// Soak test: N frames of a scene with every effect (probes re-captured every frame), then
// M shader hot reloads, headless (usage: soak SOURCE_DIR [frames=1000] [reloads=100]; ctest runs
// a shorter run so that CI stays fast (tests/CMakeLists.txt says which), the full run is the closing note's number). The live GL objects and the process's resident memory must
// stay flat: the same object counts after warm-up and at the end, and RSS growth below a bound.
// Exit 0 on success; prints the numbers for the closing note.
#include <cstdio>
#include <filesystem>
#include <fstream>
#include <string>
#include <unistd.h>

#include "gl/debug.hpp"
#include "gl/handles.hpp"
#include "platform/context.hpp"
#include "render/renderer.hpp"
#include "scene/gltf_loader.hpp"

namespace fs = std::filesystem;
using namespace candela;

namespace {
double rss_mib() {
    std::ifstream statm("/proc/self/statm");
    long pages = 0, resident = 0;
    statm >> pages >> resident;
    return static_cast<double>(resident) * static_cast<double>(sysconf(_SC_PAGESIZE)) / (1024.0 * 1024.0);
}
struct Counts {
    int textures, buffers, programs, shaders, framebuffers, queries;
    bool operator==(const Counts&) const = default;
};
Counts live() {
    return {gl::Texture::live(), gl::Buffer::live(), gl::Program::live(), gl::Shader::live(), gl::Framebuffer::live(), gl::Query::live()};
}
void print(const char* when, const Counts& c, double rss) {
    std::printf("%-28s textures %d buffers %d programs %d shaders %d framebuffers %d queries %d; RSS %.1f MiB\n", when, c.textures,
                c.buffers, c.programs, c.shaders, c.framebuffers, c.queries, rss);
}
}  // namespace

int main(int argc, char** argv) {
    const fs::path source = argc > 1 ? fs::path(argv[1]) : fs::path(CANDELA_SOURCE_DIR);
    const int frames = argc > 2 ? std::stoi(argv[2]) : 1000;
    const int reloads = argc > 3 ? std::stoi(argv[3]) : 100;
    ContextOptions options;
    options.debug = true;  // KHR_debug errors fail the soak
    ContextResult ctx = create_context(Backend::auto_select, options);
    if (!ctx.context) {
        std::fprintf(stderr, "soak: %s\n", ctx.error.c_str());
        return 3;
    }
    const Scene scene = load_gltf(source / "samples" / "scenes" / "reflections.gltf");
    const ShaderLibrary shaders(source / "shaders");
    GpuScene gpu(scene);
    RenderSettings s;
    apply_effects(s, "all");
    apply_knob(s, "probe.update=every_frame");
    apply_knob(s, "probe.resolution=32");
    Renderer renderer(shaders, scene, gpu, s);
    const Camera camera = scene.select_camera("", 1.0f);
    auto frame = [&](int i) {
        renderer.render(camera, 64 + (i % 3), 64, i % 2 ? FrameOutput::display : FrameOutput::hdr);  // sizes and outputs change
        renderer.resolve_gpu_times();
    };
    for (int i = 0; i < 50; ++i) frame(i);  // warm-up: pools, caches and the driver settle
    glFinish();
    const Counts start = live();
    const double rss_start = rss_mib();
    print("after 50 warm-up frames:", start, rss_start);
    for (int i = 0; i < frames; ++i) frame(i);
    glFinish();
    const Counts after_frames = live();
    const double rss_frames = rss_mib();
    print(("after " + std::to_string(frames) + " frames:").c_str(), after_frames, rss_frames);
    const fs::path shading = source / "shaders" / "lighting" / "shading.glsl";
    for (int i = 0; i < reloads; ++i) {
        const ShaderReload r = renderer.reload_shaders({shading});
        if (!r.errors.empty() || r.rebuilt.empty()) {
            std::fprintf(stderr, "soak: reload %d failed\n", i);
            return 1;
        }
        frame(i);
    }
    glFinish();
    const Counts end = live();
    const double rss_end = rss_mib();
    print(("after " + std::to_string(reloads) + " reloads:").c_str(), end, rss_end);
    bool ok = true;
    if (!(after_frames == start) || !(end == start)) {
        std::fprintf(stderr, "soak: live GL object counts changed\n");
        ok = false;
    }
    // A bound, not zero: the allocator and llvmpipe's shader cache may keep a little.
    const double bound = 32.0;
    if (rss_frames - rss_start > bound || rss_end - rss_start > bound) {
        std::fprintf(stderr, "soak: RSS grew by more than %.0f MiB\n", bound);
        ok = false;
    }
    if (gl::debug_error_count() > 0) {
        std::fprintf(stderr, "soak: %d GL error(s)\n", gl::debug_error_count());
        ok = false;
    }
    std::printf("soak: %s\n", ok ? "flat" : "FAILED");
    return ok ? 0 : 1;
}
