#include "gltf/gltf_loader.h"

#include <cstdint>
#include <fstream>
#include <stdexcept>
#include <string>
#include <tuple>
#include <vector>

#include <gmock/gmock.h>
#include <gtest/gtest.h>

#include "gltf/gltf_test_support.h"
#include "gltf/scene_builder.h"
#include "testing/expect_error.h"

namespace rigsim::gltf_test {
namespace {

// An index accessor whose values are all sparse, without a bufferView, is valid glTF, but tinygltf
// refuses it before rigsim sees the model, in words that name no primitive: the message adds the
// primitives that use it.
TEST(GltfLoader, SparseOnlyIndicesAreRefusedNamingThePrimitive) {
  const TempDir dir;
  GltfBuilder g;
  const int pos = g.Positions(kUnitQuad);
  const int before = int(g.doc["bufferViews"].size());
  g.Accessor<uint8_t>({0, 1, 2, 3, 4, 5}, kGltfUByte, "SCALAR", 6);  // bufferViews for the sparse data
  g.Accessor<uint16_t>({0, 1, 2, 0, 2, 3}, kGltfUShort, "SCALAR", 6);
  g.doc["accessors"].push_back({{"componentType", kGltfUShort}, {"count", 6}, {"type", "SCALAR"},
                                {"sparse", {{"count", 6}, {"indices", {{"bufferView", before}, {"componentType", kGltfUByte}}},
                                            {"values", {{"bufferView", before + 1}}}}}});
  const int indices = int(g.doc["accessors"].size()) - 1;
  g.Mesh({{"POSITION", pos}}, indices);
  g.doc["meshes"][0]["name"] = "quad";
  g.Node({{"mesh", 0}});
  g.Scene({0});
  ExpectLoadFails(g.Write(dir, "sparse_indices"), "accessor[" + std::to_string(indices) + "] invalid bufferView (the indices of mesh 0 'quad' primitive 0: glTF allows");
}

TEST(GltfLoader, TruncatedGlbThrowsWithFileName) {
  const TempDir dir;
  SceneBuilder b;
  MeshData m;
  m.positions = {{0, 0, 0}, {1, 0, 0}, {0, 1, 0}};
  m.indices = {0, 1, 2};
  b.AddNode("tri", "road", m, -1);
  std::vector<uint8_t> glb = b.ToGlb();
  const auto good = dir / "good.glb", bad = dir / "truncated.glb";
  std::ofstream(good, std::ios::binary).write(reinterpret_cast<const char*>(glb.data()), std::streamsize(glb.size()));
  std::ofstream(bad, std::ios::binary).write(reinterpret_cast<const char*>(glb.data()), std::streamsize(glb.size() - 20));
  EXPECT_EQ(LoadGltf(good).NumTriangles(), 1u);
  ExpectLoadFails(bad, "glb");
  ExpectLoadFails(dir / "does_not_exist.glb", "cannot open");
}

// glTF 2.0, "Asset": a client refuses a file whose minVersion it does not support (rigsim: 2.0),
// else one whose major version is not 2; a later 2.x minor version loads.
TEST(GltfLoader, FilesForAnotherGltfVersionAreRefused) {
  const TempDir dir;
  GltfBuilder g;
  g.Node({{"mesh", g.Mesh({{"POSITION", g.Positions({0, 0, 0, 1, 0, 0, 0, 1, 0})}})}});
  g.Scene({0});
  for (const auto& [version, min_version, error] :
       {std::tuple{"1.0", "", "asset.version is 1.0: rigsim reads glTF 2.x"},
        std::tuple{"3.0", "", "asset.version is 3.0: rigsim reads glTF 2.x"},
        std::tuple{"2.1", "2.1", "asset.minVersion is 2.1: the file needs a glTF 2.1 reader, and rigsim reads glTF 2.0"},
        std::tuple{"2", "", "asset.version '2' is not a glTF version (<major>.<minor>)"},
        std::tuple{"2.1", "", ""}, std::tuple{"3.0", "2.0", ""}, std::tuple{"2.0", "2.0", ""}}) {
    g.doc["asset"] = {{"version", version}};
    if (*min_version) g.doc["asset"]["minVersion"] = min_version;
    const std::string name = std::string(version) + "_" + min_version;
    if (*error) {
      ExpectLoadFails(g.Write(dir, name), error);
      ExpectLoadFails(g.WriteGlb(dir, name), error);
    } else {
      EXPECT_EQ(LoadGltf(g.WriteGlb(dir, name)).meshes.size(), 1u) << name;
    }
  }
}

// A file that requires an extension rigsim lacks is refused naming it, even when tinygltf would
// stumble first on what the extension changes (here an index accessor without a bufferView, which
// tinygltf refuses).
TEST(GltfLoader, UnsupportedExtensionsAreNamedWhenTheFileIsRefused) {
  const TempDir dir;
  GltfBuilder g;
  const int pos = g.Positions({0, 0, 0, 1, 0, 0, 0, 1, 0});
  g.doc["accessors"].push_back({{"componentType", kGltfUShort}, {"count", 3}, {"type", "SCALAR"}});  // no bufferView
  g.Mesh({{"POSITION", pos}}, 1);
  g.Node({{"mesh", 0}});
  g.Scene({0});
  g.doc["extensionsUsed"] = {"EXT_future_compression"};
  g.doc["extensionsRequired"] = {"EXT_future_compression"};
  ExpectLoadFails(g.Write(dir, "future"), "requires extension EXT_future_compression, which rigsim does not support");
  ExpectLoadFails(g.WriteGlb(dir, "future"), "requires extension EXT_future_compression, which rigsim does not support");
  g.doc.erase("extensionsRequired");
  ExpectLoadFails(g.Write(dir, "future_used"), "(the file also uses EXT_future_compression, which rigsim does not read)");
}

// A buffer's data URI that does not hold byteLength bytes: the message says so and quotes the
// URI's start only (tinygltf quotes it whole, megabytes for a real buffer).
TEST(GltfLoader, ABufferOfTheWrongLengthIsNamedBriefly) {
  const TempDir dir;
  GltfBuilder g;
  g.Mesh({{"POSITION", g.Positions(std::vector<float>(3000, 0.0f))}});
  g.Node({{"mesh", 0}});
  g.Scene({0});
  const auto path = g.WriteEmbedded(dir, "short");
  json doc = json::parse(std::ifstream(path));
  doc["buffers"][0]["byteLength"] = 12004;  // 4 bytes more than the data
  std::ofstream(path) << doc.dump();
  const std::string msg = ErrorMessage<std::runtime_error>([&] { LoadGltf(path); });
  EXPECT_LT(msg.size(), 400u) << msg;
  EXPECT_THAT(msg, testing::AllOf(testing::HasSubstr("data:application/octet-stream;base64,"),
                                  testing::HasSubstr("... (16000 characters)"),
                                  testing::HasSubstr("does not decode to the buffer's byteLength")));
}

}  // namespace
}  // namespace rigsim::gltf_test
