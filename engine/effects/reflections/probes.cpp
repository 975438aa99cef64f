#include "effects/reflections/probes.hpp"

#include <algorithm>
#include <cmath>
#include <cstdio>
#include <limits>
#include <map>
#include <set>

#include "effects/reflections/reflections.hpp"

namespace candela {

bool is_reflective(const Material& m, float max_roughness) {
    return (m.metallic > 0.5f && m.roughness < max_roughness) || m.transmission > 0.0f;
}

namespace {

// How much a reflective material shows its probe: transmission, or for smooth metal how far
// below the roughness cut-off it is (a mirror 1, a metal at the cut-off nearly 0).
float reflectance(const Material& m, float max_roughness) {
    float r = m.transmission;
    if (m.metallic > 0.5f && m.roughness < max_roughness) r = std::max(r, 1.0f - m.roughness / std::max(max_roughness, 1e-3f));
    return std::clamp(r, 0.05f, 1.0f);
}

// Distance from p to the nearest surface of box b: outside, the distance to the box; inside,
// to its nearest face (a room around the probe is as far as its walls).
float distance_to_surface(const glm::vec3& p, const Bounds& b) {
    const glm::vec3 outside = glm::max(glm::max(b.min - p, p - b.max), glm::vec3(0.0f));
    const float d = glm::length(outside);
    if (d > 0.0f) return d;
    const glm::vec3 in = glm::min(p - b.min, b.max - p);
    return std::min(in.x, std::min(in.y, in.z));
}

struct Group {
    std::vector<int> objects;  // indices into ProbePlan::objects
    Bounds bounds;
    float weight = 0.0f;
    bool alive = true;
};

}  // namespace

ProbeInputs probe_inputs(const Scene& scene, float max_roughness) {
    ProbeInputs in;
    std::map<int, size_t> object_of_node;
    // Every node reachable from the roots that has a mesh, as GpuScene draws them.
    std::vector<int> stack(scene.roots.begin(), scene.roots.end());
    std::set<int> seen;
    while (!stack.empty()) {
        const int ni = stack.back();
        stack.pop_back();
        if (ni < 0 || static_cast<size_t>(ni) >= scene.nodes.size() || !seen.insert(ni).second) continue;
        const Node& node = scene.nodes[static_cast<size_t>(ni)];
        stack.insert(stack.end(), node.children.begin(), node.children.end());
        if (node.mesh < 0) continue;
        for (const Primitive& p : scene.meshes[static_cast<size_t>(node.mesh)].primitives) {
            if (p.indices.empty() || p.bounds.empty()) continue;
            Bounds wb;
            for (int corner = 0; corner < 8; ++corner)
                wb.extend(glm::vec3(node.world * glm::vec4(corner & 1 ? p.bounds.max.x : p.bounds.min.x,
                                                           corner & 2 ? p.bounds.max.y : p.bounds.min.y,
                                                           corner & 4 ? p.bounds.max.z : p.bounds.min.z, 1.0f)));
            in.geometry.emplace_back(ni, wb);
            const Material& m = scene.material(p.material);
            if (m.alpha_mode == AlphaMode::blend || !is_reflective(m, max_roughness)) continue;
            auto [it, added] = object_of_node.emplace(ni, in.objects.size());
            if (added) {
                ProbeObject o;
                o.node = ni;
                o.name = node.name.empty() ? "node " + std::to_string(ni) : node.name;
                in.objects.push_back(o);
            }
            ProbeObject& o = in.objects[it->second];
            o.bounds.extend(wb);
            o.reflectance = std::max(o.reflectance, reflectance(m, max_roughness));
        }
    }
    // Node order, as the draws had it before: the plan does not depend on traversal order.
    std::sort(in.objects.begin(), in.objects.end(), [](const ProbeObject& a, const ProbeObject& b) { return a.node < b.node; });
    for (ProbeObject& o : in.objects) o.weight = (o.coverage + 1e-3f) * o.reflectance;
    return in;
}

float screen_coverage(const Bounds& b, const glm::mat4& view_proj) {
    if (b.empty()) return 0.0f;
    glm::vec2 lo(1.0f), hi(-1.0f);
    int in_front = 0;
    for (int corner = 0; corner < 8; ++corner) {
        const glm::vec4 c = view_proj * glm::vec4(corner & 1 ? b.max.x : b.min.x, corner & 2 ? b.max.y : b.min.y,
                                                  corner & 4 ? b.max.z : b.min.z, 1.0f);
        if (c.w <= 1e-6f) continue;
        ++in_front;
        const glm::vec2 ndc = glm::vec2(c) / c.w;
        lo = glm::min(lo, ndc);
        hi = glm::max(hi, ndc);
    }
    if (in_front == 0) return 0.0f;
    // Corners behind the camera: the box reaches past the image's edges towards them.
    if (in_front < 8) lo = glm::vec2(-1.0f), hi = glm::vec2(1.0f);
    lo = glm::clamp(lo, glm::vec2(-1.0f), glm::vec2(1.0f));
    hi = glm::clamp(hi, glm::vec2(-1.0f), glm::vec2(1.0f));
    const glm::vec2 size = glm::max(hi - lo, glm::vec2(0.0f));
    return size.x * size.y / 4.0f;
}

ProbePlan plan_probes(const ProbeInputs& inputs, const ProbePlanOptions& options) {
    ProbePlan plan;
    plan.objects = inputs.objects;
    const size_t n = plan.objects.size();
    std::vector<Group> groups(n);
    for (size_t i = 0; i < n; ++i) {
        groups[i].objects = {static_cast<int>(i)};
        groups[i].bounds = plan.objects[i].bounds;
        groups[i].weight = plan.objects[i].weight;
    }
    // The parallax error of one probe for the union of groups a and b (b < 0: a alone).
    auto error_of = [&](int a, int b) {
        Bounds u = groups[static_cast<size_t>(a)].bounds;
        std::set<int> members;
        for (int g : {a, b}) {
            if (g < 0) continue;
            u.extend(groups[static_cast<size_t>(g)].bounds);
            for (int o : groups[static_cast<size_t>(g)].objects) members.insert(plan.objects[static_cast<size_t>(o)].node);
        }
        const glm::vec3 c = u.center();
        float clearance = std::numeric_limits<float>::max();
        for (const auto& [node, box] : inputs.geometry)
            if (!members.count(node)) clearance = std::min(clearance, distance_to_surface(c, box));
        float offset = 0.0f;
        for (int g : {a, b}) {
            if (g < 0) continue;
            for (int o : groups[static_cast<size_t>(g)].objects)
                offset = std::max(offset, glm::length(plan.objects[static_cast<size_t>(o)].bounds.center() - c));
        }
        if (offset <= 0.0f) return 0.0f;
        return clearance <= 1e-6f ? std::numeric_limits<float>::max() : offset / clearance;
    };
    // Pair errors, kept up to date as groups merge (only the merged group's row changes).
    std::vector<std::vector<float>> err(n, std::vector<float>(n, 0.0f));
    for (size_t i = 0; i < n; ++i)
        for (size_t j = i + 1; j < n; ++j) err[i][j] = err[j][i] = error_of(static_cast<int>(i), static_cast<int>(j));
    size_t alive = n;
    const size_t budget = static_cast<size_t>(std::max(options.budget, 1));
    for (;;) {
        // The cheapest merge: by error while it is below the threshold, else (over budget) by
        // error x weight, so that what shows least on screen gives up its own probe first.
        const bool over = alive > budget;
        float best = std::numeric_limits<float>::max();
        int ba = -1, bb = -1;
        bool free_merge = false;
        for (size_t i = 0; i < n; ++i) {
            if (!groups[i].alive) continue;
            for (size_t j = i + 1; j < n; ++j) {
                if (!groups[j].alive) continue;
                const float e = err[i][j];
                if (e < options.merge_error) {
                    // Free merges first, the smallest error of them.
                    if (!free_merge || e < best) best = e, ba = static_cast<int>(i), bb = static_cast<int>(j), free_merge = true;
                } else if (!free_merge && over) {
                    const float cost = std::min(e, 1e6f) * (groups[i].weight + groups[j].weight);
                    if (cost < best) best = cost, ba = static_cast<int>(i), bb = static_cast<int>(j);
                }
            }
        }
        if (ba < 0) break;
        Group& a = groups[static_cast<size_t>(ba)];
        Group& b = groups[static_cast<size_t>(bb)];
        a.objects.insert(a.objects.end(), b.objects.begin(), b.objects.end());
        a.bounds.extend(b.bounds);
        a.weight += b.weight;
        b.alive = false;
        b.objects.clear();
        --alive;
        (free_merge ? plan.merged_freely : plan.merged_for_budget) += 1;
        for (size_t j = 0; j < n; ++j)
            if (groups[j].alive && j != static_cast<size_t>(ba)) err[static_cast<size_t>(ba)][j] = err[j][static_cast<size_t>(ba)] = error_of(ba, static_cast<int>(j));
    }
    std::vector<size_t> order;
    for (size_t i = 0; i < n; ++i)
        if (groups[i].alive) order.push_back(i);
    std::stable_sort(order.begin(), order.end(), [&](size_t x, size_t y) { return groups[x].weight > groups[y].weight; });
    plan.object_probe.assign(n, -1);
    for (size_t k = 0; k < order.size(); ++k) {
        const Group& g = groups[order[k]];
        ProbePlacement p;
        const ProbeObject& first = plan.objects[static_cast<size_t>(g.objects.front())];
        p.origin = "auto: '" + first.name + "'" + (g.objects.size() > 1 ? " + " + std::to_string(g.objects.size() - 1) + " more" : "");
        p.position = g.bounds.center();
        // The bounding sphere of its objects, slightly enlarged so that every surface point is covered.
        p.radius = 0.5f * glm::length(g.bounds.extent()) * 1.01f + 1e-4f;
        p.weight = g.weight;
        for (int o : g.objects) {
            p.nodes.push_back(plan.objects[static_cast<size_t>(o)].node);
            plan.object_probe[static_cast<size_t>(o)] = static_cast<int>(k);
        }
        plan.probes.push_back(std::move(p));
    }
    char line[256];
    std::snprintf(line, sizeof line, "%zu reflective object%s -> %zu probe%s (probe.budget %d; %d shared within probe.merge %.2g, %d more for the budget)",
                  n, n == 1 ? "" : "s", plan.probes.size(), plan.probes.size() == 1 ? "" : "s", options.budget, plan.merged_freely,
                  static_cast<double>(options.merge_error), plan.merged_for_budget);
    plan.summary = line;
    return plan;
}

std::vector<ProbePlacement> place_probes(const Scene& scene, const std::vector<GpuScene::Draw>& draws,
                                         const ReflectionsOptions& options, const glm::mat4* view_proj, std::string* summary) {
    std::vector<ProbePlacement> out;
    if (options.placement == ProbePlacementMode::scene) {
        for (const Node& node : scene.nodes) {
            if (!node.reflection_probe) continue;
            const ReflectionProbe& rp = *node.reflection_probe;
            ProbePlacement p;
            p.origin = "node '" + node.name + "'";
            p.position = glm::vec3(node.world * glm::vec4(rp.position, 1.0f));
            if (rp.has_extent) {
                const glm::vec3 c = glm::vec3(node.world * glm::vec4(rp.center, 1.0f));
                p.has_box = true;
                p.box_min = c - rp.extent;
                p.box_max = c + rp.extent;
            } else {
                // No box: it covers the whole scene (as the nearest probe).
                p.radius = 3.0e38f;
            }
            out.push_back(p);
        }
        if (summary && !out.empty()) *summary = std::to_string(out.size()) + " probe(s) declared by extras.reflection_probe nodes";
    }
    if (out.empty()) {
        ProbeInputs in = probe_inputs(scene, options.max_roughness);
        if (view_proj)
            for (ProbeObject& o : in.objects) {
                o.coverage = screen_coverage(o.bounds, *view_proj);
                o.weight = (o.coverage + 1e-3f) * o.reflectance;
            }
        ProbePlan plan = plan_probes(in, {options.probe_budget, options.probe_merge});
        for (ProbePlacement& p : plan.probes) p.reflective_only = options.max_roughness;
        out = std::move(plan.probes);
        if (summary) *summary = plan.summary;
    }
    // A probe does not capture the objects it serves, nor a reflective object it sits in: seen
    // from its probe an object would reflect or refract itself (a glass sphere sharing a probe
    // with its neighbour showed its own outside instead of what lies behind it), and from inside
    // an object would hide everything. Other geometry around the probe stays, even where its
    // bounds hold the probe: a room, a curved backdrop or a floor is what the probe is for.
    // (Objects that share a probe do not see each other in it: the lesser error.)
    for (ProbePlacement& p : out)
        for (size_t i = 0; i < draws.size(); ++i) {
            const bool served = std::find(p.nodes.begin(), p.nodes.end(), draws[i].node) != p.nodes.end();
            const int mi = draws[i].primitive_material;
            const bool reflective =
                mi >= 0 && mi < static_cast<int>(scene.materials.size()) && is_reflective(scene.materials[static_cast<size_t>(mi)], options.max_roughness);
            const Bounds& b = draws[i].world_bounds;
            const glm::vec3 eps(1e-5f * (1.0f + glm::length(b.extent())));
            const bool around = glm::all(glm::greaterThanEqual(p.position, b.min - eps)) && glm::all(glm::lessThanEqual(p.position, b.max + eps));
            if (served || (reflective && around)) p.excluded_draws.push_back(static_cast<int>(i));
        }
    return out;
}

ProbeData to_gpu(const ProbePlacement& p) {
    ProbeData d{};
    d.position = p.position;
    d.radius = p.radius;
    d.box_min = p.box_min;
    d.has_box = p.has_box ? 1.0f : 0.0f;
    d.box_max = p.box_max;
    d.reflective_only = p.reflective_only;
    return d;
}

}  // namespace candela
