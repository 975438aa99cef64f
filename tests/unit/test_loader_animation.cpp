// Loader, animation: node TRS, skins (JOINTS_n/WEIGHTS_n sets, inverse bind matrices), morph
// targets and animations as the file gives them; the rejections (exit 2, the file and the JSON
// path named); meshes duplicated per deformed instance; the rest pose applied at load.
// Test data: tests/data/models (Khronos samples) and tests/data/animation (written for these
// tests by make_animation_data.py there).
#include <gtest/gtest.h>
#include <unistd.h>

#include <fstream>
#include <functional>

#include <nlohmann/json.hpp>

#include "core/error.hpp"
#include "core/log.hpp"
#include "scene/animation.hpp"
#include "scene/gltf_loader.hpp"
#include "gltf_builder.hpp"

#ifndef CANDELA_SOURCE_DIR
#error "CANDELA_SOURCE_DIR must be defined by the build"
#endif

namespace candela {
namespace {

namespace fs = std::filesystem;
const fs::path kModels = fs::path(CANDELA_SOURCE_DIR) / "tests" / "data" / "models";
const fs::path kData = fs::path(CANDELA_SOURCE_DIR) / "tests" / "data" / "animation";

struct Loaded {
    Scene scene;
    int warnings = 0;
    std::string err;
};
Loaded load_capturing(const fs::path& file) {
    const log::Level saved = log::level();
    log::set_level(log::Level::warn);
    testing::internal::CaptureStderr();
    const int before = log::warning_count();
    Loaded out;
    try {
        out.scene = load_gltf(file);
    } catch (...) {
        testing::internal::GetCapturedStderr();
        log::set_level(saved);
        throw;
    }
    out.warnings = log::warning_count() - before;
    out.err = testing::internal::GetCapturedStderr();
    log::set_level(saved);
    return out;
}

std::string load_error(const fs::path& path) {
    const log::Level saved = log::level();
    log::set_level(log::Level::quiet);
    std::string message;
    try {
        load_gltf(path);
        ADD_FAILURE() << path << " loaded but should not";
    } catch (const Error& e) {
        EXPECT_EQ(e.code(), ExitCode::bad_input) << e.what();
        message = e.what();
    }
    log::set_level(saved);
    return message;
}

// A copy of one of the test files with its JSON changed (the buffers are embedded data: URIs).
fs::path edited(const std::string& file, const std::string& as, const std::function<void(nlohmann::json&)>& edit) {
    nlohmann::json doc = nlohmann::json::parse(std::ifstream(kData / file));
    edit(doc);
    const fs::path dir = test::test_root() / "anim_edits";
    fs::create_directories(dir);
    const fs::path out = dir / as;
    std::ofstream(out) << doc.dump();
    return out;
}

const Animation& animation_named(const Scene& scene, const std::string& name) {
    return scene.animations[static_cast<size_t>(find_animation(scene, name))];
}

size_t deformable_primitives(const Scene& scene) {
    size_t n = 0;
    for (const Mesh& m : scene.meshes)
        for (const Primitive& p : m.primitives) n += p.deformable();
    return n;
}

// ---- the Khronos sample models ----

TEST(LoaderAnimation, FoxHasItsSkinAndThreeAnimations) {
    const Loaded fox = load_capturing(kModels / "Fox" / "Fox.glb");
    EXPECT_TRUE(fox.scene.ignored.empty());
    EXPECT_EQ(fox.warnings, 0) << fox.err;
    ASSERT_EQ(fox.scene.skins.size(), 1u);
    EXPECT_EQ(fox.scene.skins[0].joints.size(), 24u);
    EXPECT_EQ(fox.scene.skins[0].inverse_bind.size(), 24u);
    ASSERT_EQ(fox.scene.animations.size(), 3u);
    // Names and durations (the last keyframe, as the file's accessor max gives them).
    const std::pair<const char*, float> expected[] = {{"Survey", 3.4166667f}, {"Walk", 0.7083333f}, {"Run", 1.1583333f}};
    for (size_t i = 0; i < 3; ++i) {
        EXPECT_EQ(fox.scene.animations[i].name, expected[i].first);
        EXPECT_NEAR(fox.scene.animations[i].end, expected[i].second, 1e-4f) << expected[i].first;
        EXPECT_GE(fox.scene.animations[i].start, 0.0f);
        EXPECT_EQ(fox.scene.animations[i].channels.size(), 21u);  // rotations of the 24 joints' animated ones
    }
    ASSERT_EQ(fox.scene.meshes.size(), 1u);
    const Primitive& p = fox.scene.meshes[0].primitives[0];
    EXPECT_EQ(p.influence_sets, 1);
    EXPECT_TRUE(p.deformable());
    EXPECT_EQ(p.rest.size(), p.vertices.size());
    EXPECT_EQ(p.joints.size(), p.vertices.size());
    EXPECT_EQ(p.weights.size(), p.vertices.size());
    int skinned_node = -1;
    for (size_t i = 0; i < fox.scene.nodes.size(); ++i)
        if (fox.scene.nodes[i].skin == 0) skinned_node = static_cast<int>(i);
    ASSERT_GE(skinned_node, 0);
    EXPECT_EQ(fox.scene.nodes[static_cast<size_t>(skinned_node)].mesh, 0);
    for (const glm::vec4& w : p.weights) {
        const float sum = w.x + w.y + w.z + w.w;
        ASSERT_TRUE(sum == 0.0f || std::fabs(sum - 1.0f) < 1e-5f) << sum;
    }
}

TEST(LoaderAnimation, RiggedModelsHaveTheirSkins) {
    const Loaded simple = load_capturing(kModels / "RiggedSimple" / "RiggedSimple.glb");
    EXPECT_EQ(simple.warnings, 0) << simple.err;
    ASSERT_EQ(simple.scene.skins.size(), 1u);
    EXPECT_EQ(simple.scene.skins[0].name, "Armature");
    EXPECT_EQ(simple.scene.skins[0].joints.size(), 2u);
    ASSERT_EQ(simple.scene.animations.size(), 1u);
    EXPECT_EQ(simple.scene.animations[0].name, "animations[0]");  // unnamed in the file
    EXPECT_NEAR(simple.scene.animations[0].start, 1.0f / 24.0f, 1e-5f);
    EXPECT_NEAR(simple.scene.animations[0].end, 50.0f / 24.0f, 1e-4f);
    EXPECT_EQ(deformable_primitives(simple.scene), 1u);

    // RiggedFigure's exporter wrote weights that do not sum to 1: normalised, with one warning.
    const Loaded figure = load_capturing(kModels / "RiggedFigure" / "RiggedFigure.glb");
    ASSERT_EQ(figure.scene.skins.size(), 1u);
    EXPECT_EQ(figure.scene.skins[0].joints.size(), 19u);
    ASSERT_EQ(figure.scene.animations.size(), 1u);
    EXPECT_NEAR(figure.scene.animations[0].end, 1.25f, 1e-4f);
    EXPECT_EQ(figure.scene.animations[0].channels.size(), 57u);
    EXPECT_EQ(figure.warnings, 1) << figure.err;
    EXPECT_NE(figure.err.find("RiggedFigure.glb: meshes[0].primitives[0].attributes.WEIGHTS_0: the skin weights of 31 of 370 vertices do not sum to 1"),
              std::string::npos)
        << figure.err;
    EXPECT_EQ(figure.scene.meshes[0].primitives[0].influence_sets, 1);
}

TEST(LoaderAnimation, MorphModelsHaveTheirTargetsAndWeights) {
    const Loaded simple = load_capturing(kModels / "SimpleMorph" / "SimpleMorph.gltf");
    EXPECT_EQ(simple.warnings, 0) << simple.err;
    ASSERT_EQ(simple.scene.meshes.size(), 1u);
    EXPECT_EQ(simple.scene.meshes[0].weights, (std::vector<float>{0.5f, 0.5f}));
    EXPECT_EQ(simple.scene.meshes[0].primitives[0].targets.size(), 2u);
    EXPECT_EQ(simple.scene.nodes[0].rest_weights, (std::vector<float>{0.5f, 0.5f}));  // the node has none: the mesh's
    EXPECT_EQ(simple.scene.nodes[0].weights, simple.scene.nodes[0].rest_weights);
    ASSERT_EQ(simple.scene.animations.size(), 1u);
    EXPECT_EQ(simple.scene.animations[0].samplers[0].width, 2);  // weights: one per target
    EXPECT_NEAR(simple.scene.animations[0].end, 4.0f, 1e-5f);

    const Loaded cube = load_capturing(kModels / "AnimatedMorphCube" / "AnimatedMorphCube.glb");
    EXPECT_TRUE(cube.scene.ignored.empty());
    EXPECT_EQ(cube.warnings, 0) << cube.err;
    ASSERT_EQ(cube.scene.animations.size(), 1u);
    EXPECT_EQ(cube.scene.animations[0].name, "Square");
    EXPECT_EQ(cube.scene.meshes[0].primitives[0].targets.size(), 2u);
    EXPECT_EQ(cube.scene.meshes[0].weights.size(), 2u);

    const Loaded stress = load_capturing(kModels / "MorphStressTest" / "MorphStressTest.gltf");
    EXPECT_EQ(stress.warnings, 0) << stress.err;
    EXPECT_EQ(stress.scene.animations.size(), 3u);
    for (const Primitive& p : stress.scene.meshes[0].primitives) EXPECT_EQ(p.targets.size(), 8u);
    EXPECT_EQ(stress.scene.meshes[0].weights.size(), 8u);
    EXPECT_EQ(animation_named(stress.scene, "TheWave").samplers[0].width, 8);
}

TEST(LoaderAnimation, BoxAnimatedIsRigidNodeAnimation) {
    const Loaded box = load_capturing(kModels / "BoxAnimated" / "BoxAnimated.glb");
    EXPECT_EQ(box.warnings, 0) << box.err;
    EXPECT_TRUE(box.scene.skins.empty());
    EXPECT_EQ(deformable_primitives(box.scene), 0u);
    ASSERT_EQ(box.scene.animations.size(), 1u);
    EXPECT_EQ(box.scene.animations[0].channels.size(), 2u);
    EXPECT_NEAR(box.scene.animations[0].end, 3.7083333f, 1e-4f);
    for (const AnimationChannel& c : box.scene.animations[0].channels) {
        const Node& n = box.scene.nodes[static_cast<size_t>(c.node)];
        EXPECT_FALSE(n.has_matrix);
        const AnimationSampler& s = box.scene.animations[0].samplers[static_cast<size_t>(c.sampler)];
        EXPECT_EQ(s.width, c.path == AnimationPath::rotation ? 4 : 3);
        EXPECT_EQ(s.values.size(), s.times.size() * static_cast<size_t>(s.width));
    }
}

// ---- the hand-written files ----

TEST(LoaderAnimation, TwoBoneBarAsWritten) {
    const Loaded bar = load_capturing(kData / "two_bone_bar.gltf");
    EXPECT_EQ(bar.warnings, 0) << bar.err;
    const Scene& s = bar.scene;
    // Node TRS.
    ASSERT_EQ(s.nodes.size(), 3u);
    EXPECT_EQ(s.nodes[2].translation, glm::vec3(0, 1, 0));
    EXPECT_EQ(s.nodes[2].scale, glm::vec3(1));
    EXPECT_FALSE(s.nodes[2].has_matrix);
    EXPECT_EQ(s.nodes[0].skin, 0);
    // Skin.
    ASSERT_EQ(s.skins.size(), 1u);
    EXPECT_EQ(s.skins[0].name, "bar skin");
    EXPECT_EQ(s.skins[0].joints, (std::vector<int>{1, 2}));
    EXPECT_EQ(s.skins[0].skeleton, 1);
    EXPECT_EQ(s.skins[0].inverse_bind[0], glm::mat4(1.0f));
    EXPECT_EQ(s.skins[0].inverse_bind[1][3], glm::vec4(0, -1, 0, 1));
    // Two influence sets: JOINTS_0 ubyte/WEIGHTS_0 float, JOINTS_1 ushort/WEIGHTS_1 normalised ushort.
    const Primitive& p = s.meshes[0].primitives[0];
    ASSERT_EQ(p.influence_sets, 2);
    ASSERT_EQ(p.joints.size(), 12u);
    ASSERT_EQ(p.weights.size(), 12u);
    EXPECT_EQ(p.joints[2 * 2 + 1], glm::u16vec4(1, 0, 0, 0));  // vertex 2, set 1
    EXPECT_NEAR(p.weights[2 * 2 + 0].x, 0.5f, 1e-4f);
    EXPECT_NEAR(p.weights[2 * 2 + 1].x, 0.5f, 1e-4f);
    EXPECT_NEAR(p.weights[5 * 2 + 1].x, 1.0f, 1e-6f);
    // Rest pose: every joint at its bind pose, so the posed vertices are the file's.
    ASSERT_EQ(p.rest.size(), 6u);
    for (size_t v = 0; v < 6; ++v) EXPECT_LT(glm::length(p.vertices[v].position - p.rest[v].position), 1e-6f) << v;
    EXPECT_EQ(p.rest[5].position, glm::vec3(0.25f, 2.0f, 0.0f));
    // Animations: one per interpolation.
    ASSERT_EQ(s.animations.size(), 3u);
    const Animation& bend = animation_named(s, "bend");
    ASSERT_EQ(bend.channels.size(), 1u);
    EXPECT_EQ(bend.channels[0].node, 2);
    EXPECT_EQ(bend.channels[0].path, AnimationPath::rotation);
    EXPECT_EQ(bend.samplers[0].interpolation, Interpolation::linear);
    EXPECT_EQ(bend.samplers[0].width, 4);
    EXPECT_EQ(bend.samplers[0].times, (std::vector<float>{0.0f, 1.0f}));
    const Animation& wave = animation_named(s, "wave");
    EXPECT_EQ(wave.samplers[0].interpolation, Interpolation::cubic_spline);
    EXPECT_EQ(wave.samplers[0].values.size(), 2u * 3u * 3u);  // 2 keyframes x (in, value, out) x vec3
    EXPECT_EQ(wave.end, 2.0f);
    const Animation& blink = animation_named(s, "blink");
    EXPECT_EQ(blink.samplers[0].interpolation, Interpolation::step);
    EXPECT_EQ(blink.start, 0.5f);
    EXPECT_EQ(blink.end, 1.5f);
}

TEST(LoaderAnimation, TwoBoneBarBendsWhenPosed) {
    Scene s = load_gltf(kData / "two_bone_bar.gltf");
    pose_scene(s, find_animation(s, "bend"), 1.0f);  // the tip joint turned 90 degrees about +Z at y = 1
    const std::vector<Vertex>& v = s.meshes[0].primitives[0].vertices;
    EXPECT_LT(glm::distance(v[0].position, glm::vec3(-0.25f, 0, 0)), 1e-5f);       // joint 0 only
    EXPECT_LT(glm::distance(v[4].position, glm::vec3(-1.0f, 0.75f, 0)), 1e-5f);    // joint 1 only
    EXPECT_LT(glm::distance(v[5].position, glm::vec3(-1.0f, 1.25f, 0)), 1e-5f);
    EXPECT_LT(glm::distance(v[3].position, glm::vec3(0.125f, 1.125f, 0)), 1e-4f);  // half and half (linear blend)
}

TEST(LoaderAnimation, WeightsAreNormalisedWithOneWarning) {
    const Loaded l = load_capturing(kData / "weights_unnormalised.gltf");
    EXPECT_EQ(l.warnings, 1) << l.err;
    EXPECT_NE(l.err.find("weights_unnormalised.gltf: meshes[0].primitives[0].attributes.WEIGHTS_0: the skin weights of 5 of 6 vertices do not sum to 1"),
              std::string::npos)
        << l.err;
    const Primitive& p = l.scene.meshes[0].primitives[0];
    for (size_t v = 0; v < 5; ++v) {
        const float sum = glm::dot(p.weights[v * 2] + p.weights[v * 2 + 1], glm::vec4(1.0f));
        EXPECT_NEAR(sum, 1.0f, 1e-6f) << v;
    }
    EXPECT_EQ(p.weights[5 * 2] + p.weights[5 * 2 + 1], glm::vec4(0.0f));  // all zero: left so
    EXPECT_NEAR(p.weights[2 * 2].x, 0.5f, 1e-4f);
    // The unbound vertex stays where the file puts it (in the node's space), also when posed.
    Scene s = l.scene;
    pose_scene(s, find_animation(s, "bend"), 1.0f);
    EXPECT_EQ(s.meshes[0].primitives[0].vertices[5].position, glm::vec3(0.25f, 2.0f, 0.0f));
}

TEST(LoaderAnimation, MeshOfASkinnedAndAnUnskinnedNodeIsDuplicated) {
    const Loaded l = load_capturing(kData / "shared_mesh.gltf");
    EXPECT_EQ(l.warnings, 0) << l.err;
    const Scene& s = l.scene;
    ASSERT_EQ(s.meshes.size(), 2u);
    const Node& skinned = s.nodes[0];
    const Node& rigid = s.nodes[3];
    ASSERT_EQ(skinned.skin, 0);
    ASSERT_EQ(rigid.skin, -1);
    ASSERT_NE(skinned.mesh, rigid.mesh);
    const Primitive& ps = s.meshes[static_cast<size_t>(skinned.mesh)].primitives[0];
    const Primitive& pr = s.meshes[static_cast<size_t>(rigid.mesh)].primitives[0];
    EXPECT_TRUE(ps.skinned());
    EXPECT_TRUE(ps.deformable());
    EXPECT_FALSE(pr.skinned());
    EXPECT_FALSE(pr.deformable());
    EXPECT_TRUE(pr.joints.empty());
    EXPECT_EQ(s.meshes[static_cast<size_t>(rigid.mesh)].name, "bar");
    // Posing bends only the skinned instance.
    Scene posed = s;
    pose_scene(posed, find_animation(posed, "bend"), 1.0f);
    EXPECT_GT(glm::distance(posed.meshes[static_cast<size_t>(skinned.mesh)].primitives[0].vertices[5].position, glm::vec3(0.25f, 2, 0)), 0.5f);
    EXPECT_EQ(posed.meshes[static_cast<size_t>(rigid.mesh)].primitives[0].vertices[5].position, glm::vec3(0.25f, 2, 0));
    EXPECT_EQ(posed.triangle_count(), 8u);
}

TEST(LoaderAnimation, MorphQuadAsWritten) {
    const Loaded l = load_capturing(kData / "morph_quad.gltf");
    EXPECT_EQ(l.warnings, 0) << l.err;
    const Scene& s = l.scene;
    // The second node has its own weights: its instance is a copy of the mesh.
    ASSERT_EQ(s.meshes.size(), 2u);
    ASSERT_NE(s.nodes[0].mesh, s.nodes[1].mesh);
    EXPECT_EQ(s.nodes[0].rest_weights, (std::vector<float>{0.25f, 0.0f}));  // the mesh's
    EXPECT_EQ(s.nodes[1].rest_weights, (std::vector<float>{0.0f, 1.0f}));   // its own
    const Mesh& m0 = s.meshes[static_cast<size_t>(s.nodes[0].mesh)];
    const Mesh& m1 = s.meshes[static_cast<size_t>(s.nodes[1].mesh)];
    EXPECT_EQ(m0.weights, (std::vector<float>{0.25f, 0.0f}));
    ASSERT_EQ(m0.primitives[0].targets.size(), 2u);
    const MorphTarget& lift = m0.primitives[0].targets[0];
    const MorphTarget& shift = m0.primitives[0].targets[1];  // a sparse accessor over zeros
    EXPECT_EQ(lift.position[2], glm::vec3(0, 0, 1));
    EXPECT_EQ(lift.normal.size(), 4u);
    EXPECT_TRUE(lift.tangent.empty());
    EXPECT_EQ(shift.position[0], glm::vec3(1, 0, 0));
    EXPECT_TRUE(shift.normal.empty());
    // The rest pose is morphed by each node's weights.
    EXPECT_NEAR(m0.primitives[0].vertices[2].position.z, 0.25f, 1e-6f);
    EXPECT_NEAR(m0.primitives[0].vertices[0].position.x, -1.0f, 1e-6f);
    EXPECT_NEAR(m1.primitives[0].vertices[0].position.x, 0.0f, 1e-6f);
    EXPECT_NEAR(m1.primitives[0].vertices[2].position.z, 0.0f, 1e-6f);
    EXPECT_EQ(m0.primitives[0].rest[2].position, glm::vec3(1, 1, 0));
    const Animation& pulse = animation_named(s, "pulse");
    EXPECT_EQ(pulse.channels[0].path, AnimationPath::weights);
    EXPECT_EQ(pulse.samplers[0].width, 2);
    EXPECT_EQ(pulse.samplers[0].values.size(), 6u);
}

TEST(LoaderAnimation, EachRejectionNamesTheFileAndTheJsonPath) {
    const nlohmann::json rejects = nlohmann::json::parse(std::ifstream(kData / "rejects.json"));
    ASSERT_GE(rejects.size(), 13u);
    for (const auto& [name, path] : rejects.items()) {
        SCOPED_TRACE(name);
        const std::string message = load_error(kData / (name + ".gltf"));
        EXPECT_NE(message.find(name + ".gltf: " + path.get<std::string>()), std::string::npos) << message;
    }
    // What each says, for the ones the issue names.
    EXPECT_NE(load_error(kData / "reject_times_not_increasing.gltf").find("not strictly increasing"), std::string::npos);
    EXPECT_NE(load_error(kData / "reject_nan_time.gltf").find("not a finite number"), std::string::npos);
    EXPECT_NE(load_error(kData / "reject_joint_out_of_range.gltf").find("joint 2 is out of range"), std::string::npos);
    EXPECT_NE(load_error(kData / "reject_too_few_inverse_bind_matrices.gltf").find("1 matrices for 2 joints"), std::string::npos);
    EXPECT_NE(load_error(kData / "reject_output_count.gltf").find("3 elements, 2 expected"), std::string::npos);
}

TEST(LoaderAnimation, ChannelOnAMatrixNodeIsDroppedWithAWarning) {
    const fs::path file = edited("two_bone_bar.gltf", "matrix_joint.gltf", [](nlohmann::json& d) {
        d["nodes"][2].erase("translation");
        d["nodes"][2]["matrix"] = {1, 0, 0, 0, 0, 1, 0, 0, 0, 0, 1, 0, 0, 1, 0, 1};
    });
    const Loaded l = load_capturing(file);
    EXPECT_TRUE(l.scene.nodes[2].has_matrix);
    EXPECT_TRUE(animation_named(l.scene, "bend").channels.empty());
    EXPECT_TRUE(animation_named(l.scene, "blink").channels.empty());
    EXPECT_EQ(animation_named(l.scene, "wave").channels.size(), 1u);  // node 1 has TRS
    EXPECT_NE(l.err.find("matrix_joint.gltf: animations[0].channels[0].target: node 2 has a matrix"), std::string::npos) << l.err;
    EXPECT_NE(l.err.find("(the channel is ignored)"), std::string::npos) << l.err;
    // The rest pose is still the file's.
    EXPECT_EQ(l.scene.meshes[0].primitives[0].vertices[5].position, glm::vec3(0.25f, 2, 0));
}

TEST(LoaderAnimation, AnimationPointerStaysAnIgnoredFeature) {
    const fs::path file = edited("two_bone_bar.gltf", "pointer.gltf", [](nlohmann::json& d) {
        d["animations"][0]["channels"][0]["target"] = {
            {"path", "pointer"}, {"extensions", {{"KHR_animation_pointer", {{"pointer", "/nodes/2/rotation"}}}}}};
        d["extensionsUsed"] = {"KHR_animation_pointer"};
    });
    const Loaded l = load_capturing(file);
    ASSERT_EQ(l.scene.ignored.size(), 1u);
    EXPECT_NE(l.scene.ignored[0].find("KHR_animation_pointer"), std::string::npos) << l.scene.ignored[0];
    EXPECT_NE(l.err.find("ignored (not implemented)"), std::string::npos) << l.err;
    EXPECT_TRUE(animation_named(l.scene, "bend").channels.empty());
    EXPECT_EQ(l.warnings, 1) << l.err;
}

TEST(LoaderAnimation, JointsWithoutASkinAreDrawnRigid) {
    const fs::path file = edited("two_bone_bar.gltf", "no_skin.gltf", [](nlohmann::json& d) { d["nodes"][0].erase("skin"); });
    const Loaded l = load_capturing(file);
    const Primitive& p = l.scene.meshes[0].primitives[0];
    EXPECT_FALSE(p.skinned());
    EXPECT_FALSE(p.deformable());
    EXPECT_TRUE(p.joints.empty());
}

TEST(LoaderAnimation, FlatNormalsKeepTheDeformationDataWithTheirCorners) {
    // Without NORMAL the loader unshares the vertices for flat normals: joints, weights and morph
    // deltas must follow their corners.
    const fs::path bar = edited("two_bone_bar.gltf", "bar_no_normals.gltf", [](nlohmann::json& d) {
        d["meshes"][0]["primitives"][0]["attributes"].erase("NORMAL");
    });
    Scene s = load_capturing(bar).scene;
    const Primitive& p = s.meshes[0].primitives[0];
    ASSERT_EQ(p.vertices.size(), 12u);  // 4 triangles, unshared
    ASSERT_EQ(p.joints.size(), 24u);
    for (size_t v = 0; v < 12; ++v) {
        const float y = p.rest[v].position.y;  // y = 0: joint 0 only, y = 2: joint 1 only
        const float w_set1 = p.weights[v * 2 + 1].x;
        EXPECT_NEAR(w_set1, y / 2.0f, 1e-4f) << v;
    }
    pose_scene(s, find_animation(s, "bend"), 1.0f);
    for (const Vertex& v : s.meshes[0].primitives[0].vertices)
        if (v.position.y > 1.5f) ADD_FAILURE() << "a tip vertex did not bend: " << v.position.x << " " << v.position.y;

    const fs::path quad = edited("morph_quad.gltf", "quad_no_normals.gltf", [](nlohmann::json& d) {
        d["meshes"][0]["primitives"][0]["attributes"].erase("NORMAL");
    });
    const Scene q = load_capturing(quad).scene;
    const Primitive& qp = q.meshes[static_cast<size_t>(q.nodes[0].mesh)].primitives[0];
    ASSERT_EQ(qp.vertices.size(), 6u);
    for (size_t v = 0; v < 6; ++v) {
        EXPECT_NEAR(qp.targets[0].position[v].z, qp.rest[v].position.y > 0 ? 1.0f : 0.0f, 1e-6f) << v;
        EXPECT_NEAR(qp.vertices[v].position.z, qp.rest[v].position.y > 0 ? 0.25f : 0.0f, 1e-6f) << v;
    }
    EXPECT_TRUE(qp.targets[0].normal.empty());  // no base NORMAL: generated normals are not morphed
}

}  // namespace
}  // namespace candela
