#include "scene/morphing.h"

#include <stdexcept>
#include <vector>

#include <gtest/gtest.h>

namespace rigsim {
namespace {

// Two vertices, two targets: target 0 lifts vertex 0 by 1 in y and tips its normal towards x;
// target 1 moves vertex 1 by 2 in x and turns no normal.
SceneMesh TwoTargets() {
  SceneMesh mesh;
  mesh.name = "face";
  mesh.morph_base_positions = {{0, 0, 0}, {1, 0, 0}};
  mesh.morph_base_normals = {{0, 0, 1}, {0, 0, 1}};
  mesh.morph_targets.resize(2);
  mesh.morph_targets[0].positions = {{0, 1, 0}, {0, 0, 0}};
  mesh.morph_targets[0].normals = {{1, 0, 0}, {0, 0, 0}};
  mesh.morph_targets[1].positions = {{0, 0, 0}, {2, 0, 0}};
  return mesh;
}

TEST(Morphing, WeightedDisplacementsAreAddedAndNormalsRenormalised) {
  SceneMesh mesh = TwoTargets();
  MorphMesh({0.5, 0.25}, &mesh);
  ASSERT_EQ(mesh.local_positions.size(), 2u);
  EXPECT_TRUE(mesh.local_positions[0].isApprox(Eigen::Vector3f(0, 0.5f, 0))) << mesh.local_positions[0].transpose();
  EXPECT_TRUE(mesh.local_positions[1].isApprox(Eigen::Vector3f(1.5f, 0, 0))) << mesh.local_positions[1].transpose();
  ASSERT_EQ(mesh.local_normals.size(), 2u);
  EXPECT_TRUE(mesh.local_normals[0].isApprox(Eigen::Vector3f(0.5f, 0, 1).normalized())) << mesh.local_normals[0].transpose();
  EXPECT_TRUE(mesh.local_normals[1].isApprox(Eigen::Vector3f(0, 0, 1)));
  // Zero weights give the base back; the base is not changed by morphing.
  MorphMesh({0.0, 0.0}, &mesh);
  EXPECT_EQ(mesh.local_positions, mesh.morph_base_positions);
  EXPECT_EQ(mesh.local_normals, mesh.morph_base_normals);
}

TEST(Morphing, SizesThatDoNotFitThrow) {
  SceneMesh mesh = TwoTargets();
  EXPECT_THROW(MorphMesh({1.0}, &mesh), std::invalid_argument);
  mesh.morph_targets[1].positions.pop_back();
  EXPECT_THROW(MorphMesh({1.0, 1.0}, &mesh), std::invalid_argument);
}

}  // namespace
}  // namespace rigsim
