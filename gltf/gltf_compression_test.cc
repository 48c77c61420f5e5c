#include "gltf/gltf_loader.h"

#include <algorithm>
#include <array>
#include <cstdint>
#include <cstring>
#include <filesystem>
#include <functional>
#include <memory>
#include <string>
#include <tuple>
#include <utility>
#include <vector>

#include <Eigen/Core>
#include <draco/compression/encode.h>
#include <draco/mesh/triangle_soup_mesh_builder.h>
#include <gtest/gtest.h>
#include <meshoptimizer.h>

#include "gltf/gltf_test_support.h"

namespace rigsim::gltf_test {
namespace {

// An n x n grid of vertices in the z = 0 plane, 2 (n - 1)^2 triangles wound counter-clockwise
// seen from +z, compressed with Draco: TEXCOORD_0 = (i, j) / (n - 1), position (i / 2, j / 4, 0)
// and COLOR_0 as normalized bytes (i, j, 255 - i, 255). `method` is Draco's sequential or
// edgebreaker coding; `position_bits` > 0 quantises the positions (lossy), 0 keeps them exact.
struct DracoGrid {
  std::vector<uint8_t> bytes;
  int position_id, texcoord_id, color_id;  // the attributes' Draco ids
};

DracoGrid EncodeDracoGrid(int n, int method, int position_bits) {
  draco::TriangleSoupMeshBuilder builder;
  builder.Start(2 * (n - 1) * (n - 1));
  const int pos = builder.AddAttribute(draco::GeometryAttribute::POSITION, 3, draco::DT_FLOAT32);
  const int uv = builder.AddAttribute(draco::GeometryAttribute::TEX_COORD, 2, draco::DT_FLOAT32);
  const int color = builder.AddAttribute(draco::GeometryAttribute::COLOR, 4, draco::DT_UINT8, true);
  int face = 0;
  auto corner = [n](int i, int j) {
    return std::tuple(std::array<float, 3>{i * 0.5f, j * 0.25f, 0.0f}, std::array<float, 2>{float(i) / (n - 1), float(j) / (n - 1)},
                      std::array<uint8_t, 4>{uint8_t(i), uint8_t(j), uint8_t(255 - i), 255});
  };
  auto add = [&](std::array<std::pair<int, int>, 3> ij) {
    const auto a = corner(ij[0].first, ij[0].second), b = corner(ij[1].first, ij[1].second), c = corner(ij[2].first, ij[2].second);
    builder.SetAttributeValuesForFace(pos, draco::FaceIndex(face), std::get<0>(a).data(), std::get<0>(b).data(), std::get<0>(c).data());
    builder.SetAttributeValuesForFace(uv, draco::FaceIndex(face), std::get<1>(a).data(), std::get<1>(b).data(), std::get<1>(c).data());
    builder.SetAttributeValuesForFace(color, draco::FaceIndex(face), std::get<2>(a).data(), std::get<2>(b).data(), std::get<2>(c).data());
    ++face;
  };
  for (int i = 0; i + 1 < n; ++i) {
    for (int j = 0; j + 1 < n; ++j) {
      add({{{i, j}, {i + 1, j}, {i + 1, j + 1}}});
      add({{{i, j}, {i + 1, j + 1}, {i, j + 1}}});
    }
  }
  const std::unique_ptr<draco::Mesh> mesh = builder.Finalize();
  draco::Encoder encoder;
  encoder.SetEncodingMethod(method);
  if (position_bits > 0) encoder.SetAttributeQuantization(draco::GeometryAttribute::POSITION, position_bits);
  draco::EncoderBuffer buffer;
  const draco::Status status = encoder.EncodeMeshToBuffer(*mesh, &buffer);
  EXPECT_TRUE(status.ok()) << status.error_msg_string();
  return {std::vector<uint8_t>(buffer.data(), buffer.data() + buffer.size()), int(mesh->attribute(pos)->unique_id()),
          int(mesh->attribute(uv)->unique_id()), int(mesh->attribute(color)->unique_id())};
}

// A glTF file whose one mesh is `grid`, the way exporters write Draco: bufferView 0 holds the
// compressed data and the primitive's accessors have no bufferView.
GltfBuilder DracoGltf(const DracoGrid& grid, int n, int index_type) {
  GltfBuilder g;
  g.bin = grid.bytes;
  g.doc["bufferViews"].push_back({{"buffer", 0}, {"byteOffset", 0}, {"byteLength", grid.bytes.size()}});
  const size_t points = size_t(n) * n;
  g.doc["accessors"] = json::array({{{"componentType", index_type}, {"count", 6 * (n - 1) * (n - 1)}, {"type", "SCALAR"}},
                                    {{"componentType", kGltfFloat}, {"count", points}, {"type", "VEC3"}},
                                    {{"componentType", kGltfFloat}, {"count", points}, {"type", "VEC2"}},
                                    {{"componentType", kGltfUByte}, {"count", points}, {"type", "VEC4"}, {"normalized", true}}});
  g.Mesh({{"POSITION", 1}, {"TEXCOORD_0", 2}, {"COLOR_0", 3}}, 0);
  g.doc["meshes"][0]["primitives"][0]["extensions"] = {
      {"KHR_draco_mesh_compression",
       {{"bufferView", 0},
        {"attributes", {{"POSITION", grid.position_id}, {"TEXCOORD_0", grid.texcoord_id}, {"COLOR_0", grid.color_id}}}}}};
  g.Node({{"mesh", 0}});
  g.Scene({0});
  g.doc["extensionsUsed"] = {"KHR_draco_mesh_compression"};
  g.doc["extensionsRequired"] = {"KHR_draco_mesh_compression"};
  return g;
}

// The loaded mesh is the grid: every triangle, its winding, and each corner's attributes. Draco
// may reorder the vertices and triangles, so corners are matched through their texture
// coordinates, which are stored exactly; positions may be off by `position_tolerance`.
void ExpectTheDracoGrid(const Scene& scene, int n, float position_tolerance) {
  ASSERT_EQ(scene.meshes.size(), 1u);
  const SceneMesh& m = scene.meshes[0];
  ASSERT_EQ(m.indices.size(), size_t(6 * (n - 1) * (n - 1)));
  ASSERT_EQ(m.texcoords.size(), m.positions.size());
  ASSERT_EQ(m.colors.size(), m.positions.size());
  std::multiset<std::array<int, 6>> triangles;
  for (size_t t = 0; t < m.indices.size() / 3; ++t) {
    EXPECT_GT(FaceNormal(m, t).z(), 0.99f) << "triangle " << t << " turned over";
    std::array<int, 6> grid_points{};
    for (int c = 0; c < 3; ++c) {
      const uint32_t v = m.indices[3 * t + c];
      const int i = int(std::lround(m.texcoords[v].x() * (n - 1))), j = int(std::lround(m.texcoords[v].y() * (n - 1)));
      EXPECT_FLOAT_EQ(m.texcoords[v].x() * (n - 1), float(i));
      EXPECT_NEAR(m.positions[v].x(), i * 0.5f, position_tolerance);
      EXPECT_NEAR(m.positions[v].y(), j * 0.25f, position_tolerance);
      EXPECT_NEAR(m.positions[v].z(), 0.0f, position_tolerance);
      EXPECT_NEAR(m.colors[v].x(), i / 255.0f, 1e-6f);
      EXPECT_NEAR(m.colors[v].z(), (255 - i) / 255.0f, 1e-6f);
      EXPECT_NEAR(m.colors[v].y(), j / 255.0f, 1e-6f);
      grid_points[2 * c] = i;
      grid_points[2 * c + 1] = j;
    }
    // Rotated so that the smallest corner comes first: the same triangle whatever corner Draco starts at.
    std::array<std::pair<int, int>, 3> corners = {{{grid_points[0], grid_points[1]}, {grid_points[2], grid_points[3]},
                                                   {grid_points[4], grid_points[5]}}};
    std::rotate(corners.begin(), std::min_element(corners.begin(), corners.end()), corners.end());
    triangles.insert({corners[0].first, corners[0].second, corners[1].first, corners[1].second, corners[2].first,
                      corners[2].second});
  }
  std::multiset<std::array<int, 6>> expected;
  for (int i = 0; i + 1 < n; ++i) {
    for (int j = 0; j + 1 < n; ++j) {
      expected.insert({i, j, i + 1, j, i + 1, j + 1});
      expected.insert({i, j, i + 1, j + 1, i, j + 1});
    }
  }
  EXPECT_EQ(triangles, expected);
}

TEST(GltfLoader, DracoCompressedMeshesLoadAsTheMeshTheyEncode) {
  const TempDir dir;
  const int n = 5;
  for (const int method : {draco::MESH_SEQUENTIAL_ENCODING, draco::MESH_EDGEBREAKER_ENCODING}) {
    SCOPED_TRACE(method == draco::MESH_SEQUENTIAL_ENCODING ? "sequential" : "edgebreaker");
    GltfBuilder g = DracoGltf(EncodeDracoGrid(n, method, 0), n, kGltfUShort);
    for (const auto& path : {g.Write(dir, "grid"), g.WriteEmbedded(dir, "grid_uri"), g.WriteGlb(dir, "grid")}) {
      SCOPED_TRACE(path.filename().string());
      const Scene scene = LoadGltf(path);
      ExpectTheDracoGrid(scene, n, 0.0f);
      for (const std::string& w : scene.warnings) EXPECT_EQ(w.find("draco"), std::string::npos) << w;
    }
  }
  // Quantised positions come back within half a quantisation step of the 2 m range.
  const int bits = 10;
  GltfBuilder q = DracoGltf(EncodeDracoGrid(n, draco::MESH_EDGEBREAKER_ENCODING, bits), n, kGltfUInt);
  ExpectTheDracoGrid(LoadGltf(q.Write(dir, "quantised")), n, 2.0f / ((1 << bits) - 1));
}

TEST(GltfLoader, MalformedDracoPrimitivesAreRefusedNamingThePrimitive) {
  const TempDir dir;
  const int n = 3;
  const DracoGrid grid = EncodeDracoGrid(n, draco::MESH_EDGEBREAKER_ENCODING, 0);
  const std::string where = "mesh 0 primitive 0: KHR_draco_mesh_compression: ";
  {
    GltfBuilder g = DracoGltf(grid, n, kGltfUShort);
    g.doc["meshes"][0]["primitives"][0]["extensions"]["KHR_draco_mesh_compression"]["bufferView"] = 4;
    ExpectLoadFails(g.Write(dir, "view"), where + "bufferView is missing or not one of the file's 1 buffer views");
    ExpectLoadFails(g.WriteGlb(dir, "view"), where + "bufferView is missing or not one of the file's 1 buffer views");
  }
  {
    GltfBuilder g = DracoGltf(grid, n, kGltfUShort);
    std::fill(g.bin.begin() + 4, g.bin.end(), uint8_t(0x5a));  // "DRAC" kept, the rest garbage
    ExpectLoadFails(g.Write(dir, "garbage"), where + "the Draco data in bufferView 0 does not decode");
  }
  {
    GltfBuilder g = DracoGltf(grid, n, kGltfUShort);
    g.doc["meshes"][0]["primitives"][0]["extensions"]["KHR_draco_mesh_compression"]["attributes"]["TEXCOORD_0"] = 9;
    ExpectLoadFails(g.Write(dir, "id"), where + "attribute TEXCOORD_0: the Draco data has no attribute with id 9");
  }
  {
    GltfBuilder g = DracoGltf(grid, n, kGltfUShort);
    g.doc["accessors"][2]["type"] = "VEC3";
    ExpectLoadFails(g.Write(dir, "components"), where + "attribute TEXCOORD_0: the Draco attribute has 2 components, its accessor 3");
  }
  {
    const int big = 17;  // 289 vertices: more than unsigned bytes can index
    GltfBuilder g = DracoGltf(EncodeDracoGrid(big, draco::MESH_SEQUENTIAL_ENCODING, 0), big, kGltfUByte);
    ExpectLoadFails(g.Write(dir, "bytes"), where + "289 vertices cannot be indexed by the indices accessor's unsigned bytes");
  }
  {
    // tinygltf reads a rewritten version from memory, and still finds external files beside the file.
    GltfBuilder g = DracoGltf(grid, n, kGltfUShort);
    const auto path = g.Write(dir, "missing");
    std::filesystem::remove(dir / "missing.bin");
    ExpectLoadFails(path, "File not found : missing.bin");
  }
}

// EXT_meshopt_compression as gltfpack writes it: buffer 0 holds the compressed streams and buffer
// 1 is the fallback without data, in which the buffer views lie. An n x n grid: positions (float,
// ATTRIBUTES), tilted normals (normalized bytes under KHR_mesh_quantization, OCTAHEDRAL filter),
// its triangles (TRIANGLES) for primitive 0 and the same as an index sequence (INDICES) for 1.
struct MeshoptGrid {
  GltfBuilder g;
  std::vector<float> xyz;
  std::vector<Eigen::Vector3f> normals;
  std::vector<uint32_t> triangles;
};

MeshoptGrid MeshoptGltf(int n) {
  MeshoptGrid out;
  const size_t count = size_t(n) * n;
  std::vector<float> normal4;  // x, y, z, w per vertex, as the octahedral encoder takes them
  for (int j = 0; j < n; ++j) {
    for (int i = 0; i < n; ++i) {
      out.xyz.insert(out.xyz.end(), {i * 0.5f, j * 0.25f, 0.1f * i * j});
      out.normals.push_back(Eigen::Vector3f(0.2f * i - 0.3f, 0.1f * j, 1.0f).normalized());
      normal4.insert(normal4.end(), {out.normals.back().x(), out.normals.back().y(), out.normals.back().z(), 0.0f});
    }
  }
  for (int j = 0; j + 1 < n; ++j) {
    for (int i = 0; i + 1 < n; ++i) {
      const uint32_t a = uint32_t(j * n + i), b = a + 1, c = a + uint32_t(n) + 1, d = a + uint32_t(n);
      out.triangles.insert(out.triangles.end(), {a, b, c, a, c, d});
    }
  }
  std::vector<int8_t> octahedral(4 * count);
  meshopt_encodeFilterOct(octahedral.data(), count, 4, 8, normal4.data());
  std::vector<uint16_t> indices16(out.triangles.begin(), out.triangles.end());

  auto encoded = [](size_t bound, const std::function<size_t(unsigned char*, size_t)>& encode) {
    std::vector<uint8_t> bytes(bound);
    bytes.resize(encode(bytes.data(), bytes.size()));
    return bytes;
  };
  struct Stream {
    std::vector<uint8_t> compressed;
    size_t stride, count;
    const char* mode;
    const char* filter;
    size_t raw_bytes;
  };
  const size_t tri = out.triangles.size();
  const std::vector<Stream> streams = {
      {encoded(meshopt_encodeVertexBufferBound(count, 12),
               [&](unsigned char* b, size_t s) { return meshopt_encodeVertexBuffer(b, s, out.xyz.data(), count, 12); }),
       12, count, "ATTRIBUTES", "NONE", count * 12},
      {encoded(meshopt_encodeVertexBufferBound(count, 4),
               [&](unsigned char* b, size_t s) { return meshopt_encodeVertexBuffer(b, s, octahedral.data(), count, 4); }),
       4, count, "ATTRIBUTES", "OCTAHEDRAL", count * 4},
      {encoded(meshopt_encodeIndexBufferBound(tri, count),
               [&](unsigned char* b, size_t s) { return meshopt_encodeIndexBuffer(b, s, out.triangles.data(), tri); }),
       2, tri, "TRIANGLES", "NONE", tri * 2},
      {encoded(meshopt_encodeIndexSequenceBound(tri, count),
               [&](unsigned char* b, size_t s) { return meshopt_encodeIndexSequence(b, s, out.triangles.data(), tri); }),
       2, tri, "INDICES", "NONE", tri * 2}};
  GltfBuilder& g = out.g;
  size_t fallback = 0;
  for (const Stream& st : streams) {
    while (g.bin.size() % 4) g.bin.push_back(0);
    const size_t offset = g.bin.size();
    g.bin.insert(g.bin.end(), st.compressed.begin(), st.compressed.end());
    json view = {{"buffer", 1}, {"byteOffset", fallback}, {"byteLength", st.raw_bytes}};
    if (std::string(st.mode) == "ATTRIBUTES") view["byteStride"] = st.stride;
    json extension = {{"buffer", 0}, {"byteOffset", offset}, {"byteLength", st.compressed.size()}, {"byteStride", st.stride},
                      {"count", st.count}, {"mode", st.mode}};
    if (std::string(st.filter) != "NONE") extension["filter"] = st.filter;
    view["extensions"] = {{"EXT_meshopt_compression", extension}};
    g.doc["bufferViews"].push_back(view);
    fallback += (st.raw_bytes + 3) / 4 * 4;
  }
  g.extra_buffers.push_back({{"byteLength", fallback}, {"extensions", {{"EXT_meshopt_compression", {{"fallback", true}}}}}});
  g.doc["accessors"] = json::array({{{"bufferView", 0}, {"componentType", kGltfFloat}, {"count", count}, {"type", "VEC3"}},
                                    {{"bufferView", 1}, {"componentType", 5120}, {"count", count}, {"type", "VEC3"}, {"normalized", true}},
                                    {{"bufferView", 2}, {"componentType", kGltfUShort}, {"count", tri}, {"type", "SCALAR"}},
                                    {{"bufferView", 3}, {"componentType", kGltfUShort}, {"count", tri}, {"type", "SCALAR"}}});
  const json attributes = {{"POSITION", 0}, {"NORMAL", 1}};
  g.doc["meshes"] = json::array({{{"primitives", json::array({{{"attributes", attributes}, {"indices", 2}},
                                                             {{"attributes", attributes}, {"indices", 3}}})}}});
  g.Node({{"mesh", 0}});
  g.Scene({0});
  g.doc["extensionsUsed"] = {"EXT_meshopt_compression", "KHR_mesh_quantization"};
  g.doc["extensionsRequired"] = {"EXT_meshopt_compression", "KHR_mesh_quantization"};
  return out;
}

TEST(GltfLoader, MeshoptCompressedBuffersLoadAsTheDataTheyEncode) {
  const TempDir dir;
  MeshoptGrid grid = MeshoptGltf(4);
  for (const auto& path : {grid.g.Write(dir, "grid"), grid.g.WriteEmbedded(dir, "grid_uri"), grid.g.WriteGlb(dir, "grid")}) {
    SCOPED_TRACE(path.filename().string());
    const Scene scene = LoadGltf(path);
    ASSERT_EQ(scene.meshes.size(), 2u);
    for (const SceneMesh& m : scene.meshes) {  // TRIANGLES, then INDICES
      ASSERT_EQ(m.positions.size(), grid.normals.size());
      for (size_t v = 0; v < m.positions.size(); ++v) {
        EXPECT_EQ(m.positions[v], Eigen::Vector3f(grid.xyz[3 * v], grid.xyz[3 * v + 1], grid.xyz[3 * v + 2])) << v;
        ASSERT_EQ(m.normals.size(), m.positions.size());
        EXPECT_LT((m.normals[v] - grid.normals[v]).norm(), 0.02f) << v << ": " << m.normals[v].transpose();
      }
      // The same triangles with the same winding (the index codec may start a triangle at another corner).
      ASSERT_EQ(m.indices.size(), grid.triangles.size());
      for (size_t t = 0; t < m.indices.size(); t += 3) {
        std::array<uint32_t, 3> got = {m.indices[t], m.indices[t + 1], m.indices[t + 2]};
        std::array<uint32_t, 3> want = {grid.triangles[t], grid.triangles[t + 1], grid.triangles[t + 2]};
        std::rotate(got.begin(), std::min_element(got.begin(), got.end()), got.end());
        std::rotate(want.begin(), std::min_element(want.begin(), want.end()), want.end());
        EXPECT_EQ(got, want) << "triangle " << t / 3;
      }
    }
    EXPECT_EQ(scene.meshes[1].indices, grid.triangles);  // an index sequence is kept as it is
    for (const std::string& w : scene.warnings) EXPECT_EQ(w.find("meshopt"), std::string::npos) << w;
  }
}

TEST(GltfLoader, MalformedMeshoptBufferViewsAreRefusedNamingTheView) {
  const TempDir dir;
  auto extension = [](GltfBuilder& g, int view) -> json& { return g.doc["bufferViews"][view]["extensions"]["EXT_meshopt_compression"]; };
  const std::string where = ": EXT_meshopt_compression: ";
  {
    MeshoptGrid grid = MeshoptGltf(3);
    extension(grid.g, 2)["mode"] = "LINES";
    ExpectLoadFails(grid.g.Write(dir, "mode"), "bufferView 2" + where + "mode 'LINES' is none of ATTRIBUTES, TRIANGLES, INDICES");
  }
  {
    MeshoptGrid grid = MeshoptGltf(3);
    extension(grid.g, 0)["byteLength"] = grid.g.bin.size() + 1;
    ExpectLoadFails(grid.g.Write(dir, "range"), "bufferView 0" + where + "bytes 0 + " + std::to_string(grid.g.bin.size() + 1) +
                                                     " lie beyond buffer 0's " + std::to_string(grid.g.bin.size()));
  }
  {
    MeshoptGrid grid = MeshoptGltf(3);
    const size_t length = extension(grid.g, 0)["byteLength"].get<size_t>();
    std::fill_n(grid.g.bin.begin(), length, uint8_t(0xff));
    ExpectLoadFails(grid.g.Write(dir, "garbage"), "bufferView 0" + where + "the compressed bytes do not decode");
  }
  {
    MeshoptGrid grid = MeshoptGltf(3);
    extension(grid.g, 0)["count"] = 10;  // 10 x 12 bytes in a view of 9 x 12
    ExpectLoadFails(grid.g.Write(dir, "count"), "bufferView 0" + where + "10 elements of 12 bytes do not fit the view's 108 bytes");
  }
  {
    MeshoptGrid grid = MeshoptGltf(3);
    extension(grid.g, 1)["filter"] = "QUATERNION";
    ExpectLoadFails(grid.g.Write(dir, "filter"), "bufferView 1" + where + "QUATERNION needs a byteStride of 8");
  }
  {
    MeshoptGrid grid = MeshoptGltf(3);
    grid.g.extra_buffers[0]["byteLength"] = 1u << 30;
    GltfLoadOptions small;
    small.max_accessor_count = 1000;
    ExpectLoadFails(grid.g.Write(dir, "huge"), small, "exceed the limit of 16000 decoded bytes");
  }
}

// Without extensionsRequired the fallback buffer may hold the data itself: it is read as it is.
TEST(GltfLoader, MeshoptViewsOverABufferWithItsDataReadThatData) {
  const TempDir dir;
  MeshoptGrid grid = MeshoptGltf(3);
  std::vector<uint8_t> raw(grid.g.extra_buffers[0]["byteLength"].get<size_t>(), 0);
  std::memcpy(raw.data(), grid.xyz.data(), grid.xyz.size() * sizeof(float));
  grid.g.extra_buffers[0] = {{"byteLength", raw.size()}, {"uri", DataUri("application/octet-stream", raw)}};
  grid.g.doc["extensionsRequired"] = {"KHR_mesh_quantization"};
  std::fill(grid.g.bin.begin(), grid.g.bin.end(), uint8_t(0xff));  // the compressed streams would not decode
  grid.g.doc["meshes"][0]["primitives"] = json::array({{{"attributes", {{"POSITION", 0}}}, {"mode", 4}}});
  const Scene scene = LoadGltf(grid.g.Write(dir, "raw"));
  ASSERT_EQ(scene.meshes.size(), 1u);
  EXPECT_EQ(scene.meshes[0].positions[4], Eigen::Vector3f(grid.xyz[12], grid.xyz[13], grid.xyz[14]));
}

}  // namespace
}  // namespace rigsim::gltf_test
