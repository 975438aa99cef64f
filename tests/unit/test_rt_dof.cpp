// Depth of field in the tracer against the thin lens's closed form.
//
// A thin lens of RADIUS A (Camera::aperture) focused at distance F along the view axis images a
// plane at distance d (parallel to the lens) as its pinhole image convolved with a uniform disk,
// the circle of confusion, of DIAMETER
//     c = 2 A |d - F| / d                                   on the focal plane, i.e.
//     c_px = 2 A |d - F| / d * H / (2 F tan(yfov / 2))       in pixels of an image H pixels tall.
// (The issue writes "aperture x |d - focus| / d x focal scale" for an aperture that is the lens
// diameter; Candela's aperture is the radius, hence the 2.) Derivation: the ray from lens point L
// through the focal-plane point P meets the plane at P d / F + L (1 - d / F): for a fixed pixel the
// lens disk maps to a disk of radius A |1 - d / F| around the pixel's pinhole point, F / d times that
// on the focal plane.
//
// The scene is an emissive square (radiance 1, black albedo, nothing else, black background) of
// pinhole side s = 16 px on the view axis. The tracer's image is the square convolved with the
// circle of confusion and the pixel's box (jitter), so the image's intensity-weighted variance per
// axis is s^2/12 + c^2/16 + 1/12 (square, uniform disk of radius c/2, box; variances of convolved
// densities add). The measured diameter is 4 sqrt(var - (s^2 + 1)/12). Sampling the image at pixel
// centres adds nothing to the second moment here: the Poisson-summation error terms carry a double
// zero from the box and from the square of integer side (below 1e-4 px^2).
// The samples are kBatches independent batches (--spp-shard k/N); the standard error of the
// measured diameter and of the image sum comes from their spread.
// Asserted, per distance (nearer and farther than F), on both backends:
// - |measured - closed form| < 1 px in diameter, and the z of the mean below kMeanZ;
// - the flux is conserved: the image sum is the square's area s^2 (z below kMeanZ) and equals
//   the pinhole image's sum within their standard error;
// - at d = F (auto focus: the focus distance 0 focuses at the scene bounds' centre, which is the
//   square) the spot is as sharp as the pinhole's.
// Every tracer mode generates its camera rays in shaders/rt/trace_common.glsl's main(); direct,
// path, whitted and primary are measured here (ao, visibility and indirect have no signal in this
// scene: nothing occludes and there is no light to reflect).
#include <gtest/gtest.h>

#include <glm/gtc/matrix_transform.hpp>

#include <cmath>
#include <cstdio>
#include <limits>
#include <string>
#include <vector>

#include "core/error.hpp"
#include "gl_fixture.hpp"
#include "image/batch_stats.hpp"
#include "gltf_builder.hpp"
#include "render/gpu_scene.hpp"
#include "render/settings.hpp"
#include "rt/ray_tracer.hpp"
#include "scene/gltf_loader.hpp"

namespace candela {
namespace {
namespace fs = std::filesystem;
using nlohmann::json;

constexpr int kSize = 96;           // image width and height
constexpr double kYfov = 0.5;       // radians
constexpr double kFocus = 4.0;      // F
constexpr double kAperture = 0.3;   // A, the lens radius
constexpr double kSquarePx = 16.0;  // the square's pinhole side, pixels
constexpr int kBatches = 8;
constexpr double kMeanZ = 5.0;

double focal_scale_px() { return kSize / (2.0 * kFocus * std::tan(kYfov / 2.0)); }  // pixels per unit on the focal plane
double closed_form_diameter_px(double d) { return 2.0 * kAperture * std::fabs(d - kFocus) / d * focal_scale_px(); }

// An emissive square of pinhole side kSquarePx at distance d in front of a camera at the origin
// looking down -Z, with the lens in the camera's extras (focus_distance 0: auto).
Scene square_scene(double d, double focus_distance) {
    test::GltfBuilder b;
    b.json()["materials"] = {{{"pbrMetallicRoughness", {{"baseColorFactor", {0, 0, 0, 1}}, {"metallicFactor", 0}, {"roughnessFactor", 1}}},
                              {"emissiveFactor", {1, 1, 1}}}};
    const double half_side = 0.5 * kSquarePx * 2.0 * d * std::tan(kYfov / 2.0) / kSize;  // unit quad: side 2
    b.add_node({{"mesh", b.add_quad_mesh(0)}, {"translation", {0, 0, -d}}, {"scale", {half_side, half_side, 1}}});
    b.json()["cameras"] = {{{"type", "perspective"},
                            {"perspective", {{"yfov", kYfov}, {"znear", 0.05}}},
                            {"extras", {{"aperture", kAperture}, {"focus_distance", focus_distance}}}}};
    b.add_node({{"camera", 0}});
    char name[64];
    std::snprintf(name, sizeof(name), "dof_square_%g_%g", d, focus_distance);
    return load_gltf(b.write(test::test_dir(name), name));
}

// The image's intensity moments (blue channel: 1 where a ray hits the square in every mode here).
struct Moments {
    double sum = 0.0, cx = 0.0, cy = 0.0, var = 0.0;  // var: the mean of the x and y variances, px^2
};
Moments moments(const ImageF& img) {
    double s = 0.0, sx = 0.0, sy = 0.0, sxx = 0.0, syy = 0.0;
    for (int y = 0; y < img.height; ++y)
        for (int x = 0; x < img.width; ++x) {
            const double v = img.at(x, y)[2], px = x + 0.5, py = y + 0.5;
            s += v, sx += v * px, sy += v * py, sxx += v * px * px, syy += v * py * py;
        }
    Moments m;
    m.sum = s;
    if (s <= 0.0) return m;
    m.cx = sx / s, m.cy = sy / s;
    m.var = 0.5 * ((sxx / s - m.cx * m.cx) + (syy / s - m.cy * m.cy));
    return m;
}


// The diameter of the uniform disk that, convolved with the square and the pixel box, gives `var`.
double diameter_from_variance(double var) { return 4.0 * std::sqrt(std::max(0.0, var - (kSquarePx * kSquarePx + 1.0) / 12.0)); }

struct Measured {
    BatchMean diameter, sum, var, cx, cy;
};

class RtDofTest : public test::GlContextTest {
protected:
    // The scene's camera (its lens) and the same camera with aperture 0, kBatches batches of
    // `spp` samples per pixel each, from one tracer.
    struct LensAndPinhole {
        Measured lens, pinhole;
    };
    LensAndPinhole measure(const Scene& scene, rt::Mode mode, int spp) {
        rt::Options o;
        o.mode = mode;
        o.spp = spp * kBatches;
        GpuScene gpu(scene);
        rt::RayTracer tracer(shaders_, scene, gpu, o);
        const Camera camera = scene.select_camera("", 1.0f);
        RenderSettings s;
        s.camera.aperture = 0.0f;  // the knob over the camera's own lens, as --set camera.aperture=0
        return {measure(tracer, camera), measure(tracer, with_lens(camera, s))};
    }
    static Measured measure(rt::RayTracer& tracer, const Camera& camera) {
        std::vector<double> d, sum, var, cx, cy;
        for (int k = 0; k < kBatches; ++k) {
            tracer.set_shard(k, kBatches);
            const rt::Result r = tracer.render(camera, kSize, kSize);
            EXPECT_EQ(r.nonfinite_samples, 0u);
            const Moments m = moments(r.image);
            d.push_back(diameter_from_variance(m.var));
            sum.push_back(m.sum);
            var.push_back(m.var);
            cx.push_back(m.cx);
            cy.push_back(m.cy);
        }
        return {batch_mean(d), batch_mean(sum), batch_mean(var), batch_mean(cx), batch_mean(cy)};
    }
    ShaderLibrary shaders_{fs::path(CANDELA_SOURCE_DIR) / "shaders"};
};

// A difference over its standard error; 0 for no difference at all (the pinhole image of a
// pixel-aligned square has no noise, nor has the in-focus lens image).
double z_score(double difference, double se) {
    if (difference == 0.0) return 0.0;
    return se > 0.0 ? difference / se : std::copysign(std::numeric_limits<double>::infinity(), difference);
}

void expect_flux_conserved(const Measured& lens, const Measured& pinhole, const std::string& what) {
    const double area = kSquarePx * kSquarePx;
    const double z_area = z_score(lens.sum.mean - area, lens.sum.se);
    const double z_pinhole = z_score(lens.sum.mean - pinhole.sum.mean, std::hypot(lens.sum.se, pinhole.sum.se));
    std::printf("%s: image sum %.3f +- %.3f (pinhole %.3f +- %.3f; closed form s^2 = %.0f): z %+.2f against s^2, %+.2f against the pinhole\n",
                what.c_str(), lens.sum.mean, lens.sum.se, pinhole.sum.mean, pinhole.sum.se, area, z_area, z_pinhole);
    EXPECT_LT(std::fabs(z_area), kMeanZ) << what << ": the lens loses or adds light";
    EXPECT_LT(std::fabs(z_pinhole), kMeanZ) << what << ": the lens image's flux differs from the pinhole's";
}

// Nearer and farther than the focus distance: the blur circle's diameter is the closed form's.
TEST_P(RtDofTest, BlurCircleDiameterIsTheThinLensClosedForm) {
    struct Case {
        double d;
        rt::Mode mode;
        int spp;
    };
    // direct at both distances with more samples; the other modes (same camera rays, other
    // shading) at the near distance.
    const std::vector<Case> cases = {{2.0, rt::Mode::direct, 16}, {8.0, rt::Mode::direct, 16}, {2.0, rt::Mode::path, 4},
                                     {2.0, rt::Mode::whitted, 4}, {2.0, rt::Mode::primary, 4}};
    for (const Case& c : cases) {
        const Scene scene = square_scene(c.d, kFocus);
        const auto [lens, pinhole] = measure(scene, c.mode, c.spp);
        const double exact = closed_form_diameter_px(c.d);
        const double z = z_score(lens.diameter.mean - exact, lens.diameter.se);
        const double radius_convention = exact / 2.0;  // A |d - F| / d: the lens radius taken for its diameter
        char what[96];
        std::snprintf(what, sizeof(what), "%s, d = %g (F = %g, A = %g)", rt::to_string(c.mode), c.d, kFocus, kAperture);
        std::printf("%s: blur circle diameter %.3f +- %.3f px, closed form %.3f px: difference %+.3f px, z %+.2f "
                    "(pinhole: %.3f px; the convention without the 2 would be off by %.1f px, z %+.0f); centre (%.2f, %.2f)\n",
                    what, lens.diameter.mean, lens.diameter.se, exact, lens.diameter.mean - exact, z, pinhole.diameter.mean,
                    exact - radius_convention, (lens.diameter.mean - radius_convention) / lens.diameter.se, lens.cx.mean, lens.cy.mean);
        EXPECT_LT(std::fabs(lens.diameter.mean - exact), 1.0) << what;
        EXPECT_LT(std::fabs(z), kMeanZ) << what;
        EXPECT_LT(pinhole.diameter.mean, 1.0) << what << ": the pinhole image is blurred";
        EXPECT_NEAR(lens.cx.mean, kSize / 2.0, 0.5) << what;
        EXPECT_NEAR(lens.cy.mean, kSize / 2.0, 0.5) << what;
        expect_flux_conserved(lens, pinhole, what);
    }
}

// At d = F the spot is as sharp as the pinhole's. The focus is auto (focus_distance 0): the scene
// bounds' centre, the square itself.
TEST_P(RtDofTest, InFocusPlaneIsAsSharpAsThePinhole) {
    const double d = kFocus;
    const Scene scene = square_scene(d, 0.0);
    ASSERT_EQ(scene.cameras.size(), 1u);
    EXPECT_NEAR(focus_distance_or_auto(scene.cameras[0], scene.world_bounds()), d, 1e-5);
    const auto [lens, pinhole] = measure(scene, rt::Mode::direct, 16);
    // The diameter of the disk that would explain the extra variance over the pinhole's.
    const double extra = lens.var.mean - pinhole.var.mean;
    const double blur = 4.0 * std::sqrt(std::max(0.0, extra));
    std::printf("in focus (d = F = %g, auto focus): variance %.4f +- %.4f px^2, pinhole %.4f +- %.4f px^2: a blur circle of %.3f px "
                "(closed form 0; out of focus by 1 %% it would be %.2f px)\n",
                d, lens.var.mean, lens.var.se, pinhole.var.mean, pinhole.var.se, blur, closed_form_diameter_px(d * 1.01));
    EXPECT_LT(blur, 1.0);
    EXPECT_LT(std::fabs(extra), 1.0 / 16.0 + kMeanZ * std::hypot(lens.var.se, pinhole.var.se));
    expect_flux_conserved(lens, pinhole, "in focus, direct");
}

INSTANTIATE_TEST_SUITE_P(Backends, RtDofTest, ::testing::Values(Backend::egl, Backend::osmesa), test::backend_name);

// --- the glTF camera extras and auto focus (no GL) ----------------------------------------------

fs::path lens_file(const std::string& name, const json& extras, bool orthographic = false) {
    test::GltfBuilder b;
    b.add_node({{"mesh", b.add_quad_mesh()}, {"translation", {0, 0, -5}}});
    json cam = orthographic ? json{{"type", "orthographic"}, {"orthographic", {{"xmag", 1}, {"ymag", 1}, {"znear", 0.1}, {"zfar", 10}}}}
                            : json{{"type", "perspective"}, {"perspective", {{"yfov", 0.7}, {"znear", 0.1}}}};
    if (!extras.is_null()) cam["extras"] = extras;
    b.json()["cameras"] = {cam};
    b.add_node({{"camera", 0}});
    return b.write(test::test_dir(name), name);
}

std::string load_error(const fs::path& file) {
    try {
        load_gltf(file);
    } catch (const Error& e) {
        return e.what();
    }
    return "";
}

TEST(CameraLens, ReadsTheCameraExtras) {
    const Scene s = load_gltf(lens_file("lens_extras", {{"aperture", 0.05}, {"focus_distance", 2.5}}));
    ASSERT_EQ(s.cameras.size(), 1u);
    EXPECT_FLOAT_EQ(s.cameras[0].aperture, 0.05f);
    EXPECT_FLOAT_EQ(s.cameras[0].focus_distance, 2.5f);
    EXPECT_TRUE(has_thin_lens(s.cameras[0]));
    const Scene none = load_gltf(lens_file("lens_none", json()));
    EXPECT_EQ(none.cameras[0].aperture, 0.0f);
    EXPECT_EQ(none.cameras[0].focus_distance, 0.0f);
    EXPECT_FALSE(has_thin_lens(none.cameras[0]));
    // Integers are numbers too.
    EXPECT_FLOAT_EQ(load_gltf(lens_file("lens_int", {{"aperture", 1}})).cameras[0].aperture, 1.0f);
}

TEST(CameraLens, RejectsBadExtrasNamingThePath) {
    const std::string negative = load_error(lens_file("lens_negative", {{"aperture", -0.1}}));
    EXPECT_NE(negative.find("cameras[0].extras.aperture"), std::string::npos) << negative;
    const std::string text = load_error(lens_file("lens_text", {{"focus_distance", "far"}}));
    EXPECT_NE(text.find("cameras[0].extras.focus_distance"), std::string::npos) << text;
    const std::string negative_focus = load_error(lens_file("lens_negative_focus", {{"focus_distance", -2}}));
    EXPECT_NE(negative_focus.find("cameras[0].extras.focus_distance"), std::string::npos) << negative_focus;
}

TEST(CameraLens, OrthographicCamerasHaveNoDepthOfField) {
    const Scene s = load_gltf(lens_file("lens_ortho", {{"aperture", 0.2}}, true));  // loads, with a warning
    EXPECT_FLOAT_EQ(s.cameras[0].aperture, 0.2f);
    EXPECT_FALSE(has_thin_lens(s.cameras[0]));
}

TEST(CameraLens, AutoFocusIsTheBoundsCentreAlongTheViewAxis) {
    Camera c;
    c.znear = 0.1f;
    c.world = glm::translate(glm::mat4(1.0f), glm::vec3(1.0f, 2.0f, 3.0f));  // looks down -Z
    Bounds b;
    b.extend(glm::vec3(-1.0f, -1.0f, -9.0f));
    b.extend(glm::vec3(5.0f, 1.0f, -5.0f));  // centre (2, 0, -7): 10 along the axis, off the axis
    EXPECT_NEAR(focus_distance_or_auto(c, b), 10.0f, 1e-5f);
    c.focus_distance = 3.0f;  // a given distance wins
    EXPECT_EQ(focus_distance_or_auto(c, b), 3.0f);
    c.focus_distance = 0.0f;
    c.world = glm::rotate(glm::mat4(1.0f), glm::radians(180.0f), glm::vec3(0, 1, 0));  // looks down +Z: the centre is behind
    EXPECT_NEAR(focus_distance_or_auto(c, b), c.znear, 1e-6f);
    EXPECT_EQ(focus_distance_or_auto(c, Bounds{}), 1.0f);  // empty scene
    // The knobs: -1 keeps the camera's own, >= 0 overrides it (0 focus: auto).
    c.aperture = 0.1f, c.focus_distance = 2.0f;
    RenderSettings s;
    EXPECT_EQ(with_lens(c, s).aperture, 0.1f);
    s.camera.aperture = 0.0f, s.camera.focus_distance = 0.0f;
    EXPECT_EQ(with_lens(c, s).aperture, 0.0f);
    EXPECT_EQ(with_lens(c, s).focus_distance, 0.0f);
}

}  // namespace
}  // namespace candela
