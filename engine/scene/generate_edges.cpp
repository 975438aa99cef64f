// generated:edges: the anti-aliasing scene. Thin and high-contrast edges against the
// tracer's box-filtered pixels: a slanted checkerboard, wires thinner than a pixel, a MASK fence
// (an alpha-tested texture: alpha to coverage) and the silhouettes of a tilted box, over a white
// wall, lit by one point light at the camera (Lambert; every shadow hides behind its caster), so
// that the flat parts shade alike in raster and tracer and the difference is the edges'.
#include <cmath>

#include <glm/gtc/matrix_transform.hpp>

#include "scene/generate.hpp"
#include "scene/mesh_utils.hpp"

namespace candela {
namespace {

// A quad in the plane z = `z` facing +z, corners (x0, y0) .. (x1, y1), uv 0..1 (scaled by `uv`).
Primitive quad(float x0, float y0, float x1, float y1, float z, int material, glm::vec2 uv = glm::vec2(1.0f)) {
    Primitive p;
    p.material = material;
    const glm::vec2 c[4] = {{x0, y0}, {x1, y0}, {x1, y1}, {x0, y1}};
    const glm::vec2 t[4] = {{0, 1}, {1, 1}, {1, 0}, {0, 0}};
    for (int i = 0; i < 4; ++i) {
        Vertex v;
        v.position = glm::vec3(c[i], z);
        v.normal = glm::vec3(0, 0, 1);
        v.uv0 = t[i] * uv;
        p.vertices.push_back(v);
    }
    p.indices = {0, 1, 2, 0, 2, 3};
    compute_bounds(p);
    return p;
}

// A long thin box from a to b (in the plane z = const) of square cross-section `w`.
Primitive wire(glm::vec3 a, glm::vec3 b, float w, int material) {
    Primitive p;
    p.material = material;
    const glm::vec3 d = glm::normalize(b - a);
    const glm::vec3 u = glm::normalize(glm::cross(d, glm::vec3(0, 0, 1))) * (0.5f * w);
    const glm::vec3 v = glm::vec3(0, 0, 0.5f * w);
    const glm::vec3 corners[4] = {u + v, -u + v, -u - v, u - v};
    // Four side faces (flat normals), each its own 4 vertices.
    for (int f = 0; f < 4; ++f) {
        const glm::vec3 c0 = corners[f], c1 = corners[(f + 1) % 4];
        const glm::vec3 n = glm::normalize(c0 + c1);
        const auto base = static_cast<std::uint32_t>(p.vertices.size());
        for (const glm::vec3& q : {a + c0, b + c0, b + c1, a + c1}) {
            Vertex vert;
            vert.position = q;
            vert.normal = n;
            p.vertices.push_back(vert);
        }
        // Counter-clockwise seen from outside (along n).
        const glm::vec3 e1 = (b + c0) - (a + c0), e2 = (a + c1) - (a + c0);
        if (glm::dot(glm::cross(e1, e2), n) > 0.0f) p.indices.insert(p.indices.end(), {base, base + 1, base + 2, base, base + 2, base + 3});
        else p.indices.insert(p.indices.end(), {base, base + 2, base + 1, base, base + 3, base + 2});
    }
    compute_bounds(p);
    return p;
}

}  // namespace

Scene make_edges_scene() {
    Scene scene;
    scene.source = "generated:edges";
    auto material = [&](const char* name, float grey) {
        Material m;
        m.name = name;
        m.base_color = glm::vec4(grey, grey, grey, 1.0f);
        m.metallic = 0.0f;
        m.roughness = 1.0f;
        scene.materials.push_back(m);
        return static_cast<int>(scene.materials.size()) - 1;
    };
    const int white = material("white", 0.85f);
    const int black = material("black", 0.02f);
    const int light_grey = material("light_grey", 0.6f);

    // The fence: a 64x64 RGBA texture, opaque bars 8 texels wide every 16 (alpha 0 between), on
    // a MASK material (cutoff 0.5).
    Image fence;
    fence.name = fence.uri = "generated_fence";
    fence.width = fence.height = 64;
    fence.rgba8.resize(64 * 64 * 4);
    for (int y = 0; y < 64; ++y)
        for (int x = 0; x < 64; ++x) {
            const bool bar = (x % 16) < 6 || (y % 16) < 6;
            std::uint8_t* px = &fence.rgba8[static_cast<size_t>((y * 64 + x) * 4)];
            px[0] = px[1] = px[2] = 20;
            px[3] = bar ? 255 : 0;
        }
    fence.valid = true;
    scene.images.push_back(fence);
    Material fm;
    fm.name = "fence";
    fm.base_color = glm::vec4(1.0f);
    fm.metallic = 0.0f;
    fm.roughness = 1.0f;
    fm.alpha_mode = AlphaMode::mask;
    fm.alpha_cutoff = 0.5f;
    fm.double_sided = true;
    fm.base_color_texture.image = 0;
    fm.base_color_texture.sampler.min_filter = 9729;  // GL_LINEAR: no mips (tracer and raster alike)
    scene.materials.push_back(fm);
    const int fence_material = static_cast<int>(scene.materials.size()) - 1;

    auto add = [&](const char* name, Primitive p, glm::mat4 local = glm::mat4(1.0f)) {
        scene.meshes.push_back({name, {std::move(p)}});
        Node n;
        n.name = name;
        n.mesh = static_cast<int>(scene.meshes.size()) - 1;
        n.local = local;
        scene.roots.push_back(static_cast<int>(scene.nodes.size()));
        scene.nodes.push_back(n);
    };
    // The wall behind everything.
    add("wall", quad(-6, -6, 6, 6, -1.0f, white));
    // A checkerboard rotated by 7 degrees about the view axis (left half of the view).
    {
        Mesh board{"checker", {}};
        for (int i = 0; i < 8; ++i)
            for (int j = 0; j < 8; ++j) {
                const float x0 = -1.0f + 0.25f * static_cast<float>(i), y0 = -1.0f + 0.25f * static_cast<float>(j);
                board.primitives.push_back(quad(x0, y0, x0 + 0.25f, y0 + 0.25f, 0.0f, (i + j) % 2 ? white : black));
            }
        scene.meshes.push_back(std::move(board));
        Node n;
        n.name = "checker";
        n.mesh = static_cast<int>(scene.meshes.size()) - 1;
        n.local = glm::translate(glm::mat4(1.0f), glm::vec3(-1.05f, 0.35f, 0.0f)) *
                  glm::rotate(glm::mat4(1.0f), glm::radians(7.0f), glm::vec3(0, 0, 1));
        scene.roots.push_back(static_cast<int>(scene.nodes.size()));
        scene.nodes.push_back(n);
    }
    // Wires: black, thinner than a pixel at 128 px (a pixel is about 0.03 units at the wall).
    add("wire_a", wire({-2.4f, -1.9f, 0.3f}, {2.4f, -0.6f, 0.3f}, 0.012f, black));
    add("wire_b", wire({-2.4f, -1.2f, 0.3f}, {2.4f, -1.75f, 0.3f}, 0.02f, black));
    add("wire_c", wire({0.35f, 1.9f, 0.3f}, {0.6f, -0.5f, 0.3f}, 0.008f, black));
    // The fence (right half), slightly rotated.
    add("fence", quad(0.0f, 0.0f, 1.5f, 1.5f, 0.0f, fence_material, glm::vec2(3.0f)),
        glm::translate(glm::mat4(1.0f), glm::vec3(0.75f, -0.2f, 0.1f)) * glm::rotate(glm::mat4(1.0f), glm::radians(-4.0f), glm::vec3(0, 0, 1)));
    // A light-grey box, tilted, in front of the black wires' ends (silhouettes against white).
    {
        Primitive box = wire({-0.3f, -0.35f, 0.0f}, {0.3f, -0.35f, 0.0f}, 0.35f, light_grey);
        add("box", std::move(box),
            glm::translate(glm::mat4(1.0f), glm::vec3(-1.3f, -1.1f, 0.2f)) * glm::rotate(glm::mat4(1.0f), glm::radians(25.0f), glm::vec3(0.3f, 0.2f, 1.0f)));
    }
    // The light: a point light at the camera, so every shadow hides exactly behind its caster
    // (raster without shadow maps and the tracer's exact visibility see the same image).
    Light lamp;
    lamp.name = "lamp";
    lamp.type = LightType::point;
    lamp.intensity = 120.0f;
    scene.lights.push_back(lamp);
    Node ln;
    ln.name = "lamp";
    ln.light = 0;
    ln.local = glm::translate(glm::mat4(1.0f), glm::vec3(0.0f, 0.0f, 6.0f));
    scene.roots.push_back(static_cast<int>(scene.nodes.size()));
    scene.nodes.push_back(ln);

    Camera camera;
    camera.name = "front";
    camera.yfov = 0.7f;
    camera.znear = 0.1f;
    camera.world = glm::inverse(glm::lookAt(glm::vec3(0.0f, 0.0f, 6.0f), glm::vec3(0.0f), glm::vec3(0, 1, 0)));
    scene.cameras.push_back(camera);
    scene.update_world_transforms();
    return scene;
}

}  // namespace candela
