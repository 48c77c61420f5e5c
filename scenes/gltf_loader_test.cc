#include "scenes/gltf_loader.h"

#include <algorithm>
#include <array>
#include <cmath>
#include <cstring>
#include <filesystem>
#include <functional>
#include <fstream>
#include <limits>
#include <map>
#include <memory>
#include <numbers>
#include <set>
#include <stdexcept>
#include <string>
#include <tuple>
#include <vector>

#include <Eigen/Geometry>
#include <gtest/gtest.h>
#include <nlohmann/json.hpp>
#include <opencv2/core.hpp>
#include <opencv2/imgcodecs.hpp>
#include <draco/compression/encode.h>
#include <draco/mesh/triangle_soup_mesh_builder.h>
#include <meshoptimizer.h>

#include "labels/cityscapes.h"
#include "scenes/scene_builder.h"
#include "tests/data_uri.h"

namespace rigsim {
namespace {

using nlohmann::json;

constexpr int kUByte = 5121, kUShort = 5123, kUInt = 5125, kFloat = 5126;

std::filesystem::path TempDir() {
  const auto* info = testing::UnitTest::GetInstance()->current_test_info();
  const auto dir = std::filesystem::temp_directory_path() / "rigsim_gltf_loader_test" / info->name();
  std::filesystem::remove_all(dir);
  std::filesystem::create_directories(dir);
  return dir;
}

// Builds small glTF documents by hand, so that tests control every byte.
struct TestGltf {
  json doc = {{"asset", {{"version", "2.0"}}}, {"bufferViews", json::array()}, {"accessors", json::array()},
              {"nodes", json::array()}, {"meshes", json::array()}};
  std::vector<uint8_t> bin;
  json extra_buffers = json::array();  // buffers 1, 2, ... as given (buffer 0 holds `bin`)

  template <typename T>
  int Accessor(const std::vector<T>& values, int component_type, const std::string& type, size_t count, bool normalized = false) {
    while (bin.size() % 4) bin.push_back(0);
    const size_t offset = bin.size();
    bin.resize(offset + values.size() * sizeof(T));
    if (!values.empty()) std::memcpy(bin.data() + offset, values.data(), values.size() * sizeof(T));  // no null source
    doc["bufferViews"].push_back({{"buffer", 0}, {"byteOffset", offset}, {"byteLength", values.size() * sizeof(T)}});
    json a = {{"bufferView", doc["bufferViews"].size() - 1}, {"componentType", component_type}, {"count", count}, {"type", type}};
    if (normalized) a["normalized"] = true;
    doc["accessors"].push_back(a);
    return int(doc["accessors"].size()) - 1;
  }
  int Positions(const std::vector<float>& xyz) { return Accessor(xyz, kFloat, "VEC3", xyz.size() / 3); }
  // kQuad's positions, TEXCOORD_0 on its corners' unit square and TEXCOORD_1 on the square's
  // middle quarter: the accessors of (POSITION, TEXCOORD_0, TEXCOORD_1).
  struct TwoSets {
    int pos, uv0, uv1;
  };
  TwoSets QuadWithTwoTexcoordSets();
  // textures[0]: a 2 x 2 PNG (TinyPngUri) as images[0].
  void TinyTexture();
  // A mesh with one primitive; returns the mesh index.
  int Mesh(json attributes, int indices = -1, int mode = 4, int material = -1, json extras = nullptr) {
    json prim = {{"attributes", attributes}, {"mode", mode}};
    if (indices >= 0) prim["indices"] = indices;
    if (material >= 0) prim["material"] = material;
    json mesh = {{"primitives", json::array({prim})}};
    if (!extras.is_null()) mesh["extras"] = extras;
    doc["meshes"].push_back(mesh);
    return int(doc["meshes"].size()) - 1;
  }
  int Node(json node) {
    doc["nodes"].push_back(node);
    return int(doc["nodes"].size()) - 1;
  }
  void Scene(std::vector<int> roots) {
    doc["scene"] = 0;
    doc["scenes"] = json::array({{{"nodes", roots}}});
  }
  // Writes `name`.gltf with an external `name`.bin (or a data URI).
  std::filesystem::path Write(const std::filesystem::path& dir, const std::string& name, bool data_uri = false) {
    json d = doc;
    if (data_uri) {
      d["buffers"] = json::array({{{"byteLength", bin.size()}, {"uri", DataUri("application/octet-stream", bin)}}});
    } else {
      std::ofstream(dir / (name + ".bin"), std::ios::binary).write(reinterpret_cast<const char*>(bin.data()), std::streamsize(bin.size()));
      d["buffers"] = json::array({{{"byteLength", bin.size()}, {"uri", name + ".bin"}}});
    }
    for (const json& b : extra_buffers) d["buffers"].push_back(b);
    const auto path = dir / (name + ".gltf");
    std::ofstream(path) << d.dump(1);
    return path;
  }
  // Writes `name`.glb: the document and its buffer in one binary file.
  std::filesystem::path WriteGlb(const std::filesystem::path& dir, const std::string& name) {
    json d = doc;
    d["buffers"] = json::array({{{"byteLength", bin.size()}}});
    for (const json& b : extra_buffers) d["buffers"].push_back(b);
    std::string text = d.dump();
    while (text.size() % 4) text += ' ';
    std::vector<uint8_t> chunk = bin;
    while (chunk.size() % 4) chunk.push_back(0);
    std::vector<uint32_t> header = {0x46546C67u, 2, uint32_t(28 + text.size() + chunk.size()), uint32_t(text.size()), 0x4E4F534Au};
    const std::vector<uint32_t> bin_header = {uint32_t(chunk.size()), 0x004E4942u};
    const auto path = dir / (name + ".glb");
    std::ofstream out(path, std::ios::binary);
    out.write(reinterpret_cast<const char*>(header.data()), 20);
    out.write(text.data(), std::streamsize(text.size()));
    out.write(reinterpret_cast<const char*>(bin_header.data()), 8);
    out.write(reinterpret_cast<const char*>(chunk.data()), std::streamsize(chunk.size()));
    return path;
  }
};

const std::vector<float> kQuad = {0, 0, 0, 1, 0, 0, 1, 1, 0, 0, 1, 0};  // 4 corners in the z = 0 plane

std::vector<Eigen::Vector3f> TriangleCorners(const SceneMesh& m) {
  std::vector<Eigen::Vector3f> out;
  for (uint32_t i : m.indices) out.push_back(m.positions[i]);
  return out;
}

Eigen::Vector3f FaceNormal(const SceneMesh& m, size_t tri) {
  const Eigen::Vector3f a = m.positions[m.indices[3 * tri]], b = m.positions[m.indices[3 * tri + 1]], c = m.positions[m.indices[3 * tri + 2]];
  return (b - a).cross(c - a).normalized();
}

bool HasWarning(const Scene& s, const std::string& part) {
  for (const std::string& w : s.warnings) {
    if (w.find(part) != std::string::npos) return true;
  }
  return false;
}

// Expects LoadGltf(path, options) to throw a message starting with the file name and containing
// `part`.
void ExpectThrowsWithOptions(const std::filesystem::path& path, const GltfLoadOptions& options, const std::string& part) {
  try {
    LoadGltf(path, options);
    ADD_FAILURE() << "no exception for " << path;
  } catch (const std::runtime_error& e) {
    const std::string msg = e.what();
    EXPECT_EQ(msg.rfind(path.string(), 0), 0u) << msg;
    EXPECT_NE(msg.find(part), std::string::npos) << msg;
  }
}

void ExpectThrowsWith(const std::filesystem::path& path, const std::string& part) {
  ExpectThrowsWithOptions(path, GltfLoadOptions{}, part);
}

TEST(GltfLoader, TrsEqualsMatrix) {
  const auto dir = TempDir();
  const Eigen::Quaterniond q(Eigen::AngleAxisd(0.7, Eigen::Vector3d(1, 2, 3).normalized()));
  const Eigen::Vector3d t(1, -2, 3), s(2, 0.5, 1.5);
  Eigen::Affine3d a = Eigen::Translation3d(t) * q * Eigen::Scaling(s);
  std::vector<double> matrix(a.matrix().data(), a.matrix().data() + 16);  // column-major like glTF

  TestGltf trs, mat;
  for (TestGltf* g : {&trs, &mat}) g->Mesh({{"POSITION", g->Positions(kQuad)}}, g->Accessor<uint8_t>({0, 1, 2, 0, 2, 3}, kUByte, "SCALAR", 6));
  trs.Node({{"mesh", 0}, {"translation", {t.x(), t.y(), t.z()}}, {"rotation", {q.x(), q.y(), q.z(), q.w()}}, {"scale", {s.x(), s.y(), s.z()}}});
  mat.Node({{"mesh", 0}, {"matrix", matrix}});
  trs.Scene({0});
  mat.Scene({0});
  const Scene a_scene = LoadGltf(trs.Write(dir, "trs"));
  const Scene b_scene = LoadGltf(mat.Write(dir, "matrix"));
  ASSERT_EQ(a_scene.meshes.size(), 1u);
  ASSERT_EQ(b_scene.meshes.size(), 1u);
  for (size_t i = 0; i < 4; ++i) {
    const Eigen::Vector3d expected = a * Eigen::Vector3d(kQuad[3 * i], kQuad[3 * i + 1], kQuad[3 * i + 2]);
    EXPECT_TRUE(a_scene.meshes[0].positions[i].isApprox(expected.cast<float>(), 1e-5f));
    EXPECT_TRUE(b_scene.meshes[0].positions[i].isApprox(expected.cast<float>(), 1e-5f));
  }
}

// glTF: matrix has 16 numbers, translation and scale 3, rotation 4, and rotation is a unit
// quaternion. tinygltf takes any count; a wrong one, or a zero quaternion, was read as identity.
// A non-unit rotation is normalised (exporters round). (Non-finite numbers cannot get this far:
// the JSON parser refuses 1e999, and the node's world transform is checked.)
TEST(GltfLoader, InvalidNodeTransformsAreRefusedNamingTheNode) {
  const auto dir = TempDir();
  TestGltf g;
  g.Node({{"name", "quad"}, {"mesh", g.Mesh({{"POSITION", g.Positions({1, 0, 0, 0, 1, 0, 0, 0, 1})}})}});
  g.Scene({0});
  const json identity15 = {1, 0, 0, 0, 0, 1, 0, 0, 0, 0, 1, 0, 0, 0, 0};
  for (const auto& [property, value, error] :
       {std::tuple{"matrix", identity15, "node 0 'quad': matrix has 15 numbers, glTF requires 16"},
        std::tuple{"translation", json{1, 2}, "node 0 'quad': translation has 2 numbers, glTF requires 3"},
        std::tuple{"rotation", json{0, 0, 0, 0}, "node 0 'quad': rotation is a zero quaternion, which is no rotation"},
        std::tuple{"scale", json{1, 1, 1, 1}, "node 0 'quad': scale has 4 numbers, glTF requires 3"}}) {
    TestGltf bad = g;
    bad.doc["nodes"][0][property] = value;
    ExpectThrowsWith(bad.Write(dir, property), error);
  }
  TestGltf turned = g;  // 90 degrees about +y, at twice unit length
  turned.doc["nodes"][0]["rotation"] = {0, std::sqrt(2.0), 0, std::sqrt(2.0)};
  const Scene s = LoadGltf(turned.Write(dir, "turned"));
  ASSERT_EQ(s.meshes.size(), 1u);
  EXPECT_TRUE(s.meshes[0].positions[0].isApprox(Eigen::Vector3f(0, 0, -1), 1e-6f)) << s.meshes[0].positions[0].transpose();
}

TEST(GltfLoader, NestedTransformsAccumulate) {
  const auto dir = TempDir();
  TestGltf g;
  g.Mesh({{"POSITION", g.Positions({1, 0, 0, 0, 1, 0, 0, 0, 1})}});
  // root translates by (10, 0, 0); child rotates 90 deg about +y; grandchild scales by 2 and has the mesh.
  const double h = std::sqrt(0.5);
  g.Node({{"translation", {10, 0, 0}}, {"children", {1}}});
  g.Node({{"rotation", {0, h, 0, h}}, {"children", {2}}});
  g.Node({{"scale", {2, 2, 2}}, {"mesh", 0}});
  g.Scene({0});
  const Scene s = LoadGltf(g.Write(dir, "nested", /*data_uri=*/true));
  ASSERT_EQ(s.meshes.size(), 1u);
  // R_y(90) maps x -> -z, z -> x.
  EXPECT_TRUE(s.meshes[0].positions[0].isApprox(Eigen::Vector3f(10, 0, -2), 1e-5f));
  EXPECT_TRUE(s.meshes[0].positions[1].isApprox(Eigen::Vector3f(10, 2, 0), 1e-5f));
  EXPECT_TRUE(s.meshes[0].positions[2].isApprox(Eigen::Vector3f(12, 0, 0), 1e-5f));
  EXPECT_EQ(s.meshes[0].indices, (std::vector<uint32_t>{0, 1, 2}));  // non-indexed
}

TEST(GltfLoader, EveryIndexTypeAndNonIndexedGiveTheSameTriangles) {
  const auto dir = TempDir();
  TestGltf g;
  const int pos = g.Positions(kQuad);
  g.Mesh({{"POSITION", pos}}, g.Accessor<uint8_t>({0, 1, 2, 0, 2, 3}, kUByte, "SCALAR", 6));
  g.Mesh({{"POSITION", pos}}, g.Accessor<uint16_t>({0, 1, 2, 0, 2, 3}, kUShort, "SCALAR", 6));
  g.Mesh({{"POSITION", pos}}, g.Accessor<uint32_t>({0, 1, 2, 0, 2, 3}, kUInt, "SCALAR", 6));
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
  const auto dir = TempDir();
  TestGltf g;
  // A strip over 5 vertices zig-zagging along x in the z = 0 plane: 3 triangles, all facing +z.
  const int strip_pos = g.Positions({0, 1, 0, 1, 1, 0, 0, 0, 0, 1, 0, 0, 2, 1, 0});
  g.Mesh({{"POSITION", strip_pos}}, g.Accessor<uint16_t>({0, 2, 1, 3, 4}, kUShort, "SCALAR", 5), /*mode=*/5);
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
  const auto dir = TempDir();
  TestGltf g;
  const int pos = g.Positions({0, 0, 0, 1, 0, 0, 0, 1, 0});
  const float n = std::sqrt(0.5f);
  const int nrm = g.Accessor<float>({n, 0, n, n, 0, n, n, 0, n}, kFloat, "VEC3", 3);
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

TEST(GltfLoader, ClassesInheritAndOverride) {
  const auto dir = TempDir();
  TestGltf g;
  const int pos = g.Positions({0, 0, 0, 1, 0, 0, 0, 1, 0});
  g.doc["materials"] = json::array({{{"name", "plain"}}, {{"name", "labelled"}, {"extras", {{"class", "vegetation"}}}}});
  const int plain = g.Mesh({{"POSITION", pos}}, -1, 4, 0);
  const int mesh_car = g.Mesh({{"POSITION", pos}}, -1, 4, 0, {{"class", "car"}});
  const int mesh_car_mat_veg = g.Mesh({{"POSITION", pos}}, -1, 4, 1, {{"class", "car"}});
  const int unknown = g.Mesh({{"POSITION", pos}}, -1, 4, 0, {{"class", "spaceship"}});
  g.Node({{"name", "root"}, {"extras", {{"class", "building"}}}, {"mesh", plain}, {"children", {1, 2, 3}}});  // 0
  g.Node({{"name", "inherits"}, {"children", {4}}});                                                       // 1
  g.Node({{"name", "mesh_wins"}, {"mesh", mesh_car}});                                                     // 2
  g.Node({{"name", "material_wins"}, {"extras", {{"class", "road"}}}, {"mesh", mesh_car_mat_veg}});        // 3
  g.Node({{"name", "grandchild"}, {"mesh", plain}});                                                       // 4
  g.Node({{"name", "unlabeled"}, {"mesh", plain}});                                                        // 5
  g.Node({{"name", "unknown"}, {"mesh", unknown}});                                                        // 6
  g.Scene({0, 5, 6});
  const Scene s = LoadGltf(g.Write(dir, "classes"));
  ASSERT_EQ(s.meshes.size(), 6u);
  // Depth-first order: root, mesh_wins, material_wins... children of root come in order 1 (no mesh) -> 4.
  std::map<std::string, const SceneMesh*> by_name;
  for (const SceneMesh& m : s.meshes) by_name[m.name] = &m;
  EXPECT_EQ(by_name.at("root")->class_id, FindClassByName("building")->id);
  EXPECT_EQ(by_name.at("grandchild")->class_id, FindClassByName("building")->id);
  EXPECT_EQ(by_name.at("mesh_wins")->class_id, FindClassByName("car")->id);
  EXPECT_EQ(by_name.at("material_wins")->class_id, FindClassByName("vegetation")->id);
  EXPECT_EQ(by_name.at("unlabeled")->class_id, kUnlabeledId);
  EXPECT_EQ(by_name.at("unknown")->class_id, kUnlabeledId);
  EXPECT_TRUE(HasWarning(s, "unknown class 'spaceship'"));
  // One summary warning for geometry without any class: only the node "unlabeled" (1 triangle).
  int summaries = 0;
  for (const std::string& w : s.warnings) summaries += w.find("have no class") != std::string::npos;
  EXPECT_EQ(summaries, 1);
  EXPECT_TRUE(HasWarning(s, "1 triangles in 1 primitive(s) have no class"));
}

TEST(GltfLoader, InstanceIdsFollowDepthFirstTraversal) {
  const auto dir = TempDir();
  TestGltf g;
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

TEST(GltfLoader, DecodesBaseColorTextureAndSampler) {
  const auto dir = TempDir();
  // 3x2 image with known pixels, written as PNG (lossless) next to the file and as a data URI.
  cv::Mat bgr(2, 3, CV_8UC3);
  for (int y = 0; y < 2; ++y) {
    for (int x = 0; x < 3; ++x) bgr.at<cv::Vec3b>(y, x) = cv::Vec3b(uchar(10 * x), uchar(100 + y), uchar(200 + x + y));  // B G R
  }
  ASSERT_TRUE(cv::imwrite((dir / "tex.png").string(), bgr));
  std::vector<uint8_t> png;
  ASSERT_TRUE(cv::imencode(".png", bgr, png));
  TestGltf g;
  const int pos = g.Positions({0, 0, 0, 1, 0, 0, 0, 1, 0});
  const int uv = g.Accessor<uint8_t>({0, 255, 255, 255, 0, 0, 0, 0}, kUByte, "VEC2", 3, /*normalized=*/true);
  g.doc["images"] = json::array({{{"uri", "tex.png"}}, {{"uri", DataUri("image/png", png)}}});
  g.doc["samplers"] = json::array({{{"magFilter", 9728}, {"minFilter", 9984}, {"wrapS", 33071}, {"wrapT", 33648}}});
  g.doc["textures"] = json::array({{{"source", 0}, {"sampler", 0}}, {{"source", 1}}});
  g.doc["materials"] = json::array({
      {{"pbrMetallicRoughness", {{"baseColorFactor", {0.5, 0.25, 1, 1}}, {"baseColorTexture", {{"index", 0}}}}},
       {"alphaMode", "MASK"}, {"alphaCutoff", 0.3}, {"doubleSided", true}},
      {{"pbrMetallicRoughness", {{"baseColorTexture", {{"index", 1}}}}}, {"alphaMode", "BLEND"}}});
  g.Mesh({{"POSITION", pos}, {"TEXCOORD_0", uv}}, -1, 4, 0);
  g.Mesh({{"POSITION", pos}}, -1, 4, 1);
  g.Node({{"mesh", 0}});
  g.Node({{"mesh", 1}});
  g.Scene({0, 1});
  const auto path = g.Write(dir, "textured");
  const Scene s = LoadGltf(path);
  ASSERT_EQ(s.textures.size(), 2u);
  ASSERT_EQ(s.materials.size(), 2u);
  for (const Texture& t : s.textures) {
    ASSERT_EQ(t.width, 3);
    ASSERT_EQ(t.height, 2);
    for (int y = 0; y < 2; ++y) {
      for (int x = 0; x < 3; ++x) {
        const uint8_t* p = &t.rgba[(y * 3 + x) * 4];
        EXPECT_EQ(p[0], 200 + x + y);
        EXPECT_EQ(p[1], 100 + y);
        EXPECT_EQ(p[2], 10 * x);
        EXPECT_EQ(p[3], 255);
      }
    }
  }
  EXPECT_TRUE(s.textures[0].nearest);
  EXPECT_TRUE(s.textures[0].min_nearest);  // NEAREST_MIPMAP_NEAREST
  EXPECT_EQ(s.textures[0].mip, MipFilter::kNearest);
  EXPECT_EQ(s.textures[0].wrap_s, WrapMode::kClampToEdge);
  EXPECT_EQ(s.textures[0].wrap_t, WrapMode::kMirroredRepeat);
  EXPECT_FALSE(s.textures[1].nearest);  // no sampler: linear, trilinear when minified
  EXPECT_FALSE(s.textures[1].min_nearest);
  EXPECT_EQ(s.textures[1].mip, MipFilter::kLinear);
  EXPECT_EQ(s.textures[1].wrap_s, WrapMode::kRepeat);
  const Material& m = s.materials[0];
  EXPECT_EQ(m.base_color_texture, 0);
  EXPECT_TRUE(m.base_color_factor.isApprox(Eigen::Vector4f(0.5f, 0.25f, 1, 1)));
  EXPECT_EQ(m.alpha_mode, AlphaMode::kMask);
  EXPECT_FLOAT_EQ(m.alpha_cutoff, 0.3f);
  EXPECT_TRUE(m.double_sided);
  EXPECT_EQ(s.materials[1].base_color_texture, 1);
  EXPECT_EQ(s.materials[1].alpha_mode, AlphaMode::kBlend);
  // Normalized unsigned-byte texcoords.
  ASSERT_EQ(s.meshes[0].texcoords.size(), 3u);
  EXPECT_TRUE(s.meshes[0].texcoords[0].isApprox(Eigen::Vector2f(0, 1)));
  EXPECT_TRUE(s.meshes[0].texcoords[1].isApprox(Eigen::Vector2f(1, 1)));

  // A missing image file is an error that names it.
  std::filesystem::remove(dir / "tex.png");
  ExpectThrowsWith(path, "tex.png");
}

// A 2x2 PNG as a data URI, for materials whose texture content does not matter.
std::string TinyPngUri() {
  cv::Mat bgr(2, 2, CV_8UC3, cv::Scalar(10, 20, 30));
  std::vector<uint8_t> png;
  cv::imencode(".png", bgr, png);
  return DataUri("image/png", png);
}

TestGltf::TwoSets TestGltf::QuadWithTwoTexcoordSets() {
  return {Positions(kQuad), Accessor<float>({0, 0, 1, 0, 1, 1, 0, 1}, kFloat, "VEC2", 4),
          Accessor<float>({0.25f, 0.25f, 0.75f, 0.25f, 0.75f, 0.75f, 0.25f, 0.75f}, kFloat, "VEC2", 4)};
}

void TestGltf::TinyTexture() {
  doc["images"] = json::array({{{"uri", TinyPngUri()}}});
  doc["textures"] = json::array({{{"source", 0}}});
}

// KHR_texture_transform: uv' = offset + R(rotation) * (scale * uv), with the rotation
// counter-clockwise in glTF's v-down UV space: at 90 deg (1, 0) -> (0, -1), as the Khronos sample
// viewer and the TextureTransformTest model have it (see ParseTextureTransform).
// EXT_texture_webp: the texture's WebP image replaces its (here absent) PNG fallback. Lossless
// pixels arrive exactly; lossy and lossless WebP headers give the size that the pixel limit checks.
TEST(GltfLoader, WebpTexturesThroughTheirExtension) {
  const auto dir = TempDir();
  cv::Mat bgra(2, 3, CV_8UC4);
  for (int y = 0; y < 2; ++y) {
    for (int x = 0; x < 3; ++x) bgra.at<cv::Vec4b>(y, x) = cv::Vec4b(uint8_t(10 * x), uint8_t(50 + y), 200, uint8_t(255 - 40 * x));
  }
  std::vector<uint8_t> lossless, lossy, lossy_alpha;  // VP8L, VP8 and VP8X first chunks
  ASSERT_TRUE(cv::imencode(".webp", bgra, lossless, {cv::IMWRITE_WEBP_QUALITY, 101}));
  ASSERT_TRUE(cv::imencode(".webp", bgra, lossy_alpha, {cv::IMWRITE_WEBP_QUALITY, 80}));
  cv::Mat bgr(2, 3, CV_8UC3, cv::Scalar(30, 60, 90));
  ASSERT_TRUE(cv::imencode(".webp", bgr, lossy, {cv::IMWRITE_WEBP_QUALITY, 80}));
  for (const std::vector<uint8_t>* webp : {&lossless, &lossy, &lossy_alpha}) {
    TestGltf g;
    const int pos = g.Positions(kQuad);
    const int uv = g.Accessor<float>({0, 0, 1, 0, 1, 1, 0, 1}, kFloat, "VEC2", 4);
    g.doc["extensionsUsed"] = {"EXT_texture_webp"};
    g.doc["extensionsRequired"] = {"EXT_texture_webp"};
    const std::string name = webp == &lossless ? "lossless" : webp == &lossy ? "lossy" : "lossy_alpha";
    EXPECT_EQ(std::string(webp->begin() + 12, webp->begin() + 16), webp == &lossless ? "VP8L" : webp == &lossy ? "VP8 " : "VP8X");
    std::ofstream(dir / (name + ".webp"), std::ios::binary).write(reinterpret_cast<const char*>(webp->data()), std::streamsize(webp->size()));
    g.doc["images"] = json::array({{{"uri", name + ".webp"}}});
    g.doc["textures"] = json::array({{{"extensions", {{"EXT_texture_webp", {{"source", 0}}}}}}});
    g.doc["materials"] = json::array({{{"pbrMetallicRoughness", {{"baseColorTexture", {{"index", 0}}}}}}});
    g.Node({{"mesh", g.Mesh({{"POSITION", pos}, {"TEXCOORD_0", uv}}, -1, 6, 0)}});
    g.Scene({0});
    const auto path = g.Write(dir, name);
    const Scene s = LoadGltf(path);
    ASSERT_EQ(s.textures.size(), 1u);
    EXPECT_EQ(s.materials[0].base_color_texture, 0);
    EXPECT_EQ(s.textures[0].width, 3);
    EXPECT_EQ(s.textures[0].height, 2);
    EXPECT_FALSE(HasWarning(s, "webp"));
    if (webp == &lossless) {
      for (int y = 0; y < 2; ++y) {
        for (int x = 0; x < 3; ++x) {
          const uint8_t* t = &s.textures[0].rgba[(size_t(y) * 3 + x) * 4];
          const cv::Vec4b& b = bgra.at<cv::Vec4b>(y, x);
          EXPECT_EQ((std::array<int, 4>{t[0], t[1], t[2], t[3]}), (std::array<int, 4>{b[2], b[1], b[0], b[3]})) << x << "," << y;
        }
      }
    }
    GltfLoadOptions small;
    small.max_image_pixels = 5;
    ExpectThrowsWithOptions(path, small, "image 0 is 3x2 pixels, more than the limit of 5");
  }
}

TEST(GltfLoader, ImagesAreCheckedBeforeDecoding) {
  const auto dir = TempDir();
  // Only a PNG's IHDR, claiming 70000 x 70000 pixels (18 GiB as RGBA); a BMP (stb would decode it,
  // glTF does not allow it); a real 3 x 2 JPEG, under a limit of 5 pixels and then the default.
  const std::vector<uint8_t> huge_png = {0x89, 'P', 'N', 'G', '\r', '\n', 0x1a, '\n', 0, 0, 0, 13, 'I', 'H', 'D', 'R',
                                         0, 1, 0x11, 0x70, 0, 1, 0x11, 0x70, 8, 6, 0, 0, 0, 0, 0, 0, 0};
  // The largest size a PNG header can state (2^32 - 1 each way).
  std::vector<uint8_t> widest_png = huge_png;
  for (int i = 16; i < 24; ++i) widest_png[i] = 0xFF;
  std::vector<uint8_t> bmp(64, 0);
  bmp[0] = 'B';
  bmp[1] = 'M';
  std::vector<uint8_t> jpeg;
  ASSERT_TRUE(cv::imencode(".jpg", cv::Mat(2, 3, CV_8UC3, cv::Scalar(40, 80, 120)), jpeg));
  struct Case {
    const std::vector<uint8_t>* bytes;
    uint64_t max_pixels;
    std::string error;  // empty: loads
  };
  const uint64_t default_limit = GltfLoadOptions{}.max_image_pixels;
  for (const Case& c : {Case{&huge_png, default_limit, "image 0 is 70000x70000 pixels, more than the limit"},
                        Case{&bmp, default_limit, "image 0 is not a PNG, JPEG or WebP image"},
                        Case{&widest_png, default_limit, "image 0 is 4294967295x4294967295 pixels, more than the limit"},
                        Case{&jpeg, 5, "image 0 is 3x2 pixels, more than the limit of 5"}, Case{&jpeg, default_limit, ""}}) {
    TestGltf g;  // the image is the base colour of the triangle's material
    const int pos = g.Positions({0, 0, 0, 1, 0, 0, 0, 1, 0});
    g.doc["images"] = json::array({{{"uri", DataUri("image/png", *c.bytes)}}});
    g.doc["textures"] = json::array({{{"source", 0}}});
    g.doc["materials"] = json::array({{{"pbrMetallicRoughness", {{"baseColorTexture", {{"index", 0}}}}}}});
    g.Mesh({{"POSITION", pos}}, -1, 4, 0);
    g.Node({{"mesh", 0}});
    g.Scene({0});
    const auto path = g.Write(dir, "image");
    GltfLoadOptions options;
    options.max_image_pixels = c.max_pixels;
    if (c.error.empty()) {
      EXPECT_NO_THROW(LoadGltf(path, options));
      continue;
    }
    try {
      LoadGltf(path, options);
      ADD_FAILURE() << "loaded; expected: " << c.error;
    } catch (const std::runtime_error& e) {
      const std::string what = e.what();
      EXPECT_NE(what.find(c.error), std::string::npos) << what;
      EXPECT_NE(what.find(path.string()), std::string::npos) << what;
    }
  }
}

// A texture whose optional extension (in extensionsUsed, not extensionsRequired) points at an
// image rigsim cannot decode falls back to its PNG `source` (glTF 2.0, "Extensions"): the other
// image is skipped with one warning naming it. An image no texture uses is skipped the same way
// when it is too large; used, either is refused (ImagesAreCheckedBeforeDecoding).
TEST(GltfLoader, ImagesNoUsedTextureSamplesAreSkippedWhenRigsimCannotDecodeThem) {
  const auto dir = TempDir();
  std::vector<uint8_t> ktx2 = {0xAB, 'K', 'T', 'X', ' ', '2', '0', 0xBB, '\r', '\n', 0x1A, '\n'};
  ktx2.resize(80, 0);  // the KTX2 identifier and a (fake) header
  std::vector<uint8_t> dds = {'D', 'D', 'S', ' ', 0x7C, 0, 0, 0};
  dds.resize(128, 0);
  for (const auto& [extension, bytes] : {std::pair{"KHR_texture_basisu", ktx2}, std::pair{"MSFT_texture_dds", dds}}) {
    const std::string file = std::string(extension) + ".image";  // tinygltf takes only PNG and JPEG data URIs
    std::ofstream(dir / file, std::ios::binary).write(reinterpret_cast<const char*>(bytes.data()), std::streamsize(bytes.size()));
    TestGltf g;
    const TestGltf::TwoSets quad = g.QuadWithTwoTexcoordSets();
    g.doc["extensionsUsed"] = {extension};
    g.doc["images"] = json::array({{{"uri", TinyPngUri()}}, {{"uri", file}}});
    g.doc["textures"] = json::array({{{"source", 0}, {"extensions", {{extension, {{"source", 1}}}}}}});
    g.doc["materials"] = json::array({{{"pbrMetallicRoughness", {{"baseColorTexture", {{"index", 0}}}}}}});
    g.Node({{"mesh", g.Mesh({{"POSITION", quad.pos}, {"TEXCOORD_0", quad.uv0}}, -1, 6, 0)}});
    g.Scene({0});
    const Scene s = LoadGltf(g.Write(dir, extension));
    ASSERT_EQ(s.textures.size(), 1u) << extension;
    EXPECT_EQ(s.materials[0].base_color_texture, 0);
    EXPECT_EQ(s.textures[0].width, 2);  // the PNG
    EXPECT_EQ(std::count_if(s.warnings.begin(), s.warnings.end(),
                            [](const std::string& w) { return w.find("image 1") != std::string::npos; }), 1) << extension;
    EXPECT_TRUE(HasWarning(s, "image 1 is not a PNG, JPEG or WebP image (the formats glTF 2.0 and EXT_texture_webp allow); "
                              "no texture rigsim uses samples it, so it is skipped")) << extension;
  }
  // An image over the pixel limit that no texture uses.
  TestGltf g;
  g.doc["images"] = json::array({{{"uri", TinyPngUri()}}});
  g.Node({{"mesh", g.Mesh({{"POSITION", g.Positions({0, 0, 0, 1, 0, 0, 0, 1, 0})}})}});
  g.Scene({0});
  GltfLoadOptions small;
  small.max_image_pixels = 3;
  const Scene s = LoadGltf(g.Write(dir, "unused_large"), small);
  EXPECT_TRUE(HasWarning(s, "image 0 is 2x2 pixels, more than the limit of 3 (GltfLoadOptions::max_image_pixels); "
                            "no texture rigsim uses samples it"));
}

TEST(GltfLoader, UnlitMaterialsAreMarked) {
  const auto dir = TempDir();
  TestGltf g;
  const int pos = g.Positions(kQuad);
  g.doc["extensionsUsed"] = {"KHR_materials_unlit"};
  g.doc["extensionsRequired"] = {"KHR_materials_unlit"};  // honoured, so not refused
  g.doc["materials"] = json::array({{{"name", "lit"}},
                                    {{"name", "flat"}, {"extensions", {{"KHR_materials_unlit", json::object()}}}}});
  g.Node({{"mesh", g.Mesh({{"POSITION", pos}}, -1, 6, 0)}});
  g.Node({{"mesh", g.Mesh({{"POSITION", pos}}, -1, 6, 1)}});
  g.Scene({0, 1});
  const Scene s = LoadGltf(g.Write(dir, "unlit"));
  ASSERT_EQ(s.materials.size(), 2u);
  EXPECT_FALSE(s.materials[0].unlit);
  EXPECT_TRUE(s.materials[1].unlit);
  EXPECT_FALSE(HasWarning(s, "unlit"));
}

// emissiveFactor times KHR_materials_emissive_strength, and an emissive texture sampled through its
// own texCoord and KHR_texture_transform, baked apart from the base colour's coordinates.
TEST(GltfLoader, EmissionIsReadWithItsStrengthAndItsOwnTexcoords) {
  const auto dir = TempDir();
  TestGltf g;
  const auto [pos, uv0, uv1] = g.QuadWithTwoTexcoordSets();
  g.doc["extensionsUsed"] = {"KHR_materials_emissive_strength", "KHR_texture_transform"};
  g.doc["extensionsRequired"] = {"KHR_materials_emissive_strength"};  // honoured, so not refused
  g.TinyTexture();
  g.doc["materials"] = json::array({
      {{"name", "sign"},
       {"pbrMetallicRoughness", {{"baseColorTexture", {{"index", 0}}}}},
       {"emissiveFactor", {0.5, 0.25, 0}},
       {"emissiveTexture", {{"index", 0}, {"texCoord", 1}, {"extensions", {{"KHR_texture_transform", {{"offset", {1, 0}}}}}}}},
       {"extensions", {{"KHR_materials_emissive_strength", {{"emissiveStrength", 4}}}}}},
      {{"name", "dark"}, {"emissiveTexture", {{"index", 0}}}},  // factor 0: the texture adds nothing
  });
  g.Node({{"mesh", g.Mesh({{"POSITION", pos}, {"TEXCOORD_0", uv0}, {"TEXCOORD_1", uv1}}, -1, 4, 0)}});
  g.Node({{"mesh", g.Mesh({{"POSITION", pos}, {"TEXCOORD_0", uv0}}, -1, 4, 1)}});
  g.Scene({0, 1});
  const Scene s = LoadGltf(g.Write(dir, "emissive"));
  ASSERT_EQ(s.materials.size(), 2u);
  EXPECT_TRUE(s.materials[0].emissive.isApprox(Eigen::Vector3f(2, 1, 0)));
  EXPECT_EQ(s.materials[0].emissive_texture, 0);
  EXPECT_EQ(s.materials[1].emissive, Eigen::Vector3f::Zero());
  EXPECT_EQ(s.materials[1].emissive_texture, -1);
  ASSERT_EQ(s.meshes.size(), 2u);
  ASSERT_EQ(s.meshes[0].texcoords.size(), 4u);
  ASSERT_EQ(s.meshes[0].emissive_texcoords.size(), 4u);
  EXPECT_EQ(s.meshes[0].texcoords[1], Eigen::Vector2f(1, 0));               // TEXCOORD_0 as it is
  EXPECT_EQ(s.meshes[0].emissive_texcoords[1], Eigen::Vector2f(1.75f, 0.25f));  // TEXCOORD_1 + offset
  EXPECT_TRUE(s.meshes[1].emissive_texcoords.empty());
  EXPECT_FALSE(HasWarning(s, "emissive"));
  EXPECT_FALSE(HasWarning(s, "TEXCOORD_1")) << "the emissive texture samples it";

  g.doc["materials"][0]["extensions"]["KHR_materials_emissive_strength"]["emissiveStrength"] = -1;
  ExpectThrowsWith(g.Write(dir, "negative_strength"), "material 0 'sign': KHR_materials_emissive_strength: emissiveStrength must be");
  g.doc["materials"][0]["extensions"]["KHR_materials_emissive_strength"]["emissiveStrength"] = 1;
  g.doc["materials"][0]["emissiveFactor"] = {0.5, -0.25, 0};
  ExpectThrowsWith(g.Write(dir, "negative_factor"), "material 0 'sign': emissiveFactor must be finite and >= 0");
}

// The two-texcoord quad on one node, with the tiny texture and `material` as its only material.
TestGltf QuadWithMaterial(const json& material) {
  TestGltf g;
  const auto [pos, uv0, uv1] = g.QuadWithTwoTexcoordSets();
  g.TinyTexture();
  g.doc["materials"] = json::array({material});
  g.Node({{"mesh", g.Mesh({{"POSITION", pos}, {"TEXCOORD_0", uv0}, {"TEXCOORD_1", uv1}}, -1, 4, 0)}});
  g.Scene({0});
  return g;
}

// normalTexture: its scale, and its own texCoord baked into SceneMesh::normal_texcoords.
TEST(GltfLoader, NormalTextureIsReadWithItsScaleAndTexcoords) {
  const auto dir = TempDir();
  TestGltf g = QuadWithMaterial({{"name", "bricks"}, {"normalTexture", {{"index", 0}, {"texCoord", 1}, {"scale", 0.5}}}});
  const Scene s = LoadGltf(g.Write(dir, "normal_map"));
  ASSERT_EQ(s.materials.size(), 1u);
  EXPECT_EQ(s.materials[0].normal_texture, 0);
  EXPECT_FLOAT_EQ(s.materials[0].normal_scale, 0.5f);
  ASSERT_EQ(s.meshes.size(), 1u);
  ASSERT_EQ(s.meshes[0].normal_texcoords.size(), 4u);
  EXPECT_EQ(s.meshes[0].normal_texcoords[1], Eigen::Vector2f(0.75f, 0.25f));
  EXPECT_FALSE(HasWarning(s, "normalTexture"));
  EXPECT_FALSE(HasWarning(s, "TEXCOORD_1"));
}

// occlusionTexture: its strength, and its own texCoord baked into SceneMesh::occlusion_texcoords;
// a strength outside glTF's [0, 1] is refused.
TEST(GltfLoader, OcclusionTextureIsReadWithItsStrengthAndTexcoords) {
  const auto dir = TempDir();
  TestGltf g = QuadWithMaterial({{"name", "baked"}, {"occlusionTexture", {{"index", 0}, {"texCoord", 1}, {"strength", 0.25}}}});
  const Scene s = LoadGltf(g.Write(dir, "occlusion"));
  ASSERT_EQ(s.materials.size(), 1u);
  EXPECT_EQ(s.materials[0].occlusion_texture, 0);
  EXPECT_FLOAT_EQ(s.materials[0].occlusion_strength, 0.25f);
  ASSERT_EQ(s.meshes.size(), 1u);
  ASSERT_EQ(s.meshes[0].occlusion_texcoords.size(), 4u);
  EXPECT_EQ(s.meshes[0].occlusion_texcoords[1], Eigen::Vector2f(0.75f, 0.25f));
  EXPECT_FALSE(HasWarning(s, "occlusion"));
  EXPECT_FALSE(HasWarning(s, "TEXCOORD_1"));
  g.doc["materials"][0]["occlusionTexture"]["strength"] = 1.5;
  ExpectThrowsWith(g.Write(dir, "strong"), "material 0 'baked' occlusionTexture: strength must be in [0, 1], got 1.5");
}

// A quad skinned to two joints: its lower edge follows joint 1 (at the origin), its upper edge
// joint 2, bound at (0, 1, 0) and at rest at (5, 1, 0). The mesh node's own translation does not
// apply (glTF: a skinned mesh is placed by its joints).
TEST(GltfLoader, SkinnedMeshesArePlacedByTheirJoints) {
  const auto dir = TempDir();
  TestGltf g;
  const int pos = g.Positions(kQuad);
  const int joints = g.Accessor<uint8_t>({0, 1, 0, 0, 0, 1, 0, 0, 0, 1, 0, 0, 0, 1, 0, 0}, kUByte, "VEC4", 4);
  const int weights = g.Accessor<float>({1, 0, 0, 0, 1, 0, 0, 0, 0, 2, 0, 0, 0, 1, 0, 0}, kFloat, "VEC4", 4);  // rescaled to sum 1
  const std::vector<float> ibm = {1, 0, 0, 0, 0, 1, 0, 0, 0, 0, 1, 0, 0, 0, 0, 1,     // joint 1: identity
                                  1, 0, 0, 0, 0, 1, 0, 0, 0, 0, 1, 0, 0, -1, 0, 1};   // joint 2: translate(0, -1, 0)
  const int ibm_acc = g.Accessor(ibm, kFloat, "MAT4", 2);
  g.doc["skins"] = json::array({{{"joints", {1, 2}}, {"inverseBindMatrices", ibm_acc}}});
  g.Node({{"mesh", g.Mesh({{"POSITION", pos}, {"JOINTS_0", joints}, {"WEIGHTS_0", weights}}, -1, 6)},
          {"skin", 0}, {"translation", {100, 0, 0}}});
  g.Node({{"children", {2}}});
  g.Node({{"translation", {5, 1, 0}}});
  g.Scene({0, 1});
  const Scene s = LoadGltf(g.Write(dir, "skinned"));
  ASSERT_EQ(s.skins.size(), 1u);
  EXPECT_EQ(s.skins[0].joints, (std::vector<int>{1, 2}));
  ASSERT_EQ(s.meshes.size(), 1u);
  const SceneMesh& m = s.meshes[0];
  EXPECT_EQ(m.skin, 0);
  ASSERT_EQ(m.positions.size(), 4u);
  const Eigen::Vector3f expected[4] = {{0, 0, 0}, {1, 0, 0}, {6, 1, 0}, {5, 1, 0}};
  for (int i = 0; i < 4; ++i) EXPECT_TRUE(m.positions[i].isApprox(expected[i])) << i << ": " << m.positions[i].transpose();
  EXPECT_FALSE(HasWarning(s, "skin"));
  EXPECT_FALSE(HasWarning(s, "JOINTS_0"));

  g.doc["skins"][0]["joints"] = {1};  // vertex 2 weighs joint 1 of a skin that now has one
  ExpectThrowsWith(g.Write(dir, "joint_beyond_skin"), "JOINTS_0): vertex 2 names joint 1 of a skin with 1");
  g.doc["skins"][0]["joints"] = {1, 2, 0};
  ExpectThrowsWith(g.Write(dir, "short_ibm"), "skin 0: 2 inverse bind matrices for 3 joints");
  g.doc["skins"][0]["joints"] = {1, 2};
  g.doc["skins"][0].erase("inverseBindMatrices");  // glTF: identity matrices
  const Scene identity = LoadGltf(g.Write(dir, "no_ibm"));
  const Eigen::Vector3f unbound[4] = {{0, 0, 0}, {1, 0, 0}, {6, 2, 0}, {5, 2, 0}};  // joint 2 no longer moves down 1
  for (int i = 0; i < 4; ++i) {
    EXPECT_TRUE(identity.meshes[0].positions[i].isApprox(unbound[i])) << i << ": " << identity.meshes[0].positions[i].transpose();
  }
  EXPECT_FALSE(HasWarning(identity, "inverseBindMatrices"));
  g.doc["skins"][0]["inverseBindMatrices"] = ibm_acc;
  g.Scene({0});  // the joints' tree is left out of the scene
  ExpectThrowsWith(g.Write(dir, "joints_outside_scene"), "skin 0: joint node 1 is not in the loaded scene");
}

TEST(GltfLoader, TextureTransformIsBakedIntoTexcoords) {
  const auto dir = TempDir();
  TestGltf g;
  const auto [pos, uv0, uv1] = g.QuadWithTwoTexcoordSets();
  const double half_pi = std::numbers::pi / 2;
  g.doc["extensionsUsed"] = {"KHR_texture_transform"};
  g.doc["extensionsRequired"] = {"KHR_texture_transform"};
  g.TinyTexture();
  auto textured = [&](json texture_info) { return json{{"pbrMetallicRoughness", {{"baseColorTexture", texture_info}}}}; };
  auto transform = [](json t) { return json{{"index", 0}, {"extensions", {{"KHR_texture_transform", t}}}}; };
  g.doc["materials"] = json::array({
      textured(transform({{"rotation", half_pi}})),                                   // 0: rotation only
      textured(transform({{"offset", {0.5, 0.25}}, {"scale", {2, 3}}})),              // 1: offset and scale
      textured(transform({{"offset", {0, 1}}, {"rotation", half_pi}, {"scale", {0.5, 0.5}}})),  // 2: the spec's example
      textured(transform({{"texCoord", 1}})),                                         // 3: the override picks TEXCOORD_1
      textured({{"index", 0}, {"texCoord", 1}, {"extensions", {{"KHR_texture_transform", {{"texCoord", 0}}}}}}),  // 4: override back to 0
      textured({{"index", 0}, {"texCoord", 1}}),                                      // 5: plain texCoord 1
  });
  for (int m = 0; m < 6; ++m) {
    g.Mesh({{"POSITION", pos}, {"TEXCOORD_0", uv0}, {"TEXCOORD_1", uv1}}, -1, 4, m);
    g.Node({{"mesh", m}});
  }
  g.Scene({0, 1, 2, 3, 4, 5});
  const Scene s = LoadGltf(g.Write(dir, "transform"));
  ASSERT_EQ(s.meshes.size(), 6u);
  EXPECT_FALSE(HasWarning(s, "extension KHR_texture_transform")) << "the extension is supported, not ignored";
  auto expect_uv = [&](int mesh, std::vector<Eigen::Vector2f> expected) {
    ASSERT_EQ(s.meshes[mesh].texcoords.size(), expected.size()) << mesh;
    for (size_t i = 0; i < expected.size(); ++i) {
      EXPECT_TRUE(s.meshes[mesh].texcoords[i].isApprox(expected[i], 1e-6f) ||
                  (s.meshes[mesh].texcoords[i] - expected[i]).norm() < 1e-6f)
          << "mesh " << mesh << " vertex " << i << ": " << s.meshes[mesh].texcoords[i].transpose() << " expected "
          << expected[i].transpose();
    }
  };
  // (0,0) (1,0) (1,1) (0,1) turned 90 deg counter-clockwise in the v-down UV plane.
  expect_uv(0, {{0, 0}, {0, -1}, {1, -1}, {1, 0}});
  expect_uv(1, {{0.5f, 0.25f}, {2.5f, 0.25f}, {2.5f, 3.25f}, {0.5f, 3.25f}});
  // The spec's example "utilizes only the lower left quadrant of the source image": u in [0, 0.5],
  // v in [0.5, 1].
  expect_uv(2, {{0, 1}, {0, 0.5f}, {0.5f, 0.5f}, {0.5f, 1}});
  expect_uv(3, {{0.25f, 0.25f}, {0.75f, 0.25f}, {0.75f, 0.75f}, {0.25f, 0.75f}});
  expect_uv(4, {{0, 0}, {1, 0}, {1, 1}, {0, 1}});
  expect_uv(5, {{0.25f, 0.25f}, {0.75f, 0.25f}, {0.75f, 0.75f}, {0.25f, 0.75f}});
  EXPECT_TRUE(HasWarning(s, "vertex attribute TEXCOORD_0")) << "the set no texture samples is reported";
  for (const Material& m : s.materials) EXPECT_EQ(m.base_color_texture, 0);
}

TEST(GltfLoader, MalformedTextureTransformThrowsAndMissingSetWarns) {
  const auto dir = TempDir();
  TestGltf g;
  const int pos = g.Positions(kQuad);
  const int uv0 = g.Accessor<float>({0, 0, 1, 0, 1, 1, 0, 1}, kFloat, "VEC2", 4);
  g.doc["images"] = json::array({{{"uri", TinyPngUri()}}});
  g.doc["textures"] = json::array({{{"source", 0}}});
  g.doc["materials"] = json::array({{{"name", "atlas"},
                                     {"pbrMetallicRoughness",
                                      {{"baseColorTexture", {{"index", 0}, {"extensions", {{"KHR_texture_transform", {{"texCoord", 2}}}}}}}}}}});
  g.Mesh({{"POSITION", pos}, {"TEXCOORD_0", uv0}}, -1, 4, 0);
  g.Node({{"mesh", 0}});
  g.Scene({0});
  const Scene s = LoadGltf(g.Write(dir, "missing_set"));
  ASSERT_EQ(s.meshes.size(), 1u);
  EXPECT_TRUE(s.meshes[0].texcoords.empty());
  EXPECT_TRUE(HasWarning(s, "without their texture's TEXCOORD_2"));

  auto& ext = g.doc["materials"][0]["pbrMetallicRoughness"]["baseColorTexture"]["extensions"]["KHR_texture_transform"];
  ext = {{"scale", {1}}};
  ExpectThrowsWith(g.Write(dir, "short_scale"), "material 0 'atlas' baseColorTexture: KHR_texture_transform: scale must be an array of 2 numbers");
  ext = {{"rotation", "quarter"}};
  ExpectThrowsWith(g.Write(dir, "text_rotation"), "rotation must be a finite number");
  ext = {{"texCoord", -1}};
  ExpectThrowsWith(g.Write(dir, "negative_set"), "texCoord must be a non-negative integer");
}

TEST(GltfLoader, SparseAccessorOverridesValues) {
  const auto dir = TempDir();
  TestGltf g;
  const int pos = g.Positions({0, 0, 0, 1, 0, 0, 0, 1, 0});
  const int before = int(g.doc["bufferViews"].size());
  g.Accessor<uint8_t>({2, 0, 0, 0}, kUByte, "SCALAR", 1);  // just to get bufferViews for sparse data
  g.Accessor<float>({5, 6, 7}, kFloat, "VEC3", 1);
  g.doc["accessors"][pos]["sparse"] = {{"count", 1},
                                       {"indices", {{"bufferView", before}, {"componentType", kUByte}}},
                                       {"values", {{"bufferView", before + 1}}}};
  g.Mesh({{"POSITION", pos}});
  g.Node({{"mesh", 0}});
  g.Scene({0});
  const Scene s = LoadGltf(g.Write(dir, "sparse"));
  ASSERT_EQ(s.meshes.size(), 1u);
  EXPECT_TRUE(s.meshes[0].positions[2].isApprox(Eigen::Vector3f(5, 6, 7)));
  EXPECT_TRUE(s.meshes[0].positions[1].isApprox(Eigen::Vector3f(1, 0, 0)));
}

// An index accessor whose values are all sparse, without a bufferView, is valid glTF, but tinygltf
// refuses it before rigsim sees the model, in words that name no primitive: the message adds the
// primitives that use it.
TEST(GltfLoader, SparseOnlyIndicesAreRefusedNamingThePrimitive) {
  const auto dir = TempDir();
  TestGltf g;
  const int pos = g.Positions(kQuad);
  const int before = int(g.doc["bufferViews"].size());
  g.Accessor<uint8_t>({0, 1, 2, 3, 4, 5}, kUByte, "SCALAR", 6);  // bufferViews for the sparse data
  g.Accessor<uint16_t>({0, 1, 2, 0, 2, 3}, kUShort, "SCALAR", 6);
  g.doc["accessors"].push_back({{"componentType", kUShort}, {"count", 6}, {"type", "SCALAR"},
                                {"sparse", {{"count", 6}, {"indices", {{"bufferView", before}, {"componentType", kUByte}}},
                                            {"values", {{"bufferView", before + 1}}}}}});
  const int indices = int(g.doc["accessors"].size()) - 1;
  g.Mesh({{"POSITION", pos}}, indices);
  g.doc["meshes"][0]["name"] = "quad";
  g.Node({{"mesh", 0}});
  g.Scene({0});
  ExpectThrowsWith(g.Write(dir, "sparse_indices"), "accessor[" + std::to_string(indices) + "] invalid bufferView (the indices of mesh 0 'quad' primitive 0: glTF allows");
}

TEST(GltfLoader, LinesAndUnsupportedFeaturesAreWarnings) {
  const auto dir = TempDir();
  TestGltf g;
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
  EXPECT_EQ(s.cameras.size(), 1u) << "cameras are loaded (scenes/scene_cameras.h), not warned about";
  EXPECT_FALSE(HasWarning(s, "camera"));
  EXPECT_TRUE(HasWarning(s, "vertex attribute COLOR_1"));
  GltfLoadOptions strict;
  strict.warnings_are_errors = true;
  EXPECT_THROW(LoadGltf(dir / "lines.gltf", strict), std::runtime_error);
}

TEST(GltfLoader, VertexColoursAreReadAsLinearRgba) {
  const auto dir = TempDir();
  TestGltf g;
  const int pos = g.Positions({0, 0, 0, 1, 0, 0, 0, 1, 0});
  // VEC3 float (alpha 1) on one mesh, VEC4 normalized unsigned byte on the other.
  const int rgb = g.Accessor(std::vector<float>{1, 0, 0, 0, 0.5f, 0, 0, 0, 2}, kFloat, "VEC3", 3);
  const int rgba = g.Accessor(std::vector<uint8_t>{255, 0, 0, 255, 0, 51, 0, 102, 0, 0, 255, 0}, kUByte, "VEC4", 3, true);
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

  TestGltf bad;
  const int bad_pos = bad.Positions({0, 0, 0, 1, 0, 0, 0, 1, 0});
  const int not_normalized = bad.Accessor(std::vector<uint8_t>{255, 0, 0, 0, 255, 0, 0, 0, 255, 0, 0, 0}, kUByte, "VEC3", 3);
  const int too_few = bad.Accessor(std::vector<float>{1, 1, 1, 1, 1, 1}, kFloat, "VEC3", 2);
  const int scalar = bad.Accessor(std::vector<float>{1, 1, 1}, kFloat, "SCALAR", 3);
  bad.Node({{"mesh", bad.Mesh({{"POSITION", bad_pos}, {"COLOR_0", not_normalized}})}});
  bad.Scene({0});
  ExpectThrowsWith(bad.Write(dir, "not_normalized"),
                   "COLOR_0): componentType must be FLOAT, or normalized UNSIGNED_BYTE or UNSIGNED_SHORT");
  bad.doc["meshes"][0]["primitives"][0]["attributes"]["COLOR_0"] = too_few;
  ExpectThrowsWith(bad.Write(dir, "too_few"), "COLOR_0): count differs from POSITION");
  bad.doc["meshes"][0]["primitives"][0]["attributes"]["COLOR_0"] = scalar;
  ExpectThrowsWith(bad.Write(dir, "scalar"), "COLOR_0): type must be VEC3 or VEC4");
}

TEST(GltfLoader, TruncatedGlbThrowsWithFileName) {
  const auto dir = TempDir();
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
  ExpectThrowsWith(bad, "glb");
  ExpectThrowsWith(dir / "does_not_exist.glb", "cannot open");
}

// glTF 2.0, "Asset": a client refuses a file whose minVersion it does not support (rigsim: 2.0),
// else one whose major version is not 2; a later 2.x minor version loads.
TEST(GltfLoader, FilesForAnotherGltfVersionAreRefused) {
  const auto dir = TempDir();
  TestGltf g;
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
      ExpectThrowsWith(g.Write(dir, name), error);
      ExpectThrowsWith(g.WriteGlb(dir, name), error);
    } else {
      EXPECT_EQ(LoadGltf(g.WriteGlb(dir, name)).meshes.size(), 1u) << name;
    }
  }
}

// A file that requires an extension rigsim lacks is refused naming it, even when tinygltf would
// stumble first on what the extension changes (here an index accessor without a bufferView, which
// tinygltf refuses).
TEST(GltfLoader, UnsupportedExtensionsAreNamedWhenTheFileIsRefused) {
  const auto dir = TempDir();
  TestGltf g;
  const int pos = g.Positions({0, 0, 0, 1, 0, 0, 0, 1, 0});
  g.doc["accessors"].push_back({{"componentType", kUShort}, {"count", 3}, {"type", "SCALAR"}});  // no bufferView
  g.Mesh({{"POSITION", pos}}, 1);
  g.Node({{"mesh", 0}});
  g.Scene({0});
  g.doc["extensionsUsed"] = {"EXT_future_compression"};
  g.doc["extensionsRequired"] = {"EXT_future_compression"};
  ExpectThrowsWith(g.Write(dir, "future"), "requires extension EXT_future_compression, which rigsim does not support");
  ExpectThrowsWith(g.WriteGlb(dir, "future"), "requires extension EXT_future_compression, which rigsim does not support");
  g.doc.erase("extensionsRequired");
  ExpectThrowsWith(g.Write(dir, "future_used"), "(the file also uses EXT_future_compression, which rigsim does not read)");
}

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
TestGltf DracoGltf(const DracoGrid& grid, int n, int index_type) {
  TestGltf g;
  g.bin = grid.bytes;
  g.doc["bufferViews"].push_back({{"buffer", 0}, {"byteOffset", 0}, {"byteLength", grid.bytes.size()}});
  const size_t points = size_t(n) * n;
  g.doc["accessors"] = json::array({{{"componentType", index_type}, {"count", 6 * (n - 1) * (n - 1)}, {"type", "SCALAR"}},
                                    {{"componentType", kFloat}, {"count", points}, {"type", "VEC3"}},
                                    {{"componentType", kFloat}, {"count", points}, {"type", "VEC2"}},
                                    {{"componentType", kUByte}, {"count", points}, {"type", "VEC4"}, {"normalized", true}}});
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
  const auto dir = TempDir();
  const int n = 5;
  for (const int method : {draco::MESH_SEQUENTIAL_ENCODING, draco::MESH_EDGEBREAKER_ENCODING}) {
    SCOPED_TRACE(method == draco::MESH_SEQUENTIAL_ENCODING ? "sequential" : "edgebreaker");
    TestGltf g = DracoGltf(EncodeDracoGrid(n, method, 0), n, kUShort);
    for (const auto& path : {g.Write(dir, "grid"), g.Write(dir, "grid_uri", true), g.WriteGlb(dir, "grid")}) {
      SCOPED_TRACE(path.filename().string());
      const Scene scene = LoadGltf(path);
      ExpectTheDracoGrid(scene, n, 0.0f);
      for (const std::string& w : scene.warnings) EXPECT_EQ(w.find("draco"), std::string::npos) << w;
    }
  }
  // Quantised positions come back within half a quantisation step of the 2 m range.
  const int bits = 10;
  TestGltf q = DracoGltf(EncodeDracoGrid(n, draco::MESH_EDGEBREAKER_ENCODING, bits), n, kUInt);
  ExpectTheDracoGrid(LoadGltf(q.Write(dir, "quantised")), n, 2.0f / ((1 << bits) - 1));
}

TEST(GltfLoader, MalformedDracoPrimitivesAreRefusedNamingThePrimitive) {
  const auto dir = TempDir();
  const int n = 3;
  const DracoGrid grid = EncodeDracoGrid(n, draco::MESH_EDGEBREAKER_ENCODING, 0);
  const std::string where = "mesh 0 primitive 0: KHR_draco_mesh_compression: ";
  {
    TestGltf g = DracoGltf(grid, n, kUShort);
    g.doc["meshes"][0]["primitives"][0]["extensions"]["KHR_draco_mesh_compression"]["bufferView"] = 4;
    ExpectThrowsWith(g.Write(dir, "view"), where + "bufferView is missing or not one of the file's 1 buffer views");
    ExpectThrowsWith(g.WriteGlb(dir, "view"), where + "bufferView is missing or not one of the file's 1 buffer views");
  }
  {
    TestGltf g = DracoGltf(grid, n, kUShort);
    std::fill(g.bin.begin() + 4, g.bin.end(), uint8_t(0x5a));  // "DRAC" kept, the rest garbage
    ExpectThrowsWith(g.Write(dir, "garbage"), where + "the Draco data in bufferView 0 does not decode");
  }
  {
    TestGltf g = DracoGltf(grid, n, kUShort);
    g.doc["meshes"][0]["primitives"][0]["extensions"]["KHR_draco_mesh_compression"]["attributes"]["TEXCOORD_0"] = 9;
    ExpectThrowsWith(g.Write(dir, "id"), where + "attribute TEXCOORD_0: the Draco data has no attribute with id 9");
  }
  {
    TestGltf g = DracoGltf(grid, n, kUShort);
    g.doc["accessors"][2]["type"] = "VEC3";
    ExpectThrowsWith(g.Write(dir, "components"), where + "attribute TEXCOORD_0: the Draco attribute has 2 components, its accessor 3");
  }
  {
    const int big = 17;  // 289 vertices: more than unsigned bytes can index
    TestGltf g = DracoGltf(EncodeDracoGrid(big, draco::MESH_SEQUENTIAL_ENCODING, 0), big, kUByte);
    ExpectThrowsWith(g.Write(dir, "bytes"), where + "289 vertices cannot be indexed by the indices accessor's unsigned bytes");
  }
  {
    // tinygltf reads a rewritten version from memory, and still finds external files beside the file.
    TestGltf g = DracoGltf(grid, n, kUShort);
    const auto path = g.Write(dir, "missing");
    std::filesystem::remove(dir / "missing.bin");
    ExpectThrowsWith(path, "File not found : missing.bin");
  }
}

// EXT_meshopt_compression as gltfpack writes it: buffer 0 holds the compressed streams and buffer
// 1 is the fallback without data, in which the buffer views lie. An n x n grid: positions (float,
// ATTRIBUTES), tilted normals (normalized bytes under KHR_mesh_quantization, OCTAHEDRAL filter),
// its triangles (TRIANGLES) for primitive 0 and the same as an index sequence (INDICES) for 1.
struct MeshoptGrid {
  TestGltf g;
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
  TestGltf& g = out.g;
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
  g.doc["accessors"] = json::array({{{"bufferView", 0}, {"componentType", kFloat}, {"count", count}, {"type", "VEC3"}},
                                    {{"bufferView", 1}, {"componentType", 5120}, {"count", count}, {"type", "VEC3"}, {"normalized", true}},
                                    {{"bufferView", 2}, {"componentType", kUShort}, {"count", tri}, {"type", "SCALAR"}},
                                    {{"bufferView", 3}, {"componentType", kUShort}, {"count", tri}, {"type", "SCALAR"}}});
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
  const auto dir = TempDir();
  MeshoptGrid grid = MeshoptGltf(4);
  for (const auto& path : {grid.g.Write(dir, "grid"), grid.g.Write(dir, "grid_uri", true), grid.g.WriteGlb(dir, "grid")}) {
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
  const auto dir = TempDir();
  auto extension = [](TestGltf& g, int view) -> json& { return g.doc["bufferViews"][view]["extensions"]["EXT_meshopt_compression"]; };
  const std::string where = ": EXT_meshopt_compression: ";
  {
    MeshoptGrid grid = MeshoptGltf(3);
    extension(grid.g, 2)["mode"] = "LINES";
    ExpectThrowsWith(grid.g.Write(dir, "mode"), "bufferView 2" + where + "mode 'LINES' is none of ATTRIBUTES, TRIANGLES, INDICES");
  }
  {
    MeshoptGrid grid = MeshoptGltf(3);
    extension(grid.g, 0)["byteLength"] = grid.g.bin.size() + 1;
    ExpectThrowsWith(grid.g.Write(dir, "range"), "bufferView 0" + where + "bytes 0 + " + std::to_string(grid.g.bin.size() + 1) +
                                                     " lie beyond buffer 0's " + std::to_string(grid.g.bin.size()));
  }
  {
    MeshoptGrid grid = MeshoptGltf(3);
    const size_t length = extension(grid.g, 0)["byteLength"].get<size_t>();
    std::fill_n(grid.g.bin.begin(), length, uint8_t(0xff));
    ExpectThrowsWith(grid.g.Write(dir, "garbage"), "bufferView 0" + where + "the compressed bytes do not decode");
  }
  {
    MeshoptGrid grid = MeshoptGltf(3);
    extension(grid.g, 0)["count"] = 10;  // 10 x 12 bytes in a view of 9 x 12
    ExpectThrowsWith(grid.g.Write(dir, "count"), "bufferView 0" + where + "10 elements of 12 bytes do not fit the view's 108 bytes");
  }
  {
    MeshoptGrid grid = MeshoptGltf(3);
    extension(grid.g, 1)["filter"] = "QUATERNION";
    ExpectThrowsWith(grid.g.Write(dir, "filter"), "bufferView 1" + where + "QUATERNION needs a byteStride of 8");
  }
  {
    MeshoptGrid grid = MeshoptGltf(3);
    grid.g.extra_buffers[0]["byteLength"] = 1u << 30;
    GltfLoadOptions small;
    small.max_accessor_count = 1000;
    ExpectThrowsWithOptions(grid.g.Write(dir, "huge"), small, "exceed the limit of 16000 decoded bytes");
  }
}

// Without extensionsRequired the fallback buffer may hold the data itself: it is read as it is.
TEST(GltfLoader, MeshoptViewsOverABufferWithItsDataReadThatData) {
  const auto dir = TempDir();
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


// A buffer's data URI that does not hold byteLength bytes: the message says so and quotes the
// URI's start only (tinygltf quotes it whole, megabytes for a real buffer).
TEST(GltfLoader, ABufferOfTheWrongLengthIsNamedBriefly) {
  const auto dir = TempDir();
  TestGltf g;
  g.Mesh({{"POSITION", g.Positions(std::vector<float>(3000, 0.0f))}});
  g.Node({{"mesh", 0}});
  g.Scene({0});
  const auto path = g.Write(dir, "short", /*data_uri=*/true);
  json doc = json::parse(std::ifstream(path));
  doc["buffers"][0]["byteLength"] = 12004;  // 4 bytes more than the data
  std::ofstream(path) << doc.dump();
  try {
    LoadGltf(path);
    ADD_FAILURE() << "no exception";
  } catch (const std::runtime_error& e) {
    const std::string msg = e.what();
    EXPECT_LT(msg.size(), 400u) << msg;
    EXPECT_NE(msg.find("data:application/octet-stream;base64,"), std::string::npos) << msg;
    EXPECT_NE(msg.find("... (16000 characters)"), std::string::npos) << msg;
    EXPECT_NE(msg.find("does not decode to the buffer's byteLength"), std::string::npos) << msg;
  }
}

TEST(GltfLoader, AccessorOutOfRangeThrows) {
  const auto dir = TempDir();
  TestGltf g;
  const int pos = g.Positions({0, 0, 0, 1, 0, 0, 0, 1, 0});
  g.doc["accessors"][pos]["count"] = 4;  // one vertex more than the bufferView holds
  g.Mesh({{"POSITION", pos}});
  g.Node({{"mesh", 0}});
  g.Scene({0});
  ExpectThrowsWith(g.Write(dir, "range"), "accessor 0 (mesh 0 primitive 0 POSITION): byteOffset 0 + 4 elements");

  TestGltf h;  // an index that points past the vertices
  h.Mesh({{"POSITION", h.Positions({0, 0, 0, 1, 0, 0, 0, 1, 0})}}, h.Accessor<uint8_t>({0, 1, 3, 0}, kUByte, "SCALAR", 3));
  h.Node({{"mesh", 0}});
  h.Scene({0});
  ExpectThrowsWith(h.Write(dir, "index"), "index 3 at position 2 is >= vertex count 3");

  TestGltf k;  // an absurd count is rejected before anything is allocated
  const int big = k.Positions({0, 0, 0, 1, 0, 0, 0, 1, 0});
  k.doc["accessors"][big]["count"] = 4000000000ull;
  k.Mesh({{"POSITION", big}});
  k.Node({{"mesh", 0}});
  k.Scene({0});
  ExpectThrowsWith(k.Write(dir, "absurd"), "exceeds the limit");
}

TEST(GltfLoader, RecursiveNodesThrow) {
  const auto dir = TempDir();
  TestGltf g;
  g.Mesh({{"POSITION", g.Positions({0, 0, 0, 1, 0, 0, 0, 1, 0})}});
  g.Node({{"mesh", 0}, {"children", {1}}});
  g.Node({{"children", {0}}});  // cycle back to the root
  g.Scene({0});
  ExpectThrowsWith(g.Write(dir, "cycle"), "reached twice");
}

TEST(GltfLoader, NonFiniteVertexThrows) {
  const auto dir = TempDir();
  TestGltf g;
  g.Mesh({{"POSITION", g.Positions({0, 0, 0, std::numeric_limits<float>::quiet_NaN(), 0, 0, 0, 1, 0})}});
  g.Node({{"mesh", 0}});
  g.Scene({0});
  ExpectThrowsWith(g.Write(dir, "nan"), "vertex 1 is not finite");
}

TEST(GltfLoader, NodeAnimationsAreKeptForPosing) {
  const auto dir = TempDir();
  TestGltf g;
  const int pos = g.Positions(kQuad);
  const int idx = g.Accessor(std::vector<uint16_t>{0, 1, 2, 0, 2, 3}, kUShort, "SCALAR", 6);
  g.Mesh({{"POSITION", pos}}, idx);
  // Parent (animated, translation) -> child with the mesh; a static mesh node beside them.
  g.Node({{"name", "parent"}, {"children", {1}}, {"translation", {0, 0, -5}}});
  g.Node({{"name", "child"}, {"mesh", 0}, {"translation", {1, 0, 0}}});
  g.Node({{"name", "static"}, {"mesh", 0}});
  g.Scene({0, 2});
  const int times = g.Accessor(std::vector<float>{0, 1, 2}, kFloat, "SCALAR", 3);
  const int moves = g.Accessor(std::vector<float>{0, 0, -5, 2, 0, -5, 2, 1, -5}, kFloat, "VEC3", 3);
  const int turns = g.Accessor(std::vector<float>{0, 0, 0, 1, 0, 0.7071068f, 0, 0.7071068f}, kFloat, "VEC4", 2);
  const int two = g.Accessor(std::vector<float>{0, 1}, kFloat, "SCALAR", 2);
  g.doc["animations"] = json::array({{{"name", "drive"},
                                      {"samplers", {{{"input", times}, {"output", moves}, {"interpolation", "LINEAR"}},
                                                    {{"input", two}, {"output", turns}, {"interpolation", "STEP"}}}},
                                      {"channels", {{{"sampler", 0}, {"target", {{"node", 0}, {"path", "translation"}}}},
                                                    {{"sampler", 1}, {"target", {{"node", 1}, {"path", "rotation"}}}}}}}});
  const Scene s = LoadGltf(g.Write(dir, "animated"));
  ASSERT_TRUE(s.IsAnimated());
  ASSERT_EQ(s.animation_channels.size(), 2u);
  ASSERT_EQ(s.nodes.size(), 3u);
  EXPECT_EQ(s.nodes[1].parent, 0);
  EXPECT_EQ(s.nodes[0].parent, -1);
  EXPECT_TRUE(s.nodes[0].translation.isApprox(Eigen::Vector3d(0, 0, -5)));
  const AnimationChannel& move = s.animation_channels[0];
  EXPECT_EQ(move.node, 0);
  EXPECT_EQ(move.path, AnimationPath::kTranslation);
  EXPECT_EQ(move.interpolation, AnimationInterpolation::kLinear);
  ASSERT_EQ(move.times_s.size(), 3u);
  EXPECT_DOUBLE_EQ(move.times_s[2], 2.0);
  EXPECT_TRUE(move.values[1].head<3>().isApprox(Eigen::Vector3d(2, 0, -5)));
  EXPECT_EQ(s.animation_channels[1].path, AnimationPath::kRotation);
  EXPECT_EQ(s.animation_channels[1].interpolation, AnimationInterpolation::kStep);
  EXPECT_NEAR(s.animation_channels[1].values[1][3], 0.7071068, 1e-6);  // (x, y, z, w)
  // The animated mesh keeps its node and node-frame vertices; positions are at the rest pose.
  ASSERT_EQ(s.meshes.size(), 2u);
  EXPECT_EQ(s.meshes[0].node, 1);
  ASSERT_EQ(s.meshes[0].local_positions.size(), 4u);
  EXPECT_TRUE(s.meshes[0].local_positions[1].isApprox(Eigen::Vector3f(1, 0, 0)));
  EXPECT_TRUE(s.meshes[0].positions[1].isApprox(Eigen::Vector3f(2, 0, -5)));
  EXPECT_EQ(s.meshes[1].node, -1);
  EXPECT_TRUE(s.meshes[1].local_positions.empty());
  EXPECT_FALSE(HasWarning(s, "animation"));
}

TEST(GltfLoader, BadAnimationsThrowOrWarn) {
  const auto dir = TempDir();
  TestGltf g;
  g.Mesh({{"POSITION", g.Positions(kQuad)}});
  g.Node({{"mesh", 0}});
  g.Scene({0});
  const int times = g.Accessor(std::vector<float>{0, 1}, kFloat, "SCALAR", 2);
  const int moves = g.Accessor(std::vector<float>{0, 0, 0, 1, 0, 0}, kFloat, "VEC3", 2);
  const int cubic = g.Accessor(std::vector<float>(18, 0.0f), kFloat, "VEC3", 6);
  g.doc["animations"] = json::array({{{"samplers", {{{"input", times}, {"output", cubic}, {"interpolation", "CUBICSPLINE"}}}},
                                      {"channels", {{{"sampler", 0}, {"target", {{"node", 0}, {"path", "translation"}}}}}}}});
  const Scene s = LoadGltf(g.Write(dir, "cubic"));
  EXPECT_EQ(s.animation_channels.size(), 1u);
  EXPECT_TRUE(HasWarning(s, "CUBICSPLINE"));
  // Keys out of order.
  const int backwards = g.Accessor(std::vector<float>{1, 0}, kFloat, "SCALAR", 2);
  g.doc["animations"][0]["samplers"][0] = {{"input", backwards}, {"output", moves}};
  ExpectThrowsWith(g.Write(dir, "backwards"), "strictly increasing");
  // Output count mismatch.
  g.doc["animations"][0]["samplers"][0] = {{"input", times}, {"output", cubic}};
  ExpectThrowsWith(g.Write(dir, "count"), "output values for 2 keyframes");
}

// glTF allows a channel without a target node: an extension (KHR_animation_pointer) names what it
// animates. Such channels are ignored with a warning, in .gltf and .glb files alike; the file's
// other channels still animate their nodes.
TEST(GltfLoader, ChannelsWithoutATargetNodeAreIgnored) {
  const auto dir = TempDir();
  TestGltf g;
  g.Mesh({{"POSITION", g.Positions(kQuad)}});
  g.Node({{"mesh", 0}});
  g.Scene({0});
  const int times = g.Accessor(std::vector<float>{0, 1}, kFloat, "SCALAR", 2);
  const int moves = g.Accessor(std::vector<float>{0, 0, 0, 1, 0, 0}, kFloat, "VEC3", 2);
  const int fades = g.Accessor(std::vector<float>{1, 0}, kFloat, "SCALAR", 2);
  const json pointer = {{"path", "pointer"},
                        {"extensions", {{"KHR_animation_pointer", {{"pointer", "/materials/0/alphaCutoff"}}}}}};
  g.doc["extensionsUsed"] = {"KHR_animation_pointer"};
  g.doc["animations"] = json::array(
      {{{"name", "move and fade"},
        {"samplers", {{{"input", times}, {"output", moves}}, {{"input", times}, {"output", fades}}}},
        {"channels", {{{"sampler", 1}, {"target", pointer}}, {{"sampler", 0}, {"target", {{"node", 0}, {"path", "translation"}}}}}}},
       {{"name", "fade only"}, {"samplers", {{{"input", times}, {"output", fades}}}}, {"channels", {{{"sampler", 0}, {"target", pointer}}}}}});
  for (const auto& path : {g.Write(dir, "pointer"), g.WriteGlb(dir, "pointer")}) {
    SCOPED_TRACE(path.string());
    const Scene s = LoadGltf(path);
    ASSERT_EQ(s.animation_channels.size(), 1u);
    EXPECT_EQ(s.animation_channels[0].node, 0);
    EXPECT_EQ(s.animation_channels[0].path, AnimationPath::kTranslation);
    EXPECT_TRUE(s.animation_channels[0].values[1].head<3>().isApprox(Eigen::Vector3d(1, 0, 0)));
    EXPECT_TRUE(HasWarning(s, "2 animation channel(s) without a target node ignored"));
    EXPECT_TRUE(HasWarning(s, "KHR_animation_pointer"));
    EXPECT_EQ(s.meshes.size(), 1u);
  }
  // A file that is broken otherwise still fails with tinygltf's message.
  g.doc["animations"][0]["channels"][1]["target"].erase("path");
  ExpectThrowsWith(g.Write(dir, "no_path"), "`path` field is missing");
}

// kQuad (indexed as a fan) with two morph targets: target 0 lifts vertex i by 2 (i + 1) in z and
// tips the normals (0, 0, 1) towards +x by 1; target 1, quantized (normalized BYTE, as
// KHR_mesh_quantization allows), moves every vertex by 1 in y.
int MorphedQuadMesh(TestGltf& g, json weights = nullptr) {
  constexpr int kByte = 5120;
  const int pos = g.Positions(kQuad);
  const int nrm = g.Accessor(std::vector<float>{0, 0, 1, 0, 0, 1, 0, 0, 1, 0, 0, 1}, kFloat, "VEC3", 4);
  const int lift = g.Positions({0, 0, 2, 0, 0, 4, 0, 0, 6, 0, 0, 8});
  const int tip = g.Accessor(std::vector<float>{1, 0, 0, 1, 0, 0, 1, 0, 0, 1, 0, 0}, kFloat, "VEC3", 4);
  const int shift = g.Accessor(std::vector<int8_t>{0, 127, 0, 0, 127, 0, 0, 127, 0, 0, 127, 0}, kByte, "VEC3", 4, /*normalized=*/true);
  const int mesh = g.Mesh({{"POSITION", pos}, {"NORMAL", nrm}}, -1, /*TRIANGLE_FAN=*/6);
  g.doc["meshes"][mesh]["primitives"][0]["targets"] = {{{"POSITION", lift}, {"NORMAL", tip}}, {{"POSITION", shift}}};
  if (!weights.is_null()) g.doc["meshes"][mesh]["weights"] = weights;
  return mesh;
}

// Static morphs are applied at load with the rest weights: node.weights, else mesh.weights, else 0.
TEST(GltfLoader, MorphTargetsAreAppliedAtTheRestWeights) {
  const auto dir = TempDir();
  TestGltf g;
  const int mesh = MorphedQuadMesh(g, {0.5, 0.0});
  g.Node({{"mesh", mesh}, {"translation", {10, 0, 0}}});     // mesh.weights (0.5, 0)
  g.Node({{"mesh", mesh}, {"weights", {1.0, 0.0}}});          // node.weights override them
  g.Node({{"mesh", mesh}, {"weights", {0.0, 1.0}}});          // the quantized target alone
  g.Scene({0, 1, 2});
  const Scene s = LoadGltf(g.Write(dir, "morphed"));
  ASSERT_EQ(s.meshes.size(), 3u);
  for (int i = 0; i < 4; ++i) {
    const Eigen::Vector3f base(kQuad[3 * i], kQuad[3 * i + 1], kQuad[3 * i + 2]);
    EXPECT_TRUE(s.meshes[0].positions[i].isApprox(base + Eigen::Vector3f(10, 0, i + 1))) << i << ": " << s.meshes[0].positions[i].transpose();
    EXPECT_TRUE(s.meshes[1].positions[i].isApprox(base + Eigen::Vector3f(0, 0, 2 * (i + 1)))) << i << ": " << s.meshes[1].positions[i].transpose();
    EXPECT_TRUE(s.meshes[2].positions[i].isApprox(base + Eigen::Vector3f(0, 1, 0))) << i << ": " << s.meshes[2].positions[i].transpose();
  }
  ASSERT_EQ(s.meshes[0].normals.size(), 4u);
  EXPECT_TRUE(s.meshes[0].normals[0].isApprox(Eigen::Vector3f(0.5f, 0, 1).normalized())) << s.meshes[0].normals[0].transpose();
  EXPECT_TRUE(s.meshes[1].normals[3].isApprox(Eigen::Vector3f(1, 0, 1).normalized())) << s.meshes[1].normals[3].transpose();
  EXPECT_TRUE(s.meshes[2].normals[3].isApprox(Eigen::Vector3f(0, 0, 1)));
  // Static meshes carry no copy of the targets.
  EXPECT_EQ(s.meshes[0].num_morph_targets, 2);
  EXPECT_TRUE(s.meshes[0].morph_targets.empty());
  EXPECT_TRUE(s.meshes[0].morph_base_positions.empty());
  EXPECT_EQ(s.meshes[0].node, -1);
  EXPECT_FALSE(HasWarning(s, "morph"));
  EXPECT_FALSE(s.IsAnimated());
}

// glTF 2.0 "Skins": morphing comes first, in the mesh's frame. The joint scales by 2, so skinning
// before morphing would lift the quad by 1 instead of 2.
TEST(GltfLoader, MorphingComesBeforeSkinning) {
  const auto dir = TempDir();
  TestGltf g;
  const int mesh = MorphedQuadMesh(g, {0.0, 1.0});
  g.doc["meshes"][mesh]["primitives"][0]["attributes"]["JOINTS_0"] = g.Accessor<uint8_t>(std::vector<uint8_t>(16, 0), kUByte, "VEC4", 4);
  g.doc["meshes"][mesh]["primitives"][0]["attributes"]["WEIGHTS_0"] =
      g.Accessor<float>({1, 0, 0, 0, 1, 0, 0, 0, 1, 0, 0, 0, 1, 0, 0, 0}, kFloat, "VEC4", 4);
  const int ibm = g.Accessor(std::vector<float>{1, 0, 0, 0, 0, 1, 0, 0, 0, 0, 1, 0, 0, 0, 0, 1}, kFloat, "MAT4", 1);
  g.doc["skins"] = json::array({{{"joints", {1}}, {"inverseBindMatrices", ibm}}});
  g.Node({{"mesh", mesh}, {"skin", 0}});
  g.Node({{"scale", {2, 2, 2}}});
  g.Scene({0, 1});
  const Scene s = LoadGltf(g.Write(dir, "skinned_morph"));
  ASSERT_EQ(s.meshes.size(), 1u);
  for (int i = 0; i < 4; ++i) {
    const Eigen::Vector3f expected = 2 * (Eigen::Vector3f(kQuad[3 * i], kQuad[3 * i + 1], kQuad[3 * i + 2]) + Eigen::Vector3f(0, 1, 0));
    EXPECT_TRUE(s.meshes[0].positions[i].isApprox(expected)) << i << ": " << s.meshes[0].positions[i].transpose();
  }
}

TEST(GltfLoader, MalformedMorphTargetsThrow) {
  const auto dir = TempDir();
  TestGltf g;
  const int mesh = MorphedQuadMesh(g);
  g.Node({{"mesh", mesh}, {"name", "face"}});
  g.Scene({0});
  json& prim = g.doc["meshes"][mesh]["primitives"][0];
  const json good_targets = prim["targets"];
  EXPECT_FALSE(HasWarning(LoadGltf(g.Write(dir, "zero_weights")), "morph"));  // no weights: all 0
  g.doc["meshes"][mesh]["weights"] = {0.5};
  ExpectThrowsWith(g.Write(dir, "mesh_weights"), "mesh 0: 1 morph weights for 2 morph targets");
  g.doc["meshes"][mesh].erase("weights");
  g.doc["nodes"][0]["weights"] = {0.5, 0.5, 0.5};
  ExpectThrowsWith(g.Write(dir, "node_weights"), "node 0 'face': 3 morph weights for 2 morph targets");
  g.doc["nodes"][0].erase("weights");
  TestGltf plain;  // weights on a mesh without targets: nothing to morph, so a warning
  plain.Mesh({{"POSITION", plain.Positions(kQuad)}});
  plain.doc["meshes"][0]["weights"] = {0.5};
  plain.Node({{"mesh", 0}});
  plain.Scene({0});
  EXPECT_TRUE(HasWarning(LoadGltf(plain.Write(dir, "no_targets")), "mesh 0: 1 morph weights but no morph targets"));
  prim["targets"][0]["POSITION"] = g.Positions({0, 0, 1, 0, 0, 1, 0, 0, 1});
  ExpectThrowsWith(g.Write(dir, "count"), "(mesh 0 primitive 0 target 0 POSITION): count 3 differs from POSITION's 4");
  prim["targets"][0]["POSITION"] = g.Accessor(std::vector<float>(8, 0.0f), kFloat, "VEC2", 4);
  ExpectThrowsWith(g.Write(dir, "type"), "(mesh 0 primitive 0 target 0 POSITION): unexpected type");
  prim["targets"][0]["POSITION"] = g.Accessor(std::vector<uint32_t>(12, 0), kUInt, "VEC3", 4);
  ExpectThrowsWith(g.Write(dir, "component"), "target 0 POSITION): componentType must be FLOAT, BYTE or SHORT");
  prim["targets"][0]["POSITION"] = g.Positions({0, 0, 0, 0, std::numeric_limits<float>::infinity(), 0, 0, 0, 0, 0, 0, 0});
  ExpectThrowsWith(g.Write(dir, "infinite"), "target 0 POSITION): vertex 1 is not finite");
  prim["targets"] = good_targets;
  g.doc["meshes"][mesh]["primitives"].push_back(prim);
  g.doc["meshes"][mesh]["primitives"][1]["targets"].erase(1);
  ExpectThrowsWith(g.Write(dir, "primitives_differ"), "mesh 0 primitive 1: 1 morph targets, primitive 0 has 2");
}

// A "weights" channel keeps one weight per target per key, and the mesh on its node keeps its base
// vertices and targets for PoseSceneAt; another instance of the same mesh stays static.
TEST(GltfLoader, MorphWeightAnimationsAreKeptForPosing) {
  const auto dir = TempDir();
  TestGltf g;
  const int mesh = MorphedQuadMesh(g, {0.5, 0.0});
  g.Node({{"mesh", mesh}, {"children", {1}}});
  g.Node({{"mesh", mesh}, {"translation", {0, 0, 5}}});
  g.Scene({0});
  const int times = g.Accessor(std::vector<float>{0, 1}, kFloat, "SCALAR", 2);
  const int weights = g.Accessor(std::vector<float>{0, 0, 1, 0.5f}, kFloat, "SCALAR", 4);
  g.doc["animations"] = json::array({{{"samplers", {{{"input", times}, {"output", weights}, {"interpolation", "STEP"}}}},
                                      {"channels", {{{"sampler", 0}, {"target", {{"node", 0}, {"path", "weights"}}}}}}}});
  const Scene s = LoadGltf(g.Write(dir, "morph_animated"));
  ASSERT_TRUE(s.IsAnimated());
  ASSERT_EQ(s.animation_channels.size(), 1u);
  const AnimationChannel& ch = s.animation_channels[0];
  EXPECT_EQ(ch.node, 0);
  EXPECT_EQ(ch.path, AnimationPath::kWeights);
  EXPECT_EQ(ch.interpolation, AnimationInterpolation::kStep);
  EXPECT_TRUE(ch.values.empty());
  ASSERT_EQ(ch.weights.size(), 2u);
  EXPECT_TRUE(ch.weights[0].isApprox(Eigen::Vector2d(0, 0)) && ch.weights[0].size() == 2) << ch.weights[0].transpose();
  EXPECT_TRUE(ch.weights[1].isApprox(Eigen::Vector2d(1, 0.5))) << ch.weights[1].transpose();
  ASSERT_EQ(s.meshes.size(), 2u);
  const SceneMesh& animated = s.meshes[0];
  EXPECT_EQ(animated.node, 0);
  ASSERT_EQ(animated.morph_targets.size(), 2u);
  ASSERT_EQ(animated.morph_base_positions.size(), 4u);
  EXPECT_TRUE(animated.morph_base_positions[2].isApprox(Eigen::Vector3f(1, 1, 0)));
  EXPECT_EQ(animated.morph_base_normals.size(), 4u);
  EXPECT_TRUE(animated.morph_targets[0].positions[2].isApprox(Eigen::Vector3f(0, 0, 6)));
  EXPECT_TRUE(animated.morph_targets[1].normals.empty());
  EXPECT_TRUE(animated.local_positions[2].isApprox(Eigen::Vector3f(1, 1, 3))) << "morphed at rest (mesh.weights)";
  EXPECT_TRUE(animated.positions[2].isApprox(Eigen::Vector3f(1, 1, 3)));
  // The child's node does not move: its mesh is static, without the targets.
  EXPECT_EQ(s.meshes[1].node, -1);
  EXPECT_TRUE(s.meshes[1].morph_targets.empty());
  EXPECT_TRUE(s.meshes[1].positions[2].isApprox(Eigen::Vector3f(1, 1, 8)));
  EXPECT_FALSE(HasWarning(s, "weights"));

  // CUBICSPLINE: the key values (the middle of each in-tangent, value, out-tangent triple), warned.
  const int cubic = g.Accessor(std::vector<float>{9, 9, 0, 0, 9, 9, 9, 9, 1, 0.5f, 9, 9}, kFloat, "SCALAR", 12);
  g.doc["animations"][0]["samplers"][0] = {{"input", times}, {"output", cubic}, {"interpolation", "CUBICSPLINE"}};
  const Scene c = LoadGltf(g.Write(dir, "cubic"));
  ASSERT_EQ(c.animation_channels.size(), 1u);
  EXPECT_TRUE(c.animation_channels[0].weights[1].isApprox(Eigen::Vector2d(1, 0.5))) << c.animation_channels[0].weights[1].transpose();
  EXPECT_TRUE(HasWarning(c, "CUBICSPLINE"));
  // One weight per key is too few for two targets.
  g.doc["animations"][0]["samplers"][0] = {{"input", times}, {"output", times}};
  ExpectThrowsWith(g.Write(dir, "short"), "2 output values for 2 keyframes of 2 morph target weights");
  // A node without morph targets: the channel is ignored with a warning.
  g.doc["animations"][0]["samplers"][0] = {{"input", times}, {"output", weights}};
  g.doc["nodes"].push_back({{"name", "empty"}});
  g.doc["animations"][0]["channels"][0]["target"]["node"] = 2;
  const Scene ignored = LoadGltf(g.Write(dir, "no_targets"));
  EXPECT_TRUE(ignored.animation_channels.empty());
  EXPECT_TRUE(HasWarning(ignored, "whose mesh has no morph targets; ignored"));
}

// EXT_mesh_gpu_instancing: a quad (with a tilted normal) on node 0 "forest" at translation (10, 0,
// 0), drawn by three instances: identity; T (0, 2, 0) R 90 deg about z S (2, 1, 1); T (0, 0, 3)
// S (-1, 1, 1), a mirror. ROTATION as float, or as normalized short when `short_rotation`.
TestGltf InstancedQuad(bool short_rotation) {
  constexpr int kShort = 5122;
  TestGltf g;
  g.doc["extensionsUsed"] = {"EXT_mesh_gpu_instancing"};
  g.doc["extensionsRequired"] = {"EXT_mesh_gpu_instancing"};
  const float n = std::sqrt(0.5f);
  const int pos = g.Positions(kQuad);
  const int nrm = g.Accessor<float>({n, 0, n, n, 0, n, n, 0, n, n, 0, n}, kFloat, "VEC3", 4);
  g.doc["materials"] = json::array({{{"name", "bark"}}});
  g.Mesh({{"POSITION", pos}, {"NORMAL", nrm}}, g.Accessor<uint8_t>({0, 1, 2, 0, 2, 3}, kUByte, "SCALAR", 6), 4, 0, {{"class", "vegetation"}});
  const int t = g.Accessor<float>({0, 0, 0, 0, 2, 0, 0, 0, 3}, kFloat, "VEC3", 3);
  const int s = g.Accessor<float>({1, 1, 1, 2, 1, 1, -1, 1, 1}, kFloat, "VEC3", 3);
  const float h = std::sqrt(0.5f);
  const int r = short_rotation
                    ? g.Accessor<int16_t>({0, 0, 0, 32767, 0, 0, 23170, 23170, 0, 0, 0, 32767}, kShort, "VEC4", 3, /*normalized=*/true)
                    : g.Accessor<float>({0, 0, 0, 1, 0, 0, h, h, 0, 0, 0, 1}, kFloat, "VEC4", 3);
  g.Node({{"name", "forest"}, {"mesh", 0}, {"translation", {10, 0, 0}},
          {"extensions", {{"EXT_mesh_gpu_instancing", {{"attributes", {{"TRANSLATION", t}, {"ROTATION", r}, {"SCALE", s}}}}}}}});
  g.Scene({0});
  return g;
}

TEST(GltfLoader, GpuInstancesAreSeparateObjectsPlacedByNodeTimesInstance) {
  const auto dir = TempDir();
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
  const auto dir = TempDir();
  TestGltf g;
  g.Mesh({{"POSITION", g.Positions(kQuad)}}, g.Accessor<uint8_t>({0, 1, 2, 0, 2, 3}, kUByte, "SCALAR", 6));
  const int t = g.Accessor<float>({1, 0, 0}, kFloat, "VEC3", 1);
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
  const auto dir = TempDir();
  TestGltf g;
  g.doc["extensionsUsed"] = {"EXT_mesh_gpu_instancing"};
  g.Mesh({{"POSITION", g.Positions({0, 0, 0, 1, 0, 0, 0, 1, 0})}});
  const int t = g.Accessor<float>({0, 0, 0, 5, 0, 0}, kFloat, "VEC3", 2);
  const int id = g.Accessor<float>({7, 8}, kFloat, "SCALAR", 2);
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
  const auto dir = TempDir();
  constexpr int kUShortNormalized = 5123;
  TestGltf g = InstancedQuad(false);  // accessors: 0 POSITION, 1 NORMAL, 2 indices, 3 T, 4 S, 5 R
  json& attributes = g.doc["nodes"][0]["extensions"]["EXT_mesh_gpu_instancing"]["attributes"];
  const int two = g.Accessor<float>({0, 0, 0, 1, 1, 1}, kFloat, "VEC3", 2);
  attributes["SCALE"] = two;
  ExpectThrowsWith(g.Write(dir, "counts"), "accessor " + std::to_string(two) +
                                               " (node 0 'forest' EXT_mesh_gpu_instancing SCALE): count 2 differs from ROTATION's 3");
  attributes["SCALE"] = 4;
  attributes["TRANSLATION"] = 5;  // a VEC4
  ExpectThrowsWith(g.Write(dir, "type"), "accessor 5 (node 0 'forest' EXT_mesh_gpu_instancing TRANSLATION): type must be VEC3");
  attributes["TRANSLATION"] = 3;
  attributes["ROTATION"] = g.Accessor<uint16_t>({0, 0, 0, 65535, 0, 0, 0, 65535, 0, 0, 0, 65535}, kUShortNormalized, "VEC4", 3, true);
  ExpectThrowsWith(g.Write(dir, "component"), "EXT_mesh_gpu_instancing ROTATION): componentType must be FLOAT, or normalized BYTE or SHORT");
  attributes["ROTATION"] = g.Accessor<float>({0, 0, 0, 1, 0, 0, 0, 0, 0, 0, 0, 1}, kFloat, "VEC4", 3);
  ExpectThrowsWith(g.Write(dir, "zero_quaternion"), "ROTATION): instance 1 has a zero quaternion");
  attributes["ROTATION"] = 5;
  attributes["SCALE"] = g.Accessor<float>({1, 1, 1, 1, std::numeric_limits<float>::infinity(), 1, 1, 1, 1}, kFloat, "VEC3", 3);
  ExpectThrowsWith(g.Write(dir, "infinite"), "EXT_mesh_gpu_instancing SCALE): instance 1 is not finite");
  attributes.erase("ROTATION");
  attributes["SCALE"] = g.Accessor<float>({}, kFloat, "VEC3", 0);
  ExpectThrowsWith(g.Write(dir, "empty"), "EXT_mesh_gpu_instancing SCALE): count is 0");
  attributes["SCALE"] = 99;
  ExpectThrowsWith(g.Write(dir, "range"), "accessor 99 (node 0 'forest' EXT_mesh_gpu_instancing SCALE): index out of range");
  g.doc["nodes"][0]["extensions"]["EXT_mesh_gpu_instancing"] = json::object();
  ExpectThrowsWith(g.Write(dir, "no_attributes"), "node 0 'forest' EXT_mesh_gpu_instancing: has no attributes object");
}

// Instances copy geometry decoded once per node, and what they make in all is bounded: a file
// asking for more fails naming the limit. 100 instances of a quad (4 vertices + 6 indices) make
// 1000; decoded are 10 + 3 x 100 elements, 1300 had the quad been decoded again per instance.
TEST(GltfLoader, GpuInstancesAreDecodedOnceAndBoundedInTotal) {
  const auto dir = TempDir();
  TestGltf g;
  g.Mesh({{"POSITION", g.Positions(kQuad)}}, g.Accessor<uint8_t>({0, 1, 2, 0, 2, 3}, kUByte, "SCALAR", 6));
  std::vector<float> t, r, s;
  for (int i = 0; i < 100; ++i) {
    t.insert(t.end(), {float(i), 0, 0});
    r.insert(r.end(), {0, 0, 0, 1});
    s.insert(s.end(), {1, 1, 1});
  }
  const json attributes = {{"TRANSLATION", g.Accessor(t, kFloat, "VEC3", 100)}, {"ROTATION", g.Accessor(r, kFloat, "VEC4", 100)},
                           {"SCALE", g.Accessor(s, kFloat, "VEC3", 100)}};
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
  ExpectThrowsWithOptions(path, options,
                          "node 0 EXT_mesh_gpu_instancing: 100 instances of a mesh of 10 vertices and indices each exceed the limit "
                          "of 999 on all instanced geometry (GltfLoadOptions::max_accessor_count");
  // An absurd count is refused from the accessor's metadata, before anything is allocated.
  g.doc["accessors"][int(attributes["TRANSLATION"])]["count"] = 4000000000ull;
  g.doc["accessors"][int(attributes["ROTATION"])]["count"] = 4000000000ull;
  g.doc["accessors"][int(attributes["SCALE"])]["count"] = 4000000000ull;
  ExpectThrowsWith(g.Write(dir, "absurd"), "4000000000 instances of a mesh of 10 vertices and indices each exceed the limit of 67108864");
}

// Instance ids are uint16: past 65535 instances, further ones get 0 and one warning says so.
TEST(GltfLoader, GpuInstancesBeyond65535GetIdZeroWithOneWarning) {
  const auto dir = TempDir();
  TestGltf g;
  g.Mesh({{"POSITION", g.Positions({0, 0, 0, 1, 0, 0, 0, 1, 0})}});
  constexpr int kCount = 65540;
  std::vector<float> t(3 * kCount);
  for (int i = 0; i < kCount; ++i) t[3 * i] = float(i);
  const int ta = g.Accessor(t, kFloat, "VEC3", kCount);
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
  const auto dir = TempDir();
  TestGltf g;
  g.Mesh({{"POSITION", g.Positions(kQuad)}}, g.Accessor<uint8_t>({0, 1, 2, 0, 2, 3}, kUByte, "SCALAR", 6));
  const int t = g.Accessor<float>({0, 0, 0, 0, 3, 0}, kFloat, "VEC3", 2);
  const json instancing = {{"EXT_mesh_gpu_instancing", {{"attributes", {{"TRANSLATION", t}}}}}};
  g.Node({{"mesh", 0}, {"translation", {1, 0, 0}}, {"extensions", instancing}});
  g.Node({{"name", "empty"}, {"extensions", instancing}});
  g.Scene({0, 1});
  const int times = g.Accessor(std::vector<float>{0, 1}, kFloat, "SCALAR", 2);
  const int moves = g.Accessor(std::vector<float>{1, 0, 0, 2, 0, 0}, kFloat, "VEC3", 2);
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

  TestGltf k;  // the skinned quad of SkinnedMeshesArePlacedByTheirJoints, with two instances
  const int pos = k.Positions(kQuad);
  const int joints = k.Accessor<uint8_t>(std::vector<uint8_t>(16, 0), kUByte, "VEC4", 4);
  const int weights = k.Accessor<float>({1, 0, 0, 0, 1, 0, 0, 0, 1, 0, 0, 0, 1, 0, 0, 0}, kFloat, "VEC4", 4);
  k.doc["skins"] = json::array({{{"joints", {1}}}});
  const int kt = k.Accessor<float>({0, 0, 0, 0, 3, 0}, kFloat, "VEC3", 2);
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
}  // namespace rigsim
