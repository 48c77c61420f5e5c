#include "scene/scene_pose.h"

#include <cmath>
#include <stdexcept>
#include <string>
#include <vector>

#include <Eigen/Geometry>
#include <gtest/gtest.h>

#include "scene/test_scenes.h"

namespace rigsim {
namespace {

constexpr double kPi = 3.14159265358979323846;

Eigen::Vector3d MeshCentre(const SceneMesh& mesh) {
  Eigen::Vector3d sum = Eigen::Vector3d::Zero();
  for (const Eigen::Vector3f& p : mesh.positions) sum += p.cast<double>();
  return sum / double(mesh.positions.size());
}

// The animated box of AnimatedBoxScene, skinned instead to joint node 1, which moves from
// (0, 0, 6) at t = 0 to (2, 0, 6) at t = 1; node 0, which carries the mesh, stays put and does not
// place it.
TEST(ScenePoseTest, SkinnedMeshFollowsItsAnimatedJoint) {
  Scene scene = AnimatedBoxScene();
  scene.animation_channels[0].node = 1;
  scene.animation_channels[0].values = {Eigen::Vector4d(0, 0, 6, 0), Eigen::Vector4d(2, 0, 6, 0)};
  SceneNode joint;
  joint.name = "joint";
  scene.nodes.push_back(joint);
  scene.skins.push_back(SceneSkin{{1}, {Eigen::Matrix4d::Identity()}});
  SceneMesh& box = scene.meshes[0];
  box.skin = 0;
  box.joints.assign(box.local_positions.size(), {0, 0, 0, 0});
  box.weights.assign(box.local_positions.size(), Eigen::Vector4f(1, 0, 0, 0));
  for (double t : {0.0, 0.5, 1.0}) {
    const std::vector<SceneMesh> posed = PoseMeshesAt(scene, t);
    EXPECT_TRUE(MeshCentre(posed[0]).isApprox(Eigen::Vector3d(2 * t, 0, 6), 1e-6)) << t << ": " << MeshCentre(posed[0]).transpose();
  }
  scene.skins[0].joints = {7};  // no such node
  EXPECT_THROW(PoseMeshesAt(scene, 0.5), std::invalid_argument);
}

// The box of AnimatedBoxScene on a node that stays at (0, 0, 6), with two morph targets: target 0
// moves every vertex by 2 in x and tips the normals towards +x, target 1 by 1 in y. A weights
// channel goes from (0, 0) at t = 0 to (1, 0.5) at t = 1.
Scene MorphedBoxScene(AnimationInterpolation interpolation) {
  Scene scene = AnimatedBoxScene();
  scene.nodes[0].translation = Eigen::Vector3d(0, 0, 6);
  AnimationChannel& ch = scene.animation_channels[0];
  ch.path = AnimationPath::kWeights;
  ch.interpolation = interpolation;
  ch.values.clear();
  ch.weights = {Eigen::Vector2d(0, 0), Eigen::Vector2d(1, 0.5)};
  SceneMesh& box = scene.meshes[0];
  box.morph_base_positions = box.local_positions;
  box.morph_base_normals.assign(8, Eigen::Vector3f(0, 0, -1));
  box.local_normals = box.morph_base_normals;
  box.num_morph_targets = 2;
  box.morph_targets.resize(2);
  box.morph_targets[0].positions.assign(8, Eigen::Vector3f(2, 0, 0));
  box.morph_targets[0].normals.assign(8, Eigen::Vector3f(1, 0, 0));
  box.morph_targets[1].positions.assign(8, Eigen::Vector3f(0, 1, 0));
  return scene;
}

TEST(ScenePoseTest, MorphWeightsAreInterpolatedOrHeld) {
  const Scene linear = MorphedBoxScene(AnimationInterpolation::kLinear);
  for (double t : {0.0, 0.5, 1.0}) {
    const std::vector<SceneMesh> posed = PoseMeshesAt(linear, t);
    EXPECT_TRUE(MeshCentre(posed[0]).isApprox(Eigen::Vector3d(2 * t, 0.5 * t, 6), 1e-6)) << t << ": " << MeshCentre(posed[0]).transpose();
    ASSERT_EQ(posed[0].normals.size(), 8u);
    EXPECT_TRUE(posed[0].normals[3].isApprox(Eigen::Vector3f(float(t), 0, -1).normalized(), 1e-6f)) << t << ": " << posed[0].normals[3].transpose();
  }
  EXPECT_EQ(MorphWeightsAt(linear, 0.5)[0], (std::vector<double>{0.5, 0.25}));
  EXPECT_TRUE(MeshCentre(PoseMeshesAt(linear, 9.0)[0]).isApprox(Eigen::Vector3d(2, 0.5, 6), 1e-6));  // clamped
  // Posing reads the base vertices, never its own output: posing twice gives the same.
  const Scene posed = PoseSceneAt(linear, 1.0);
  EXPECT_TRUE(MeshCentre(PoseMeshesAt(posed, 0.5)[0]).isApprox(Eigen::Vector3d(1, 0.25, 6), 1e-6));

  const Scene step = MorphedBoxScene(AnimationInterpolation::kStep);
  EXPECT_TRUE(MeshCentre(PoseMeshesAt(step, 0.0)[0]).isApprox(Eigen::Vector3d(0, 0, 6), 1e-6));
  EXPECT_TRUE(MeshCentre(PoseMeshesAt(step, 0.5)[0]).isApprox(Eigen::Vector3d(0, 0, 6), 1e-6));
  EXPECT_TRUE(MeshCentre(PoseMeshesAt(step, 1.0)[0]).isApprox(Eigen::Vector3d(2, 0.5, 6), 1e-6));

  Scene broken = MorphedBoxScene(AnimationInterpolation::kLinear);
  broken.animation_channels[0].weights[1] = Eigen::Vector3d(1, 0, 0);  // three weights for two targets
  EXPECT_THROW(PoseMeshesAt(broken, 0.5), std::invalid_argument);
  broken.animation_channels.clear();
  broken.animation_channels.push_back(AnimatedBoxScene().animation_channels[0]);  // moved, but no weights
  EXPECT_THROW(PoseMeshesAt(broken, 0.5), std::invalid_argument);
}

// Morphing comes before skinning: the joint scales by 2 and moves from (0, 0, 6) to (2, 0, 6), so
// the lift of target 1 (0.5 at t = 0.5) is doubled; skinning first would leave it at 0.5.
TEST(ScenePoseTest, SkinnedMeshIsMorphedBeforeItIsSkinned) {
  Scene scene = MorphedBoxScene(AnimationInterpolation::kLinear);
  scene.meshes[0].morph_targets[0].positions.assign(8, Eigen::Vector3f::Zero());
  scene.animation_channels[0].weights = {Eigen::Vector2d(0, 0), Eigen::Vector2d(0, 1)};
  SceneNode joint;
  joint.scale = Eigen::Vector3d(2, 2, 2);
  scene.nodes.push_back(joint);
  AnimationChannel move = AnimatedBoxScene().animation_channels[0];
  move.node = 1;
  move.values = {Eigen::Vector4d(0, 0, 6, 0), Eigen::Vector4d(2, 0, 6, 0)};
  scene.animation_channels.push_back(move);
  scene.skins.push_back(SceneSkin{{1}, {Eigen::Matrix4d::Identity()}});
  SceneMesh& box = scene.meshes[0];
  box.skin = 0;
  box.joints.assign(8, {0, 0, 0, 0});
  box.weights.assign(8, Eigen::Vector4f(1, 0, 0, 0));
  for (double t : {0.0, 0.5, 1.0}) {
    EXPECT_TRUE(MeshCentre(PoseMeshesAt(scene, t)[0]).isApprox(Eigen::Vector3d(2 * t, 2 * t, 6), 1e-6))
        << t << ": " << MeshCentre(PoseMeshesAt(scene, t)[0]).transpose();
  }
}

TEST(ScenePoseTest, LinearAndStepTranslation) {
  const Scene linear = AnimatedBoxScene();
  EXPECT_TRUE(MeshCentre(PoseMeshesAt(linear, 0.0)[0]).isApprox(Eigen::Vector3d(-1, 0, 6), 1e-6));
  EXPECT_TRUE(MeshCentre(PoseMeshesAt(linear, 0.25)[0]).isApprox(Eigen::Vector3d(-0.5, 0, 6), 1e-6));
  EXPECT_TRUE(MeshCentre(PoseMeshesAt(linear, 7.0)[0]).isApprox(Eigen::Vector3d(1, 0, 6), 1e-6));   // clamped
  EXPECT_TRUE(MeshCentre(PoseMeshesAt(linear, -3.0)[0]).isApprox(Eigen::Vector3d(-1, 0, 6), 1e-6));  // clamped
  const Scene step = AnimatedBoxScene(AnimationInterpolation::kStep);
  EXPECT_TRUE(MeshCentre(PoseMeshesAt(step, 0.99)[0]).isApprox(Eigen::Vector3d(-1, 0, 6), 1e-6));
  EXPECT_TRUE(MeshCentre(PoseMeshesAt(step, 1.0)[0]).isApprox(Eigen::Vector3d(1, 0, 6), 1e-6));
  // PoseSceneAt is the same meshes in a whole scene.
  const Scene posed = PoseSceneAt(linear, 0.5);
  EXPECT_TRUE(MeshCentre(posed.meshes[0]).isApprox(Eigen::Vector3d(0, 0, 6), 1e-6));
}

TEST(ScenePoseTest, RotationSlerpsAndChildrenFollowTheirParent) {
  Scene scene = AnimatedBoxScene();
  scene.animation_channels.clear();
  SceneNode child;
  child.parent = 0;
  child.translation = Eigen::Vector3d(0, 0, 2);
  scene.nodes.push_back(child);
  scene.meshes[0].node = 1;
  AnimationChannel turn;
  turn.node = 0;
  turn.path = AnimationPath::kRotation;
  turn.times_s = {0.0, 2.0};
  const Eigen::Quaterniond q90(Eigen::AngleAxisd(kPi / 2, Eigen::Vector3d::UnitY()));
  turn.values = {Eigen::Vector4d(0, 0, 0, 1), Eigen::Vector4d(q90.x(), q90.y(), q90.z(), q90.w())};
  scene.animation_channels.push_back(turn);
  // At t = 1 the parent has turned 45 degrees about y: the child's offset (0, 0, 2) turns with it.
  const std::vector<Eigen::Matrix4d> world = NodeWorldTransformsAt(scene, 1.0);
  const Eigen::Vector3d expected = Eigen::Vector3d(-1, 0, 6) + Eigen::AngleAxisd(kPi / 4, Eigen::Vector3d::UnitY()) * Eigen::Vector3d(0, 0, 2);
  const Eigen::Vector3d world_child = world[1].topRightCorner<3, 1>();
  EXPECT_TRUE(world_child.isApprox(expected, 1e-9));
  EXPECT_TRUE(MeshCentre(PoseMeshesAt(scene, 1.0)[0]).isApprox(expected, 1e-6));
}

// A valid file may nest nodes very deep (a chain of 100,000 here, each 1 mm along z below an
// animated root): posing resolves parents without recursing, so it does not overflow the stack.
TEST(ScenePoseTest, DeepNodeChainsArePosed) {
  Scene scene = AnimatedBoxScene();  // node 0 moves from (-1, 0, 6) to (1, 0, 6)
  constexpr int kDepth = 100000;
  SceneNode link;
  link.translation = Eigen::Vector3d(0, 0, 1e-3);
  for (int i = 1; i < kDepth; ++i) {
    link.parent = i - 1;
    scene.nodes.push_back(link);
  }
  scene.meshes[0].node = kDepth - 1;
  const std::vector<Eigen::Matrix4d> world = NodeWorldTransformsAt(scene, 0.5);
  const Eigen::Vector3d leaf = world.back().topRightCorner<3, 1>();
  EXPECT_TRUE(leaf.isApprox(Eigen::Vector3d(0, 0, 6 + (kDepth - 1) * 1e-3), 1e-9)) << leaf.transpose();
  EXPECT_TRUE(MeshCentre(PoseMeshesAt(scene, 0.5)[0]).isApprox(leaf, 1e-6));
  scene.nodes[0].parent = kDepth - 1;  // a cycle is still refused
  EXPECT_THROW(NodeWorldTransformsAt(scene, 0.5), std::invalid_argument);
}

// EXT_mesh_gpu_instancing: three instances of the box on node 0, which moves along x and turns
// 90 deg about y from t = 0 to 1. Each follows its node in the node's frame, world_from_node(t) *
// node_from_instance: the instance 2 m along the node's z is at (-1, 0, 8) at t = 0 and at (1, 0,
// 6) + R_y(90) (0, 0, 2) = (3, 0, 6) at t = 1 (node_from_instance first would leave it at (1, 0, 8)).
// The instance scaled by 2 and turned has its normals by the inverse transpose; morphing comes
// before both.
TEST(ScenePoseTest, GpuInstancesFollowTheirAnimatedNode) {
  Scene scene = AnimatedBoxScene();
  AnimationChannel turn;
  turn.node = 0;
  turn.path = AnimationPath::kRotation;
  turn.times_s = {0.0, 1.0};
  const Eigen::Quaterniond q90(Eigen::AngleAxisd(kPi / 2, Eigen::Vector3d::UnitY()));
  turn.values = {Eigen::Vector4d(0, 0, 0, 1), Eigen::Vector4d(q90.x(), q90.y(), q90.z(), q90.w())};
  scene.animation_channels.push_back(turn);
  const SceneMesh box = scene.meshes[0];
  scene.meshes.clear();
  const Eigen::Affine3d along_z(Eigen::Translation3d(0, 0, 2));
  const Eigen::Affine3d stretched = Eigen::Translation3d(0, 3, 0) * Eigen::AngleAxisd(kPi / 2, Eigen::Vector3d::UnitZ()) * Eigen::Scaling(2.0, 1.0, 1.0);
  const Eigen::Matrix4d instances[3] = {Eigen::Matrix4d::Identity(), along_z.matrix(), stretched.matrix()};
  for (int i = 0; i < 3; ++i) {
    SceneMesh m = box;
    m.instance_id = uint16_t(10 + i);
    m.gpu_instance = i;
    m.node_from_instance = instances[i];
    m.local_normals.assign(m.local_positions.size(), Eigen::Vector3f(1, 0, 1).normalized());
    scene.meshes.push_back(m);
  }
  for (double t : {0.0, 1.0}) {
    const std::vector<SceneMesh> posed = PoseMeshesAt(scene, t);
    ASSERT_EQ(posed.size(), 3u);
    const Eigen::Vector3d node(2 * t - 1, 0, 6);
    const Eigen::Matrix3d r = t == 0.0 ? Eigen::Matrix3d::Identity() : q90.toRotationMatrix();
    EXPECT_TRUE(MeshCentre(posed[0]).isApprox(node, 1e-6)) << t << ": " << MeshCentre(posed[0]).transpose();
    EXPECT_TRUE(MeshCentre(posed[1]).isApprox(node + r * Eigen::Vector3d(0, 0, 2), 1e-6)) << t << ": " << MeshCentre(posed[1]).transpose();
    EXPECT_TRUE(MeshCentre(posed[2]).isApprox(node + r * Eigen::Vector3d(0, 3, 0), 1e-6)) << t << ": " << MeshCentre(posed[2]).transpose();
    // Corner (0.5, 0.5, 0.5) of the stretched instance: S (1, 0.5, 0.5), R_z (-0.5, 1, 0.5), T (-0.5, 4, 0.5).
    EXPECT_TRUE(posed[2].positions[7].cast<double>().isApprox(node + r * Eigen::Vector3d(-0.5, 4, 0.5), 1e-6)) << posed[2].positions[7].transpose();
    // Normal (1, 0, 1): S^-T (0.5, 0, 1), R_z (0, 0.5, 1), then the node's turn.
    const Eigen::Vector3d normal = r * Eigen::Vector3d(0, 0.5, 1).normalized();
    EXPECT_TRUE(posed[2].normals[0].cast<double>().isApprox(normal, 1e-6)) << t << ": " << posed[2].normals[0].transpose();
  }

  // Morph weights animated on the instanced node: each instance is morphed, then placed.
  Scene morphed = MorphedBoxScene(AnimationInterpolation::kLinear);
  SceneMesh moved = morphed.meshes[0];
  moved.gpu_instance = 1;
  moved.node_from_instance = along_z.matrix();
  morphed.meshes[0].gpu_instance = 0;
  morphed.meshes.push_back(moved);
  const std::vector<SceneMesh> posed = PoseMeshesAt(morphed, 1.0);
  EXPECT_TRUE(MeshCentre(posed[0]).isApprox(Eigen::Vector3d(2, 0.5, 6), 1e-6)) << MeshCentre(posed[0]).transpose();
  EXPECT_TRUE(MeshCentre(posed[1]).isApprox(Eigen::Vector3d(2, 0.5, 8), 1e-6)) << MeshCentre(posed[1]).transpose();
}

TEST(ScenePoseTest, StaticScenesAreCopiedUnchanged) {
  Scene scene = AnimatedBoxScene();
  scene.animation_channels.clear();
  scene.meshes[0].node = -1;
  EXPECT_FALSE(scene.IsAnimated());
  EXPECT_EQ(PoseMeshesAt(scene, 3.0)[0].positions, scene.meshes[0].positions);
}

}  // namespace
}  // namespace rigsim
