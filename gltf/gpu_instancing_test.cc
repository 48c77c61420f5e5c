#include "gltf/gltf_loader.h"

#include <cmath>
#include <cstdint>
#include <limits>
#include <string>
#include <vector>

#include <Eigen/Core>
#include <gtest/gtest.h>

#include "gltf/gltf_test_support.h"
#include "labels/cityscapes.h"

namespace rigsim::gltf_test {
namespace {

// EXT_mesh_gpu_instancing: a quad (with a tilted normal) on node 0 "forest" at translation (10, 0,
// 0), drawn by three instances: identity; T (0, 2, 0) R 90 deg about z S (2, 1, 1); T (0, 0, 3)
// S (-1, 1, 1), a mirror. ROTATION as float, or as normalized short when `short_rotation`.
GltfBuilder InstancedQuad(bool short_rotation) {
  constexpr int kShort = 5122;
  GltfBuilder g;
  g.doc["extensionsUsed"] = {"EXT_mesh_gpu_instancing"};
  g.doc["extensionsRequired"] = {"EXT_mesh_gpu_instancing"};
  const float n = std::sqrt(0.5f);
  const int pos = g.Positions(kUnitQuad);
  const int nrm = g.Accessor<float>({n, 0, n, n, 0, n, n, 0, n, n, 0, n}, kGltfFloat, "VEC3", 4);
  g.doc["materials"] = json::array({{{"name", "bark"}}});
  g.Mesh({{"POSITION", pos}, {"NORMAL", nrm}}, g.Accessor<uint8_t>({0, 1, 2, 0, 2, 3}, kGltfUByte, "SCALAR", 6), 4, 0, {{"class", "vegetation"}});
  const int t = g.Accessor<float>({0, 0, 0, 0, 2, 0, 0, 0, 3}, kGltfFloat, "VEC3", 3);
  const int s = g.Accessor<float>({1, 1, 1, 2, 1, 1, -1, 1, 1}, kGltfFloat, "VEC3", 3);
  const float h = std::sqrt(0.5f);
  const int r = short_rotation
                    ? g.Accessor<int16_t>({0, 0, 0, 32767, 0, 0, 23170, 23170, 0, 0, 0, 32767}, kShort, "VEC4", 3, /*normalized=*/true)
                    : g.Accessor<float>({0, 0, 0, 1, 0, 0, h, h, 0, 0, 0, 1}, kGltfFloat, "VEC4", 3);
  g.Node({{"name", "forest"}, {"mesh", 0}, {"translation", {10, 0, 0}},
          {"extensions", {{"EXT_mesh_gpu_instancing", {{"attributes", {{"TRANSLATION", t}, {"ROTATION", r}, {"SCALE", s}}}}}}}});
  g.Scene({0});
  return g;
}

TEST(GltfLoader, GpuInstancesAreSeparateObjectsPlacedByNodeTimesInstance) {
  const TempDir dir;
  for (bool short_rotation : {false, true}) {
    SCOPED_TRACE(short_rotation ? "normalized short rotation" : "float rotation");
    const Scene s = LoadGltf(InstancedQuad(short_rotation).Write(dir, short_rotation ? "short" : "float"));
    ASSERT_EQ(s.meshes.size(), 3u);
    EXPECT_EQ(s.NumTriangles(), 6u);
    EXPECT_TRUE(s.warnings.empty()) << s.warnings.front();
    // world = node * T * R * S * vertex, corners (0,0,0) (1,0,0) (1,1,0) (0,1,0).
    const std::vector<std::vector<Eigen::Vector3f>> expected = {
        {{10, 0, 0}, {11, 0, 0}, {11, 1, 0}, {10, 1, 0}},
        {{10, 2, 0}, {10, 4, 0}, {9, 4, 0}, {9, 2, 0}},  // (1,0,0) -> S (2,0,0) -> R (0,2,0) -> T (0,4,0)
        {{10, 0, 3}, {9, 0, 3}, {9, 1, 3}, {10, 1, 3}}};
    for (int i = 0; i < 3; ++i) {
      const SceneMesh& m = s.meshes[i];
      EXPECT_EQ(m.instance_id, i + 1);
      EXPECT_EQ(m.gpu_instance, i);
      EXPECT_EQ(m.class_id, FindClassByName("vegetation")->id);
      EXPECT_EQ(m.material, 0);
      EXPECT_EQ(m.name, "forest");
      ASSERT_EQ(m.positions.size(), 4u);
      for (int v = 0; v < 4; ++v) {
        EXPECT_TRUE(m.positions[v].isApprox(expected[i][v], 1e-4f)) << i << " " << v << ": " << m.positions[v].transpose();
      }
      // Every instance faces +z, the mirrored one too: its winding is turned, as for a mirroring node.
      EXPECT_TRUE(FaceNormal(m, 0).isApprox(Eigen::Vector3f(0, 0, 1), 1e-4f)) << i << ": " << FaceNormal(m, 0).transpose();
    }
    // Normals by the inverse transpose: S (2, 1, 1) tilts (1, 0, 1) to (1, 0, 2), R turns it to (0, 1, 2).
    const float n = std::sqrt(0.5f);
    EXPECT_TRUE(s.meshes[0].normals[0].isApprox(Eigen::Vector3f(n, 0, n), 1e-4f));
    EXPECT_TRUE(s.meshes[1].normals[0].isApprox(Eigen::Vector3f(0, 1, 2).normalized(), 1e-4f)) << s.meshes[1].normals[0].transpose();
    EXPECT_TRUE(s.meshes[2].normals[0].isApprox(Eigen::Vector3f(-n, 0, n), 1e-4f)) << s.meshes[2].normals[0].transpose();
  }
}

// The node's own transform (with its parent's) applies after the instance's: a node turned 90 deg
// about z with an instance moved 1 along x puts the quad's origin at (0, 1, 0) in the node's
// parent, not at (1, 0, 0).
TEST(GltfLoader, GpuInstanceTransformComesBeforeTheNodes) {
  const TempDir dir;
  GltfBuilder g;
  g.Mesh({{"POSITION", g.Positions(kUnitQuad)}}, g.Accessor<uint8_t>({0, 1, 2, 0, 2, 3}, kGltfUByte, "SCALAR", 6));
  const int t = g.Accessor<float>({1, 0, 0}, kGltfFloat, "VEC3", 1);
  const double h = std::sqrt(0.5);
  g.Node({{"translation", {0, 0, 5}}, {"children", {1}}});
  g.Node({{"mesh", 0}, {"rotation", {0, 0, h, h}}, {"extensions", {{"EXT_mesh_gpu_instancing", {{"attributes", {{"TRANSLATION", t}}}}}}}});
  g.Scene({0});
  const Scene s = LoadGltf(g.Write(dir, "order"));
  ASSERT_EQ(s.meshes.size(), 1u);
  EXPECT_TRUE(s.meshes[0].positions[0].isApprox(Eigen::Vector3f(0, 1, 5), 1e-5f)) << s.meshes[0].positions[0].transpose();
  EXPECT_TRUE(s.meshes[0].positions[1].isApprox(Eigen::Vector3f(0, 2, 5), 1e-5f)) << s.meshes[0].positions[1].transpose();
}

// TRANSLATION alone: rotation and scale are identity. A custom attribute (_ID) is named as ignored;
// the extension itself is not warned about.
TEST(GltfLoader, GpuInstancesDefaultToIdentityAndIgnoreCustomAttributes) {
  const TempDir dir;
  GltfBuilder g;
  g.doc["extensionsUsed"] = {"EXT_mesh_gpu_instancing"};
  g.Mesh({{"POSITION", g.Positions({0, 0, 0, 1, 0, 0, 0, 1, 0})}});
  const int t = g.Accessor<float>({0, 0, 0, 5, 0, 0}, kGltfFloat, "VEC3", 2);
  const int id = g.Accessor<float>({7, 8}, kGltfFloat, "SCALAR", 2);
  g.Node({{"mesh", 0}, {"extensions", {{"EXT_mesh_gpu_instancing", {{"attributes", {{"TRANSLATION", t}, {"_ID", id}}}}}}}});
  g.Node({{"mesh", 0}, {"translation", {0, 0, 9}}});  // not instanced: one instance, after the two
  g.Scene({0, 1});
  const Scene s = LoadGltf(g.Write(dir, "defaults"));
  ASSERT_EQ(s.meshes.size(), 3u);
  EXPECT_EQ(s.meshes[0].positions, (std::vector<Eigen::Vector3f>{{0, 0, 0}, {1, 0, 0}, {0, 1, 0}}));
  EXPECT_EQ(s.meshes[1].positions, (std::vector<Eigen::Vector3f>{{5, 0, 0}, {6, 0, 0}, {5, 1, 0}}));
  EXPECT_EQ(s.meshes[1].indices, (std::vector<uint32_t>{0, 1, 2}));
  EXPECT_EQ(s.meshes[2].positions[0], Eigen::Vector3f(0, 0, 9));
  EXPECT_EQ(s.meshes[0].instance_id, 1);
  EXPECT_EQ(s.meshes[1].instance_id, 2);
  EXPECT_EQ(s.meshes[2].instance_id, 3);
  EXPECT_EQ(s.meshes[2].gpu_instance, -1);
  EXPECT_TRUE(HasWarning(s, "EXT_mesh_gpu_instancing attribute _ID"));
  EXPECT_FALSE(HasWarning(s, "extension EXT_mesh_gpu_instancing"));
  EXPECT_FALSE(HasWarning(s, "node extension"));
}

TEST(GltfLoader, MalformedGpuInstancingThrowsNamingNodeAndAccessor) {
  const TempDir dir;
  constexpr int kUShortNormalized = 5123;
  GltfBuilder g = InstancedQuad(false);  // accessors: 0 POSITION, 1 NORMAL, 2 indices, 3 T, 4 S, 5 R
  json& attributes = g.doc["nodes"][0]["extensions"]["EXT_mesh_gpu_instancing"]["attributes"];
  const int two = g.Accessor<float>({0, 0, 0, 1, 1, 1}, kGltfFloat, "VEC3", 2);
  attributes["SCALE"] = two;
  ExpectLoadFails(g.Write(dir, "counts"), "accessor " + std::to_string(two) +
                                               " (node 0 'forest' EXT_mesh_gpu_instancing SCALE): count 2 differs from ROTATION's 3");
  attributes["SCALE"] = 4;
  attributes["TRANSLATION"] = 5;  // a VEC4
  ExpectLoadFails(g.Write(dir, "type"), "accessor 5 (node 0 'forest' EXT_mesh_gpu_instancing TRANSLATION): type must be VEC3");
  attributes["TRANSLATION"] = 3;
  attributes["ROTATION"] = g.Accessor<uint16_t>({0, 0, 0, 65535, 0, 0, 0, 65535, 0, 0, 0, 65535}, kUShortNormalized, "VEC4", 3, true);
  ExpectLoadFails(g.Write(dir, "component"), "EXT_mesh_gpu_instancing ROTATION): componentType must be FLOAT, or normalized BYTE or SHORT");
  attributes["ROTATION"] = g.Accessor<float>({0, 0, 0, 1, 0, 0, 0, 0, 0, 0, 0, 1}, kGltfFloat, "VEC4", 3);
  ExpectLoadFails(g.Write(dir, "zero_quaternion"), "ROTATION): instance 1 has a zero quaternion");
  attributes["ROTATION"] = 5;
  attributes["SCALE"] = g.Accessor<float>({1, 1, 1, 1, std::numeric_limits<float>::infinity(), 1, 1, 1, 1}, kGltfFloat, "VEC3", 3);
  ExpectLoadFails(g.Write(dir, "infinite"), "EXT_mesh_gpu_instancing SCALE): instance 1 is not finite");
  attributes.erase("ROTATION");
  attributes["SCALE"] = g.Accessor<float>({}, kGltfFloat, "VEC3", 0);
  ExpectLoadFails(g.Write(dir, "empty"), "EXT_mesh_gpu_instancing SCALE): count is 0");
  attributes["SCALE"] = 99;
  ExpectLoadFails(g.Write(dir, "range"), "accessor 99 (node 0 'forest' EXT_mesh_gpu_instancing SCALE): index out of range");
  g.doc["nodes"][0]["extensions"]["EXT_mesh_gpu_instancing"] = json::object();
  ExpectLoadFails(g.Write(dir, "no_attributes"), "node 0 'forest' EXT_mesh_gpu_instancing: has no attributes object");
}

// Instances copy geometry decoded once per node, and what they make in all is bounded: a file
// asking for more fails naming the limit. 100 instances of a quad (4 vertices + 6 indices) make
// 1000; decoded are 10 + 3 x 100 elements, 1300 had the quad been decoded again per instance.
TEST(GltfLoader, GpuInstancesAreDecodedOnceAndBoundedInTotal) {
  const TempDir dir;
  GltfBuilder g;
  g.Mesh({{"POSITION", g.Positions(kUnitQuad)}}, g.Accessor<uint8_t>({0, 1, 2, 0, 2, 3}, kGltfUByte, "SCALAR", 6));
  std::vector<float> t, r, s;
  for (int i = 0; i < 100; ++i) {
    t.insert(t.end(), {float(i), 0, 0});
    r.insert(r.end(), {0, 0, 0, 1});
    s.insert(s.end(), {1, 1, 1});
  }
  const json attributes = {{"TRANSLATION", g.Accessor(t, kGltfFloat, "VEC3", 100)}, {"ROTATION", g.Accessor(r, kGltfFloat, "VEC4", 100)},
                           {"SCALE", g.Accessor(s, kGltfFloat, "VEC3", 100)}};
  g.Node({{"mesh", 0}, {"extensions", {{"EXT_mesh_gpu_instancing", {{"attributes", attributes}}}}}});
  g.Scene({0});
  const auto path = g.Write(dir, "forest");
  GltfLoadOptions options;
  options.max_accessor_count = 1299;
  const Scene forest = LoadGltf(path, options);
  ASSERT_EQ(forest.meshes.size(), 100u);
  EXPECT_EQ(forest.meshes[99].positions[0], Eigen::Vector3f(99, 0, 0));
  EXPECT_EQ(forest.meshes[99].instance_id, 100);
  options.max_accessor_count = 999;
  ExpectLoadFails(path, options,
                          "node 0 EXT_mesh_gpu_instancing: 100 instances of a mesh of 10 vertices and indices each exceed the limit "
                          "of 999 on all instanced geometry (GltfLoadOptions::max_accessor_count");
  // An absurd count is refused from the accessor's metadata, before anything is allocated.
  g.doc["accessors"][int(attributes["TRANSLATION"])]["count"] = 4000000000ull;
  g.doc["accessors"][int(attributes["ROTATION"])]["count"] = 4000000000ull;
  g.doc["accessors"][int(attributes["SCALE"])]["count"] = 4000000000ull;
  ExpectLoadFails(g.Write(dir, "absurd"), "4000000000 instances of a mesh of 10 vertices and indices each exceed the limit of 67108864");
}

// Instance ids are uint16: past 65535 instances, further ones get 0 and one warning says so.
TEST(GltfLoader, GpuInstancesBeyond65535GetIdZeroWithOneWarning) {
  const TempDir dir;
  GltfBuilder g;
  g.Mesh({{"POSITION", g.Positions({0, 0, 0, 1, 0, 0, 0, 1, 0})}});
  constexpr int kCount = 65540;
  std::vector<float> t(3 * kCount);
  for (int i = 0; i < kCount; ++i) t[3 * i] = float(i);
  const int ta = g.Accessor(t, kGltfFloat, "VEC3", kCount);
  g.Node({{"mesh", 0}, {"extras", {{"class", "person"}}}, {"extensions", {{"EXT_mesh_gpu_instancing", {{"attributes", {{"TRANSLATION", ta}}}}}}}});
  g.Scene({0});
  const Scene s = LoadGltf(g.Write(dir, "crowd"));
  ASSERT_EQ(s.meshes.size(), size_t(kCount));
  EXPECT_EQ(s.meshes[65534].instance_id, 65535);
  EXPECT_EQ(s.meshes[65535].instance_id, 0);
  EXPECT_EQ(s.meshes[kCount - 1].instance_id, 0);
  EXPECT_EQ(s.meshes[kCount - 1].positions[0], Eigen::Vector3f(kCount - 1, 0, 0));
  EXPECT_EQ(s.warnings, (std::vector<std::string>{"more than 65535 mesh nodes or instances: further ones get instance id 0"}));
}

// Under an animated node, every instance keeps its node, its mesh-frame vertices and its
// node_from_instance for PoseSceneAt. A skinned node with the extension (undefined by it) is drawn
// once, by its joints, with a warning; on a node without a mesh the extension is warned about.
TEST(GltfLoader, GpuInstancesUnderAnimationSkinsAndMeshlessNodes) {
  const TempDir dir;
  GltfBuilder g;
  g.Mesh({{"POSITION", g.Positions(kUnitQuad)}}, g.Accessor<uint8_t>({0, 1, 2, 0, 2, 3}, kGltfUByte, "SCALAR", 6));
  const int t = g.Accessor<float>({0, 0, 0, 0, 3, 0}, kGltfFloat, "VEC3", 2);
  const json instancing = {{"EXT_mesh_gpu_instancing", {{"attributes", {{"TRANSLATION", t}}}}}};
  g.Node({{"mesh", 0}, {"translation", {1, 0, 0}}, {"extensions", instancing}});
  g.Node({{"name", "empty"}, {"extensions", instancing}});
  g.Scene({0, 1});
  const int times = g.Accessor(std::vector<float>{0, 1}, kGltfFloat, "SCALAR", 2);
  const int moves = g.Accessor(std::vector<float>{1, 0, 0, 2, 0, 0}, kGltfFloat, "VEC3", 2);
  g.doc["animations"] = json::array({{{"samplers", {{{"input", times}, {"output", moves}}}},
                                      {"channels", {{{"sampler", 0}, {"target", {{"node", 0}, {"path", "translation"}}}}}}}});
  const Scene s = LoadGltf(g.Write(dir, "animated"));
  ASSERT_EQ(s.meshes.size(), 2u);
  for (int i = 0; i < 2; ++i) {
    const SceneMesh& m = s.meshes[i];
    EXPECT_EQ(m.node, 0);
    EXPECT_EQ(m.gpu_instance, i);
    EXPECT_EQ(m.local_positions[1], Eigen::Vector3f(1, 0, 0)) << "the mesh's own frame";
    const Eigen::Vector3d offset = m.node_from_instance.topRightCorner<3, 1>();
    EXPECT_TRUE(offset.isApprox(Eigen::Vector3d(0, 3 * i, 0)) || (i == 0 && offset.isZero()));
    EXPECT_EQ(m.positions[1], Eigen::Vector3f(2, 3 * i, 0)) << "at rest";
  }
  EXPECT_TRUE(HasWarning(s, "node 1 'empty': EXT_mesh_gpu_instancing on a node without a mesh"));

  GltfBuilder k;  // the skinned quad of SkinnedMeshesArePlacedByTheirJoints, with two instances
  const int pos = k.Positions(kUnitQuad);
  const int joints = k.Accessor<uint8_t>(std::vector<uint8_t>(16, 0), kGltfUByte, "VEC4", 4);
  const int weights = k.Accessor<float>({1, 0, 0, 0, 1, 0, 0, 0, 1, 0, 0, 0, 1, 0, 0, 0}, kGltfFloat, "VEC4", 4);
  k.doc["skins"] = json::array({{{"joints", {1}}}});
  const int kt = k.Accessor<float>({0, 0, 0, 0, 3, 0}, kGltfFloat, "VEC3", 2);
  k.Node({{"mesh", k.Mesh({{"POSITION", pos}, {"JOINTS_0", joints}, {"WEIGHTS_0", weights}}, -1, 6)}, {"skin", 0},
          {"extensions", {{"EXT_mesh_gpu_instancing", {{"attributes", {{"TRANSLATION", kt}}}}}}}});
  k.Node({{"translation", {5, 0, 0}}});
  k.Scene({0, 1});
  const Scene skinned = LoadGltf(k.Write(dir, "skinned"));
  ASSERT_EQ(skinned.meshes.size(), 1u);
  EXPECT_EQ(skinned.meshes[0].skin, 0);
  EXPECT_EQ(skinned.meshes[0].gpu_instance, -1);
  EXPECT_TRUE(skinned.meshes[0].positions[1].isApprox(Eigen::Vector3f(6, 0, 0))) << skinned.meshes[0].positions[1].transpose();
  EXPECT_TRUE(HasWarning(skinned, "node 0 EXT_mesh_gpu_instancing: on a skinned node"));
}

}  // namespace
}  // namespace rigsim::gltf_test
