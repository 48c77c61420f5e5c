#include "gltf/gltf_loader.h"

#include <cstdint>
#include <limits>
#include <vector>

#include <Eigen/Core>
#include <gtest/gtest.h>

#include "gltf/gltf_test_support.h"

namespace rigsim::gltf_test {
namespace {

// A quad skinned to two joints: its lower edge follows joint 1 (at the origin), its upper edge
// joint 2, bound at (0, 1, 0) and at rest at (5, 1, 0). The mesh node's own translation does not
// apply (glTF: a skinned mesh is placed by its joints).
TEST(GltfLoader, SkinnedMeshesArePlacedByTheirJoints) {
  const TempDir dir;
  GltfBuilder g;
  const int pos = g.Positions(kUnitQuad);
  const int joints = g.Accessor<uint8_t>({0, 1, 0, 0, 0, 1, 0, 0, 0, 1, 0, 0, 0, 1, 0, 0}, kGltfUByte, "VEC4", 4);
  const int weights = g.Accessor<float>({1, 0, 0, 0, 1, 0, 0, 0, 0, 2, 0, 0, 0, 1, 0, 0}, kGltfFloat, "VEC4", 4);  // rescaled to sum 1
  const std::vector<float> ibm = {1, 0, 0, 0, 0, 1, 0, 0, 0, 0, 1, 0, 0, 0, 0, 1,     // joint 1: identity
                                  1, 0, 0, 0, 0, 1, 0, 0, 0, 0, 1, 0, 0, -1, 0, 1};   // joint 2: translate(0, -1, 0)
  const int ibm_acc = g.Accessor(ibm, kGltfFloat, "MAT4", 2);
  g.doc["skins"] = json::array({{{"joints", {1, 2}}, {"inverseBindMatrices", ibm_acc}}});
  g.Node({{"mesh", g.Mesh({{"POSITION", pos}, {"JOINTS_0", joints}, {"WEIGHTS_0", weights}}, -1, 6)},
          {"skin", 0}, {"translation", {100, 0, 0}}});
  g.Node({{"children", {2}}});
  g.Node({{"translation", {5, 1, 0}}});
  g.Scene({0, 1});
  const Scene s = LoadGltf(g.Write(dir, "skinned"));
  ASSERT_EQ(s.skins.size(), 1u);
  EXPECT_EQ(s.skins[0].joints, (std::vector<int>{1, 2}));
  ASSERT_EQ(s.meshes.size(), 1u);
  const SceneMesh& m = s.meshes[0];
  EXPECT_EQ(m.skin, 0);
  ASSERT_EQ(m.positions.size(), 4u);
  const Eigen::Vector3f expected[4] = {{0, 0, 0}, {1, 0, 0}, {6, 1, 0}, {5, 1, 0}};
  for (int i = 0; i < 4; ++i) EXPECT_TRUE(m.positions[i].isApprox(expected[i])) << i << ": " << m.positions[i].transpose();
  EXPECT_FALSE(HasWarning(s, "skin"));
  EXPECT_FALSE(HasWarning(s, "JOINTS_0"));

  g.doc["skins"][0]["joints"] = {1};  // vertex 2 weighs joint 1 of a skin that now has one
  ExpectLoadFails(g.Write(dir, "joint_beyond_skin"), "JOINTS_0): vertex 2 names joint 1 of a skin with 1");
  g.doc["skins"][0]["joints"] = {1, 2, 0};
  ExpectLoadFails(g.Write(dir, "short_ibm"), "skin 0: 2 inverse bind matrices for 3 joints");
  g.doc["skins"][0]["joints"] = {1, 2};
  g.doc["skins"][0].erase("inverseBindMatrices");  // glTF: identity matrices
  const Scene identity = LoadGltf(g.Write(dir, "no_ibm"));
  const Eigen::Vector3f unbound[4] = {{0, 0, 0}, {1, 0, 0}, {6, 2, 0}, {5, 2, 0}};  // joint 2 no longer moves down 1
  for (int i = 0; i < 4; ++i) {
    EXPECT_TRUE(identity.meshes[0].positions[i].isApprox(unbound[i])) << i << ": " << identity.meshes[0].positions[i].transpose();
  }
  EXPECT_FALSE(HasWarning(identity, "inverseBindMatrices"));
  g.doc["skins"][0]["inverseBindMatrices"] = ibm_acc;
  g.Scene({0});  // the joints' tree is left out of the scene
  ExpectLoadFails(g.Write(dir, "joints_outside_scene"), "skin 0: joint node 1 is not in the loaded scene");
}

TEST(GltfLoader, NodeAnimationsAreKeptForPosing) {
  const TempDir dir;
  GltfBuilder g;
  const int pos = g.Positions(kUnitQuad);
  const int idx = g.Accessor(std::vector<uint16_t>{0, 1, 2, 0, 2, 3}, kGltfUShort, "SCALAR", 6);
  g.Mesh({{"POSITION", pos}}, idx);
  // Parent (animated, translation) -> child with the mesh; a static mesh node beside them.
  g.Node({{"name", "parent"}, {"children", {1}}, {"translation", {0, 0, -5}}});
  g.Node({{"name", "child"}, {"mesh", 0}, {"translation", {1, 0, 0}}});
  g.Node({{"name", "static"}, {"mesh", 0}});
  g.Scene({0, 2});
  const int times = g.Accessor(std::vector<float>{0, 1, 2}, kGltfFloat, "SCALAR", 3);
  const int moves = g.Accessor(std::vector<float>{0, 0, -5, 2, 0, -5, 2, 1, -5}, kGltfFloat, "VEC3", 3);
  const int turns = g.Accessor(std::vector<float>{0, 0, 0, 1, 0, 0.7071068f, 0, 0.7071068f}, kGltfFloat, "VEC4", 2);
  const int two = g.Accessor(std::vector<float>{0, 1}, kGltfFloat, "SCALAR", 2);
  g.doc["animations"] = json::array({{{"name", "drive"},
                                      {"samplers", {{{"input", times}, {"output", moves}, {"interpolation", "LINEAR"}},
                                                    {{"input", two}, {"output", turns}, {"interpolation", "STEP"}}}},
                                      {"channels", {{{"sampler", 0}, {"target", {{"node", 0}, {"path", "translation"}}}},
                                                    {{"sampler", 1}, {"target", {{"node", 1}, {"path", "rotation"}}}}}}}});
  const Scene s = LoadGltf(g.Write(dir, "animated"));
  ASSERT_TRUE(s.IsAnimated());
  ASSERT_EQ(s.animation_channels.size(), 2u);
  ASSERT_EQ(s.nodes.size(), 3u);
  EXPECT_EQ(s.nodes[1].parent, 0);
  EXPECT_EQ(s.nodes[0].parent, -1);
  EXPECT_TRUE(s.nodes[0].translation.isApprox(Eigen::Vector3d(0, 0, -5)));
  const AnimationChannel& move = s.animation_channels[0];
  EXPECT_EQ(move.node, 0);
  EXPECT_EQ(move.path, AnimationPath::kTranslation);
  EXPECT_EQ(move.interpolation, AnimationInterpolation::kLinear);
  ASSERT_EQ(move.times_s.size(), 3u);
  EXPECT_DOUBLE_EQ(move.times_s[2], 2.0);
  EXPECT_TRUE(move.values[1].head<3>().isApprox(Eigen::Vector3d(2, 0, -5)));
  EXPECT_EQ(s.animation_channels[1].path, AnimationPath::kRotation);
  EXPECT_EQ(s.animation_channels[1].interpolation, AnimationInterpolation::kStep);
  EXPECT_NEAR(s.animation_channels[1].values[1][3], 0.7071068, 1e-6);  // (x, y, z, w)
  // The animated mesh keeps its node and node-frame vertices; positions are at the rest pose.
  ASSERT_EQ(s.meshes.size(), 2u);
  EXPECT_EQ(s.meshes[0].node, 1);
  ASSERT_EQ(s.meshes[0].local_positions.size(), 4u);
  EXPECT_TRUE(s.meshes[0].local_positions[1].isApprox(Eigen::Vector3f(1, 0, 0)));
  EXPECT_TRUE(s.meshes[0].positions[1].isApprox(Eigen::Vector3f(2, 0, -5)));
  EXPECT_EQ(s.meshes[1].node, -1);
  EXPECT_TRUE(s.meshes[1].local_positions.empty());
  EXPECT_FALSE(HasWarning(s, "animation"));
}

TEST(GltfLoader, BadAnimationsThrowOrWarn) {
  const TempDir dir;
  GltfBuilder g;
  g.Mesh({{"POSITION", g.Positions(kUnitQuad)}});
  g.Node({{"mesh", 0}});
  g.Scene({0});
  const int times = g.Accessor(std::vector<float>{0, 1}, kGltfFloat, "SCALAR", 2);
  const int moves = g.Accessor(std::vector<float>{0, 0, 0, 1, 0, 0}, kGltfFloat, "VEC3", 2);
  const int cubic = g.Accessor(std::vector<float>(18, 0.0f), kGltfFloat, "VEC3", 6);
  g.doc["animations"] = json::array({{{"samplers", {{{"input", times}, {"output", cubic}, {"interpolation", "CUBICSPLINE"}}}},
                                      {"channels", {{{"sampler", 0}, {"target", {{"node", 0}, {"path", "translation"}}}}}}}});
  const Scene s = LoadGltf(g.Write(dir, "cubic"));
  EXPECT_EQ(s.animation_channels.size(), 1u);
  EXPECT_TRUE(HasWarning(s, "CUBICSPLINE"));
  // Keys out of order.
  const int backwards = g.Accessor(std::vector<float>{1, 0}, kGltfFloat, "SCALAR", 2);
  g.doc["animations"][0]["samplers"][0] = {{"input", backwards}, {"output", moves}};
  ExpectLoadFails(g.Write(dir, "backwards"), "strictly increasing");
  // Output count mismatch.
  g.doc["animations"][0]["samplers"][0] = {{"input", times}, {"output", cubic}};
  ExpectLoadFails(g.Write(dir, "count"), "output values for 2 keyframes");
}

// glTF allows a channel without a target node: an extension (KHR_animation_pointer) names what it
// animates. Such channels are ignored with a warning, in .gltf and .glb files alike; the file's
// other channels still animate their nodes.
TEST(GltfLoader, ChannelsWithoutATargetNodeAreIgnored) {
  const TempDir dir;
  GltfBuilder g;
  g.Mesh({{"POSITION", g.Positions(kUnitQuad)}});
  g.Node({{"mesh", 0}});
  g.Scene({0});
  const int times = g.Accessor(std::vector<float>{0, 1}, kGltfFloat, "SCALAR", 2);
  const int moves = g.Accessor(std::vector<float>{0, 0, 0, 1, 0, 0}, kGltfFloat, "VEC3", 2);
  const int fades = g.Accessor(std::vector<float>{1, 0}, kGltfFloat, "SCALAR", 2);
  const json pointer = {{"path", "pointer"},
                        {"extensions", {{"KHR_animation_pointer", {{"pointer", "/materials/0/alphaCutoff"}}}}}};
  g.doc["extensionsUsed"] = {"KHR_animation_pointer"};
  g.doc["animations"] = json::array(
      {{{"name", "move and fade"},
        {"samplers", {{{"input", times}, {"output", moves}}, {{"input", times}, {"output", fades}}}},
        {"channels", {{{"sampler", 1}, {"target", pointer}}, {{"sampler", 0}, {"target", {{"node", 0}, {"path", "translation"}}}}}}},
       {{"name", "fade only"}, {"samplers", {{{"input", times}, {"output", fades}}}}, {"channels", {{{"sampler", 0}, {"target", pointer}}}}}});
  for (const auto& path : {g.Write(dir, "pointer"), g.WriteGlb(dir, "pointer")}) {
    SCOPED_TRACE(path.string());
    const Scene s = LoadGltf(path);
    ASSERT_EQ(s.animation_channels.size(), 1u);
    EXPECT_EQ(s.animation_channels[0].node, 0);
    EXPECT_EQ(s.animation_channels[0].path, AnimationPath::kTranslation);
    EXPECT_TRUE(s.animation_channels[0].values[1].head<3>().isApprox(Eigen::Vector3d(1, 0, 0)));
    EXPECT_TRUE(HasWarning(s, "2 animation channel(s) without a target node ignored"));
    EXPECT_TRUE(HasWarning(s, "KHR_animation_pointer"));
    EXPECT_EQ(s.meshes.size(), 1u);
  }
  // A file that is broken otherwise still fails with tinygltf's message.
  g.doc["animations"][0]["channels"][1]["target"].erase("path");
  ExpectLoadFails(g.Write(dir, "no_path"), "`path` field is missing");
}

// kUnitQuad (indexed as a fan) with two morph targets: target 0 lifts vertex i by 2 (i + 1) in z and
// tips the normals (0, 0, 1) towards +x by 1; target 1, quantized (normalized BYTE, as
// KHR_mesh_quantization allows), moves every vertex by 1 in y.
int MorphedQuadMesh(GltfBuilder& g, json weights = nullptr) {
  constexpr int kByte = 5120;
  const int pos = g.Positions(kUnitQuad);
  const int nrm = g.Accessor(std::vector<float>{0, 0, 1, 0, 0, 1, 0, 0, 1, 0, 0, 1}, kGltfFloat, "VEC3", 4);
  const int lift = g.Positions({0, 0, 2, 0, 0, 4, 0, 0, 6, 0, 0, 8});
  const int tip = g.Accessor(std::vector<float>{1, 0, 0, 1, 0, 0, 1, 0, 0, 1, 0, 0}, kGltfFloat, "VEC3", 4);
  const int shift = g.Accessor(std::vector<int8_t>{0, 127, 0, 0, 127, 0, 0, 127, 0, 0, 127, 0}, kByte, "VEC3", 4, /*normalized=*/true);
  const int mesh = g.Mesh({{"POSITION", pos}, {"NORMAL", nrm}}, -1, /*TRIANGLE_FAN=*/6);
  g.doc["meshes"][mesh]["primitives"][0]["targets"] = {{{"POSITION", lift}, {"NORMAL", tip}}, {{"POSITION", shift}}};
  if (!weights.is_null()) g.doc["meshes"][mesh]["weights"] = weights;
  return mesh;
}

// Static morphs are applied at load with the rest weights: node.weights, else mesh.weights, else 0.
TEST(GltfLoader, MorphTargetsAreAppliedAtTheRestWeights) {
  const TempDir dir;
  GltfBuilder g;
  const int mesh = MorphedQuadMesh(g, {0.5, 0.0});
  g.Node({{"mesh", mesh}, {"translation", {10, 0, 0}}});     // mesh.weights (0.5, 0)
  g.Node({{"mesh", mesh}, {"weights", {1.0, 0.0}}});          // node.weights override them
  g.Node({{"mesh", mesh}, {"weights", {0.0, 1.0}}});          // the quantized target alone
  g.Scene({0, 1, 2});
  const Scene s = LoadGltf(g.Write(dir, "morphed"));
  ASSERT_EQ(s.meshes.size(), 3u);
  for (int i = 0; i < 4; ++i) {
    const Eigen::Vector3f base(kUnitQuad[3 * i], kUnitQuad[3 * i + 1], kUnitQuad[3 * i + 2]);
    EXPECT_TRUE(s.meshes[0].positions[i].isApprox(base + Eigen::Vector3f(10, 0, i + 1))) << i << ": " << s.meshes[0].positions[i].transpose();
    EXPECT_TRUE(s.meshes[1].positions[i].isApprox(base + Eigen::Vector3f(0, 0, 2 * (i + 1)))) << i << ": " << s.meshes[1].positions[i].transpose();
    EXPECT_TRUE(s.meshes[2].positions[i].isApprox(base + Eigen::Vector3f(0, 1, 0))) << i << ": " << s.meshes[2].positions[i].transpose();
  }
  ASSERT_EQ(s.meshes[0].normals.size(), 4u);
  EXPECT_TRUE(s.meshes[0].normals[0].isApprox(Eigen::Vector3f(0.5f, 0, 1).normalized())) << s.meshes[0].normals[0].transpose();
  EXPECT_TRUE(s.meshes[1].normals[3].isApprox(Eigen::Vector3f(1, 0, 1).normalized())) << s.meshes[1].normals[3].transpose();
  EXPECT_TRUE(s.meshes[2].normals[3].isApprox(Eigen::Vector3f(0, 0, 1)));
  // Static meshes carry no copy of the targets.
  EXPECT_EQ(s.meshes[0].num_morph_targets, 2);
  EXPECT_TRUE(s.meshes[0].morph_targets.empty());
  EXPECT_TRUE(s.meshes[0].morph_base_positions.empty());
  EXPECT_EQ(s.meshes[0].node, -1);
  EXPECT_FALSE(HasWarning(s, "morph"));
  EXPECT_FALSE(s.IsAnimated());
}

// glTF 2.0 "Skins": morphing comes first, in the mesh's frame. The joint scales by 2, so skinning
// before morphing would lift the quad by 1 instead of 2.
TEST(GltfLoader, MorphingComesBeforeSkinning) {
  const TempDir dir;
  GltfBuilder g;
  const int mesh = MorphedQuadMesh(g, {0.0, 1.0});
  g.doc["meshes"][mesh]["primitives"][0]["attributes"]["JOINTS_0"] = g.Accessor<uint8_t>(std::vector<uint8_t>(16, 0), kGltfUByte, "VEC4", 4);
  g.doc["meshes"][mesh]["primitives"][0]["attributes"]["WEIGHTS_0"] =
      g.Accessor<float>({1, 0, 0, 0, 1, 0, 0, 0, 1, 0, 0, 0, 1, 0, 0, 0}, kGltfFloat, "VEC4", 4);
  const int ibm = g.Accessor(std::vector<float>{1, 0, 0, 0, 0, 1, 0, 0, 0, 0, 1, 0, 0, 0, 0, 1}, kGltfFloat, "MAT4", 1);
  g.doc["skins"] = json::array({{{"joints", {1}}, {"inverseBindMatrices", ibm}}});
  g.Node({{"mesh", mesh}, {"skin", 0}});
  g.Node({{"scale", {2, 2, 2}}});
  g.Scene({0, 1});
  const Scene s = LoadGltf(g.Write(dir, "skinned_morph"));
  ASSERT_EQ(s.meshes.size(), 1u);
  for (int i = 0; i < 4; ++i) {
    const Eigen::Vector3f expected = 2 * (Eigen::Vector3f(kUnitQuad[3 * i], kUnitQuad[3 * i + 1], kUnitQuad[3 * i + 2]) + Eigen::Vector3f(0, 1, 0));
    EXPECT_TRUE(s.meshes[0].positions[i].isApprox(expected)) << i << ": " << s.meshes[0].positions[i].transpose();
  }
}

TEST(GltfLoader, MalformedMorphTargetsThrow) {
  const TempDir dir;
  GltfBuilder g;
  const int mesh = MorphedQuadMesh(g);
  g.Node({{"mesh", mesh}, {"name", "face"}});
  g.Scene({0});
  json& prim = g.doc["meshes"][mesh]["primitives"][0];
  const json good_targets = prim["targets"];
  EXPECT_FALSE(HasWarning(LoadGltf(g.Write(dir, "zero_weights")), "morph"));  // no weights: all 0
  g.doc["meshes"][mesh]["weights"] = {0.5};
  ExpectLoadFails(g.Write(dir, "mesh_weights"), "mesh 0: 1 morph weights for 2 morph targets");
  g.doc["meshes"][mesh].erase("weights");
  g.doc["nodes"][0]["weights"] = {0.5, 0.5, 0.5};
  ExpectLoadFails(g.Write(dir, "node_weights"), "node 0 'face': 3 morph weights for 2 morph targets");
  g.doc["nodes"][0].erase("weights");
  GltfBuilder plain;  // weights on a mesh without targets: nothing to morph, so a warning
  plain.Mesh({{"POSITION", plain.Positions(kUnitQuad)}});
  plain.doc["meshes"][0]["weights"] = {0.5};
  plain.Node({{"mesh", 0}});
  plain.Scene({0});
  EXPECT_TRUE(HasWarning(LoadGltf(plain.Write(dir, "no_targets")), "mesh 0: 1 morph weights but no morph targets"));
  prim["targets"][0]["POSITION"] = g.Positions({0, 0, 1, 0, 0, 1, 0, 0, 1});
  ExpectLoadFails(g.Write(dir, "count"), "(mesh 0 primitive 0 target 0 POSITION): count 3 differs from POSITION's 4");
  prim["targets"][0]["POSITION"] = g.Accessor(std::vector<float>(8, 0.0f), kGltfFloat, "VEC2", 4);
  ExpectLoadFails(g.Write(dir, "type"), "(mesh 0 primitive 0 target 0 POSITION): unexpected type");
  prim["targets"][0]["POSITION"] = g.Accessor(std::vector<uint32_t>(12, 0), kGltfUInt, "VEC3", 4);
  ExpectLoadFails(g.Write(dir, "component"), "target 0 POSITION): componentType must be FLOAT, BYTE or SHORT");
  prim["targets"][0]["POSITION"] = g.Positions({0, 0, 0, 0, std::numeric_limits<float>::infinity(), 0, 0, 0, 0, 0, 0, 0});
  ExpectLoadFails(g.Write(dir, "infinite"), "target 0 POSITION): vertex 1 is not finite");
  prim["targets"] = good_targets;
  g.doc["meshes"][mesh]["primitives"].push_back(prim);
  g.doc["meshes"][mesh]["primitives"][1]["targets"].erase(1);
  ExpectLoadFails(g.Write(dir, "primitives_differ"), "mesh 0 primitive 1: 1 morph targets, primitive 0 has 2");
}

// A "weights" channel keeps one weight per target per key, and the mesh on its node keeps its base
// vertices and targets for PoseSceneAt; another instance of the same mesh stays static.
TEST(GltfLoader, MorphWeightAnimationsAreKeptForPosing) {
  const TempDir dir;
  GltfBuilder g;
  const int mesh = MorphedQuadMesh(g, {0.5, 0.0});
  g.Node({{"mesh", mesh}, {"children", {1}}});
  g.Node({{"mesh", mesh}, {"translation", {0, 0, 5}}});
  g.Scene({0});
  const int times = g.Accessor(std::vector<float>{0, 1}, kGltfFloat, "SCALAR", 2);
  const int weights = g.Accessor(std::vector<float>{0, 0, 1, 0.5f}, kGltfFloat, "SCALAR", 4);
  g.doc["animations"] = json::array({{{"samplers", {{{"input", times}, {"output", weights}, {"interpolation", "STEP"}}}},
                                      {"channels", {{{"sampler", 0}, {"target", {{"node", 0}, {"path", "weights"}}}}}}}});
  const Scene s = LoadGltf(g.Write(dir, "morph_animated"));
  ASSERT_TRUE(s.IsAnimated());
  ASSERT_EQ(s.animation_channels.size(), 1u);
  const AnimationChannel& ch = s.animation_channels[0];
  EXPECT_EQ(ch.node, 0);
  EXPECT_EQ(ch.path, AnimationPath::kWeights);
  EXPECT_EQ(ch.interpolation, AnimationInterpolation::kStep);
  EXPECT_TRUE(ch.values.empty());
  ASSERT_EQ(ch.weights.size(), 2u);
  EXPECT_TRUE(ch.weights[0].isApprox(Eigen::Vector2d(0, 0)) && ch.weights[0].size() == 2) << ch.weights[0].transpose();
  EXPECT_TRUE(ch.weights[1].isApprox(Eigen::Vector2d(1, 0.5))) << ch.weights[1].transpose();
  ASSERT_EQ(s.meshes.size(), 2u);
  const SceneMesh& animated = s.meshes[0];
  EXPECT_EQ(animated.node, 0);
  ASSERT_EQ(animated.morph_targets.size(), 2u);
  ASSERT_EQ(animated.morph_base_positions.size(), 4u);
  EXPECT_TRUE(animated.morph_base_positions[2].isApprox(Eigen::Vector3f(1, 1, 0)));
  EXPECT_EQ(animated.morph_base_normals.size(), 4u);
  EXPECT_TRUE(animated.morph_targets[0].positions[2].isApprox(Eigen::Vector3f(0, 0, 6)));
  EXPECT_TRUE(animated.morph_targets[1].normals.empty());
  EXPECT_TRUE(animated.local_positions[2].isApprox(Eigen::Vector3f(1, 1, 3))) << "morphed at rest (mesh.weights)";
  EXPECT_TRUE(animated.positions[2].isApprox(Eigen::Vector3f(1, 1, 3)));
  // The child's node does not move: its mesh is static, without the targets.
  EXPECT_EQ(s.meshes[1].node, -1);
  EXPECT_TRUE(s.meshes[1].morph_targets.empty());
  EXPECT_TRUE(s.meshes[1].positions[2].isApprox(Eigen::Vector3f(1, 1, 8)));
  EXPECT_FALSE(HasWarning(s, "weights"));

  // CUBICSPLINE: the key values (the middle of each in-tangent, value, out-tangent triple), warned.
  const int cubic = g.Accessor(std::vector<float>{9, 9, 0, 0, 9, 9, 9, 9, 1, 0.5f, 9, 9}, kGltfFloat, "SCALAR", 12);
  g.doc["animations"][0]["samplers"][0] = {{"input", times}, {"output", cubic}, {"interpolation", "CUBICSPLINE"}};
  const Scene c = LoadGltf(g.Write(dir, "cubic"));
  ASSERT_EQ(c.animation_channels.size(), 1u);
  EXPECT_TRUE(c.animation_channels[0].weights[1].isApprox(Eigen::Vector2d(1, 0.5))) << c.animation_channels[0].weights[1].transpose();
  EXPECT_TRUE(HasWarning(c, "CUBICSPLINE"));
  // One weight per key is too few for two targets.
  g.doc["animations"][0]["samplers"][0] = {{"input", times}, {"output", times}};
  ExpectLoadFails(g.Write(dir, "short"), "2 output values for 2 keyframes of 2 morph target weights");
  // A node without morph targets: the channel is ignored with a warning.
  g.doc["animations"][0]["samplers"][0] = {{"input", times}, {"output", weights}};
  g.doc["nodes"].push_back({{"name", "empty"}});
  g.doc["animations"][0]["channels"][0]["target"]["node"] = 2;
  const Scene ignored = LoadGltf(g.Write(dir, "no_targets"));
  EXPECT_TRUE(ignored.animation_channels.empty());
  EXPECT_TRUE(HasWarning(ignored, "whose mesh has no morph targets; ignored"));
}

}  // namespace
}  // namespace rigsim::gltf_test
