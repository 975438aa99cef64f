// The same rays as `candela bench rays`, through Embree 3's single-ray API on the CPU, and the
// compute-shader tracer's rates (rt::measure_ray_rates, on llvmpipe through EGL or OSMesa) in the
// same run on the same cores, with their ratio. Optional: built only when Debian's libembree-dev
// is installed (it is not a dependency of Candela).
//   bench_rays_embree SCENE|generated:N ... [--size WxH] [--spp N] [--threads N] [--repeat N] [--tracer-only]
//                     [--ab DIR [--ab-env NAME=VALUE]]
// --tracer-only skips Embree. --ab DIR: an A/B of the tracer instead of Embree: the default shader
// directory (A) against DIR (B), renders alternating ABBA in one process (load changes on a
// shared machine hit both alike), medians, B/A and the largest pixel difference between A's and
// B's images (0: the same hits). --ab-env sets an environment variable while B's tracers are
// made (for switches read when the geometry is packed or uploaded). After the table: traversal
// work per camera ray (RT_STATS) and the bytes of the traversal layout (nodes, primitive records).
// Embree's rates are medians of --repeat runs of --spp samples; the tracer's of --repeat runs of
// 4 x --spp samples (a dispatch's fixed cost is then small against its work).
// Camera rays through pixel centres (the tracer's primary mode without jitter), and per hit one
// cosine-distributed any-hit ray of unbounded length (the tracer's AO rays with ao.radius = inf).
#include <embree3/rtcore.h>

#include <algorithm>
#include <atomic>
#include <chrono>
#include <cmath>
#include <cstdio>
#include <cstdlib>
#include <cstring>
#include <string>
#include <thread>
#include <vector>

#include "platform/context.hpp"
#include "render/gpu_scene.hpp"
#include "render/still.hpp"
#include "rt/ray_rates.hpp"
#include "rt/ray_tracer.hpp"
#include "rt/sampling.hpp"
#include "scene/generate.hpp"
#include "scene/gltf_loader.hpp"

using namespace candela;

namespace {

struct Rates {
    double primary_mrays = 0, ao_mrays = 0;
};

Rates measure(const Scene& scene, int w, int h, int spp, int threads, int repeats) {
    RTCDevice device = rtcNewDevice(nullptr);
    RTCScene rtc_scene = rtcNewScene(device);
    const std::vector<WorldTriangle> tris = scene.world_triangles();
    RTCGeometry geom = rtcNewGeometry(device, RTC_GEOMETRY_TYPE_TRIANGLE);
    auto* v = static_cast<float*>(rtcSetNewGeometryBuffer(geom, RTC_BUFFER_TYPE_VERTEX, 0, RTC_FORMAT_FLOAT3,
                                                          3 * sizeof(float), tris.size() * 3));
    auto* idx = static_cast<unsigned*>(rtcSetNewGeometryBuffer(geom, RTC_BUFFER_TYPE_INDEX, 0, RTC_FORMAT_UINT3,
                                                               3 * sizeof(unsigned), tris.size()));
    for (size_t t = 0; t < tris.size(); ++t)
        for (int k = 0; k < 3; ++k) {
            std::memcpy(v + (t * 3 + static_cast<size_t>(k)) * 3, &tris[t].p[static_cast<size_t>(k)], 12);
            idx[t * 3 + static_cast<size_t>(k)] = static_cast<unsigned>(t * 3 + static_cast<size_t>(k));
        }
    rtcCommitGeometry(geom);
    rtcAttachGeometry(rtc_scene, geom);
    rtcReleaseGeometry(geom);
    rtcCommitScene(rtc_scene);

    const float aspect = static_cast<float>(w) / static_cast<float>(h);
    const Camera camera = scene.select_camera("", aspect);
    const glm::mat4 inv = glm::inverse(projection_matrix(camera, aspect) * glm::inverse(camera.world));
    auto run = [&](bool ao) {
        std::atomic<int> next_row{0};
        auto worker = [&] {
            RTCIntersectContext ctx;
            rtcInitIntersectContext(&ctx);
            for (int y; (y = next_row++) < h;)
                for (int x = 0; x < w; ++x)
                    for (int s = 0; s < spp; ++s) {
                        const glm::vec2 ndc((static_cast<float>(x) + 0.5f) / static_cast<float>(w) * 2.0f - 1.0f,
                                            1.0f - (static_cast<float>(y) + 0.5f) / static_cast<float>(h) * 2.0f);
                        const glm::vec4 a4 = inv * glm::vec4(ndc, 1.0f, 1.0f), b4 = inv * glm::vec4(ndc, 0.5f, 1.0f);
                        const glm::vec3 a = glm::vec3(a4) / a4.w, d = glm::normalize(glm::vec3(b4) / b4.w - a);
                        RTCRayHit rh{};
                        rh.ray.org_x = a.x, rh.ray.org_y = a.y, rh.ray.org_z = a.z;
                        rh.ray.dir_x = d.x, rh.ray.dir_y = d.y, rh.ray.dir_z = d.z;
                        rh.ray.tnear = 0.0f;
                        rh.ray.tfar = 1e30f;
                        rh.ray.mask = ~0u;
                        rh.hit.geomID = RTC_INVALID_GEOMETRY_ID;
                        rtcIntersect1(rtc_scene, &ctx, &rh);
                        if (!ao || rh.hit.geomID == RTC_INVALID_GEOMETRY_ID) continue;
                        glm::vec3 n = glm::normalize(glm::vec3(rh.hit.Ng_x, rh.hit.Ng_y, rh.hit.Ng_z));
                        if (glm::dot(n, d) > 0.0f) n = -n;
                        const std::uint32_t r0 = rt::pcg_hash(static_cast<std::uint32_t>((y * w + x) * 977 + s));
                        const std::uint32_t r1 = rt::pcg_hash(r0);
                        glm::vec3 t, b;
                        rt::onb(n, t, b);
                        const glm::vec3 l = rt::sample_cosine_hemisphere({static_cast<float>(r0 >> 8) / 16777216.0f,
                                                                          static_cast<float>(r1 >> 8) / 16777216.0f});
                        const glm::vec3 dir = l.x * t + l.y * b + l.z * n;
                        const glm::vec3 p = a + d * rh.ray.tfar + n * 1e-4f;
                        RTCRay shadow{};
                        shadow.org_x = p.x, shadow.org_y = p.y, shadow.org_z = p.z;
                        shadow.dir_x = dir.x, shadow.dir_y = dir.y, shadow.dir_z = dir.z;
                        shadow.tnear = 0.0f;
                        shadow.tfar = 1e30f;
                        shadow.mask = ~0u;
                        rtcOccluded1(rtc_scene, &ctx, &shadow);
                    }
        };
        const auto t0 = std::chrono::steady_clock::now();
        std::vector<std::thread> pool;
        for (int i = 0; i < threads; ++i) pool.emplace_back(worker);
        for (auto& th : pool) th.join();
        return std::chrono::duration<double, std::milli>(std::chrono::steady_clock::now() - t0).count();
    };
    run(false);  // warm-up
    std::vector<double> primary_ms, ao_extra_ms;
    for (int r = 0; r < repeats; ++r) {
        primary_ms.push_back(run(false));
        ao_extra_ms.push_back(run(true) - primary_ms.back());
    }
    rtcReleaseScene(rtc_scene);
    rtcReleaseDevice(device);
    const double rays = static_cast<double>(w) * h * spp;
    const double p = median(primary_ms), a = median(ao_extra_ms);
    return {rays / (p * 1e3), a > 0.0 ? rays / (a * 1e3) : 0.0};
}

// Primary and AO rates of the tracer with shaders A and B (B's tracers made with `ab_env` set),
// renders alternating ABBA; the AO rate prices the second ray as measure_ray_rates does.
void ab(const ShaderLibrary& a, const ShaderLibrary& b, const Scene& scene, const std::string& name, int w, int h, int spp,
        int repeats, std::string& ab_env) {
    GpuScene gpu(scene);
    const Camera camera = scene.select_camera("", static_cast<float>(w) / static_cast<float>(h));
    const rt::Mode modes[2] = {rt::Mode::primary, rt::Mode::ao};
    std::vector<std::unique_ptr<rt::RayTracer>> tracers;  // A primary, A ao, B primary, B ao
    for (const ShaderLibrary* lib : {&a, &b})
        for (const rt::Mode m : modes) {
            if (lib == &b && !ab_env.empty()) putenv(ab_env.data());
            rt::Options o;
            o.mode = m;
            o.ao_radius = 1e30f;
            o.spp = 1;
            tracers.push_back(std::make_unique<rt::RayTracer>(*lib, scene, gpu, o));
            tracers.back()->render(camera, w, h);
            tracers.back()->set_spp(spp);
        }
    if (!ab_env.empty()) unsetenv(ab_env.substr(0, ab_env.find('=')).c_str());
    std::vector<double> ms[4];
    float diff[2] = {0.0f, 0.0f};
    for (int r = 0; r < repeats; ++r)
        for (int k = 0; k < 2; ++k) {
            const int first = (r + k) % 2;  // ABBA...
            for (int side : {first, 1 - first})
                for (int m = 0; m < 2; ++m)
                    ms[side * 2 + m].push_back(tracers[static_cast<std::size_t>(side * 2 + m)]->render(camera, w, h).trace_ms);
        }
    for (int m = 0; m < 2; ++m) {
        const rt::Result ra = tracers[static_cast<std::size_t>(m)]->render(camera, w, h);
        const rt::Result rb = tracers[static_cast<std::size_t>(2 + m)]->render(camera, w, h);
        for (std::size_t i = 0; i < ra.image.pixels.size(); ++i)
            diff[m] = std::max(diff[m], std::abs(ra.image.pixels[i] - rb.image.pixels[i]));
    }
    const double rays = static_cast<double>(w) * h * spp;
    const double pa = median(ms[0]), pb = median(ms[2]);
    std::vector<double> aoa, aob;
    for (std::size_t i = 0; i < ms[0].size(); ++i) {
        aoa.push_back(ms[1][i] - ms[0][i]);
        aob.push_back(ms[3][i] - ms[2][i]);
    }
    const double xa = median(aoa), xb = median(aob);
    std::printf("%-28s primary A %.2f B %.2f Mrays/s (B/A %.3f, max diff %g); AO A %.2f B %.2f (B/A %.3f, max diff %g)\n",
                name.substr(name.size() > 28 ? name.size() - 28 : 0).c_str(), rays / (pa * 1e3), rays / (pb * 1e3), pa / pb, diff[0],
                rays / (xa * 1e3), rays / (xb * 1e3), xa / xb, diff[1]);
    std::fflush(stdout);
}

}  // namespace

int main(int argc, char** argv) {
    int w = 512, h = 512, spp = 4, threads = 2, repeats = 3;
    bool tracer_only = false;
    std::string ab_dir, ab_env;
    std::vector<std::string> scenes;
    for (int i = 1; i < argc; ++i) {
        const std::string a = argv[i];
        if (a == "--size" && i + 1 < argc) std::sscanf(argv[++i], "%dx%d", &w, &h);
        else if (a == "--spp" && i + 1 < argc) spp = std::max(1, std::atoi(argv[++i]));
        else if (a == "--threads" && i + 1 < argc) threads = std::max(1, std::atoi(argv[++i]));
        else if (a == "--repeat" && i + 1 < argc) repeats = std::max(1, std::atoi(argv[++i]));
        else if (a == "--tracer-only") tracer_only = true;
        else if (a == "--ab" && i + 1 < argc) ab_dir = argv[++i];
        else if (a == "--ab-env" && i + 1 < argc) ab_env = argv[++i];
        else scenes.push_back(a);
    }
    ContextResult ctx = create_context(Backend::auto_select);
    if (!ctx.context) {
        std::fprintf(stderr, "bench_rays_embree: no usable OpenGL: %s\n", ctx.error.c_str());
        return 3;
    }
    const ShaderLibrary shaders(ShaderLibrary::default_root());
    if (!ab_dir.empty()) {
        const ShaderLibrary b(ab_dir);
        std::printf("A/B: A %s, B %s; %s, %d spp, %dx%d, medians of %d ABBA rounds\n", ShaderLibrary::default_root().c_str(),
                    ab_dir.c_str(), ctx.context->device_string().c_str(), 4 * spp, w, h, 2 * repeats);
        for (const std::string& name : scenes) {
            const Scene scene = name.rfind("generated:", 0) == 0 ? make_bumpy_sphere_scene(std::stoul(name.substr(10))) : load_gltf(name);
            ab(shaders, b, scene, name, w, h, 4 * spp, repeats, ab_env);
        }
        return 0;
    }
    std::printf("Embree %d.%d.%d single-ray API, %d threads, %d spp; tracer: %s, %d spp; %dx%d, medians of %d runs\n",
                RTC_VERSION_MAJOR, RTC_VERSION_MINOR, RTC_VERSION_PATCH, threads, spp, ctx.context->device_string().c_str(),
                4 * spp, w, h, repeats);
    std::printf("%-28s %22s %22s\n", "", "primary Mrays/s", "AO Mrays/s");
    std::printf("%-28s %7s %7s %6s %7s %7s %6s\n", "scene", "tracer", "Embree", "ratio", "tracer", "Embree", "ratio");
    std::vector<std::string> work_lines;
    for (const std::string& name : scenes) {
        const Scene scene = name.rfind("generated:", 0) == 0 ? make_bumpy_sphere_scene(std::stoul(name.substr(10))) : load_gltf(name);
        const Rates e = tracer_only ? Rates{} : measure(scene, w, h, spp, threads, repeats);
        GpuScene gpu(scene);
        const Camera camera = scene.select_camera("", static_cast<float>(w) / static_cast<float>(h));
        const rt::RayRates t = rt::measure_ray_rates(shaders, scene, gpu, camera, w, h, 4 * spp, repeats);
        auto ratio = [](double a, double b) { return b > 0.0 ? a / b : 0.0; };
        std::printf("%-28s %7.2f %7.2f %5.0f%% %7.2f %7.2f %5.0f%%\n", name.substr(name.size() > 28 ? name.size() - 28 : 0).c_str(),
                    t.primary_mrays, e.primary_mrays, 100.0 * ratio(t.primary_mrays, e.primary_mrays), t.ao_mrays, e.ao_mrays,
                    100.0 * ratio(t.ao_mrays, e.ao_mrays));
        char line[384];
        std::snprintf(line, sizeof line,
                      "%-28s per camera ray %.1f nodes + %.1f primitives, %.0f %% of SIMD lanes busy; per AO ray %.1f + %.1f, %.0f %%; "
                      "layout %.1f MB nodes + %.1f MB primitives\n",
                      name.substr(name.size() > 28 ? name.size() - 28 : 0).c_str(), t.nodes_per_ray, t.primitives_per_ray,
                      100.0 * t.lane_utilisation, t.ao_nodes_per_ray, t.ao_primitives_per_ray, 100.0 * t.ao_lane_utilisation,
                      static_cast<double>(t.node_bytes) / 1e6, static_cast<double>(t.prim_bytes) / 1e6);
        work_lines.push_back(line);
    }
    for (const std::string& l : work_lines) std::fputs(l.c_str(), stdout);
    return 0;
}
