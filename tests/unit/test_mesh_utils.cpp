#include <gtest/gtest.h>

#include <cmath>

#include "scene/mesh_utils.hpp"

namespace candela {
namespace {

Primitive roof() {
    // Two triangles sharing the edge (0,0,0)-(0,0,-1), folded 90 degrees along it.
    Primitive p;
    p.vertices.resize(4);
    p.vertices[0].position = {0, 0, 0};
    p.vertices[1].position = {0, 0, -1};
    p.vertices[2].position = {-1, -1, 0};
    p.vertices[3].position = {1, -1, 0};
    p.indices = {0, 1, 2, 0, 3, 1};
    return p;
}

TEST(MeshUtils, FlatNormalsAreFaceNormals) {
    Primitive p = roof();
    generate_flat_normals(p);
    ASSERT_EQ(p.vertices.size(), 6u);
    const glm::vec3 left = p.vertices[0].normal, right = p.vertices[3].normal;
    EXPECT_NEAR(glm::length(left), 1.0f, 1e-6f);
    EXPECT_NEAR(glm::dot(left, right), 0.0f, 1e-6f);  // the roof folds by 90 degrees
    EXPECT_GT(left.y, 0.0f);
}

TEST(MeshUtils, SmoothNormalsAverageAtSharedVertices) {
    Primitive p = roof();
    generate_smooth_normals(p);
    // The ridge vertices get the mean of both faces: straight up.
    EXPECT_NEAR(p.vertices[0].normal.x, 0.0f, 1e-6f);
    EXPECT_NEAR(p.vertices[0].normal.y, 1.0f, 1e-6f);
    // The eaves keep their own face's normal.
    EXPECT_NEAR(p.vertices[2].normal.x, -std::sqrt(0.5f), 1e-6f);
}

TEST(MeshUtils, TangentsFollowUAndGltfNormalMapHandedness) {
    Primitive p;
    p.vertices.resize(4);
    const glm::vec3 pos[4] = {{-1, -1, 0}, {1, -1, 0}, {1, 1, 0}, {-1, 1, 0}};
    const glm::vec2 uv[4] = {{0, 1}, {1, 1}, {1, 0}, {0, 0}};  // v grows downwards, as in glTF
    for (int i = 0; i < 4; ++i) {
        p.vertices[static_cast<size_t>(i)].position = pos[i];
        p.vertices[static_cast<size_t>(i)].normal = {0, 0, 1};
        p.vertices[static_cast<size_t>(i)].uv0 = uv[i];
    }
    p.indices = {0, 1, 2, 0, 2, 3};
    generate_tangents(p, 0);
    for (const Vertex& v : p.vertices) {
        EXPECT_NEAR(v.tangent.x, 1.0f, 1e-6f);
        const glm::vec3 bitangent = glm::cross(v.normal, glm::vec3(v.tangent)) * v.tangent.w;
        EXPECT_NEAR(bitangent.y, 1.0f, 1e-6f);  // towards the top of the image
    }
}

TEST(MeshUtils, DegenerateUvsStillGivePerpendicularTangents) {
    Primitive p = roof();
    generate_smooth_normals(p);
    generate_tangents(p, 0);  // all UVs are zero
    for (const Vertex& v : p.vertices) {
        EXPECT_NEAR(glm::dot(glm::vec3(v.tangent), v.normal), 0.0f, 1e-5f);
        EXPECT_NEAR(glm::length(glm::vec3(v.tangent)), 1.0f, 1e-5f);
    }
}

TEST(MeshUtils, RepairReplacesZeroAndNanNormals) {
    Primitive p = roof();
    generate_smooth_normals(p);
    p.vertices[1].normal = glm::vec3(0.0f);
    p.vertices[2].normal = glm::vec3(NAN, 0, 0);
    EXPECT_EQ(repair_normals(p), 2);
    for (const Vertex& v : p.vertices) EXPECT_NEAR(glm::length(v.normal), 1.0f, 1e-5f);
}

}  // namespace
}  // namespace candela
