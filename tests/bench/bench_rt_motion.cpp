// The tracer's posed geometry: BVH rebuild against refit, on the Khronos Fox (1.7k
// triangles, skinned, "Walk") and on a generated ~1M-triangle skinned tube bent by two bones.
//
//   build/bin/bench_rt_motion [--size WxH] [--spp N] [--repeats N] [--triangles N] [--fox PATH]
//                             [--image out.png [--image-shutter S]] [--backend egl|osmesa]
//
// Per scene: the frame at time T, the shutter [T - h, T + h] (30 fps, camera.shutter 0.5: h =
// 1/120 s). The tracer's geometry is built at T (as render() does at its start), then posed at
// T + h (the shutter's end, the farthest a slice's refit goes from the tree's pose) and
//   rebuild: a new binned-SAH BVH there;  refit: the tree built at T, boxes recomputed.
// For each: geometry (world triangles, emitters), BVH, pack (traversal layout) and upload ms, the
// tree's SAH cost, and the camera-ray rate (primary mode, the fastest of the repeats; the camera
// close on the deforming mesh) with the mean nodes and primitives visited per ray. Then the same for a far pose (T + 0.25 s), where refit degrades,
// and a full motion-blurred render (Options::pose_at, one slice per sample) with its time split.
#include <algorithm>
#include <chrono>
#include <cmath>
#include <cstdio>
#include <cstring>
#include <filesystem>
#include <memory>
#include <string>
#include <utility>
#include <vector>

#include <glm/gtc/matrix_transform.hpp>
#include <glm/gtc/quaternion.hpp>

#include "image/image.hpp"
#include "platform/context.hpp"
#include "render/gpu_scene.hpp"
#include "rt/ray_tracer.hpp"
#include "scene/animation.hpp"
#include "scene/gltf_loader.hpp"
#include "scene/mesh_utils.hpp"

namespace candela {
namespace {
namespace fs = std::filesystem;

double ms_since(std::chrono::steady_clock::time_point t0) {
    return std::chrono::duration<double, std::milli>(std::chrono::steady_clock::now() - t0).count();
}

// A tube along +x of length 4 and radius 0.3 with about `triangles` triangles, skinned to two
// joints (the second at x = 2, weights blending over x in [1.5, 2.5]), on a floor; animation 0
// bends the second joint 90 degrees about z over one second and slides the root 1 unit along z.
Scene skinned_tube(std::size_t triangles) {
    Scene scene;
    scene.source = "bench:skinned tube";
    Material m;
    m.name = "white";
    m.base_color = glm::vec4(0.8f, 0.8f, 0.8f, 1.0f);
    scene.materials.push_back(m);
    const int around = 256;
    const int along = std::max(2, static_cast<int>(triangles / (2 * around)));
    const float length = 4.0f, radius = 0.3f, pi = 3.14159265f;
    Primitive tube;
    tube.material = 0;
    tube.influence_sets = 1;
    for (int i = 0; i <= along; ++i)
        for (int j = 0; j < around; ++j) {
            const float x = length * static_cast<float>(i) / static_cast<float>(along);
            const float a = 2.0f * pi * static_cast<float>(j) / static_cast<float>(around);
            Vertex v;
            v.position = glm::vec3(x, radius * std::cos(a), radius * std::sin(a));
            v.normal = glm::vec3(0.0f, std::cos(a), std::sin(a));
            v.tangent = glm::vec4(1.0f, 0.0f, 0.0f, 1.0f);
            tube.vertices.push_back(v);
            const float w = std::clamp(x - 1.5f, 0.0f, 1.0f);
            tube.joints.emplace_back(0, 1, 0, 0);
            tube.weights.emplace_back(1.0f - w, w, 0.0f, 0.0f);
        }
    for (int i = 0; i < along; ++i)
        for (int j = 0; j < around; ++j) {
            const auto a = static_cast<std::uint32_t>(i * around + j), b = static_cast<std::uint32_t>(i * around + (j + 1) % around);
            const auto c = a + static_cast<std::uint32_t>(around), d = b + static_cast<std::uint32_t>(around);
            tube.indices.insert(tube.indices.end(), {a, c, d, a, d, b});
        }
    tube.rest = tube.vertices;
    compute_bounds(tube);
    Primitive floor;
    floor.material = 0;
    for (const glm::vec2 c : {glm::vec2(-3, -3), glm::vec2(-3, 5), glm::vec2(7, 5), glm::vec2(7, -3)}) {
        Vertex v;
        v.position = glm::vec3(c.x, -1.0f, c.y);
        v.normal = glm::vec3(0, 1, 0);
        floor.vertices.push_back(v);
    }
    floor.indices = {0, 1, 2, 0, 2, 3};
    compute_bounds(floor);
    Mesh tube_mesh;
    tube_mesh.name = "tube";
    tube_mesh.primitives.push_back(std::move(tube));
    Mesh floor_mesh;
    floor_mesh.name = "floor";
    floor_mesh.primitives.push_back(std::move(floor));
    scene.meshes.push_back(std::move(tube_mesh));
    scene.meshes.push_back(std::move(floor_mesh));
    scene.nodes.resize(4);
    scene.nodes[0].name = "tube";
    scene.nodes[0].mesh = 0;
    scene.nodes[0].skin = 0;
    scene.nodes[1].name = "root joint";
    scene.nodes[1].children = {2};
    scene.nodes[2].name = "bend joint";
    scene.nodes[2].parent = 1;
    scene.nodes[2].translation = glm::vec3(2.0f, 0.0f, 0.0f);
    scene.nodes[2].local = glm::translate(glm::mat4(1.0f), scene.nodes[2].translation);
    scene.nodes[3].name = "floor";
    scene.nodes[3].mesh = 1;
    scene.roots = {0, 1, 3};
    Skin skin;
    skin.joints = {1, 2};
    skin.inverse_bind = {glm::mat4(1.0f), glm::translate(glm::mat4(1.0f), glm::vec3(-2.0f, 0.0f, 0.0f))};
    scene.skins.push_back(skin);
    Animation a;
    a.name = "bend";
    AnimationSampler rot;
    rot.times = {0.0f, 1.0f};
    const float s = std::sin(pi / 4.0f), c = std::cos(pi / 4.0f);
    rot.values = {0, 0, 0, 1, 0, 0, s, c};  // xyzw: identity, then 90 degrees about z
    rot.width = 4;
    AnimationSampler slide;
    slide.times = {0.0f, 1.0f};
    slide.values = {0, 0, 0, 0, 0, 1};
    a.samplers = {rot, slide};
    a.channels = {{0, 2, AnimationPath::rotation}, {1, 1, AnimationPath::translation}};
    a.end = 1.0f;
    scene.animations.push_back(a);
    scene.update_world_transforms();
    return scene;
}

struct Args {
    int width = 320, height = 240, spp = 4, repeats = 3;
    std::size_t triangles = 1000000;
    fs::path fox = fs::path(CANDELA_SOURCE_DIR) / "tests/data/models/Fox/Fox.glb";
    Backend backend = Backend::egl;
    fs::path image;  // --image: write the motion-blurred render of each scene here (name appended)
    float image_shutter = 0.0f;  // --image-shutter S: also a render with an S-second shutter to look at
};

struct Measure {
    rt::RtUpdateStats update;
    double sah = 0.0, mrays = 0.0, nodes = 0.0, prims = 0.0;
};

class Bench {
public:
    // The camera looks at the deforming mesh (node `subject`'s bounds at the frame's time), from the
    // front (+z) or the side (+x), close enough that it fills most of the image: the rays measure
    // the tree over the mesh rather than misses.
    Bench(const Args& args, Scene& scene, int animation, float frame_time, int subject, bool side)
        : args_(args), scene_(scene), animation_(animation), frame_(frame_time) {
        pose_scene(scene_, animation_, frame_);
        gpu_ = std::make_unique<GpuScene>(scene_);
        Bounds b;
        const Node& node = scene_.nodes[static_cast<std::size_t>(subject)];
        for (const Primitive& p : scene_.meshes[static_cast<std::size_t>(node.mesh)].primitives)
            for (int corner = 0; corner < 8; ++corner)
                b.extend(glm::vec3(node.world * glm::vec4(corner & 1 ? p.bounds.max.x : p.bounds.min.x, corner & 2 ? p.bounds.max.y : p.bounds.min.y,
                                                          corner & 4 ? p.bounds.max.z : p.bounds.min.z, 1.0f)));
        camera_.yfov = 0.8f;
        const float radius = 0.5f * glm::length(b.extent());
        const float distance = 0.8f * radius / std::sin(camera_.yfov * 0.5f);
        const glm::vec3 eye = b.center() + glm::normalize(side ? glm::vec3(1.0f, 0.2f, 0.0f) : glm::vec3(0.0f, 0.2f, 1.0f)) * distance;
        camera_.znear = 0.01f * distance;
        camera_.world = glm::inverse(glm::lookAt(eye, b.center(), glm::vec3(0, 1, 0)));
        rt::Options o;
        o.mode = rt::Mode::primary;
        o.spp = 1;
        tracer_ = std::make_unique<rt::RayTracer>(shaders_, scene_, *gpu_, o);
        refit_ = std::make_unique<rt::RayTracer>(shaders_, scene_, *gpu_, o);
        for (rt::RayTracer* t : {tracer_.get(), refit_.get()}) {
            t->render(camera_, args.width, args.height);  // warm-up: llvmpipe compiles at the first dispatch
            t->set_spp(args.spp);
        }
        o.traversal_stats = true;
        counter_ = std::make_unique<rt::RayTracer>(shaders_, scene_, *gpu_, o);
    }

    double pose_ms(float time) {
        const auto t0 = std::chrono::steady_clock::now();
        pose_scene(scene_, animation_, time);
        return ms_since(t0);
    }

    // Both trees built at the frame's time, then posed at `time`: one rebuilt, one refit. Their
    // renders alternate (the fastest of each kept), so a change of load on a shared machine hits
    // both alike; the traversal counts are exact.
    std::pair<Measure, Measure> at(float time) {
        pose_scene(scene_, animation_, frame_);
        tracer_->update_geometry(rt::RtUpdate::rebuild);
        refit_->update_geometry(rt::RtUpdate::rebuild);
        pose_scene(scene_, animation_, time);
        Measure rebuilt, refit;
        rebuilt.update = tracer_->update_geometry(rt::RtUpdate::rebuild);
        refit.update = refit_->update_geometry(rt::RtUpdate::refit);
        rebuilt.sah = tracer_->scene().geometry().bvh.stats.sah_cost;
        refit.sah = refit_->scene().geometry().bvh.stats.sah_cost;
        double fastest[2] = {1e30, 1e30};
        for (int r = 0; r < args_.repeats; ++r) {
            fastest[0] = std::min(fastest[0], tracer_->render(camera_, args_.width, args_.height).trace_ms);
            fastest[1] = std::min(fastest[1], refit_->render(camera_, args_.width, args_.height).trace_ms);
        }
        const double rays = static_cast<double>(args_.width) * args_.height * args_.spp;
        rebuilt.mrays = rays / (fastest[0] * 1e3);
        refit.mrays = rays / (fastest[1] * 1e3);
        for (Measure* m : {&rebuilt, &refit}) {
            pose_scene(scene_, animation_, frame_);
            counter_->update_geometry(rt::RtUpdate::rebuild);
            pose_scene(scene_, animation_, time);
            counter_->update_geometry(m == &refit ? rt::RtUpdate::refit : rt::RtUpdate::rebuild);
            const rt::Result counted = counter_->render(camera_, args_.width, args_.height);
            m->nodes = counted.nodes_per_ray;
            m->prims = counted.primitives_per_ray;
        }
        return {rebuilt, refit};
    }

    // A motion-blurred render: one slice per sample over [T - h, T + h].
    rt::Result blurred(float half_shutter, int spp, rt::Mode mode, const std::string& image) {
        rt::Options o;
        o.mode = mode;
        o.spp = spp;
        o.ao_radius = 0.1f * glm::length(scene_.world_bounds().extent());
        o.pose_at = [this, half_shutter](float u) { pose_scene(scene_, animation_, frame_ - half_shutter + 2.0f * half_shutter * u); };
        rt::RayTracer tracer(shaders_, scene_, *gpu_, o);
        const rt::Result r = tracer.render(camera_, args_.width, args_.height);
        if (!image.empty()) write_image(image, r.image);
        return r;
    }

private:
    const Args& args_;
    Scene& scene_;
    int animation_;
    float frame_;
    ShaderLibrary shaders_{fs::path(CANDELA_SOURCE_DIR) / "shaders"};
    std::unique_ptr<GpuScene> gpu_;
    Camera camera_;
    std::unique_ptr<rt::RayTracer> tracer_, refit_, counter_;
};

void print(const char* what, const Measure& m) {
    std::printf("  %-26s %s: geometry %8.1f ms, BVH %8.1f ms, pack %7.1f ms, upload %7.1f ms (total %8.1f ms); SAH %7.2f; "
                "%6.2f Mrays/s, %6.1f nodes + %5.1f prims per ray\n",
                what, m.update.refit ? "refit  " : "rebuild", m.update.geometry_ms, m.update.bvh_ms, m.update.pack_ms,
                m.update.upload_ms, m.update.total_ms(), m.sah, m.mrays, m.nodes, m.prims);
}

void run(const Args& args, const char* name, Scene& scene, int animation, float frame_time, int subject, bool side) {
    std::printf("%s: %zu triangles, animation '%s', frame at %.3f s, %dx%d, %d spp primary rays\n", name, scene.triangle_count(),
                scene.animations[static_cast<std::size_t>(animation)].name.c_str(), frame_time, args.width, args.height, args.spp);
    Bench bench(args, scene, animation, frame_time, subject, side);
    const float h = 0.5f * 0.5f / 30.0f;  // camera.shutter 0.5 at 30 fps
    double pose = 0.0;
    for (int r = 0; r < 3; ++r) pose += bench.pose_ms(frame_time + h) / 3.0;
    std::printf("  pose (evaluate_pose + apply_pose, CPU skinning): %.1f ms\n", pose);
    for (const auto& [what, time] : {std::pair<const char*, float>{"shutter end (T + 1/120 s)", frame_time + h}, {"far pose (T + 0.25 s)", frame_time + 0.25f}}) {
        const auto [rebuilt, refit] = bench.at(time);
        print(what, rebuilt);
        print(what, refit);
    }
    const int spp = 8;
    std::string image;
    if (!args.image.empty()) image = (args.image.parent_path() / (args.image.stem().string() + "_" + name + args.image.extension().string())).string();
    const rt::Result r = bench.blurred(h, spp, rt::Mode::primary, image);
    std::printf("  motion-blurred render (primary, %d spp, %d slices): %.0f ms, of which posing %.0f ms, geometry %.0f ms "
                "(%.1f ms per slice)%s%s\n",
                spp, r.shutter_slices, r.trace_ms, r.pose_ms, r.geometry_ms, (r.pose_ms + r.geometry_ms) / std::max(1, r.shutter_slices + 1),
                image.empty() ? "" : ", written to ", image.c_str());
    if (!image.empty() && args.image_shutter > 0.0f) {
        // A long shutter to look at: shading normals, 64 samples.
        const std::string looked = (args.image.parent_path() / (args.image.stem().string() + "_" + name + "_long" + args.image.extension().string())).string();
        const rt::Result l = bench.blurred(0.5f * args.image_shutter, 64, rt::Mode::primary, looked);
        std::printf("  long shutter (%.3f s, primary, 64 spp): %.0f ms, written to %s\n", args.image_shutter, l.trace_ms, looked.c_str());
    }
}

}  // namespace
}  // namespace candela

int main(int argc, char** argv) {
    using namespace candela;
    Args args;
    for (int i = 1; i < argc; ++i) {
        const std::string a = argv[i];
        const char* next = i + 1 < argc ? argv[i + 1] : "";
        if (a == "--size" && std::sscanf(next, "%dx%d", &args.width, &args.height) == 2) ++i;
        else if (a == "--spp") args.spp = std::atoi(next), ++i;
        else if (a == "--repeats") args.repeats = std::atoi(next), ++i;
        else if (a == "--triangles") args.triangles = static_cast<std::size_t>(std::atof(next)), ++i;
        else if (a == "--fox") args.fox = next, ++i;
        else if (a == "--image") args.image = next, ++i;
        else if (a == "--image-shutter") args.image_shutter = static_cast<float>(std::atof(next)), ++i;
        else if (a == "--backend") args.backend = std::strcmp(next, "osmesa") == 0 ? Backend::osmesa : Backend::egl, ++i;
        else {
            std::fprintf(stderr, "usage: bench_rt_motion [--size WxH] [--spp N] [--repeats N] [--triangles N] [--fox PATH] [--image out.png [--image-shutter S]] [--backend egl|osmesa]\n");
            return 2;
        }
    }
    ContextResult context = create_context(args.backend);
    if (!context.context) {
        std::fprintf(stderr, "no GL context: %s\n", context.error.c_str());
        return 1;
    }
    {
        Scene fox = load_gltf(args.fox);
        int subject = 0;
        while (fox.nodes[static_cast<std::size_t>(subject)].mesh < 0) ++subject;
        run(args, "fox", fox, find_animation(fox, "Walk"), 0.5f, subject, true);
    }
    if (args.triangles > 0) {
        Scene tube = skinned_tube(args.triangles);
        run(args, "tube", tube, 0, 0.5f, 0, false);
    }
    return 0;
}
