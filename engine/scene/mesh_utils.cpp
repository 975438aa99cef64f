#include "scene/mesh_utils.hpp"

#include <algorithm>
#include <cmath>

namespace candela {
namespace {

glm::vec3 face_normal_area(const glm::vec3& a, const glm::vec3& b, const glm::vec3& c) {
    return glm::cross(b - a, c - a);  // length = 2 * area
}

bool finite(const glm::vec3& v) { return std::isfinite(v.x) && std::isfinite(v.y) && std::isfinite(v.z); }

// v / |v|, or `fallback` when v has no direction (no component above `tiny`, or not finite).
// Scaled by its largest component first: a vector of denormal or huge components has a length
// whose float square underflows or overflows, and dividing by that length does not give a unit
// vector.
glm::vec3 unit_or(const glm::vec3& v, const glm::vec3& fallback, float tiny = 0.0f) {
    if (!finite(v)) return fallback;
    const float m = std::max(std::fabs(v.x), std::max(std::fabs(v.y), std::fabs(v.z)));
    if (!(m > tiny)) return fallback;
    const glm::vec3 u = v / m;  // largest component +-1: the length lies in [1, sqrt 3]
    return u / glm::length(u);
}

glm::vec3 any_perpendicular(const glm::vec3& n) {
    const glm::vec3 a = std::fabs(n.x) < 0.9f ? glm::vec3(1, 0, 0) : glm::vec3(0, 1, 0);
    return glm::normalize(glm::cross(n, a));
}

}  // namespace

void generate_flat_normals(Primitive& primitive) {
    std::vector<Vertex> out;
    out.reserve(primitive.indices.size());
    for (size_t t = 0; t + 2 < primitive.indices.size(); t += 3) {
        Vertex v[3];
        for (int k = 0; k < 3; ++k) v[k] = primitive.vertices[primitive.indices[t + static_cast<size_t>(k)]];
        const glm::vec3 n = unit_or(face_normal_area(v[0].position, v[1].position, v[2].position), glm::vec3(0, 0, 1));
        for (auto& vertex : v) {
            vertex.normal = n;
            out.push_back(vertex);
        }
    }
    primitive.vertices = std::move(out);
    for (size_t i = 0; i < primitive.indices.size(); ++i) primitive.indices[i] = static_cast<uint32_t>(i);
}

void generate_smooth_normals(Primitive& primitive) {
    std::vector<glm::vec3> sum(primitive.vertices.size(), glm::vec3(0.0f));
    for (size_t t = 0; t + 2 < primitive.indices.size(); t += 3) {
        const uint32_t i0 = primitive.indices[t], i1 = primitive.indices[t + 1], i2 = primitive.indices[t + 2];
        const glm::vec3 n = face_normal_area(primitive.vertices[i0].position, primitive.vertices[i1].position,
                                             primitive.vertices[i2].position);
        if (!finite(n)) continue;
        sum[i0] += n, sum[i1] += n, sum[i2] += n;
    }
    for (size_t i = 0; i < sum.size(); ++i) primitive.vertices[i].normal = unit_or(sum[i], glm::vec3(0, 0, 1));
}

void generate_tangents(Primitive& primitive, int texcoord) {
    const size_t n = primitive.vertices.size();
    std::vector<glm::vec3> tan(n, glm::vec3(0.0f)), bitan(n, glm::vec3(0.0f));
    // glTF normal maps have +Y towards the top of the image, which is decreasing v: the
    // bitangent follows -v, so v is negated here.
    auto uv = [&](uint32_t i) {
        const glm::vec2 t = texcoord == 1 ? primitive.vertices[i].uv1 : primitive.vertices[i].uv0;
        return glm::vec2(t.x, -t.y);
    };
    for (size_t t = 0; t + 2 < primitive.indices.size(); t += 3) {
        const uint32_t i[3] = {primitive.indices[t], primitive.indices[t + 1], primitive.indices[t + 2]};
        const glm::vec3 e1 = primitive.vertices[i[1]].position - primitive.vertices[i[0]].position;
        const glm::vec3 e2 = primitive.vertices[i[2]].position - primitive.vertices[i[0]].position;
        const glm::vec2 d1 = uv(i[1]) - uv(i[0]);
        const glm::vec2 d2 = uv(i[2]) - uv(i[0]);
        const float det = d1.x * d2.y - d2.x * d1.y;
        if (std::fabs(det) < 1e-20f) continue;
        const float r = 1.0f / det;
        const glm::vec3 s = (e1 * d2.y - e2 * d1.y) * r;
        const glm::vec3 b = (e2 * d1.x - e1 * d2.x) * r;
        if (!finite(s) || !finite(b)) continue;
        for (uint32_t k : i) tan[k] += s, bitan[k] += b;
    }
    for (size_t k = 0; k < n; ++k) {
        const glm::vec3 nrm = primitive.vertices[k].normal;
        const glm::vec3 t = unit_or(tan[k] - nrm * glm::dot(nrm, tan[k]), any_perpendicular(nrm), 1e-12f);
        const float w = glm::dot(glm::cross(nrm, t), bitan[k]) < 0.0f ? -1.0f : 1.0f;
        primitive.vertices[k].tangent = glm::vec4(t, w);
    }
}

int repair_normals(Primitive& primitive) {
    int repaired = 0;
    std::vector<glm::vec3> face(primitive.vertices.size(), glm::vec3(0.0f));
    for (size_t t = 0; t + 2 < primitive.indices.size(); t += 3) {
        const uint32_t i0 = primitive.indices[t], i1 = primitive.indices[t + 1], i2 = primitive.indices[t + 2];
        const glm::vec3 n = face_normal_area(primitive.vertices[i0].position, primitive.vertices[i1].position,
                                             primitive.vertices[i2].position);
        if (finite(n)) face[i0] += n, face[i1] += n, face[i2] += n;
    }
    for (size_t i = 0; i < primitive.vertices.size(); ++i) {
        glm::vec3& normal = primitive.vertices[i].normal;
        const glm::vec3 given = unit_or(normal, glm::vec3(0.0f), 1e-12f);  // below: zero-length
        if (given != glm::vec3(0.0f)) {
            normal = given;
            continue;
        }
        normal = unit_or(face[i], glm::vec3(0, 0, 1));
        ++repaired;
    }
    return repaired;
}

void compute_bounds(Primitive& primitive) {
    primitive.bounds = Bounds{};
    for (const Vertex& v : primitive.vertices) primitive.bounds.extend(v.position);
}

}  // namespace candela
