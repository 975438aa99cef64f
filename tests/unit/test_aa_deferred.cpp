// Anti-aliasing on the deferred path: a multisampled G-buffer, shaded once per pixel
// where the samples see one surface and once per surface (group of samples) at the edge pixels
// only (shaders/deferred/light.comp, MULTISAMPLED).
//
// The lit counterpart of test_aa.cpp's emissive square: generated:edges (a slanted checker,
// sub-pixel wires, a MASK fence, a tilted box, Lambert under a point light at the camera) against
// the tracer's box-filtered pixels (`direct`, jittered camera rays), so the lighting pass's
// per-sample shading is what converges.
#include <gtest/gtest.h>

#include <cmath>
#include <cstdio>
#include <cstdlib>
#include <filesystem>

#include "box_reference.hpp"
#include "gl_fixture.hpp"
#include "image/image.hpp"
#include "render/passes/deferred_lighting.hpp"
#include "render/settings.hpp"
#include "render/still.hpp"
#include "rt/ray_tracer.hpp"
#include "scene/generate.hpp"
#include "scene/gltf_loader.hpp"

namespace candela {
namespace {

namespace fs = std::filesystem;

constexpr int kW = 128, kH = 128;

using Reference = test::BoxReference;

// `batches` independent traces of `spp` box-filtered samples each (box_reference.hpp).
Reference trace_reference(const ShaderLibrary& lib, const Scene& scene, int batches, int spp) {
    return test::trace_box_reference(lib, scene, kW, kH, batches, spp, 211u);
}

StillResult raster(const ShaderLibrary& lib, const Scene& scene, RenderPath path, int samples, const char* effects = "none",
                   bool a2c = true, int w = kW, int h = kH) {
    StillOptions so;
    so.width = w;
    so.height = h;
    so.settings.path = path;
    apply_effects(so.settings, effects);
    if (samples > 1) {
        apply_knob(so.settings, "aa.mode=msaa");
        apply_knob(so.settings, "aa.samples=" + std::to_string(samples));
    }
    apply_knob(so.settings, a2c ? "aa.alpha_to_coverage=1" : "aa.alpha_to_coverage=0");
    StillResult r = render_still(scene, lib, so);
    EXPECT_EQ(count_nonfinite(r.radiance), 0u) << samples << " samples";
    return r;
}

// Edge pixels: where the reference changes by more than 0.05 within the 3x3 neighbourhood (the
// flat parts of generated:edges are smooth at this scale; its edges are 0.02 against 0.85).
std::vector<bool> edge_mask(const Reference& ref) {
    std::vector<bool> edge(ref.mean.size(), false);
    for (int y = 1; y + 1 < kH; ++y)
        for (int x = 1; x + 1 < kW; ++x) {
            double lo = 1e30, hi = -1e30;
            for (int dy = -1; dy <= 1; ++dy)
                for (int dx = -1; dx <= 1; ++dx) {
                    const double v = ref.mean[static_cast<size_t>((y + dy) * kW + x + dx)];
                    lo = std::min(lo, v);
                    hi = std::max(hi, v);
                }
            edge[static_cast<size_t>(y * kW + x)] = hi - lo > 0.05;
        }
    return edge;
}

// Root mean squared difference over the edge pixels, less the reference's own variance.
double edge_error(const ImageF& img, const Reference& ref, const std::vector<bool>& edge) {
    double sum = 0;
    int n = 0;
    for (int y = 0; y < kH; ++y)
        for (int x = 0; x < kW; ++x) {
            const size_t i = static_cast<size_t>(y * kW + x);
            if (!edge[i]) continue;
            const double d = img.at(x, y)[0] - ref.mean[i];
            sum += d * d - ref.se[i] * ref.se[i];
            ++n;
        }
    return std::sqrt(std::max(0.0, sum / std::max(n, 1)));
}


// CANDELA_AA_STATS=1 for the scope: the lighting pass counts its per-sample pixels.
struct CountEdges {
    CountEdges() { setenv("CANDELA_AA_STATS", "1", 1); }
    ~CountEdges() { unsetenv("CANDELA_AA_STATS"); }
};

class AaDeferredTest : public test::GlContextTest {
protected:
    ShaderLibrary lib_{ShaderLibrary::default_root()};
};

TEST_P(AaDeferredTest, LitEdgesConvergeToTheTracerWithTheSampleCount) {
    // One backend (CI time: 17 s each): both are llvmpipe and gave the same numbers to the last
    // digit; AaTest's slanted edge covers both backends on both paths.
    if (GetParam() == Backend::osmesa) GTEST_SKIP() << "the EGL instance covers it (identical pixels on llvmpipe)";
    const Scene scene = make_edges_scene();
    const Reference ref = trace_reference(lib_, scene, 8, 32);
    const std::vector<bool> edge = edge_mask(ref);
    const long edges = std::count(edge.begin(), edge.end(), true);
    ASSERT_GT(edges, 500);
    double previous = 1e9;
    for (int samples : {1, 2, 4, 8}) {
        const double err = edge_error(raster(lib_, scene, RenderPath::deferred, samples).radiance, ref, edge);
        std::printf("%s deferred generated:edges %dx%d: %d sample(s): edge RMSE %.4f over %ld edge pixels\n",
                    to_string(GetParam()), kW, kH, samples, err, edges);
        EXPECT_LT(err, previous) << samples << " samples: the edge error must fall with the sample count";
        previous = err;
    }
}

// The two paths anti-alias alike: forward shades a fragment once for the samples it covers,
// deferred once per pixel or once per surface at edges. With the alpha test on both (no alpha to
// coverage) they differ by the G-buffer's precision and the edge pixels' shading positions (the
// mean of a surface's samples on the deferred path, the pixel centre on the forward path); with alpha to coverage
// also by which samples a MASK fragment keeps (GL's own pattern vs gbuffer.frag's).
TEST_P(AaDeferredTest, ForwardAndDeferredAgreeAtFourSamples) {
    const Scene scene = make_edges_scene();
    for (bool a2c : {false, true}) {
        const ImageF f = raster(lib_, scene, RenderPath::forward, 4, "none", a2c).radiance;
        const ImageF d = raster(lib_, scene, RenderPath::deferred, 4, "none", a2c).radiance;
        const ImageF f1 = raster(lib_, scene, RenderPath::forward, 1, "none", a2c).radiance;
        const double e = rmse(f, d), aliased = rmse(f, f1);
        std::printf("%s generated:edges 4 samples, alpha to coverage %s: RMSE forward vs deferred %.4f (forward 4 vs 1 sample %.4f)\n",
                    to_string(GetParam()), a2c ? "on" : "off", e, aliased);
        EXPECT_LT(e, a2c ? 0.02 : 0.005);
        EXPECT_LT(e, 0.25 * aliased) << "the paths differ by much less than anti-aliasing changes the image";
    }
}

// Shading once where the samples agree: pixels away from every edge get the single-sample value
// (the centre, with the mean of the sample depths, which for one plane is the centre's depth);
// only a small share of the pixels is shaded more than once.
TEST_P(AaDeferredTest, OnlyEdgePixelsAreShadedMoreThanOnce) {
    // One backend (CI time): the counts are the shader's, the same on both llvmpipe backends.
    if (GetParam() == Backend::osmesa) GTEST_SKIP() << "the EGL instance covers it (identical counts on llvmpipe)";
    const Scene edges_scene = make_edges_scene();
    const Scene cornell = load_gltf(fs::path(CANDELA_SOURCE_DIR) / "samples" / "scenes" / "cornell_box.gltf");
    CountEdges count;
    // aa.samples=1 plans no anti-aliasing: the image of aa.mode=off, bit for bit.
    const ImageF off = raster(lib_, edges_scene, RenderPath::deferred, 0).radiance;
    const ImageF one = [&] {
        StillOptions so;
        so.width = kW;
        so.height = kH;
        so.settings.path = RenderPath::deferred;
        apply_effects(so.settings, "none");
        apply_knob(so.settings, "aa.mode=msaa");
        apply_knob(so.settings, "aa.samples=1");
        return render_still(edges_scene, lib_, so).radiance;
    }();
    EXPECT_EQ(rmse(off, one), 0.0);

    struct Case {
        const char* name;
        const Scene* scene;
        const char* effects;
        double max_share;
    };
    for (const Case& c : {Case{"generated:edges", &edges_scene, "none", 0.25}, Case{"cornell_box", &cornell, "all", 0.10}}) {
        const ImageF single = raster(lib_, *c.scene, RenderPath::deferred, 1, c.effects).radiance;
        const StillResult ms = raster(lib_, *c.scene, RenderPath::deferred, 4, c.effects);
        const DeferredEdgeStats st = last_deferred_edge_stats();
        ASSERT_EQ(st.samples, 4);
        ASSERT_GT(st.geometry_pixels, 0);
        const double share = static_cast<double>(st.edge_pixels) / static_cast<double>(st.geometry_pixels);
        std::printf("%s %s %dx%d, 4 samples: %lld of %lld pixels shaded more than once (%.2f %%), %.4f shadings per pixel\n",
                    to_string(GetParam()), c.name, kW, kH, st.edge_pixels, st.geometry_pixels, 100.0 * share,
                    static_cast<double>(st.shadings) / static_cast<double>(st.geometry_pixels));
        // An edge pixel shades once per surface its samples show: between 2 and 4 times.
        EXPECT_GE(st.shadings, st.geometry_pixels + st.edge_pixels);
        EXPECT_LE(st.shadings, st.geometry_pixels + 3 * st.edge_pixels);
        EXPECT_GT(st.edge_pixels, 0);
        EXPECT_LT(share, c.max_share);
        if (c.scene != &edges_scene) continue;
        // Interior pixels (no edge in the 3x3 neighbourhood of the single-sample image nor of
        // the multisampled one, which also shows the wires one sample misses): equal to the
        // single-sample shading within float precision.
        double worst = 0;
        int interior = 0;
        for (int y = 1; y + 1 < kH; ++y)
            for (int x = 1; x + 1 < kW; ++x) {
                bool flat = true;
                for (const ImageF* im : {&single, &ms.radiance}) {
                    double lo = 1e30, hi = -1e30;
                    for (int dy = -1; dy <= 1; ++dy)
                        for (int dx = -1; dx <= 1; ++dx) {
                            lo = std::min(lo, static_cast<double>(im->at(x + dx, y + dy)[0]));
                            hi = std::max(hi, static_cast<double>(im->at(x + dx, y + dy)[0]));
                        }
                    flat = flat && hi - lo <= 0.02;
                }
                if (!flat) continue;
                ++interior;
                const double s = single.at(x, y)[0];
                worst = std::max(worst, std::abs(ms.radiance.at(x, y)[0] - s) / std::max(s, 1e-3));
            }
        std::printf("  %d interior pixels: largest relative difference to one sample %.2g\n", interior, worst);
        EXPECT_GT(interior, kW * kH / 3);
        EXPECT_LT(worst, 1e-3);
    }
}

INSTANTIATE_TEST_SUITE_P(Backends, AaDeferredTest, ::testing::Values(Backend::egl, Backend::osmesa), test::backend_name);

}  // namespace
}  // namespace candela
