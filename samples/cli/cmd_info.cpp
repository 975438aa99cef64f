// `candela info`: what a scene holds and what the renderer would do with it (`--knobs`: every knob).
#include "commands.hpp"

#include <cstdio>
#include <memory>
#include <optional>
#include <string>

#include "core/error.hpp"
#include "options.hpp"
#include "budget.hpp"
#include "render/effect_registry.hpp"
#include "platform/context.hpp"
#include "render/features.hpp"
#include "render/gpu_scene.hpp"
#include "shader/shader_library.hpp"
#include "render/settings.hpp"
#include "rt/view_light.hpp"
#include "rt/view_lighting.hpp"
#include "render/light_reach.hpp"

namespace candela::cli {

int cmd_info(const Args& args) {
    const Parsed p = parse(args, {"--effects", "--set", "--path", "--lighting", "--environment", "--camera", "--shader-dir", "--size", "--variant",
                                  "--error-budget", "--budget-model"},
                           {"--strict", "--knobs"});
    if (p.flags.count("--knobs")) {
        for (const KnobInfo& k : knob_infos())
            std::printf("%-28s %-6s %-22s %s\n", k.name.c_str(), k.type.c_str(), k.range.c_str(), k.help.c_str());
        return 0;
    }
    if (p.positional.size() != 1) throw bad_input("info needs exactly one SCENE");
    const std::optional<BudgetRequest> budget_req = budget_request(p);
    RenderSettings settings;
    if (p.has("--effects")) apply_effects(settings, p.get("--effects"));
    if (p.has("--path")) apply_knob(settings, "render.path=" + p.get("--path"));
    apply_knobs(settings, p.all("--set"));
    Scene scene = load_scene(p.positional[0], p.flags.count("--strict") > 0);
    if (p.has("--variant")) select_variant(scene, find_variant(scene, p.get("--variant")));
    const std::string camera_choice = p.has("--camera") ? p.get("--camera") : "";
    // The render's size (its aspect frames the camera the planner measures from): as render's.
    int width = 512, height = 512;
    if (p.has("--size")) parse_size(p.get("--size"), width, height);
    const float aspect = static_cast<float>(width) / static_cast<float>(height);
    anchor_scene(scene, camera_choice, aspect, -1, 0.0f);
    LightingChoice lighting = setup_lighting(scene, p, camera_choice, aspect);
    // The tracer measures the view (whether the file's lights light it; the effects' view
    // estimates) and some effects plan with the device (Effect::plans_with_device): a headless
    // context when one can be had (without one, `info` says what is missing).
    ContextResult ctx;
    if (lighting.check_view || planning_needs_gl(settings) || budget_req)
        ctx = create_context(Backend::auto_select);
    std::optional<ShaderLibrary> shaders;
    if (ctx.context) shaders.emplace(shader_dir_option(p));
    // The view measurements share one tracer geometry: the BVH of a million triangles is most of
    // their time.
    std::shared_ptr<rt::RtScene> tracer_scene;
    if (lighting.check_view && shaders)
        complete_lighting(scene, lighting, *shaders, scene.select_camera(camera_choice, aspect), aspect, &tracer_scene);
    int directional = 0, point = 0, spot = 0;
    for (const auto& pl : scene.placed_lights()) {
        directional += pl.light->type == LightType::directional;
        point += pl.light->type == LightType::point;
        spot += pl.light->type == LightType::spot;
    }
    int valid_images = 0;
    for (const Image& img : scene.images) valid_images += img.valid && img.name != "fallback";
    const Bounds b = scene.world_bounds();
    std::printf("scene: %s\n", scene.source.string().c_str());
    std::printf("nodes: %zu  meshes: %zu  triangles: %zu  materials: %zu  textures: %d (%d missing)\n",
                scene.nodes.size(), scene.meshes.size(), scene.triangle_count(), scene.materials.size(), valid_images,
                scene.sanitized.missing_textures);
    std::printf("lights: %d directional, %d point, %d spot\n", directional, point, spot);
    if (!scene.ignored.empty()) {
        std::string list;
        for (const std::string& what : scene.ignored) list += (list.empty() ? "" : "; ") + what;
        std::printf("ignored (not implemented): %s\n", list.c_str());
    }
    if (b.empty()) std::printf("bounds: empty\n");
    else
        std::printf("bounds: min (%.4g, %.4g, %.4g)  max (%.4g, %.4g, %.4g)\n", b.min.x, b.min.y, b.min.z, b.max.x,
                    b.max.y, b.max.z);
    if (scene.origin != glm::dvec3(0.0))
        std::printf("origin: (%.17g, %.17g, %.17g): far from the file's origin, the scene is rendered relative to this "
                    "point (its bounds above are relative to it)\n", scene.origin.x, scene.origin.y, scene.origin.z);
    // Animation: what posing changes, and each animation with its duration.
    {
        size_t skinned = 0, morphed = 0;
        for (const Mesh& m : scene.meshes)
            for (const Primitive& prim : m.primitives) skinned += prim.skinned(), morphed += !prim.targets.empty();
        std::printf("animations: %zu  skins: %zu  skinned primitives: %zu  morphed primitives: %zu\n", scene.animations.size(),
                    scene.skins.size(), skinned, morphed);
        for (size_t i = 0; i < scene.animations.size(); ++i) {
            const Animation& a = scene.animations[i];
            std::printf("  [%zu] '%s' %.3f s (keyframes %.3f to %.3f s), %zu channels\n", i, a.name.c_str(), a.end, a.start, a.end,
                        a.channels.size());
        }
    }
    if (!scene.variants.empty()) {
        std::printf("material variants: %zu (KHR_materials_variants; selected: %s)\n", scene.variants.size(),
                    scene.active_variant < 0 ? "default" : ("[" + std::to_string(scene.active_variant) + "]").c_str());
        for (size_t i = 0; i < scene.variants.size(); ++i) {
            const int n = variant_changes(scene, static_cast<int>(i));
            std::printf("  [%zu] '%s' changes %d primitive%s\n", i, scene.variants[i].c_str(), n, n == 1 ? "" : "s");
        }
    }
    std::printf("cameras: %zu\n", scene.cameras.size());
    for (size_t i = 0; i < scene.cameras.size(); ++i) {
        const Camera& c = scene.cameras[i];
        const glm::vec3 pos(c.world[3]);
        std::printf("  [%zu] '%s' %s at (%.3g, %.3g, %.3g)\n", i, c.name.c_str(),
                    c.orthographic ? "orthographic" : (std::string("perspective yfov ") + format_number("%.3g", c.yfov)).c_str(),
                    pos.x, pos.y, pos.z);
    }
    {
        const Camera auto_cam = framing_camera(b);
        const glm::vec3 pos(auto_cam.world[3]);
        std::printf("  [auto] framing camera from the bounds, perspective yfov %.3g at (%.3g, %.3g, %.3g)%s\n", auto_cam.yfov,
                    pos.x, pos.y, pos.z, scene.cameras.empty() ? " (the default: the file has no camera)" : "");
    }
    std::printf("lighting: %s\n", lighting.reason.c_str());
    std::printf("environment: %s\n", scene.environment.image ? scene.environment.label.c_str()
                                     : !scene.environment.map.empty() ? scene.environment.map.string().c_str()
                                     : scene.environment.present()
                                         ? ("constant (" + format_number("%.3g", scene.environment.radiance.r) + ", " +
                                            format_number("%.3g", scene.environment.radiance.g) + ", " +
                                            format_number("%.3g", scene.environment.radiance.b) + ")").c_str()
                                         : "none");
    if (lighting.check_view) std::printf("lighting check: none (no usable OpenGL: %s)\n", ctx.error.c_str());
    // --error-budget: the candidates' predictions and the choice; what follows plans the chosen settings.
    if (budget_req && shaders) {
        std::string text;
        const budget::Choice choice = choose_for_scene(*budget_req, scene, *shaders, camera_choice, width, height, true, text);
        std::printf("%s", text.c_str());
        settings = budget_settings(choice, p);
        if (choice.trace) std::printf("error budget: the plan below is that of the most accurate raster candidate (render traces the frame)\n");
    } else if (budget_req) {
        std::printf("error budget: no choice (no usable OpenGL: %s; the statistics need the tracer)\n", ctx.error.c_str());
    }
    ViewEstimates estimates;
    // ... and one upload of the scene (after the lighting check, which may add a sky).
    std::optional<GpuScene> measured;
    auto measured_gpu = [&]() -> GpuScene& {
        if (!measured) measured.emplace(scene);
        return *measured;
    };
    for (const Effect* e : effects_needing_view_estimate(settings)) {
        if (shaders) {
            const Camera camera = scene.select_camera(camera_choice, aspect);
            const ViewEstimate& v = estimates[e->name()] = e->estimate_view({*shaders, scene, measured_gpu(), camera, aspect, &tracer_scene});
            std::printf("%s: %s\n", e->view_estimate(settings), v.text.c_str());
        } else {
            std::printf("%s: none (no usable OpenGL: %s)\n", e->view_estimate(settings), ctx.error.c_str());
        }
    }
    // Caustics: what no raster effect carries, measured where glass or a mirror could pass one.
    // 16 samples (4 batches of 4): info reports the share with its standard error, which stays
    // far below the share on the shared models (TransmissionTest: 4.2 % +- 0.1 %; 4.4 % +- 0.0 %
    // at 32), for about 0.45 s less of info's time there (the caustics took half of it).
    if (shaders && can_have_caustics(scene)) {
        try {
            const Caustics c = measure_caustics(*shaders, scene, measured_gpu(), scene.select_camera(camera_choice, aspect), aspect,
                                                16, kViewLightPixels, &tracer_scene);
            std::printf("caustics: %s\n", c.text().c_str());
        } catch (const Error& error) {
            if (error.code() == ExitCode::internal) throw;
            std::printf("caustics: not measured (%s)\n", error.what());
        }
    }
    const Camera view_camera = scene.select_camera(camera_choice, aspect);  // its lens plans depth of field
    const Features features = analyze(scene, settings, &estimates, &view_camera);
    std::printf("scene features:\n");
    for (const Feature* feat : features.scene.all())
        std::printf("  %-22s %-4s %s\n", (feat->name + ":").c_str(), feat->needed ? "yes" : "no", feat->reason.c_str());
    // Under "effects" exactly the names --effects switches; the others are planned by the scene
    // (emitters are lights) or by their own knobs (Effect::switchable).
    for (const bool switchable : {true, false}) {
        std::printf(switchable ? "effects (--effects):\n" : "planned by the scene or their knobs (not in --effects):\n");
        for (const EffectDecision* d : features.effects()) {
            const Effect* e = find_effect(d->name);
            if ((e && e->switchable()) == switchable) std::printf("  %-22s %s\n", (d->name + ":").c_str(), d->reason.c_str());
        }
    }
    // The shadow budget, as the renderer's light buffer shares it for this view.
    if (shaders && features.decision("shadows").planned) {
        const LightSetup& ls = features.lights;
        const glm::vec3 viewer(view_camera.world[3]);
        GpuScene& gpu = measured_gpu();
        gpu.update_lights(ls.area_samples, ls.split_emitters, ls.shadows, ls.cascades, ls.max_shadowed, ls.cutoff, ls.shadow_resolution,
                          ls.shadow_budget_mb, &viewer);
        std::printf("shadow budget: %s\n", gpu.shadow_atlas().text(ls.shadow_budget_mb).c_str());
    }
    // The point and spot lights' reach, and what it culls per tile at this view and size.
    if (features.punctual_lights > 0) {
        const glm::mat4 vp = projection_matrix(view_camera, aspect) * glm::inverse(view_camera.world);
        std::printf("light reach: %s\n", light_reach(scene, features.lights.cutoff, vp, width, height).text().c_str());
    }
    std::printf("planned passes:\n");
    for (const PlannedPass& pass : plan_passes(features, settings))
        std::printf("  %-22s %s\n", pass.name.c_str(), pass.why.c_str());
    // What each planned effect adds about its plan for this view (e.g. where its probes go).
    const glm::mat4 view_proj = projection_matrix(view_camera, aspect) * glm::inverse(view_camera.world);
    for (const EffectDecision* d : features.effects())
        if (const Effect* e = find_effect(d->name); e && d->planned)
            for (const std::string& line : e->info_lines(scene, settings, view_proj)) std::printf("%s\n", line.c_str());
    return 0;
}

}  // namespace candela::cli
