// Real content: the public glTF models in tests/data/models, rendered as a new user
// renders them (default options, default lighting), and the sample scenes.
// - Raster against the path tracer, per model: the raster's image must agree with the tracer's in
//   brightness and, pixel by pixel after a 4x4 box filter (which takes out most of the tracer's
//   noise), in display values. A black image, a model left unlit, or texture speckle fails it.
// - Gating is lossless: forcing every skipped effect on (render.gating=off) gives the same image
//   within the golden tolerance, on every model and sample scene.
// Every image is checked for NaN/Inf. Images are written to build/models-out for a look.
#include <gtest/gtest.h>

#include <algorithm>
#include <cmath>
#include <cstdio>
#include <filesystem>
#include <string>
#include <vector>

#include "core/log.hpp"
#include "gl_fixture.hpp"
#include "image/image.hpp"
#include "render/features.hpp"
#include "render/still.hpp"
#include "rt/ray_tracer.hpp"
#include "scene/gltf_loader.hpp"
#include "scene/lighting.hpp"

namespace fs = std::filesystem;

namespace candela::test {
namespace {

const fs::path kSource = CANDELA_SOURCE_DIR;
const fs::path kOut = fs::path(CANDELA_BINARY_DIR) / "models-out";

// Every model folder's .gltf or .glb (one per folder), sorted by name.
std::vector<fs::path> model_files() {
    std::vector<fs::path> files;
    for (const auto& dir : fs::directory_iterator(kSource / "tests" / "data" / "models")) {
        if (!dir.is_directory()) continue;
        for (const auto& f : fs::directory_iterator(dir.path()))
            if (f.path().extension() == ".gltf" || f.path().extension() == ".glb") files.push_back(f.path());
    }
    std::sort(files.begin(), files.end());
    return files;
}

std::vector<fs::path> sample_scenes() {
    std::vector<fs::path> files;
    for (const auto& f : fs::directory_iterator(kSource / "samples" / "scenes"))
        if (f.path().extension() == ".gltf") files.push_back(f.path());
    std::sort(files.begin(), files.end());
    return files;
}

// The scene as `candela render FILE` sees it: loaded, then lit by --lighting auto.
Scene load_as_user(const fs::path& file, int w, int h) {
    Scene scene = load_gltf(file);
    apply_lighting(scene, LightingMode::auto_select, scene.select_camera("", static_cast<float>(w) / static_cast<float>(h)));
    return scene;
}

// Bounds of the raster-vs-tracer agreement. The raster lacks multiple bounces and shadows the
// sky only by SSAO, so it is not expected to match; these bounds sit above the measured values
// of every model (measured as below) and far below what a black, unlit or speckled
// image gives.
constexpr double kMinMeanRatio = 0.85, kMaxMeanRatio = 1.15;
constexpr double kMinTracerDisplay = 0.3;  // the model is lit: not a black image
struct Bound {
    const char* model;
    double mean_abs, p99_abs;
    double min_display = kMinTracerDisplay;
};
// Display-value differences: the default, and the models whose raster differs more for known
// reasons, each about 1.5x its measured value. Measured at 128x128, 16 spp: most
// models 0.001-0.008 mean / 0.02-0.13 p99. Before the texture and shading-normal fixes, FlightHelmet's texture
// speckle measured 0.0147 / 0.185 and NormalTangentMirrorTest's black rings 0.0183 / 0.233:
// both fail the default bound.
constexpr Bound kDefaultBound{"", 0.010, 0.15};
constexpr Bound kBounds[] = {
    // The smooth black "coating only" column: the tracer's 16 spp are noisy there, the raster's
    // split-sum reflection is smooth (measured 0.0151 / 0.211 with the coat in both).
    {"ClearCoatTest", 0.022, 0.30},
    // The raster reflects the environment off anisotropic metal along one bent normal, the tracer
    // integrates the stretched lobe (measured 0.0121 / 0.164).
    {"AnisotropyStrengthTest", 0.018, 0.25},
    // Refraction: the raster looks the refracted direction up in a probe or the environment
    // once, the tracer follows the light through both surfaces of each sphere (measured 0.0578 / 0.232).
    {"TransmissionTest", 0.09, 0.38},
    // The tinted slabs (KHR_materials_volume): both apply Beer-Lambert along the path through each
    // slab, but the raster looks up what is behind in a probe (measured 0.0110 / 0.302; as clear
    // glass, before the raster followed rays through boxes, 0.0191 / 0.526).
    {"AttenuationTest", 0.017, 0.45},
    // The velvet's sheen: the tracer's 16 spp leave sparkles on the fabric (its sheen lobe is
    // reached by the cosine lobe's samples), the raster's split sum is smooth (measured 0.0067 / 0.208).
    {"SheenChair", kDefaultBound.mean_abs, 0.31},
    // Lit only by its own emitters of strength > 1 in the dark, as authored: a dark image, where the
    // 16 spp reference's noise is much of the difference. 37 % of its light is indirect, so the GI
    // probes are denser (10 along the longest axis, gi_planned_probes), and the raster's mean went
    // from 0.996 to 1.026 of a 1024 spp reference (4x4 blocks 0.0078 -> 0.0081, p99 0.137 ->
    // 0.148); against these 16 spp it measures 0.0106 / 0.154 (0.0081 / 0.122 before).
    {"EmissiveStrengthTest", 0.012, 0.17, 0.05},
    // Dark creases shadowed by the key light's PCSS penumbrae, sharper in the tracer.
    {"MorphStressTest", 0.014, 0.30},
    // Blended layers over the opaque ones: the tracer composites stochastically.
    {"AlphaBlendModeTest", 0.013, 0.21},
    // 125 small instanced boxes that shadow and light each other: the tracer's 16 spp are noisy
    // on every face and it has the bounces between the boxes the raster lacks (measured 0.0190 / 0.217).
    {"SimpleInstancing", 0.029, 0.33},
    // A fine checker texture at grazing angles: the raster's mip filtering and the tracer's
    // per-sample lookups differ along the checker edges (measured 0.0077 / 0.161).
    {"MorphPrimitivesTest", 0.012, 0.24},
};
Bound bound_for(const std::string& model) {
    for (const Bound& b : kBounds)
        if (model == b.model) return b;
    return kDefaultBound;
}

class ModelTest : public GlContextTest {};

TEST_P(ModelTest, EveryModelRasterAgreesWithThePathTracer) {
    const int w = 128, h = 128;
    fs::create_directories(kOut);
    const ShaderLibrary lib(ShaderLibrary::default_root());
    int checked = 0;
    for (const fs::path& file : model_files()) {
        SCOPED_TRACE(file.filename().string());
        const Scene scene = load_as_user(file, w, h);
        StillOptions o;
        o.width = w;
        o.height = h;
        const StillResult raster = render_still(scene, lib, o);
        ASSERT_EQ(count_nonfinite(raster.radiance), 0u);
        rt::Options ro;
        ro.mode = rt::Mode::path;
        ro.spp = 16;
        GpuScene gpu(scene);
        rt::RayTracer tracer(lib, scene, gpu, ro);
        const rt::Result traced = tracer.render(scene.select_camera("", 1.0f), w, h);
        ASSERT_EQ(count_nonfinite(traced.image), 0u);
        EXPECT_EQ(traced.nonfinite_samples, 0u);
        const std::string stem = file.stem().string() + "." + to_string(GetParam());
        write_image(kOut / (stem + ".raster.png"), raster.radiance);
        write_image(kOut / (stem + ".path.png"), traced.image);
        const BlockAgreement a = block_agreement(raster.radiance, traced.image, 4);
        std::printf("%-26s mean raster/path %.3f  |display diff| mean %.4f p99 %.4f  path display mean %.3f\n",
                    file.stem().string().c_str(), a.luminance_ratio, a.mean_abs, a.p99_abs, a.b_display_mean);
        const Bound bound = bound_for(file.stem().string());
        EXPECT_GT(a.b_display_mean, bound.min_display) << "the model is not lit";
        EXPECT_GT(a.luminance_ratio, kMinMeanRatio);
        EXPECT_LT(a.luminance_ratio, kMaxMeanRatio);
        EXPECT_LT(a.mean_abs, bound.mean_abs);
        EXPECT_LT(a.p99_abs, bound.p99_abs);
        ++checked;
    }
    EXPECT_GE(checked, 29);
}

// An effect skipped because the scene does not call for it must not change the image when forced.
TEST_P(ModelTest, GatingNeverChangesThePicture) {
    const int w = 128, h = 128;
    const ShaderLibrary lib(ShaderLibrary::default_root());
    std::vector<fs::path> files = sample_scenes();
    for (const fs::path& f : model_files()) files.push_back(f);
    int forced_somewhere = 0;
    for (const fs::path& file : files) {
        SCOPED_TRACE(file.filename().string());
        const Scene scene = load_as_user(file, w, h);
        StillOptions gated;
        gated.width = w;
        gated.height = h;
        gated.output = FrameOutput::display;
        // Both renders with 32x32 reflection-probe faces: what is compared is gating, at any probe
        // resolution alike (CI time: TransmissionTest's eight probes at the default 128 were 60
        // of the test's 113 s; the default resolution renders in the golden suite).
        apply_knob(gated.settings, "probe.resolution=32");
        StillOptions forced = gated;
        apply_knob(forced.settings, "render.gating=off");
        const StillResult a = render_still(scene, lib, gated);
        const StillResult b = render_still(scene, lib, forced);
        ASSERT_EQ(count_nonfinite(a.radiance), 0u);
        ASSERT_EQ(count_nonfinite(b.radiance), 0u);
        int skipped = 0;
        std::string which;
        for (const EffectDecision* d : a.features.effects())
            if (d->enabled && !d->planned) ++skipped, which += " " + d->name;
        // RSM, GI and the area lights are not forced: RSM needs shadow views and stays off where
        // GI runs; GI is off where its indirect light is small but not zero, and emitters are
        // emission only where their light is, so forcing either would change the image.
        for (const EffectDecision* d : b.features.effects())
            if (d->enabled && d->implemented && d->name != "rsm" && d->name != "gi" && d->name != "area_lights")
                EXPECT_TRUE(d->planned) << d->name << " not forced on";
        forced_somewhere += skipped > 0;
        ImageF da(w, h, 3), db(w, h, 3);
        for (size_t i = 0; i < static_cast<size_t>(w) * h; ++i)
            for (int c = 0; c < 3; ++c) {
                da.pixels[i * 3 + c] = a.display[i * 4 + c] / 255.0f;
                db.pixels[i * 3 + c] = b.display[i * 4 + c] / 255.0f;
            }
        const CompareResult r = compare(db, da, 2.0 / 255.0);
        std::printf("%-26s skipped:%-40s forced vs gated: %zu pixels (%.3f %%) beyond 2/255, max %.4f\n",
                    file.stem().string().c_str(), which.empty() ? " none" : which.c_str(), r.failing_pixels,
                    100.0 * r.failing_fraction, r.max_abs);
        EXPECT_LE(r.failing_fraction, 0.001) << "forcing" << which << " on changed the image";
    }
    EXPECT_GT(forced_somewhere, 0) << "no scene skipped any effect: the property was not exercised";
}

// The rig's key light follows the camera; a degenerate camera frame (zero scale) still gives a
// finite, unit light direction, and --lighting default replaces the file's lights and sky.
TEST(DefaultLighting, RigIsFiniteForADegenerateCameraAndReplacesTheFileLightsOnRequest) {
    Scene scene = load_gltf(kSource / "samples" / "scenes" / "cornell_point.gltf");
    ASSERT_EQ(scene.placed_lights().size(), 1u);
    Camera degenerate;
    degenerate.world = glm::mat4(0.0f);
    const LightingChoice choice = apply_lighting(scene, LightingMode::default_rig, degenerate);
    EXPECT_TRUE(choice.rig);
    const auto lights = scene.placed_lights();
    ASSERT_EQ(lights.size(), 1u) << "the file's point light is dropped, the key light added";
    EXPECT_EQ(lights[0].light->type, LightType::directional);
    EXPECT_FALSE(glm::any(glm::isnan(lights[0].direction)));
    EXPECT_NEAR(glm::length(lights[0].direction), 1.0f, 1e-5f);
    EXPECT_LT(lights[0].direction.y, 0.0f) << "the key light shines downwards";
    EXPECT_TRUE(scene.environment.image != nullptr);

    Scene own = load_gltf(kSource / "samples" / "scenes" / "cornell_point.gltf");
    const LightingChoice kept = apply_lighting(own, LightingMode::auto_select, own.select_camera("", 1.0f));
    EXPECT_FALSE(kept.rig) << kept.reason;
    EXPECT_EQ(own.placed_lights().size(), 1u);
}

INSTANTIATE_TEST_SUITE_P(Backends, ModelTest, ::testing::Values(Backend::egl), backend_name);

}  // namespace
}  // namespace candela::test
