// Valid glTF 2.0 that tinygltf 2.7 refuses loads (gltf/readable_gltf.h): a file for each kind, as
// .gltf and as .glb where the container matters. What rigsim cannot read is refused naming it.
#include "gltf/readable_gltf.h"

#include <cstdint>
#include <cstdio>
#include <fstream>
#include <string>
#include <vector>

#include <gtest/gtest.h>
#include <opencv2/core.hpp>
#include <opencv2/imgcodecs.hpp>

#include "gltf/gltf_loader.h"
#include "gltf/gltf_test_support.h"

namespace rigsim::gltf_test {
namespace {

// A quad of two triangles whose indices are `indices` (an accessor the caller adds).
void QuadWithIndices(GltfBuilder& g, int pos, int indices) {
  g.Node({{"mesh", g.Mesh({{"POSITION", pos}}, indices)}, {"extras", {{"class", "building"}}}});
  g.Scene({0});
}

std::vector<uint32_t> Indices(const Scene& s) { return s.meshes.empty() ? std::vector<uint32_t>{} : s.meshes[0].indices; }

TEST(ReadableGltf, ABufferWithoutUriLoadsWhenNothingReadsIt) {
  const TempDir dir;
  GltfBuilder g;
  const int pos = g.Positions(kUnitQuad);
  QuadWithIndices(g, pos, g.Accessor<uint16_t>({0, 1, 2, 0, 2, 3}, kGltfUShort, "SCALAR", 6));
  g.extra_buffers.push_back({{"byteLength", 64}});  // e.g. filled by an extension rigsim does not use
  for (const auto& path : {g.Write(dir, "unused"), g.WriteGlb(dir, "unused")}) {
    const Scene s = LoadGltf(path);
    EXPECT_EQ(s.NumTriangles(), 2u) << path;
  }
  // Read by an accessor: refused, saying which buffer has no data.
  g.doc["bufferViews"].push_back({{"buffer", 1}, {"byteLength", 48}});
  g.doc["accessors"][0]["bufferView"] = int(g.doc["bufferViews"].size()) - 1;
  ExpectLoadFails(g.Write(dir, "read"), "lies in buffer 1, which has no uri and so no data");
  ExpectLoadFails(g.WriteGlb(dir, "read"), "lies in buffer 1, which has no uri and so no data");
}

TEST(ReadableGltf, AccessorsWithoutABufferViewAreZerosAndTheirSparseValues) {
  const TempDir dir;
  GltfBuilder g;
  const int pos = g.Positions(kUnitQuad);
  // Indices: zeros but for the sparse values 1, 2 at 1, 2 and 2, 3 at 4, 5: (0 1 2) (0 2 3).
  const int where = int(g.doc["bufferViews"].size());
  g.Accessor<uint8_t>({1, 2, 4, 5}, kGltfUByte, "SCALAR", 4);
  g.Accessor<uint16_t>({1, 2, 2, 3}, kGltfUShort, "SCALAR", 4);
  g.doc["accessors"].push_back({{"componentType", kGltfUShort}, {"count", 6}, {"type", "SCALAR"},
                                {"sparse", {{"count", 4}, {"indices", {{"bufferView", where}, {"componentType", kGltfUByte}}},
                                            {"values", {{"bufferView", where + 1}}}}}});
  QuadWithIndices(g, pos, int(g.doc["accessors"].size()) - 1);
  // An animation whose key times are zeros but for the sparse 1 and 2 at keys 1 and 2.
  const int times_at = int(g.doc["bufferViews"].size());
  g.Accessor<uint8_t>({1, 2}, kGltfUByte, "SCALAR", 2);
  g.Accessor<float>({1, 2}, kGltfFloat, "SCALAR", 2);
  g.doc["accessors"].push_back({{"componentType", kGltfFloat}, {"count", 3}, {"type", "SCALAR"}, {"min", {0}}, {"max", {2}},
                                {"sparse", {{"count", 2}, {"indices", {{"bufferView", times_at}, {"componentType", kGltfUByte}}},
                                            {"values", {{"bufferView", times_at + 1}}}}}});
  const int times = int(g.doc["accessors"].size()) - 1;
  const int moves = g.Accessor<float>({0, 0, 0, 1, 0, 0, 2, 0, 0}, kGltfFloat, "VEC3", 3);
  g.doc["animations"] = json::array({{{"channels", {{{"sampler", 0}, {"target", {{"node", 0}, {"path", "translation"}}}}}},
                                      {"samplers", {{{"input", times}, {"output", moves}}}}}});
  for (const auto& path : {g.Write(dir, "sparse"), g.WriteGlb(dir, "sparse")}) {
    const Scene s = LoadGltf(path);
    EXPECT_EQ(Indices(s), (std::vector<uint32_t>{0, 1, 2, 0, 2, 3})) << path;
    ASSERT_EQ(s.animation_channels.size(), 1u) << path;
    EXPECT_EQ(s.animation_channels[0].times_s, (std::vector<double>{0, 1, 2})) << path;
  }
}

TEST(ReadableGltf, DataUrisTinygltfDoesNotDecode) {
  const TempDir dir;
  GltfBuilder g;
  const int pos = g.Positions(kUnitQuad);
  QuadWithIndices(g, pos, g.Accessor<uint16_t>({0, 1, 2, 0, 2, 3}, kGltfUShort, "SCALAR", 6));
  // The buffer percent-encoded (RFC 2397 without ;base64), then base64 of a media type tinygltf
  // does not know.
  std::string percent = "data:application/gltf-buffer,";
  for (uint8_t byte : g.bin) {
    char hex[4];
    std::snprintf(hex, sizeof(hex), "%%%02X", byte);
    percent += hex;
  }
  for (const std::string& uri : {percent, DataUri("application/x-binary", g.bin)}) {
    json doc = g.doc;
    doc["buffers"] = json::array({{{"byteLength", g.bin.size()}, {"uri", uri}}});
    const auto path = dir / "uri.gltf";
    std::ofstream(path) << doc.dump();
    EXPECT_EQ(Indices(LoadGltf(path)), (std::vector<uint32_t>{0, 1, 2, 0, 2, 3})) << uri.substr(0, 40);
  }
  // A WebP image as a data URI, the texture's own source.
  cv::Mat bgr(2, 3, CV_8UC3, cv::Scalar(30, 60, 90));
  std::vector<uint8_t> webp;
  ASSERT_TRUE(cv::imencode(".webp", bgr, webp, {cv::IMWRITE_WEBP_QUALITY, 101}));
  const int uv = g.Accessor<float>({0, 0, 1, 0, 1, 1, 0, 1}, kGltfFloat, "VEC2", 4);
  g.doc["meshes"][0]["primitives"][0]["attributes"]["TEXCOORD_0"] = uv;
  g.doc["meshes"][0]["primitives"][0]["material"] = 0;
  g.doc["images"] = json::array({{{"uri", DataUri("image/webp", webp)}}});
  g.doc["textures"] = json::array({{{"source", 0}}});
  g.doc["materials"] = json::array({{{"pbrMetallicRoughness", {{"baseColorTexture", {{"index", 0}}}}}}});
  const Scene s = LoadGltf(g.Write(dir, "webp"));
  ASSERT_EQ(s.textures.size(), 1u);
  EXPECT_EQ(s.textures[0].width, 3);
  EXPECT_EQ(s.textures[0].rgba[0], 90);  // red, as OpenCV's BGR (30, 60, 90) holds it
}

TEST(ReadableGltf, AnUnusedAccessorOfATypeGltfDoesNotDefineLoads) {
  const TempDir dir;
  GltfBuilder g;
  const int pos = g.Positions(kUnitQuad);
  QuadWithIndices(g, pos, g.Accessor<uint16_t>({0, 1, 2, 0, 2, 3}, kGltfUShort, "SCALAR", 6));
  g.doc["accessors"].push_back({{"bufferView", 0}, {"componentType", kGltfFloat}, {"count", 1}, {"type", "VEC5"}});
  const int vec5 = int(g.doc["accessors"].size()) - 1;
  g.doc["accessors"].push_back({{"bufferView", 0}, {"componentType", 1234}, {"count", 1}, {"type", "VEC3"}});
  const int odd = int(g.doc["accessors"].size()) - 1;
  for (const auto& path : {g.Write(dir, "unused"), g.WriteGlb(dir, "unused")}) EXPECT_EQ(LoadGltf(path).NumTriangles(), 2u) << path;
  // Read: refused, naming the accessor and its type.
  g.doc["meshes"][0]["primitives"][0]["attributes"]["POSITION"] = vec5;
  ExpectLoadFails(g.Write(dir, "vec5"), "accessor " + std::to_string(vec5) + " (mesh 0 primitive 0 POSITION): type 'VEC5' is not a glTF accessor type");
  g.doc["meshes"][0]["primitives"][0]["attributes"]["POSITION"] = odd;
  ExpectLoadFails(g.Write(dir, "odd"), "invalid componentType 1234");
}

TEST(ReadableGltf, RemoteResourcesAreRefusedSayingSo) {
  const TempDir dir;
  GltfBuilder g;
  QuadWithIndices(g, g.Positions(kUnitQuad), -1);
  json doc = g.doc;
  doc["buffers"] = json::array({{{"byteLength", g.bin.size()}, {"uri", "https://example.com/quad.bin"}}});
  std::ofstream(dir / "remote.gltf") << doc.dump();
  ExpectLoadFails(dir / "remote.gltf", "buffer 0: its uri 'https://example.com/quad.bin' is a web address");
  g.doc["images"] = json::array({{{"uri", "http://example.com/brick.png"}}});
  ExpectLoadFails(g.Write(dir, "image"), "image 0: its uri 'http://example.com/brick.png' is a web address");
}

}  // namespace
}  // namespace rigsim::gltf_test
