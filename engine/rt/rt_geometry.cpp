#include "rt/rt_geometry.hpp"

#include <glm/gtc/matrix_inverse.hpp>

#include <algorithm>
#include <bit>
#include <cmath>
#include <cstring>
#include <limits>
#include <stdexcept>
#include <string>
#include <utility>

namespace candela::rt {
namespace {

int as_int_bits(float f) {
    int i;
    std::memcpy(&i, &f, 4);
    return i;
}
float from_int_bits(int i) {
    float f;
    std::memcpy(&f, &i, 4);
    return f;
}
float luminance(const glm::vec3& c) { return 0.2126f * c.r + 0.7152f * c.g + 0.0722f * c.b; }

}  // namespace

std::vector<Aabb> primitive_boxes(const RtGeometry& g) {
    std::vector<Aabb> boxes;
    boxes.reserve(g.triangles.size() + g.spheres.size());
    for (const TriangleGpu& t : g.triangles) {
        Aabb b;
        b.extend(glm::vec3(t.p0));
        b.extend(glm::vec3(t.p1));
        b.extend(glm::vec3(t.p2));
        boxes.push_back(b);
    }
    for (const SphereGpu& s : g.spheres) {
        Aabb b;
        b.extend(s.center - glm::vec3(s.radius));
        b.extend(s.center + glm::vec3(s.radius));
        boxes.push_back(b);
    }
    return boxes;
}

namespace {
// The scene's triangles in world space as Scene::world_triangles() gives them (the same order and
// the same arithmetic, so the same bits: test_rt_motion.cpp compares), written straight into the
// tracer's layout, each vertex transformed once per node that draws it instead of once per
// triangle corner, without world_triangles()'s intermediate copy (posed scenes redo this per time
// slice). Nodes marked extras.sphere are left out: they are traced as the exact sphere.
void append_world_triangles(const Scene& scene, int default_material, std::vector<TriangleGpu>& out,
                            std::vector<glm::vec4>* colors) {
    out.reserve(scene.triangle_count());
    struct Transformed {
        glm::vec3 p, n;
        glm::vec4 t;
    };
    std::vector<Transformed> xf;
    std::vector<int> stack(scene.roots.begin(), scene.roots.end());  // only nodes reachable from the roots are drawn
    while (!stack.empty()) {
        const int node_index = stack.back();
        stack.pop_back();
        const Node& node = scene.nodes[static_cast<size_t>(node_index)];
        stack.insert(stack.end(), node.children.begin(), node.children.end());
        if (node.mesh < 0 || node.sphere_radius) continue;
        const glm::mat3 normal_matrix = glm::inverseTranspose(glm::mat3(node.world));
        const bool flip = node.mirrored();
        const float handedness = flip ? -1.0f : 1.0f;
        for (const Primitive& prim : scene.meshes[static_cast<size_t>(node.mesh)].primitives) {
            xf.resize(prim.vertices.size());
            for (size_t i = 0; i < prim.vertices.size(); ++i) {
                const Vertex& v = prim.vertices[i];
                Transformed& x = xf[i];
                x.p = glm::vec3(node.world * glm::vec4(v.position, 1.0f));
                const glm::vec3 n = normal_matrix * v.normal;
                const float len = glm::length(n);
                x.n = len > 0.0f ? n / len : glm::vec3(0, 0, 1);
                const glm::vec3 t = glm::mat3(node.world) * glm::vec3(v.tangent);
                const float tl = glm::length(t);
                x.t = glm::vec4(tl > 0.0f ? t / tl : glm::vec3(1, 0, 0), (v.tangent.w < 0.0f ? -1.0f : 1.0f) * handedness);
            }
            const float material = from_int_bits(prim.material >= 0 ? prim.material : default_material);
            // Seeing rays pass the back of a single-sided opaque triangle (back-face culling, as
            // the rasterizer draws it); transmissive ones are seen from inside (scene.glsl).
            const Material& mat = scene.material(prim.material);
            const float cull_back = !mat.double_sided && mat.transmission <= 0.0f ? 1.0f : 0.0f;
            const float node_bits = from_int_bits(node_index);
            for (size_t t = 0; t + 2 < prim.indices.size(); t += 3) {
                // Corners 0, 2, 1 under a mirroring transform: counter-clockwise from the front.
                const std::uint32_t i0 = prim.indices[t], i1 = prim.indices[t + (flip ? 2 : 1)], i2 = prim.indices[t + (flip ? 1 : 2)];
                const Transformed &a = xf[i0], &b = xf[i1], &c = xf[i2];
                const Vertex &va = prim.vertices[i0], &vb = prim.vertices[i1], &vc = prim.vertices[i2];
                TriangleGpu tri{};
                tri.p0 = glm::vec4(a.p, material);
                tri.p1 = glm::vec4(b.p, node_bits);
                tri.p2 = glm::vec4(c.p, cull_back);
                tri.n0 = glm::vec4(a.n, 0.0f);
                tri.n1 = glm::vec4(b.n, 0.0f);
                tri.n2 = glm::vec4(c.n, 0.0f);
                tri.uv_a = glm::vec4(va.uv0, vb.uv0);
                tri.uv_b = glm::vec4(vc.uv0, va.uv1);
                tri.uv_c = glm::vec4(vb.uv1, vc.uv1);
                tri.t0 = a.t;
                tri.t1 = b.t;
                tri.t2 = c.t;
                out.push_back(tri);
                if (colors) colors->insert(colors->end(), {va.color, vb.color, vc.color});
            }
        }
    }
}

// What append_world_triangles and the sphere loop below would produce, counted without building.
std::size_t count_triangles(const Scene& scene) {
    std::size_t count = 0;
    std::vector<int> stack(scene.roots.begin(), scene.roots.end());
    while (!stack.empty()) {
        const Node& node = scene.nodes[static_cast<size_t>(stack.back())];
        stack.pop_back();
        stack.insert(stack.end(), node.children.begin(), node.children.end());
        if (node.mesh < 0 || node.sphere_radius) continue;
        for (const Primitive& prim : scene.meshes[static_cast<size_t>(node.mesh)].primitives) count += prim.indices.size() / 3;
    }
    return count;
}
std::size_t count_spheres(const Scene& scene) {
    return static_cast<std::size_t>(
        std::count_if(scene.nodes.begin(), scene.nodes.end(), [](const Node& n) { return n.sphere_radius && n.mesh >= 0; }));
}

// Everything but the BVH. `recycled`: a previous geometry whose vectors' storage is reused (a
// posed scene rebuilds this per time slice; fresh allocations of this size cost page faults).
RtGeometry build_primitives(const Scene& scene, int default_material, RtGeometry&& recycled = {}) {
    RtGeometry g;
    g.triangles = std::move(recycled.triangles);
    g.spheres = std::move(recycled.spheres);
    g.emitters = std::move(recycled.emitters);
    g.surfaces = std::move(recycled.surfaces);
    g.triangles.clear();
    g.spheres.clear();
    g.emitters.clear();
    g.surfaces.clear();
    // Vertex colours only when one is not white: most scenes have none, and the tracer then
    // compiles without them.
    g.colors = std::move(recycled.colors);
    g.colors.clear();
    g.has_vertex_colors = false;
    for (const Mesh& mesh : scene.meshes)
        for (const Primitive& prim : mesh.primitives)
            for (const Vertex& v : prim.vertices)
                if (v.color != glm::vec4(1.0f)) {
                    g.has_vertex_colors = true;
                    break;
                }
    append_world_triangles(scene, default_material, g.triangles, g.has_vertex_colors ? &g.colors : nullptr);
    for (size_t i = 0; i < scene.nodes.size(); ++i) {
        const Node& node = scene.nodes[i];
        if (!node.sphere_radius || node.mesh < 0) continue;
        // The radius is in world units for an unscaled node; a scaled node scales it by its
        // largest axis scale (non-uniform scale is not a sphere any more).
        const float scale = std::max({glm::length(glm::vec3(node.world[0])), glm::length(glm::vec3(node.world[1])),
                                      glm::length(glm::vec3(node.world[2]))});
        int material = default_material;
        const Mesh& mesh = scene.meshes[static_cast<size_t>(node.mesh)];
        if (!mesh.primitives.empty() && mesh.primitives[0].material >= 0) material = mesh.primitives[0].material;
        SphereGpu sp{};
        sp.center = glm::vec3(node.world[3]);
        sp.radius = *node.sphere_radius * scale;
        sp.material = material;
        sp.node = static_cast<int>(i);
        g.spheres.push_back(sp);
    }
    // Emitters by power.
    std::vector<float> power;
    for (size_t i = 0; i < g.triangles.size(); ++i) {
        const TriangleGpu& t = g.triangles[i];
        const int mat = as_int_bits(t.p0.w);
        const Material& m = scene.material(mat < static_cast<int>(scene.materials.size()) ? mat : -1);
        const glm::vec3 e = m.emission();
        const float area = 0.5f * glm::length(glm::cross(glm::vec3(t.p1 - t.p0), glm::vec3(t.p2 - t.p0)));
        if (luminance(e) <= 0.0f || !(area > 0.0f) || !std::isfinite(area)) continue;
        g.emitters.push_back({static_cast<std::uint32_t>(i), 0.0f, 0.0f, area});
        power.push_back(luminance(e) * area * (m.double_sided ? 2.0f : 1.0f));
    }
    // Emissive spheres (untextured emission) too, sampled by the cone they subtend: their
    // `triangle` is triangles.size() + sphere index, their pdf is also kept in emitter_pdf.
    for (size_t i = 0; i < g.spheres.size(); ++i) {
        const SphereGpu& sp = g.spheres[i];
        const int mat = sp.material;
        const Material& m = scene.material(mat < static_cast<int>(scene.materials.size()) ? mat : -1);
        const float r = sp.radius;
        const float area = 4.0f * 3.14159265f * r * r;
        if (luminance(m.emission()) <= 0.0f || m.emissive_texture.present() || !(area > 0.0f) || !std::isfinite(area)) continue;
        g.emitters.push_back({static_cast<std::uint32_t>(g.triangles.size() + i), 0.0f, 0.0f, area});
        power.push_back(luminance(m.emission()) * area);
    }
    double total = 0.0;
    for (float p : power) total += p;
    g.emitted_power = total;
    double running = 0.0;
    for (size_t i = 0; i < g.emitters.size(); ++i) {
        running += power[i];
        g.emitters[i].pdf = static_cast<float>(power[i] / total);
        g.emitters[i].cdf = static_cast<float>(running / total);
        const std::uint32_t t = g.emitters[i].triangle;
        if (t < g.triangles.size()) g.triangles[t].n0.w = g.emitters[i].pdf;
        else g.spheres[t - g.triangles.size()].emitter_pdf = g.emitters[i].pdf;
    }
    if (!g.emitters.empty()) g.emitters.back().cdf = 1.0f;
    double total_area = 0.0;
    for (size_t i = 0; i < g.triangles.size(); ++i) {
        const TriangleGpu& t = g.triangles[i];
        const float area = 0.5f * glm::length(glm::cross(glm::vec3(t.p1 - t.p0), glm::vec3(t.p2 - t.p0)));
        if (!(area > 0.0f) || !std::isfinite(area)) continue;
        g.surfaces.push_back({static_cast<std::uint32_t>(i), 0.0f, 0.0f, area});
        total_area += area;
    }
    double running_area = 0.0;
    for (EmitterGpu& s : g.surfaces) {
        running_area += s.area;
        s.pdf = static_cast<float>(s.area / total_area);
        s.cdf = static_cast<float>(running_area / total_area);
    }
    if (!g.surfaces.empty()) g.surfaces.back().cdf = 1.0f;
    for (const Material& m : scene.materials) {
        g.has_transmission = g.has_transmission || m.transmission > 0.0f;
        g.has_blend = g.has_blend || m.alpha_mode == AlphaMode::blend;
        g.has_mask = g.has_mask || m.alpha_mode == AlphaMode::mask;
    }
    return g;
}
}  // namespace

RtGeometry build_rt_geometry(const Scene& scene, int default_material, const BvhOptions& options) {
    RtGeometry g = build_primitives(scene, default_material);
    g.bvh = build_bvh_binned_sah(primitive_boxes(g), options);
    return g;
}

void rebuild_rt_geometry(RtGeometry& geometry, const Scene& scene, int default_material, const BvhOptions& options) {
    geometry.bvh = Bvh{};
    RtGeometry g = build_primitives(scene, default_material, std::move(geometry));
    g.bvh = build_bvh_binned_sah(primitive_boxes(g), options);
    geometry = std::move(g);
}

double refit_rt_geometry(RtGeometry& geometry, const Scene& scene, int default_material, const BvhOptions& options) {
    if (count_triangles(scene) != geometry.triangles.size() || count_spheres(scene) != geometry.spheres.size()) return -1.0;
    Bvh bvh = std::move(geometry.bvh);
    RtGeometry g = build_primitives(scene, default_material, std::move(geometry));
    g.bvh = std::move(bvh);
    const double ms = refit_bvh(g.bvh, primitive_boxes(g), options);
    geometry = std::move(g);
    return ms;
}

TraversalLayout pack_traversal(const RtGeometry& g) {
    TraversalLayout out;
    pack_traversal(g, out);
    return out;
}

void pack_traversal(const RtGeometry& g, TraversalLayout& out) {
    const Bvh& bvh = g.bvh;
    const std::size_t triangle_count = g.triangles.size();
    const std::size_t prim_count = triangle_count + g.spheres.size();
    if (prim_count > kTraversalMaxPrimitives)
        throw std::length_error("ray tracer: " + std::to_string(prim_count) + " primitives; the GPU BVH layout holds at most " +
                                std::to_string(kTraversalMaxPrimitives));
    out.nodes.clear();
    out.prims.clear();
    out.prims.reserve(bvh.prim_indices.size() * 3);
    for (const std::uint32_t id : bvh.prim_indices) {
        const float id_bits = std::bit_cast<float>(static_cast<std::int32_t>(id));
        if (id < triangle_count) {
            const TriangleGpu& t = g.triangles[id];
            out.prims.emplace_back(glm::vec3(t.p0), id_bits);
            out.prims.emplace_back(glm::vec3(t.p1), 0.0f);
            out.prims.emplace_back(glm::vec3(t.p2), 0.0f);
            out.prims[out.prims.size() - 2].w = t.p2.w;  // 1: culled for seeing rays (scene.glsl's trace)
        } else {
            const SphereGpu& s = g.spheres[id - triangle_count];
            out.prims.emplace_back(s.center, id_bits);
            out.prims.emplace_back(s.radius, 0.0f, 0.0f, 0.0f);
            out.prims.emplace_back(0.0f);
        }
    }
    // Interior nodes keep their depth-first order; compact[i] is node i's index among them.
    std::vector<std::int32_t> compact(bvh.nodes.size(), -1);
    std::int32_t interior = 0;
    const bool root_is_interior = bvh.nodes.size() > 1 && !bvh.nodes[0].leaf();
    for (std::size_t i = 0; i < bvh.nodes.size(); ++i)
        if (!bvh.nodes[i].leaf() && (i > 0 || root_is_interior)) compact[i] = interior++;
    auto ref = [&](std::size_t i) -> std::int32_t {
        const BvhNode& n = bvh.nodes[i];
        if (!n.leaf()) return compact[i];
        if (n.count > 64) throw std::logic_error("pack_traversal: a leaf of more than 64 primitives");
        return -1 - (n.right_or_first * 64 + (n.count - 1));
    };
    auto child = [&](glm::vec3 bmin, glm::vec3 bmax, std::int32_t r) {
        out.nodes.emplace_back(bmin, std::bit_cast<float>(r));
        out.nodes.emplace_back(bmax, 0.0f);
    };
    const float inf = std::numeric_limits<float>::infinity();
    if (!root_is_interior) {
        // A single leaf, or the empty BVH (one node with count 0 and an empty box).
        const BvhNode& root = bvh.nodes.at(0);
        child(root.bmin, root.bmax, root.leaf() ? ref(0) : kTraversalNoChild);
        child(glm::vec3(inf), glm::vec3(-inf), kTraversalNoChild);
        return;
    }
    out.nodes.reserve(static_cast<std::size_t>(interior) * 4);
    for (std::size_t i = 0; i < bvh.nodes.size(); ++i) {
        if (compact[i] < 0) continue;
        const std::size_t left = i + 1, right = static_cast<std::size_t>(bvh.nodes[i].right_or_first);
        child(bvh.nodes[left].bmin, bvh.nodes[left].bmax, ref(left));
        child(bvh.nodes[right].bmin, bvh.nodes[right].bmax, ref(right));
    }
}

namespace {
bool same_bits(glm::vec3 a, glm::vec3 b) { return std::memcmp(&a, &b, sizeof a) == 0; }
bool inside(glm::vec3 p, glm::vec3 bmin, glm::vec3 bmax) {
    return glm::all(glm::lessThanEqual(bmin, p)) && glm::all(glm::lessThanEqual(p, bmax));
}
}  // namespace

std::string traversal_layout_violation(const RtGeometry& g, const TraversalLayout& layout) {
    const std::size_t triangle_count = g.triangles.size(), prim_count = triangle_count + g.spheres.size();
    if (layout.prims.size() != prim_count * 3)
        return std::to_string(layout.prims.size()) + " primitive texels for " + std::to_string(prim_count) + " primitives";
    if (layout.nodes.size() < 4 || layout.nodes.size() % 4 != 0) return "node texels: " + std::to_string(layout.nodes.size());
    const std::size_t node_count = layout.nodes.size() / 4;
    std::vector<int> reached(prim_count, 0);
    std::vector<char> visited(node_count, 0);
    const std::vector<Aabb> boxes = primitive_boxes(g);  // what the builder saw
    struct Item {
        std::int32_t ref;
        glm::vec3 bmin, bmax;  // the box the ref was reached through
    };
    const float inf = std::numeric_limits<float>::infinity();
    std::vector<Item> stack{{0, glm::vec3(-inf), glm::vec3(inf)}};
    while (!stack.empty()) {
        const Item item = stack.back();
        stack.pop_back();
        const bool empty_box = !glm::all(glm::lessThanEqual(item.bmin, item.bmax));
        if (item.ref == kTraversalNoChild) {
            if (!empty_box) return "a placeholder child with a box that rays can enter";
            continue;
        }
        if (item.ref >= 0) {
            const auto n = static_cast<std::size_t>(item.ref);
            if (n >= node_count) return "node ref " + std::to_string(item.ref) + " out of range";
            if (visited[n]++) return "node " + std::to_string(n) + " reached twice";
            for (int c = 0; c < 2; ++c) {
                const glm::vec4 lo = layout.nodes[n * 4 + static_cast<std::size_t>(c) * 2];
                const glm::vec4 hi = layout.nodes[n * 4 + static_cast<std::size_t>(c) * 2 + 1];
                const bool child_empty = !glm::all(glm::lessThanEqual(glm::vec3(lo), glm::vec3(hi)));
                if (!child_empty && !empty_box && !(inside(glm::vec3(lo), item.bmin, item.bmax) && inside(glm::vec3(hi), item.bmin, item.bmax)))
                    return "node " + std::to_string(n) + ": a child's box is not inside its parent's";
                stack.push_back({std::bit_cast<std::int32_t>(lo.w), glm::vec3(lo), glm::vec3(hi)});
            }
            continue;
        }
        const std::int32_t code = -1 - item.ref;
        const std::size_t first = static_cast<std::size_t>(code >> 6), count = static_cast<std::size_t>(code & 63) + 1;
        if (first + count > prim_count) return "leaf ref " + std::to_string(item.ref) + " past the primitives";
        for (std::size_t r = first; r < first + count; ++r) {
            const glm::vec4* rec = &layout.prims[r * 3];
            const auto id = static_cast<std::size_t>(std::bit_cast<std::int32_t>(rec[0].w));
            if (id >= prim_count) return "record " + std::to_string(r) + ": id " + std::to_string(id) + " out of range";
            if (reached[id]++) return "primitive " + std::to_string(id) + " reached twice";
            if (id < triangle_count) {
                const TriangleGpu& t = g.triangles[id];
                if (!same_bits(rec[0], t.p0) || !same_bits(rec[1], t.p1) || !same_bits(rec[2], t.p2))
                    return "record " + std::to_string(r) + ": positions differ from triangle " + std::to_string(id);
            } else {
                const SphereGpu& sp = g.spheres[id - triangle_count];
                const glm::vec4 cr(sp.center, sp.radius);
                if (!same_bits(rec[0], cr) || std::bit_cast<std::uint32_t>(rec[1].x) != std::bit_cast<std::uint32_t>(cr.w))
                    return "record " + std::to_string(r) + ": centre or radius differ from sphere " + std::to_string(id - triangle_count);
            }
            const glm::vec3 lo = boxes[id].min, hi = boxes[id].max;
            // Primitives with non-finite coordinates sit under empty boxes, never hit.
            const bool finite = !glm::any(glm::isnan(lo)) && !glm::any(glm::isinf(lo)) && !glm::any(glm::isnan(hi)) && !glm::any(glm::isinf(hi));
            if (finite && !boxes[id].empty() && !empty_box && !(inside(lo, item.bmin, item.bmax) && inside(hi, item.bmin, item.bmax)))
                return "primitive " + std::to_string(id) + " is outside the box of its leaf";
        }
    }
    for (std::size_t i = 0; i < prim_count; ++i)
        if (reached[i] != 1) return "primitive " + std::to_string(i) + " is not reachable";
    return {};
}

}  // namespace candela::rt
