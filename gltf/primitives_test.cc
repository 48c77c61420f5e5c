#include "gltf/gltf_loader.h"

#include <cmath>
#include <cstdint>
#include <limits>
#include <stdexcept>
#include <vector>

#include <Eigen/Core>
#include <gtest/gtest.h>

#include "gltf/gltf_test_support.h"

namespace rigsim::gltf_test {
namespace {

TEST(GltfLoader, EveryIndexTypeAndNonIndexedGiveTheSameTriangles) {
  const TempDir dir;
  GltfBuilder g;
  const int pos = g.Positions(kUnitQuad);
  g.Mesh({{"POSITION", pos}}, g.Accessor<uint8_t>({0, 1, 2, 0, 2, 3}, kGltfUByte, "SCALAR", 6));
  g.Mesh({{"POSITION", pos}}, g.Accessor<uint16_t>({0, 1, 2, 0, 2, 3}, kGltfUShort, "SCALAR", 6));
  g.Mesh({{"POSITION", pos}}, g.Accessor<uint32_t>({0, 1, 2, 0, 2, 3}, kGltfUInt, "SCALAR", 6));
  g.Mesh({{"POSITION", g.Positions({0, 0, 0, 1, 0, 0, 1, 1, 0, 0, 0, 0, 1, 1, 0, 0, 1, 0})}});
  for (int i = 0; i < 4; ++i) g.Node({{"mesh", i}});
  g.Scene({0, 1, 2, 3});
  const Scene s = LoadGltf(g.Write(dir, "indices"));
  ASSERT_EQ(s.meshes.size(), 4u);
  const auto expected = TriangleCorners(s.meshes[0]);
  ASSERT_EQ(expected.size(), 6u);
  EXPECT_TRUE(expected[4].isApprox(Eigen::Vector3f(1, 1, 0)));
  for (int i = 1; i < 4; ++i) {
    const auto corners = TriangleCorners(s.meshes[i]);
    ASSERT_EQ(corners.size(), 6u) << i;
    for (size_t k = 0; k < 6; ++k) EXPECT_TRUE(corners[k].isApprox(expected[k])) << i << " " << k;
  }
  EXPECT_EQ(s.NumTriangles(), 8u);
}

TEST(GltfLoader, StripsAndFansBecomeTriangles) {
  const TempDir dir;
  GltfBuilder g;
  // A strip over 5 vertices zig-zagging along x in the z = 0 plane: 3 triangles, all facing +z.
  const int strip_pos = g.Positions({0, 1, 0, 1, 1, 0, 0, 0, 0, 1, 0, 0, 2, 1, 0});
  g.Mesh({{"POSITION", strip_pos}}, g.Accessor<uint16_t>({0, 2, 1, 3, 4}, kGltfUShort, "SCALAR", 5), /*mode=*/5);
  // A fan around the origin over 5 vertices: 3 triangles facing +z.
  const int fan_pos = g.Positions({0, 0, 0, 1, 0, 0, 1, 1, 0, 0, 1, 0, -1, 1, 0});
  g.Mesh({{"POSITION", fan_pos}}, -1, /*mode=*/6);
  g.Node({{"mesh", 0}});
  g.Node({{"mesh", 1}});
  g.Scene({0, 1});
  const Scene s = LoadGltf(g.Write(dir, "strips"));
  ASSERT_EQ(s.meshes.size(), 2u);
  ASSERT_EQ(s.meshes[0].indices.size(), 9u);
  ASSERT_EQ(s.meshes[1].indices.size(), 9u);
  for (const SceneMesh& m : s.meshes) {
    for (size_t t = 0; t < 3; ++t) EXPECT_TRUE(FaceNormal(m, t).isApprox(Eigen::Vector3f(0, 0, 1), 1e-5f)) << m.name << t;
  }
  EXPECT_EQ(s.meshes[0].indices, (std::vector<uint32_t>{0, 2, 1, 2, 3, 1, 1, 3, 4}));
  EXPECT_EQ(s.meshes[1].indices, (std::vector<uint32_t>{1, 2, 0, 2, 3, 0, 3, 4, 0}));
}

TEST(GltfLoader, MirroringTransformFlipsWindingAndNormalsUseInverseTranspose) {
  const TempDir dir;
  GltfBuilder g;
  const int pos = g.Positions({0, 0, 0, 1, 0, 0, 0, 1, 0});
  const float n = std::sqrt(0.5f);
  const int nrm = g.Accessor<float>({n, 0, n, n, 0, n, n, 0, n}, kGltfFloat, "VEC3", 3);
  g.Mesh({{"POSITION", pos}, {"NORMAL", nrm}});
  g.Node({{"mesh", 0}, {"scale", {-1, 1, 1}}});  // mirror
  g.Node({{"mesh", 0}, {"scale", {4, 1, 1}}});   // non-uniform
  g.Scene({0, 1});
  const Scene s = LoadGltf(g.Write(dir, "mirror"));
  ASSERT_EQ(s.meshes.size(), 2u);
  // The unmirrored triangle faces +z; mirrored in x it must still face +z (winding flipped).
  EXPECT_TRUE(FaceNormal(s.meshes[0], 0).isApprox(Eigen::Vector3f(0, 0, 1), 1e-5f));
  EXPECT_TRUE(s.meshes[0].normals[0].isApprox(Eigen::Vector3f(-n, 0, n), 1e-5f));
  // Scaling x by 4 tilts the normal towards z: inverse transpose = diag(1/4, 1, 1), renormalised.
  EXPECT_TRUE(s.meshes[1].normals[0].isApprox(Eigen::Vector3f(0.25f, 0, 1).normalized(), 1e-5f));
  EXPECT_TRUE(FaceNormal(s.meshes[1], 0).isApprox(Eigen::Vector3f(0, 0, 1), 1e-5f));
}

TEST(GltfLoader, LinesAndUnsupportedFeaturesAreWarnings) {
  const TempDir dir;
  GltfBuilder g;
  const int pos = g.Positions({0, 0, 0, 1, 0, 0, 0, 1, 0});
  g.Mesh({{"POSITION", pos}}, -1, /*LINES=*/1);
  g.doc["meshes"][0]["name"] = "wires";
  g.Mesh({{"POSITION", pos}, {"COLOR_1", pos}}, -1, 4);
  g.doc["extensionsUsed"] = {"KHR_materials_clearcoat"};
  g.doc["cameras"] = json::array({{{"type", "perspective"}, {"perspective", {{"yfov", 1.0}, {"znear", 0.1}}}}});
  g.Node({{"mesh", 0}});
  g.Node({{"mesh", 1}, {"camera", 0}});
  g.Scene({0, 1});
  const Scene s = LoadGltf(g.Write(dir, "lines"));
  EXPECT_EQ(s.meshes.size(), 1u);
  EXPECT_TRUE(HasWarning(s, "mesh 0 'wires' primitive 0: lines primitive"));
  EXPECT_TRUE(HasWarning(s, "KHR_materials_clearcoat"));
  EXPECT_EQ(s.cameras.size(), 1u) << "cameras are loaded (gltf/scene_cameras.h), not warned about";
  EXPECT_FALSE(HasWarning(s, "camera"));
  EXPECT_TRUE(HasWarning(s, "vertex attribute COLOR_1"));
  GltfLoadOptions strict;
  strict.warnings_are_errors = true;
  EXPECT_THROW(LoadGltf(dir / "lines.gltf", strict), std::runtime_error);
}

TEST(GltfLoader, VertexColoursAreReadAsLinearRgba) {
  const TempDir dir;
  GltfBuilder g;
  const int pos = g.Positions({0, 0, 0, 1, 0, 0, 0, 1, 0});
  // VEC3 float (alpha 1) on one mesh, VEC4 normalized unsigned byte on the other.
  const int rgb = g.Accessor(std::vector<float>{1, 0, 0, 0, 0.5f, 0, 0, 0, 2}, kGltfFloat, "VEC3", 3);
  const int rgba = g.Accessor(std::vector<uint8_t>{255, 0, 0, 255, 0, 51, 0, 102, 0, 0, 255, 0}, kGltfUByte, "VEC4", 3, true);
  g.Mesh({{"POSITION", pos}, {"COLOR_0", rgb}});
  g.Mesh({{"POSITION", pos}, {"COLOR_0", rgba}});
  g.Node({{"mesh", 0}});
  g.Node({{"mesh", 1}});
  g.Scene({0, 1});
  const Scene s = LoadGltf(g.Write(dir, "colours"));
  ASSERT_EQ(s.meshes.size(), 2u);
  ASSERT_EQ(s.meshes[0].colors.size(), 3u);
  EXPECT_TRUE(s.meshes[0].colors[0].isApprox(Eigen::Vector4f(1, 0, 0, 1)));
  EXPECT_TRUE(s.meshes[0].colors[1].isApprox(Eigen::Vector4f(0, 0.5f, 0, 1)));
  EXPECT_TRUE(s.meshes[0].colors[2].isApprox(Eigen::Vector4f(0, 0, 1, 1))) << "clipped to the spec's [0, 1]";
  ASSERT_EQ(s.meshes[1].colors.size(), 3u);
  EXPECT_TRUE(s.meshes[1].colors[1].isApprox(Eigen::Vector4f(0, 0.2f, 0, 0.4f)));
  EXPECT_TRUE(s.meshes[1].colors[2].isApprox(Eigen::Vector4f(0, 0, 1, 0)));
  EXPECT_FALSE(HasWarning(s, "COLOR_0"));

  GltfBuilder bad;
  const int bad_pos = bad.Positions({0, 0, 0, 1, 0, 0, 0, 1, 0});
  const int not_normalized = bad.Accessor(std::vector<uint8_t>{255, 0, 0, 0, 255, 0, 0, 0, 255, 0, 0, 0}, kGltfUByte, "VEC3", 3);
  const int too_few = bad.Accessor(std::vector<float>{1, 1, 1, 1, 1, 1}, kGltfFloat, "VEC3", 2);
  const int scalar = bad.Accessor(std::vector<float>{1, 1, 1}, kGltfFloat, "SCALAR", 3);
  bad.Node({{"mesh", bad.Mesh({{"POSITION", bad_pos}, {"COLOR_0", not_normalized}})}});
  bad.Scene({0});
  ExpectLoadFails(bad.Write(dir, "not_normalized"),
                   "COLOR_0): componentType must be FLOAT, or normalized UNSIGNED_BYTE or UNSIGNED_SHORT");
  bad.doc["meshes"][0]["primitives"][0]["attributes"]["COLOR_0"] = too_few;
  ExpectLoadFails(bad.Write(dir, "too_few"), "COLOR_0): count differs from POSITION");
  bad.doc["meshes"][0]["primitives"][0]["attributes"]["COLOR_0"] = scalar;
  ExpectLoadFails(bad.Write(dir, "scalar"), "COLOR_0): type must be VEC3 or VEC4");
}

TEST(GltfLoader, NonFiniteVertexThrows) {
  const TempDir dir;
  GltfBuilder g;
  g.Mesh({{"POSITION", g.Positions({0, 0, 0, std::numeric_limits<float>::quiet_NaN(), 0, 0, 0, 1, 0})}});
  g.Node({{"mesh", 0}});
  g.Scene({0});
  ExpectLoadFails(g.Write(dir, "nan"), "vertex 1 is not finite");
}

}  // namespace
}  // namespace rigsim::gltf_test
