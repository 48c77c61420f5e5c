#include "gltf/gltf_loader.h"

#include <cstdint>

#include <Eigen/Core>
#include <gtest/gtest.h>

#include "gltf/gltf_test_support.h"

namespace rigsim::gltf_test {
namespace {

TEST(GltfLoader, SparseAccessorOverridesValues) {
  const TempDir dir;
  GltfBuilder g;
  const int pos = g.Positions({0, 0, 0, 1, 0, 0, 0, 1, 0});
  const int before = int(g.doc["bufferViews"].size());
  g.Accessor<uint8_t>({2, 0, 0, 0}, kGltfUByte, "SCALAR", 1);  // just to get bufferViews for sparse data
  g.Accessor<float>({5, 6, 7}, kGltfFloat, "VEC3", 1);
  g.doc["accessors"][pos]["sparse"] = {{"count", 1},
                                       {"indices", {{"bufferView", before}, {"componentType", kGltfUByte}}},
                                       {"values", {{"bufferView", before + 1}}}};
  g.Mesh({{"POSITION", pos}});
  g.Node({{"mesh", 0}});
  g.Scene({0});
  const Scene s = LoadGltf(g.Write(dir, "sparse"));
  ASSERT_EQ(s.meshes.size(), 1u);
  EXPECT_TRUE(s.meshes[0].positions[2].isApprox(Eigen::Vector3f(5, 6, 7)));
  EXPECT_TRUE(s.meshes[0].positions[1].isApprox(Eigen::Vector3f(1, 0, 0)));
}

TEST(GltfLoader, AccessorOutOfRangeThrows) {
  const TempDir dir;
  GltfBuilder g;
  const int pos = g.Positions({0, 0, 0, 1, 0, 0, 0, 1, 0});
  g.doc["accessors"][pos]["count"] = 4;  // one vertex more than the bufferView holds
  g.Mesh({{"POSITION", pos}});
  g.Node({{"mesh", 0}});
  g.Scene({0});
  ExpectLoadFails(g.Write(dir, "range"), "accessor 0 (mesh 0 primitive 0 POSITION): byteOffset 0 + 4 elements");

  GltfBuilder h;  // an index that points past the vertices
  h.Mesh({{"POSITION", h.Positions({0, 0, 0, 1, 0, 0, 0, 1, 0})}}, h.Accessor<uint8_t>({0, 1, 3, 0}, kGltfUByte, "SCALAR", 3));
  h.Node({{"mesh", 0}});
  h.Scene({0});
  ExpectLoadFails(h.Write(dir, "index"), "index 3 at position 2 is >= vertex count 3");

  GltfBuilder k;  // an absurd count is rejected before anything is allocated
  const int big = k.Positions({0, 0, 0, 1, 0, 0, 0, 1, 0});
  k.doc["accessors"][big]["count"] = 4000000000ull;
  k.Mesh({{"POSITION", big}});
  k.Node({{"mesh", 0}});
  k.Scene({0});
  ExpectLoadFails(k.Write(dir, "absurd"), "exceeds the limit");
}

}  // namespace
}  // namespace rigsim::gltf_test
