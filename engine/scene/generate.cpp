#include "scene/generate.hpp"

#include <cmath>

#include <glm/gtc/matrix_transform.hpp>

#include "scene/mesh_utils.hpp"

namespace candela {

Scene make_bumpy_sphere_scene(std::size_t triangles) {
    Scene scene;
    scene.source = "generated:" + std::to_string(triangles);
    Material white;
    white.name = "white";
    white.base_color = glm::vec4(0.8f, 0.8f, 0.8f, 1.0f);
    white.metallic = 0.0f;
    white.roughness = 0.8f;
    scene.materials.push_back(white);

    // rings * segments * 2 = triangles, with segments = 2 * rings.
    const int rings = std::max(2, static_cast<int>(std::sqrt(static_cast<double>(triangles) / 4.0)));
    const int segments = 2 * rings;
    Primitive sphere;
    sphere.material = 0;
    const float pi = 3.14159265358979f;
    for (int i = 0; i <= rings; ++i)
        for (int j = 0; j <= segments; ++j) {
            const float th = pi * static_cast<float>(i) / static_cast<float>(rings);
            const float ph = 2.0f * pi * static_cast<float>(j) / static_cast<float>(segments);
            const glm::vec3 d(std::sin(th) * std::cos(ph), std::cos(th), std::sin(th) * std::sin(ph));
            const float bump = 1.0f + 0.05f * std::sin(13.0f * th) * std::cos(17.0f * ph);
            Vertex v;
            v.position = d * bump + glm::vec3(0.0f, 1.2f, 0.0f);
            sphere.vertices.push_back(v);
        }
    for (int i = 0; i < rings; ++i)
        for (int j = 0; j < segments; ++j) {
            const auto a = static_cast<std::uint32_t>(i * (segments + 1) + j), c = a + static_cast<std::uint32_t>(segments + 1);
            // The first and last rings touch the poles: one of their two triangles has no area.
            if (i > 0) sphere.indices.insert(sphere.indices.end(), {a, a + 1, c});
            if (i < rings - 1) sphere.indices.insert(sphere.indices.end(), {a + 1, c + 1, c});
        }
    generate_smooth_normals(sphere);
    compute_bounds(sphere);

    Primitive ground;
    ground.material = 0;
    append_quad(ground, {-4, 0, 4}, {8, 0, 0}, {0, 0, -8});
    compute_bounds(ground);

    scene.meshes.push_back({"bumpy_sphere", {std::move(sphere)}});
    scene.meshes.push_back({"ground", {std::move(ground)}});
    Node s;
    s.name = "bumpy_sphere";
    s.mesh = 0;
    Node g;
    g.name = "ground";
    g.mesh = 1;
    Light sun;
    sun.name = "sun";
    sun.type = LightType::directional;
    sun.intensity = 3.0f;
    scene.lights.push_back(sun);
    Node l;
    l.name = "sun";
    l.light = 0;
    // Pointing down and away from the camera.
    l.local = glm::mat4(glm::mat3(glm::vec3(1, 0, 0), glm::normalize(glm::vec3(0, 0.6f, -0.8f)), glm::normalize(glm::vec3(0, 0.8f, 0.6f))));
    scene.nodes = {s, g, l};
    scene.roots = {0, 1, 2};
    scene.environment.radiance = glm::vec3(0.2f);
    // A camera the sphere fills, so that ray benchmarks measure rays that hit it, not sky.
    add_look_at_camera(scene, {0.0f, 1.4f, 2.6f}, {0.0f, 1.2f, 0.0f}, 0.8f, glm::vec3(0, 1, 0), "close");
    scene.update_world_transforms();
    return scene;
}

int add_mesh_node(Scene& scene, const std::string& name, Primitive primitive, const glm::mat4& local) {
    compute_bounds(primitive);
    scene.meshes.push_back({name, {std::move(primitive)}});
    Node n;
    n.name = name;
    n.mesh = static_cast<int>(scene.meshes.size()) - 1;
    n.local = local;
    n.has_matrix = true;
    scene.nodes.push_back(std::move(n));
    scene.roots.push_back(static_cast<int>(scene.nodes.size()) - 1);
    return scene.roots.back();
}

int add_light_node(Scene& scene, const Light& light, const glm::mat4& local) {
    scene.lights.push_back(light);
    Node n;
    n.name = light.name;
    n.light = static_cast<int>(scene.lights.size()) - 1;
    n.local = local;
    n.has_matrix = true;
    scene.nodes.push_back(std::move(n));
    scene.roots.push_back(static_cast<int>(scene.nodes.size()) - 1);
    return scene.roots.back();
}

int add_sun(Scene& scene, glm::vec3 to_light, float intensity) {
    Light sun;
    sun.name = "sun";
    sun.type = LightType::directional;
    sun.intensity = intensity;
    // The node's -Z is the light's direction: its Z axis points to the light.
    const glm::vec3 z = glm::normalize(to_light);
    // Any up vector not parallel to z gives the same light; straight up/down needs another one.
    const glm::vec3 up = std::fabs(z.y) > 0.99f ? glm::vec3(1, 0, 0) : glm::vec3(0, 1, 0);
    const glm::vec3 side = glm::normalize(glm::cross(up, z));
    return add_light_node(scene, sun, glm::mat4(glm::mat3(side, glm::cross(z, side), z)));
}

Camera& add_look_at_camera(Scene& scene, glm::vec3 eye, glm::vec3 target, float yfov, glm::vec3 up, const char* name) {
    Camera c;
    c.name = name;
    c.yfov = yfov;
    c.znear = 0.05f;
    c.world = glm::inverse(glm::lookAt(eye, target, up));
    scene.cameras.push_back(c);
    return scene.cameras.back();
}

void append_quad(Primitive& p, glm::vec3 o, glm::vec3 eu, glm::vec3 ev) {
    const glm::vec3 n = glm::normalize(glm::cross(eu, ev));
    const auto base = static_cast<std::uint32_t>(p.vertices.size());
    for (const glm::vec3& q : {o, o + eu, o + eu + ev, o + ev}) {
        Vertex vert;
        vert.position = q;
        vert.normal = n;
        p.vertices.push_back(vert);
    }
    p.indices.insert(p.indices.end(), {base, base + 1, base + 2, base, base + 2, base + 3});
}

Material lambert_material(const char* name, glm::vec3 colour) {
    Material m;
    m.name = name;
    m.base_color = glm::vec4(colour, 1.0f);
    m.metallic = 0.0f;
    m.roughness = 0.9f;
    return m;
}

void append_box(Primitive& p, glm::vec3 lo, glm::vec3 hi) {
    for (int axis = 0; axis < 3; ++axis)
        for (int sign = 0; sign < 2; ++sign) {
            glm::vec3 n(0.0f);
            n[axis] = sign ? 1.0f : -1.0f;
            const int u = (axis + 1) % 3, v = (axis + 2) % 3;
            const auto base = static_cast<std::uint32_t>(p.vertices.size());
            for (int k = 0; k < 4; ++k) {
                glm::vec3 q;
                q[axis] = sign ? hi[axis] : lo[axis];
                q[u] = (k == 1 || k == 2) ? hi[u] : lo[u];
                q[v] = k >= 2 ? hi[v] : lo[v];
                Vertex vert;
                vert.position = q;
                vert.normal = n;
                p.vertices.push_back(vert);
            }
            // Counter-clockwise seen from outside.
            const bool flip = (sign == 0);
            if (!flip) p.indices.insert(p.indices.end(), {base, base + 1, base + 2, base, base + 2, base + 3});
            else p.indices.insert(p.indices.end(), {base, base + 2, base + 1, base, base + 3, base + 2});
        }
}

namespace {

// The radical inverse of `index` in `base`: one coordinate of a Halton sequence.
float halton(int index, int base) {
    float f = 1.0f, r = 0.0f;
    for (int i = index; i > 0; i /= base) {
        f /= static_cast<float>(base);
        r += f * static_cast<float>(i % base);
    }
    return r;
}

Primitive box_primitive(glm::vec3 lo, glm::vec3 hi) {
    Primitive p;
    p.material = 0;
    append_box(p, lo, hi);
    compute_bounds(p);
    return p;
}

}  // namespace

Scene make_street_scene(int lamps) {
    Scene scene;
    scene.source = "generated:street:" + std::to_string(lamps);
    scene.materials.push_back(lambert_material("asphalt", glm::vec3(0.5f)));
    const float length = 20.0f * static_cast<float>(lamps);
    Primitive road;
    road.material = 0;
    append_box(road, {-10.0f, -0.1f, -10.0f}, {length, 0.0f, 10.0f});
    add_mesh_node(scene, "road", std::move(road));
    for (int i = 0; i < lamps; ++i) {
        Light l;
        l.name = "lamp" + std::to_string(i);
        l.type = LightType::point;
        l.intensity = 2.0f;  // 0.16 W/m^2/sr under the lamp, 2 m below it
        l.range = 0.0f;
        scene.lights.push_back(l);
        Node n;
        n.name = l.name;
        n.light = i;
        n.local = glm::translate(glm::mat4(1.0f), glm::vec3(20.0f * static_cast<float>(i), 2.0f, 0.0f));
        scene.roots.push_back(static_cast<int>(scene.nodes.size()));
        scene.nodes.push_back(n);
    }
    add_look_at_camera(scene, {-8.0f, 6.0f, 0.0f}, {60.0f, 0.0f, 0.0f}, 0.9f);
    scene.update_world_transforms();
    return scene;
}

Scene make_emitters_scene(int emitters) {
    // The floor and boxes of generated:lights-bounded:N without its point lights.
    Scene scene = make_many_lights_scene(1, true);
    scene.source = "generated:emitters:" + std::to_string(emitters);
    scene.lights.clear();
    for (auto it = scene.roots.begin(); it != scene.roots.end();)
        if (scene.nodes[static_cast<size_t>(*it)].light >= 0) it = scene.roots.erase(it);
        else ++it;
    for (Node& n : scene.nodes) n.light = -1;
    const float shrink = emitters > 16 ? std::sqrt(16.0f / static_cast<float>(emitters)) : 1.0f;
    // Eight hues, one emissive material and one quad mesh each (a 0.2 m square facing down).
    const int first_material = static_cast<int>(scene.materials.size());
    for (int k = 0; k < 8; ++k) {
        const float hue = static_cast<float>(k) * 0.75f;
        Material m = lambert_material("emitter", glm::vec3(0.8f));
        m.emissive = glm::clamp(glm::vec3(std::abs(hue - 3.0f) - 1.0f, 2.0f - std::abs(hue - 2.0f), 2.0f - std::abs(hue - 4.0f)), 0.0f, 1.0f);
        // 50 W/m^2/sr over 0.04 m^2: 2 W/sr straight down, a point light of generated:lights-bounded:N.
        m.emissive_strength = 50.0f * shrink * shrink;
        scene.materials.push_back(m);
    }
    const int first_mesh = static_cast<int>(scene.meshes.size());
    for (int k = 0; k < 8; ++k) {
        Primitive q;
        q.material = first_material + k;
        append_quad(q, {-0.1f, 0.0f, -0.1f}, {0.2f, 0.0f, 0.0f}, {0.0f, 0.0f, 0.2f});  // normal -y: emits down
        compute_bounds(q);
        scene.meshes.push_back({"emitter", {std::move(q)}});
    }
    for (int i = 0; i < emitters; ++i) {
        Node n;
        n.name = "emitter" + std::to_string(i);
        n.mesh = first_mesh + static_cast<int>(halton(i + 1, 5) * 8.0f) % 8;
        n.local = glm::translate(glm::mat4(1.0f), glm::vec3(-9.5f + 19.0f * halton(i + 1, 2), (0.3f + 1.2f * halton(i + 1, 7)) * shrink,
                                                           -9.5f + 19.0f * halton(i + 1, 3)));
        scene.roots.push_back(static_cast<int>(scene.nodes.size()));
        scene.nodes.push_back(n);
    }
    scene.update_world_transforms();
    return scene;
}

Scene make_many_lights_scene(int lights, bool bounded) {
    Scene scene;
    scene.source = std::string(bounded ? "generated:lights-bounded:" : "generated:lights:") + std::to_string(lights);
    const float shrink = bounded && lights > 16 ? std::sqrt(16.0f / static_cast<float>(lights)) : 1.0f;
    Material grey;
    grey.name = "grey";
    grey.base_color = glm::vec4(0.7f, 0.7f, 0.7f, 1.0f);
    grey.metallic = 0.0f;
    grey.roughness = 0.5f;
    scene.materials.push_back(grey);
    Primitive floor = box_primitive({-10, -0.1f, -10}, {10, 0, 10});
    scene.meshes.push_back({"floor", {std::move(floor)}});
    scene.meshes.push_back({"box", {box_primitive({-0.4f, 0, -0.4f}, {0.4f, 1.2f, 0.4f})}});
    Node f;
    f.name = "floor";
    f.mesh = 0;
    scene.nodes.push_back(f);
    scene.roots.push_back(0);
    for (int i = 0; i < 8; ++i)
        for (int j = 0; j < 8; ++j) {
            Node b;
            b.name = "box";
            b.mesh = 1;
            b.local = glm::translate(glm::mat4(1.0f), glm::vec3(-8.75f + 2.5f * static_cast<float>(i), 0.0f, -8.75f + 2.5f * static_cast<float>(j)));
            scene.roots.push_back(static_cast<int>(scene.nodes.size()));
            scene.nodes.push_back(b);
        }
    // Deterministic scatter: a 2D Halton sequence over the floor, heights and hues from it.
    for (int i = 0; i < lights; ++i) {
        Light l;
        l.name = "light" + std::to_string(i);
        l.type = LightType::point;
        const float hue = halton(i + 1, 5) * 6.0f;
        l.color = glm::clamp(glm::vec3(std::abs(hue - 3.0f) - 1.0f, 2.0f - std::abs(hue - 2.0f), 2.0f - std::abs(hue - 4.0f)), 0.0f, 1.0f);
        l.intensity = 2.0f;
        l.range = 3.0f * shrink;
        scene.lights.push_back(l);
        Node n;
        n.name = l.name;
        n.light = i;
        n.local = glm::translate(glm::mat4(1.0f), glm::vec3(-9.5f + 19.0f * halton(i + 1, 2), (0.3f + 1.2f * halton(i + 1, 7)) * shrink,
                                                           -9.5f + 19.0f * halton(i + 1, 3)));
        scene.roots.push_back(static_cast<int>(scene.nodes.size()));
        scene.nodes.push_back(n);
    }
    scene.environment.radiance = glm::vec3(0.03f);
    add_look_at_camera(scene, {0.0f, 7.0f, 13.0f}, {0.0f, 0.0f, 1.0f}, 0.9f, glm::vec3(0, 1, 0), "overview");
    scene.update_world_transforms();
    return scene;
}

}  // namespace candela
