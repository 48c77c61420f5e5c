#include "scene/skinning.h"

#include <stdexcept>
#include <vector>

#include <Eigen/Geometry>
#include <gmock/gmock.h>
#include <gtest/gtest.h>

#include "testing/expect_error.h"

namespace rigsim {
namespace {

Eigen::Matrix4d Translation(double x, double y, double z) {
  Eigen::Matrix4d m = Eigen::Matrix4d::Identity();
  m.topRightCorner<3, 1>() = Eigen::Vector3d(x, y, z);
  return m;
}

// Two joints (nodes 0 and 1); joint 1 is bound at (0, 1, 0). Vertex 0 follows joint 0, vertex 1
// joint 1, vertex 2 both half and half.
struct TwoJoints {
  SceneSkin skin;
  SceneMesh mesh;
  TwoJoints() {
    skin.joints = {0, 1};
    skin.inverse_bind = {Eigen::Matrix4d::Identity(), Translation(0, -1, 0)};
    mesh.name = "arm";
    mesh.skin = 0;
    mesh.local_positions = {{0, 0, 0}, {0, 1, 0}, {1, 0, 0}};
    mesh.local_normals = {{1, 0, 0}, {1, 0, 0}, {1, 0, 0}};
    mesh.joints = {{0, 0, 0, 0}, {1, 0, 0, 0}, {0, 1, 0, 0}};
    mesh.weights = {{1, 0, 0, 0}, {1, 0, 0, 0}, {0.5f, 0.5f, 0, 0}};
  }
};

TEST(Skinning, VerticesFollowTheirJointsWeighted) {
  TwoJoints t;
  // Joint 0 stays at the origin; joint 1 moved from its bind place (0, 1, 0) to (3, 1, 0) and
  // turned 90 degrees about z.
  Eigen::Affine3d joint1 = Eigen::Translation3d(3, 1, 0) * Eigen::AngleAxisd(EIGEN_PI / 2, Eigen::Vector3d::UnitZ());
  SkinMesh(t.skin, {Eigen::Matrix4d::Identity(), joint1.matrix()}, &t.mesh);
  ASSERT_EQ(t.mesh.positions.size(), 3u);
  EXPECT_TRUE(t.mesh.positions[0].isApprox(Eigen::Vector3f(0, 0, 0)));
  EXPECT_TRUE(t.mesh.positions[1].isApprox(Eigen::Vector3f(3, 1, 0))) << t.mesh.positions[1].transpose();
  // Vertex 2: half where joint 0 puts it, half where joint 1 does.
  const Eigen::Vector3d by_joint1 = joint1 * (Translation(0, -1, 0) * Eigen::Vector4d(1, 0, 0, 1)).head<3>();
  const Eigen::Vector3f expected = (0.5 * Eigen::Vector3d(1, 0, 0) + 0.5 * by_joint1).cast<float>();
  EXPECT_TRUE(t.mesh.positions[2].isApprox(expected)) << t.mesh.positions[2].transpose();
  // Normals turn with their joint.
  ASSERT_EQ(t.mesh.normals.size(), 3u);
  EXPECT_TRUE(t.mesh.normals[0].isApprox(Eigen::Vector3f(1, 0, 0)));
  EXPECT_LT((t.mesh.normals[1] - Eigen::Vector3f(0, 1, 0)).norm(), 1e-6f) << t.mesh.normals[1].transpose();
  EXPECT_NEAR(t.mesh.normals[2].norm(), 1.0f, 1e-6f);
}

TEST(Skinning, InconsistentDataThrowNamingTheMesh) {
  TwoJoints t;
  t.mesh.joints[1][0] = 2;  // the skin has joints 0 and 1
  EXPECT_THROW(SkinMesh(t.skin, {Eigen::Matrix4d::Identity(), Eigen::Matrix4d::Identity()}, &t.mesh),
               std::invalid_argument);
  TwoJoints u;
  EXPECT_THAT([&] { SkinMesh(u.skin, {Eigen::Matrix4d::Identity()}, &u.mesh); },  // no transform for node 1
              ThrowsWith<std::invalid_argument>("skinned mesh 'arm': joint 1 is node 1"));
  TwoJoints v;
  v.mesh.weights.pop_back();
  EXPECT_THROW(SkinMesh(v.skin, {Eigen::Matrix4d::Identity(), Eigen::Matrix4d::Identity()}, &v.mesh),
               std::invalid_argument);
}

}  // namespace
}  // namespace rigsim
