// Golden-image check of one sample scene on one backend:
//   candela_golden SCENE.gltf GOLDEN.png OUT_DIR --backend egl|osmesa [--size WxH] [--update]
//                  [--animation N|NAME --time T] [--orbit DEGREES]
// --animation/--time pose the scene (issue 21); --orbit turns the framing camera about the bounds'
// vertical axis (a side view of an animated model).
// Renders with GL debug output on; fails on any GL error, any non-finite pixel, or more than
// 0.1 % of pixels differing by more than 2/255 from the golden (shared/DESIGN.md section 5).
// On failure the actual image and a heat-map diff are written to OUT_DIR and their paths printed.
// --update (used only by the `update-goldens` target) overwrites the golden instead.
#include <cstdio>
#include <cstdlib>
#include <filesystem>
#include <string>
#include <vector>

#include <glm/gtc/matrix_transform.hpp>

#include "core/error.hpp"
#include "gl/debug.hpp"
#include "image/image.hpp"
#include "platform/context.hpp"
#include "render/still.hpp"
#include "scene/animation.hpp"
#include "scene/gltf_loader.hpp"
#include "scene/lighting.hpp"

namespace fs = std::filesystem;
using namespace candela;

namespace {
constexpr double kTolerance = 2.0 / 255.0;
constexpr double kMaxFailingFraction = 0.001;
}  // namespace

int main(int argc, char** argv) {
    if (argc < 4) {
        std::fprintf(stderr, "usage: candela_golden SCENE GOLDEN.png OUT_DIR --backend B [--path forward|deferred] [--size WxH] [--set KNOB=V] [--update]\n");
        return 2;
    }
    const fs::path scene_path = argv[1], golden = argv[2], out_dir = argv[3];
    Backend backend = Backend::egl;
    StillOptions options;
    options.width = options.height = 256;
    bool update = false;
    std::vector<std::string> knobs;
    std::string animation;
    float time = 0.0f, orbit = 0.0f;
    for (int i = 4; i < argc; ++i) {
        const std::string a = argv[i];
        if (a == "--update") update = true;
        else if (a == "--backend" && i + 1 < argc) backend = parse_backend(argv[++i]).value_or(Backend::egl);
        else if (a == "--size" && i + 1 < argc) std::sscanf(argv[++i], "%dx%d", &options.width, &options.height);
        else if (a == "--path" && i + 1 < argc) knobs.push_back(std::string("render.path=") + argv[++i]);  // forward|deferred: one golden for both
        else if (a == "--set" && i + 1 < argc) knobs.push_back(argv[++i]);
        else if (a == "--animation" && i + 1 < argc) animation = argv[++i];
        else if (a == "--time" && i + 1 < argc) time = std::strtof(argv[++i], nullptr);
        else if (a == "--orbit" && i + 1 < argc) orbit = std::strtof(argv[++i], nullptr);
        else {
            std::fprintf(stderr, "candela_golden: unknown argument '%s'\n", a.c_str());
            return 2;
        }
    }
    try {
        for (const std::string& knob : knobs) apply_knob(options.settings, knob);
        Scene scene = load_gltf(scene_path);
        if (!animation.empty()) {
            options.animation = find_animation(scene, animation);
            options.time = time;
            pose_scene(scene, options.animation, time);
        }
        if (orbit != 0.0f) {
            Camera cam = framing_camera(scene.world_bounds());
            const glm::vec3 c = scene.world_bounds().center();
            cam.world = glm::translate(glm::mat4(1.0f), c) * glm::rotate(glm::mat4(1.0f), glm::radians(orbit), glm::vec3(0, 1, 0)) *
                        glm::translate(glm::mat4(1.0f), -c) * cam.world;
            cam.name = "orbit";
            scene.cameras.insert(scene.cameras.begin(), cam);  // the first camera is the default
        }
        // As `candela render`: a file without lights gets the default rig (--lighting auto).
        apply_lighting(scene, LightingMode::auto_select,
                       scene.select_camera(options.camera, static_cast<float>(options.width) / static_cast<float>(options.height)));
        ContextOptions ctx_options;
        ctx_options.debug = true;
        ContextResult ctx = create_context(backend, ctx_options);
        if (!ctx.context) {
            std::fprintf(stderr, "FAIL: no usable OpenGL: %s\n", ctx.error.c_str());
            return 3;
        }
        std::printf("device: %s (%s)\n", ctx.context->device_string().c_str(), to_string(backend));
        options.output = FrameOutput::display;  // the GPU tonemap pass, as `candela render x.png`
        options.verify_state = true;
        const StillResult result = render_still(scene, ShaderLibrary(ShaderLibrary::default_root()), options);
        int failures = 0;
        if (gl::debug_error_count() > 0) {
            std::fprintf(stderr, "FAIL: %d GL error(s) during the render\n", gl::debug_error_count());
            ++failures;
        }
        if (const size_t bad = count_nonfinite(result.radiance)) {
            std::fprintf(stderr, "FAIL: %zu non-finite values in the rendered radiance\n", bad);
            ++failures;
        }
        fs::create_directories(out_dir);
        const std::string stem = golden.stem().string() + "." + to_string(backend) + "." + choice_name(kRenderPaths, options.settings.path);
        const fs::path actual_path = out_dir / (stem + ".actual.png");
        write_display_rgba8(actual_path, result.display, options.width, options.height);
        if (update) {
            if (failures) return 1;
            fs::create_directories(golden.parent_path());
            fs::copy_file(actual_path, golden, fs::copy_options::overwrite_existing);
            std::printf("updated %s\n", golden.string().c_str());
            return 0;
        }
        // Compare the PNG as written (8-bit quantised) with the golden.
        const ImageF actual = read_image(actual_path);
        const ImageF expected = read_image(golden);
        if (actual.width != expected.width || actual.height != expected.height) {
            std::fprintf(stderr, "FAIL: %s is %dx%d, the render is %dx%d\n", golden.string().c_str(), expected.width,
                         expected.height, actual.width, actual.height);
            return 1;
        }
        const CompareResult r = compare(actual, expected, kTolerance);
        std::printf("%s vs %s: rmse %.6f, max %.4f, %zu pixels (%.4f %%) beyond %.4f\n", actual_path.filename().c_str(),
                    golden.filename().c_str(), r.rmse, r.max_abs, r.failing_pixels, 100.0 * r.failing_fraction, kTolerance);
        if (r.failing_fraction > kMaxFailingFraction || r.nonfinite) {
            const fs::path diff_path = out_dir / (stem + ".diff.png");
            write_display_image(diff_path, heatmap(actual, expected, 8.0 * kTolerance));
            std::fprintf(stderr, "FAIL: beyond tolerance (max %.2f %% of pixels)\n  actual:  %s\n  heatmap: %s\n",
                         100.0 * kMaxFailingFraction, fs::absolute(actual_path).c_str(), fs::absolute(diff_path).c_str());
            ++failures;
        }
        return failures ? 1 : 0;
    } catch (const Error& e) {
        std::fprintf(stderr, "FAIL: %s\n", e.what());
        return static_cast<int>(e.code());
    }
}
