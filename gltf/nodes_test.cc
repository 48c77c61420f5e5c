#include "gltf/gltf_loader.h"

#include <cmath>
#include <cstdint>
#include <tuple>
#include <vector>

#include <Eigen/Geometry>
#include <gtest/gtest.h>

#include "gltf/gltf_test_support.h"

namespace rigsim::gltf_test {
namespace {

TEST(GltfLoader, TrsEqualsMatrix) {
  const TempDir dir;
  const Eigen::Quaterniond q(Eigen::AngleAxisd(0.7, Eigen::Vector3d(1, 2, 3).normalized()));
  const Eigen::Vector3d t(1, -2, 3), s(2, 0.5, 1.5);
  Eigen::Affine3d a = Eigen::Translation3d(t) * q * Eigen::Scaling(s);
  std::vector<double> matrix(a.matrix().data(), a.matrix().data() + 16);  // column-major like glTF

  GltfBuilder trs, mat;
  for (GltfBuilder* g : {&trs, &mat}) g->Mesh({{"POSITION", g->Positions(kUnitQuad)}}, g->Accessor<uint8_t>({0, 1, 2, 0, 2, 3}, kGltfUByte, "SCALAR", 6));
  trs.Node({{"mesh", 0}, {"translation", {t.x(), t.y(), t.z()}}, {"rotation", {q.x(), q.y(), q.z(), q.w()}}, {"scale", {s.x(), s.y(), s.z()}}});
  mat.Node({{"mesh", 0}, {"matrix", matrix}});
  trs.Scene({0});
  mat.Scene({0});
  const Scene a_scene = LoadGltf(trs.Write(dir, "trs"));
  const Scene b_scene = LoadGltf(mat.Write(dir, "matrix"));
  ASSERT_EQ(a_scene.meshes.size(), 1u);
  ASSERT_EQ(b_scene.meshes.size(), 1u);
  for (size_t i = 0; i < 4; ++i) {
    const Eigen::Vector3d expected = a * Eigen::Vector3d(kUnitQuad[3 * i], kUnitQuad[3 * i + 1], kUnitQuad[3 * i + 2]);
    EXPECT_TRUE(a_scene.meshes[0].positions[i].isApprox(expected.cast<float>(), 1e-5f));
    EXPECT_TRUE(b_scene.meshes[0].positions[i].isApprox(expected.cast<float>(), 1e-5f));
  }
}

// glTF: matrix has 16 numbers, translation and scale 3, rotation 4, and rotation is a unit
// quaternion. tinygltf takes any count; a wrong one, or a zero quaternion, was read as identity.
// A non-unit rotation is normalised (exporters round). (Non-finite numbers cannot get this far:
// the JSON parser refuses 1e999, and the node's world transform is checked.)
TEST(GltfLoader, InvalidNodeTransformsAreRefusedNamingTheNode) {
  const TempDir dir;
  GltfBuilder g;
  g.Node({{"name", "quad"}, {"mesh", g.Mesh({{"POSITION", g.Positions({1, 0, 0, 0, 1, 0, 0, 0, 1})}})}});
  g.Scene({0});
  const json identity15 = {1, 0, 0, 0, 0, 1, 0, 0, 0, 0, 1, 0, 0, 0, 0};
  for (const auto& [property, value, error] :
       {std::tuple{"matrix", identity15, "node 0 'quad': matrix has 15 numbers, glTF requires 16"},
        std::tuple{"translation", json{1, 2}, "node 0 'quad': translation has 2 numbers, glTF requires 3"},
        std::tuple{"rotation", json{0, 0, 0, 0}, "node 0 'quad': rotation is a zero quaternion, which is no rotation"},
        std::tuple{"scale", json{1, 1, 1, 1}, "node 0 'quad': scale has 4 numbers, glTF requires 3"}}) {
    GltfBuilder bad = g;
    bad.doc["nodes"][0][property] = value;
    ExpectLoadFails(bad.Write(dir, property), error);
  }
  GltfBuilder turned = g;  // 90 degrees about +y, at twice unit length
  turned.doc["nodes"][0]["rotation"] = {0, std::sqrt(2.0), 0, std::sqrt(2.0)};
  const Scene s = LoadGltf(turned.Write(dir, "turned"));
  ASSERT_EQ(s.meshes.size(), 1u);
  EXPECT_TRUE(s.meshes[0].positions[0].isApprox(Eigen::Vector3f(0, 0, -1), 1e-6f)) << s.meshes[0].positions[0].transpose();
}

TEST(GltfLoader, NestedTransformsAccumulate) {
  const TempDir dir;
  GltfBuilder g;
  g.Mesh({{"POSITION", g.Positions({1, 0, 0, 0, 1, 0, 0, 0, 1})}});
  // root translates by (10, 0, 0); child rotates 90 deg about +y; grandchild scales by 2 and has the mesh.
  const double h = std::sqrt(0.5);
  g.Node({{"translation", {10, 0, 0}}, {"children", {1}}});
  g.Node({{"rotation", {0, h, 0, h}}, {"children", {2}}});
  g.Node({{"scale", {2, 2, 2}}, {"mesh", 0}});
  g.Scene({0});
  const Scene s = LoadGltf(g.WriteEmbedded(dir, "nested"));
  ASSERT_EQ(s.meshes.size(), 1u);
  // R_y(90) maps x -> -z, z -> x.
  EXPECT_TRUE(s.meshes[0].positions[0].isApprox(Eigen::Vector3f(10, 0, -2), 1e-5f));
  EXPECT_TRUE(s.meshes[0].positions[1].isApprox(Eigen::Vector3f(10, 2, 0), 1e-5f));
  EXPECT_TRUE(s.meshes[0].positions[2].isApprox(Eigen::Vector3f(12, 0, 0), 1e-5f));
  EXPECT_EQ(s.meshes[0].indices, (std::vector<uint32_t>{0, 1, 2}));  // non-indexed
}

TEST(GltfLoader, InstanceIdsFollowDepthFirstTraversal) {
  const TempDir dir;
  GltfBuilder g;
  const int mesh = g.Mesh({{"POSITION", g.Positions({0, 0, 0, 1, 0, 0, 0, 1, 0})}});
  g.Node({{"name", "a"}, {"mesh", mesh}, {"children", {2}}});  // 0
  g.Node({{"name", "c"}, {"mesh", mesh}});                     // 1
  g.Node({{"name", "b"}, {"children", {3}}});                  // 2: no mesh, no id
  g.Node({{"name", "b1"}, {"mesh", mesh}});                    // 3
  g.Scene({0, 1});
  const Scene s = LoadGltf(g.Write(dir, "instances"));
  ASSERT_EQ(s.meshes.size(), 3u);
  EXPECT_EQ(s.meshes[0].name, "a");
  EXPECT_EQ(s.meshes[0].instance_id, 1);
  EXPECT_EQ(s.meshes[1].name, "b1");
  EXPECT_EQ(s.meshes[1].instance_id, 2);
  EXPECT_EQ(s.meshes[2].name, "c");
  EXPECT_EQ(s.meshes[2].instance_id, 3);
}

TEST(GltfLoader, RecursiveNodesThrow) {
  const TempDir dir;
  GltfBuilder g;
  g.Mesh({{"POSITION", g.Positions({0, 0, 0, 1, 0, 0, 0, 1, 0})}});
  g.Node({{"mesh", 0}, {"children", {1}}});
  g.Node({{"children", {0}}});  // cycle back to the root
  g.Scene({0});
  ExpectLoadFails(g.Write(dir, "cycle"), "reached twice");
}

}  // namespace
}  // namespace rigsim::gltf_test
