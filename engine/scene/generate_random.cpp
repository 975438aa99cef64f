// generated:random:SEED: random scenes for the statistical property tests
// (tests/unit/test_random_scenes.cpp). The engine's rules (which effect runs, how a file is lit)
// were tuned on scenes someone wrote; these are scenes nobody wrote, drawn from a seed:
// - a room: closed (a light-tight box of thick walls), open (a floor and a back wall) or none;
// - 1 to 6 objects on the floor (floating when there is none): boxes, exact spheres (a mesh for
//   the raster, extras.sphere for the tracer), thin walls; diffuse, glossy, metal (smooth or
//   rough) or glass (transmission, solid or thin-walled);
// - 1 to 3 lights of every kind: point, spot, directional, a quad emitter brighter than 1
//   (emissive strength) and a constant environment; inside a closed room only those inside it;
// - a camera inside or outside the room, often seeing the background;
// - a scale factor from 0.1 to 20 for every length (light intensities follow, so the
//   exposure stays sane).
// Every number comes from one PRNG (splitmix64) through distributions written out here, so a seed
// gives the same scene on every platform and standard library.
#include <algorithm>
#include <cmath>
#include <cstdint>
#include <string>
#include <vector>

#include <glm/gtc/matrix_transform.hpp>

#include "scene/generate.hpp"
#include "scene/mesh_utils.hpp"

namespace candela {
namespace {

constexpr float kPi = 3.14159265358979f;

class Rng {
public:
    explicit Rng(std::uint64_t seed) : state_(seed * 0x9E3779B97F4A7C15ull + 0x632BE59BD9B4E019ull) {}
    std::uint64_t next() {
        std::uint64_t z = (state_ += 0x9E3779B97F4A7C15ull);
        z = (z ^ (z >> 30)) * 0xBF58476D1CE4E5B9ull;
        z = (z ^ (z >> 27)) * 0x94D049BB133111EBull;
        return z ^ (z >> 31);
    }
    // [0, 1) with 24 bits: exactly representable floats.
    float uniform() { return static_cast<float>(next() >> 40) * (1.0f / 16777216.0f); }
    float range(float a, float b) { return a + (b - a) * uniform(); }
    // Log-uniform in [a, b] (a, b > 0).
    float log_range(float a, float b) { return a * std::exp(std::log(b / a) * uniform()); }
    int below(int n) { return static_cast<int>((next() >> 33) % static_cast<std::uint64_t>(n)); }
    bool chance(float p) { return uniform() < p; }

private:
    std::uint64_t state_;
};

// An axis-aligned box in the plane with a rotation about +Y: what the placement tests against.
struct Footprint {
    glm::vec3 center;  // world, of the object's bounding box
    glm::vec3 half;    // world-axis half extents of its bounding box
    float radius;      // in the XZ plane, around center
};

bool inside(const Footprint& f, glm::vec3 p, float margin) {
    return glm::all(glm::lessThan(glm::abs(p - f.center), f.half + glm::vec3(margin)));
}

struct Builder {
    Scene scene;
    float s = 1.0f;  // the scale factor

    int material(Material m) {
        scene.materials.push_back(std::move(m));
        return static_cast<int>(scene.materials.size()) - 1;
    }
    int node(Node n) {
        scene.roots.push_back(static_cast<int>(scene.nodes.size()));
        scene.nodes.push_back(std::move(n));
        return static_cast<int>(scene.nodes.size()) - 1;
    }
    int mesh_node(const std::string& name, Primitive p, int mat, const glm::mat4& local = glm::mat4(1.0f)) {
        p.material = mat;
        compute_bounds(p);
        scene.meshes.push_back({name, {std::move(p)}});
        Node n;
        n.name = name;
        n.mesh = static_cast<int>(scene.meshes.size()) - 1;
        n.local = local;
        return node(std::move(n));
    }
    // A box of world corners lo..hi (already scaled).
    int box(const std::string& name, glm::vec3 lo, glm::vec3 hi, int mat) {
        Primitive p;
        append_box(p, lo, hi);
        return mesh_node(name, std::move(p), mat);
    }
    int light(const std::string& name, Light l, const glm::mat4& local) {
        l.name = name;
        scene.lights.push_back(l);
        Node n;
        n.name = name;
        n.light = static_cast<int>(scene.lights.size()) - 1;
        n.local = local;
        return node(std::move(n));
    }
};

glm::vec3 tint(Rng& rng, float lo, float hi) {
    // A colour of albedo between lo and hi, saturated at most moderately.
    const float base = rng.range(lo, hi);
    glm::vec3 c;
    for (int i = 0; i < 3; ++i) c[i] = std::clamp(base * rng.range(0.6f, 1.25f), 0.02f, 0.95f);
    return c;
}

glm::vec3 light_colour(Rng& rng) {
    // Near-white: warm to cool.
    const float t = rng.range(-1.0f, 1.0f);
    const glm::vec3 c(1.0f + 0.15f * t, 1.0f, 1.0f - 0.2f * t);
    return c / std::max({c.r, c.g, c.b});  // glTF light colours are at most 1
}

enum class Kind { diffuse, glossy, metal, rough_metal, glass };
const char* kind_name(Kind k) {
    switch (k) {
        case Kind::diffuse: return "diffuse";
        case Kind::glossy: return "glossy";
        case Kind::metal: return "metal";
        case Kind::rough_metal: return "rough_metal";
        case Kind::glass: return "glass";
    }
    return "?";
}

Material object_material(Rng& rng, Kind kind, float thickness, int index) {
    Material m;
    m.name = std::string(kind_name(kind)) + "_" + std::to_string(index);
    m.metallic = 0.0f;
    switch (kind) {
        case Kind::diffuse:
            m.base_color = glm::vec4(tint(rng, 0.2f, 0.85f), 1.0f);
            m.roughness = rng.range(0.7f, 1.0f);
            break;
        case Kind::glossy:
            m.base_color = glm::vec4(tint(rng, 0.1f, 0.8f), 1.0f);
            m.roughness = rng.range(0.2f, 0.5f);
            break;
        case Kind::metal:
            m.base_color = glm::vec4(tint(rng, 0.55f, 0.95f), 1.0f);
            m.metallic = 1.0f;
            m.roughness = rng.range(0.05f, 0.3f);
            break;
        case Kind::rough_metal:
            m.base_color = glm::vec4(tint(rng, 0.5f, 0.95f), 1.0f);
            m.metallic = 1.0f;
            m.roughness = rng.range(0.5f, 0.9f);
            break;
        case Kind::glass:
            m.base_color = glm::vec4(glm::mix(glm::vec3(1.0f), tint(rng, 0.7f, 0.95f), 0.5f), 1.0f);
            m.roughness = rng.range(0.0f, 0.1f);
            m.transmission = 1.0f;
            m.ior = rng.range(1.33f, 1.6f);
            m.thickness = thickness;  // 0: thin-walled
            break;
    }
    return m;
}

Kind draw_kind(Rng& rng) {
    const float u = rng.uniform();
    if (u < 0.40f) return Kind::diffuse;
    if (u < 0.55f) return Kind::glossy;
    if (u < 0.70f) return Kind::metal;
    if (u < 0.82f) return Kind::rough_metal;
    return Kind::glass;
}

// A camera at `eye` looking at `target` (+Y up unless the view is vertical).
Camera look_camera(const std::string& name, glm::vec3 eye, glm::vec3 target, float yfov, float znear) {
    Camera c;
    c.name = name;
    c.yfov = yfov;
    c.znear = znear;
    glm::vec3 up(0, 1, 0);
    if (std::abs(glm::dot(glm::normalize(target - eye), up)) > 0.98f) up = glm::vec3(0, 0, -1);
    c.world = glm::inverse(glm::lookAt(eye, target, up));
    return c;
}

// A light node's transform: at `pos`, its -Z axis along `dir`.
glm::mat4 aim(glm::vec3 pos, glm::vec3 dir) {
    dir = glm::normalize(dir);
    glm::vec3 up(0, 1, 0);
    if (std::abs(glm::dot(dir, up)) > 0.98f) up = glm::vec3(1, 0, 0);
    return glm::inverse(glm::lookAt(pos, pos + dir, up));
}

}  // namespace

// A UV sphere of radius r around the origin with exact normals; rings x 2 rings quads.
Primitive uv_sphere(float r, int rings) {
    Primitive p;
    const int segments = 2 * rings;
    for (int i = 0; i <= rings; ++i)
        for (int j = 0; j <= segments; ++j) {
            const float th = kPi * static_cast<float>(i) / static_cast<float>(rings);
            const float ph = 2.0f * kPi * static_cast<float>(j) / static_cast<float>(segments);
            const glm::vec3 d(std::sin(th) * std::cos(ph), std::cos(th), -std::sin(th) * std::sin(ph));
            Vertex v;
            v.position = d * r;
            v.normal = d;
            p.vertices.push_back(v);
        }
    for (int i = 0; i < rings; ++i)
        for (int j = 0; j < segments; ++j) {
            const auto a = static_cast<std::uint32_t>(i * (segments + 1) + j), c = a + static_cast<std::uint32_t>(segments + 1);
            // Counter-clockwise from outside; the pole rows' degenerate triangles are left out.
            if (i > 0) p.indices.insert(p.indices.end(), {a, c, a + 1});
            if (i < rings - 1) p.indices.insert(p.indices.end(), {a + 1, c, c + 1});
        }
    return p;
}

Scene make_random_scene(std::uint32_t seed) {
    Rng rng(seed);
    Builder b;
    b.scene.source = "generated:random:" + std::to_string(seed);
    const float s = b.s = rng.log_range(0.1f, 20.0f);

    // The room, in units of s: interior x in [-w/2, w/2], z in [-d/2, d/2], y in [0, h].
    enum class Room { closed, open, none };
    const float r_room = rng.uniform();
    const Room room = r_room < 0.4f ? Room::closed : r_room < 0.75f ? Room::open : Room::none;
    // Without a room the objects gather on a smaller patch, so that a camera framing them all
    // still sees each one at more than a few pixels.
    const float extent = room == Room::none ? 0.6f : 1.0f;
    const float w = extent * rng.range(4.0f, 9.0f), d = extent * rng.range(4.0f, 9.0f), h = rng.range(2.5f, 4.5f);
    const float t = 0.15f;  // wall thickness
    const char* room_name = room == Room::closed ? "closed_room" : room == Room::open ? "open_room" : "no_room";
    auto wall_material = [&](const char* name) {
        Material m = lambert_material(name, tint(rng, 0.3f, 0.85f));
        m.roughness = rng.range(0.8f, 1.0f);
        return b.material(m);
    };
    std::vector<Footprint> solids;  // walls and objects: what cameras and lights stay out of
    auto add_wall = [&](const std::string& name, glm::vec3 lo, glm::vec3 hi, int mat) {
        b.box(std::string(room_name) + "." + name, lo * s, hi * s, mat);
        solids.push_back({(lo + hi) * 0.5f * s, (hi - lo) * 0.5f * s, 0.0f});
    };
    if (room == Room::closed) {
        const int floor_m = wall_material("floor"), wall_m = wall_material("walls"), ceiling_m = wall_material("ceiling");
        const int accent_m = wall_material("accent_wall");
        add_wall("floor", {-w / 2 - t, -t, -d / 2 - t}, {w / 2 + t, 0, d / 2 + t}, floor_m);
        add_wall("ceiling", {-w / 2 - t, h, -d / 2 - t}, {w / 2 + t, h + t, d / 2 + t}, ceiling_m);
        add_wall("back", {-w / 2 - t, 0, -d / 2 - t}, {w / 2 + t, h, -d / 2}, wall_m);
        add_wall("front", {-w / 2 - t, 0, d / 2}, {w / 2 + t, h, d / 2 + t}, wall_m);
        add_wall("left", {-w / 2 - t, 0, -d / 2}, {-w / 2, h, d / 2}, accent_m);
        add_wall("right", {w / 2, 0, -d / 2}, {w / 2 + t, h, d / 2}, wall_m);
    } else if (room == Room::open) {
        const int floor_m = wall_material("floor"), wall_m = wall_material("back_wall");
        add_wall("floor", {-w / 2 - 1.0f, -t, -d / 2}, {w / 2 + 1.0f, 0, d / 2 + 1.0f}, floor_m);
        add_wall("back", {-w / 2 - 1.0f, 0, -d / 2 - t}, {w / 2 + 1.0f, h, -d / 2}, wall_m);
    }
    const bool has_floor = room != Room::none;

    // Objects: non-overlapping footprints inside the room (0.5 from the walls).
    const int wanted = 1 + rng.below(6);
    std::vector<Footprint> objects;
    for (int i = 0; i < wanted; ++i) {
        const int shape = rng.below(3);  // 0 box, 1 sphere, 2 thin wall
        const Kind kind = draw_kind(rng);
        const float yaw = rng.range(0.0f, 0.5f * kPi);
        glm::vec3 size;
        if (shape == 0) size = {rng.range(0.4f, 1.6f), rng.range(0.4f, 1.8f), rng.range(0.4f, 1.6f)};
        else if (shape == 1) size = glm::vec3(2.0f * rng.range(0.25f, 0.9f));
        else size = {rng.range(1.0f, 2.5f), rng.range(0.8f, 2.0f), 0.04f};
        const float lift = has_floor ? 0.0f : rng.range(-1.0f, 1.5f);
        const float radius = 0.5f * std::sqrt(size.x * size.x + size.z * size.z);
        bool placed = false;
        glm::vec3 c(0.0f);
        for (int attempt = 0; attempt < 40 && !placed; ++attempt) {
            const float x = rng.range(-w / 2 + 0.5f + radius, w / 2 - 0.5f - radius);
            const float z = rng.range(-d / 2 + 0.5f + radius, d / 2 - 0.5f - radius);
            c = glm::vec3(x, lift + 0.5f * size.y, z);
            placed = radius < std::min(w, d) / 2 - 0.5f;
            for (const Footprint& o : objects)
                if (glm::length(glm::vec2(c.x - o.center.x / s, c.z - o.center.z / s)) < radius + o.radius / s + 0.15f) placed = false;
        }
        if (!placed) continue;
        const int index = static_cast<int>(objects.size());
        // Glass: solid boxes and spheres (a volume as thick as the object), thin-walled walls.
        const float thickness = shape == 2 ? 0.0f : std::min({size.x, size.y, size.z}) * s;
        const int mat = b.material(object_material(rng, kind, thickness, index));
        const std::string name = std::string(shape == 0 ? "box" : shape == 1 ? "sphere" : "thin_wall") + "_" + std::to_string(index);
        const glm::mat4 local = glm::translate(glm::mat4(1.0f), c * s) * glm::rotate(glm::mat4(1.0f), yaw, glm::vec3(0, 1, 0));
        if (shape == 1) {
            // 32 rings: the mesh's normals within 0.25 degrees of the exact sphere's (16 rings:
            // 0.93), so that its faceting does not count as the raster's error against the tracer.
            const int n = b.mesh_node(name, uv_sphere(0.5f * size.x * s, 32), mat, glm::translate(glm::mat4(1.0f), c * s));
            b.scene.nodes[static_cast<size_t>(n)].sphere_radius = 0.5f * size.x * s;
        } else {
            Primitive p;
            append_box(p, -0.5f * size * s, 0.5f * size * s);
            b.mesh_node(name, std::move(p), mat, local);
        }
        // World bounding box of the rotated footprint.
        const float cs = std::abs(std::cos(yaw)), sn = std::abs(std::sin(yaw));
        const glm::vec3 half = shape == 1 ? 0.5f * size
                                          : glm::vec3(0.5f * (cs * size.x + sn * size.z), 0.5f * size.y, 0.5f * (sn * size.x + cs * size.z));
        objects.push_back({c * s, half * s, radius * s});
        solids.push_back(objects.back());
    }
    // Keep at least one object: a diffuse box in the middle (every earlier attempt failed only if
    // the first object was too large for the room, which the bounds above never allow).
    if (objects.empty()) {
        const int mat = b.material(object_material(rng, Kind::diffuse, 0.0f, 0));
        b.box("box_0", glm::vec3(-0.4f, 0.0f, -0.4f) * s, glm::vec3(0.4f, 0.8f, 0.4f) * s, mat);
        objects.push_back({glm::vec3(0, 0.4f, 0) * s, glm::vec3(0.4f) * s, 0.57f * s});
        solids.push_back(objects.back());
    }
    float top = 0.0f;  // the highest object top, in units of s
    for (const Footprint& o : objects) top = std::max(top, (o.center.y + o.half.y) / s);

    // The camera: inside the room (always in a closed room unless it looks at its outside) or
    // outside; never inside a solid, and at least 3 near distances from every one.
    const float znear = 0.05f * s;
    const bool outside = room == Room::closed ? rng.chance(0.15f) : (room == Room::open ? rng.chance(0.5f) : true);
    auto clear_of_solids = [&](glm::vec3 p, float margin) {
        for (const Footprint& f : solids)
            if (inside(f, p, margin)) return false;
        return true;
    };
    Camera camera;
    {
        const float yfov = rng.range(0.6f, 1.2f);
        glm::vec3 eye(0.0f), target(0.0f);
        bool ok = false;
        for (int attempt = 0; attempt < 64 && !ok; ++attempt) {
            const Footprint& look = objects[static_cast<size_t>(rng.below(static_cast<int>(objects.size())))];
            target = look.center / s + glm::vec3(rng.range(-0.5f, 0.5f), rng.range(-0.3f, 0.6f), rng.range(-0.5f, 0.5f));
            if (!outside) {
                eye = glm::vec3(rng.range(-w / 2 + 0.4f, w / 2 - 0.4f), rng.range(0.5f, std::min(h - 0.4f, 2.5f)),
                                room == Room::open ? rng.range(-d / 2 + 1.0f, d / 2 + 0.5f) : rng.range(-d / 2 + 0.4f, d / 2 - 0.4f));
            } else {
                // Around the room (or the objects) from 1.2 to 2.2 room radii, 5 to 45 degrees up,
                // from the open side for an open room.
                const float az = room == Room::open ? rng.range(-1.1f, 1.1f) : rng.range(-kPi, kPi);
                const float el = rng.range(0.09f, 0.8f);
                const glm::vec3 dir(std::sin(az) * std::cos(el), std::sin(el), std::cos(az) * std::cos(el));
                if (room == Room::none) {
                    // Framing the objects' bounding sphere, from just inside it to a little beyond.
                    glm::vec3 c(0.0f);
                    for (const Footprint& o : objects) c += o.center / s / static_cast<float>(objects.size());
                    float r = 0.0f;
                    for (const Footprint& o : objects) r = std::max(r, glm::length(o.center / s - c) + glm::length(o.half / s));
                    eye = c + dir * (r / std::sin(0.5f * yfov) * rng.range(0.7f, 1.4f));
                    target = c + (target - c) * 0.3f;
                } else {
                    eye = dir * (rng.range(1.2f, 2.2f) * 0.5f * std::sqrt(w * w + d * d + h * h));
                }
                if (room == Room::closed) target = glm::vec3(0.0f, 0.5f * h, 0.0f);
            }
            ok = clear_of_solids(eye * s, 3.0f * znear + 0.2f * s) && glm::length(target - eye) > 0.5f;
            // Outside a closed room means outside its walls' outer box.
            if (outside && room == Room::closed)
                ok = ok && glm::any(glm::greaterThan(glm::abs(eye - glm::vec3(0.0f, 0.5f * h, 0.0f)), glm::vec3(w / 2 + t + 0.3f, h / 2 + t + 0.3f, d / 2 + t + 0.3f)));
        }
        if (!ok && outside) {  // in front of the room, looking at its middle
            eye = glm::vec3(0.0f, 0.6f * h, d / 2 + 3.0f);
            target = glm::vec3(0.0f, 0.5f * h, 0.0f);
        } else if (!ok) {  // above the objects near the front wall, looking down the room
            eye = glm::vec3(0.0f, std::min(h - 0.4f, top + 0.6f), d / 2 - 0.5f);
            target = glm::vec3(0.0f, 0.3f, -d / 2);
        }
        camera = look_camera(outside ? "outside" : "inside", eye * s, target * s, yfov, znear);
    }
    const glm::vec3 eye = glm::vec3(camera.world[3]);
    b.scene.cameras.push_back(camera);

    // Lights. Inside a closed room (with the camera inside) only point, spot and quad emitters
    // light anything; seen from outside, a closed room is lit by the sun, the sky or a point lamp
    // outside it. Elsewhere any kind.
    enum Type { point, spot, directional, emitter, environment };
    std::vector<Type> allowed;
    if (room == Room::closed && !outside) allowed = {point, spot, emitter};
    else if (room == Room::closed) allowed = {point, directional, environment};
    else allowed = {point, spot, directional, emitter, environment};
    const int lights = 1 + rng.below(3);
    // The point lit lights aim at: the middle of the objects' floor, in units of s.
    glm::vec3 focus(0.0f);
    for (const Footprint& o : objects) focus += o.center / s / static_cast<float>(objects.size());
    focus.y = has_floor ? 0.0f : focus.y;
    bool have_environment = false, have_directional = false;
    for (int i = 0; i < lights; ++i) {
        Type type = allowed[static_cast<size_t>(rng.below(static_cast<int>(allowed.size())))];
        if (type == environment && have_environment) type = point;
        if (type == directional && have_directional) type = point;
        const float irradiance = rng.range(1.0f, 4.0f) / static_cast<float>(lights);  // W/m^2 at the focus
        const std::string name = "light_" + std::to_string(i);
        // A position for point and spot lights and emitters: inside the room near its ceiling, or
        // above the objects; outside a closed room, around it.
        auto lamp_position = [&](float clearance) {
            glm::vec3 p(0.0f);
            for (int attempt = 0; attempt < 64; ++attempt) {
                if (room == Room::closed && outside) {
                    const float az = rng.range(-kPi, kPi);
                    p = glm::vec3(std::sin(az) * (0.5f * w + 1.5f), rng.range(0.5f, 1.2f) * h, std::cos(az) * (0.5f * d + 1.5f));
                } else if (room == Room::closed) {
                    p = glm::vec3(rng.range(-w / 2 + 0.5f, w / 2 - 0.5f), rng.range(0.6f, 0.9f) * h, rng.range(-d / 2 + 0.5f, d / 2 - 0.5f));
                } else {
                    p = glm::vec3(rng.range(-w / 2, w / 2), rng.range(std::max(top + 0.5f, 1.5f), std::max(top + 0.5f, 1.5f) + 2.5f),
                                  rng.range(-d / 2 + 0.3f, d / 2));
                }
                if (clear_of_solids(p * s, clearance * s)) return p;
            }
            return glm::vec3(0.0f, room == Room::closed ? 0.85f * h : top + 1.0f, 0.0f);
        };
        Light l;
        l.color = light_colour(rng);
        switch (type) {
            case point:
            case spot: {
                const glm::vec3 p = lamp_position(0.2f);
                const float dist = std::max(glm::length(p - focus), 0.5f);
                l.type = type == point ? LightType::point : LightType::spot;
                l.intensity = irradiance * dist * dist * s * s;  // W/sr: irradiance * d^2 at the focus
                glm::vec3 dir(0, -1, 0);
                if (type == spot) {
                    l.outer_cone = rng.range(0.35f, 0.9f);
                    l.inner_cone = l.outer_cone * rng.range(0.4f, 0.9f);
                    const Footprint& o = objects[static_cast<size_t>(rng.below(static_cast<int>(objects.size())))];
                    dir = o.center / s - p;
                }
                b.light(name, l, aim(p * s, dir));
                break;
            }
            case directional: {
                have_directional = true;
                const float az = rng.range(-kPi, kPi), el = rng.range(0.45f, 1.3f);
                l.type = LightType::directional;
                l.intensity = irradiance;
                b.light(name, l, aim(glm::vec3(0.0f), -glm::vec3(std::sin(az) * std::cos(el), std::sin(el), std::cos(az) * std::cos(el))));
                break;
            }
            case environment: {
                have_environment = true;
                // Uniform radiance L gives an unoccluded upward surface an irradiance of pi L.
                b.scene.environment.radiance = glm::vec3(0.85f, 0.92f, 1.0f) * (irradiance / kPi) * rng.range(0.5f, 1.5f);
                break;
            }
            case emitter: {
                // A one-sided quad facing down (its back to the ceiling in a closed room), its
                // radiance set for the irradiance at the focus (E = L A cos cos / d^2, the 1.5 for
                // the cosines off its axis) and at least 2 (an HDR emitter).
                const float ew = rng.range(0.4f, 1.5f), ed = rng.range(0.4f, 1.5f);
                glm::vec3 p = lamp_position(0.3f);
                if (room == Room::closed) p.y = h - 0.02f;
                else p.y = std::max(p.y, top + 0.8f);
                const float dist = std::max(glm::length(p - focus), 0.5f);
                const float area = ew * ed;
                Material m;
                m.name = "emitter_" + std::to_string(i);
                m.base_color = glm::vec4(0.0f, 0.0f, 0.0f, 1.0f);
                m.metallic = 0.0f;
                m.roughness = 1.0f;
                m.emissive = l.color;
                m.emissive_strength = std::max(2.0f, irradiance * dist * dist / area * 1.5f);
                const int mat = b.material(m);
                Primitive q;
                append_quad(q, glm::vec3(p.x - ew / 2, p.y, p.z - ed / 2) * s, glm::vec3(ew, 0, 0) * s, glm::vec3(0, 0, ed) * s);
                b.mesh_node(name, std::move(q), mat);
                // The camera must see its front: below it (it faces -Y).
                if (eye.y >= p.y * s - znear) {
                    // Raise the quad above the camera (outside views of open scenes look down).
                    const float raise = eye.y / s - p.y + 0.5f;
                    Node& n = b.scene.nodes.back();
                    n.local = glm::translate(glm::mat4(1.0f), glm::vec3(0.0f, raise * s, 0.0f));
                    const float d2 = dist + raise;
                    b.scene.materials[static_cast<size_t>(mat)].emissive_strength = std::max(2.0f, irradiance * d2 * d2 / area * 1.5f);
                }
                break;
            }
        }
    }
    b.scene.update_world_transforms();
    return std::move(b.scene);
}

}  // namespace candela
