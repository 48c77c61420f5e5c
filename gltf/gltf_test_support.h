// What the glTF tests share: TestGltf, which writes small glTF files by hand so that a test
// controls every byte, a temporary folder per test, and checks on what LoadGltf returns or throws.
#pragma once

#include <cstddef>
#include <cstdint>
#include <cstring>
#include <filesystem>
#include <string>
#include <vector>

#include <Eigen/Core>
#include <nlohmann/json.hpp>

#include "gltf/gltf_loader.h"
#include "scene/scene.h"

namespace rigsim::gltf_test {

using json = nlohmann::json;

constexpr int kUByte = 5121, kUShort = 5123, kUInt = 5125, kFloat = 5126;

inline const std::vector<float> kQuad = {0, 0, 0, 1, 0, 0, 1, 1, 0, 0, 1, 0};  // 4 corners in the z = 0 plane

// An empty folder named after the running test.
std::filesystem::path TempDir();

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
  std::filesystem::path Write(const std::filesystem::path& dir, const std::string& name, bool data_uri = false);
  // Writes `name`.glb: the document and its buffer in one binary file.
  std::filesystem::path WriteGlb(const std::filesystem::path& dir, const std::string& name);
};

// A 2x2 PNG as a data URI, for materials whose texture content does not matter.
std::string TinyPngUri();

std::vector<Eigen::Vector3f> TriangleCorners(const SceneMesh& m);
Eigen::Vector3f FaceNormal(const SceneMesh& m, size_t tri);
bool HasWarning(const Scene& s, const std::string& part);

// Expects LoadGltf(path, options) to throw a message starting with the file name and containing
// `part`.
void ExpectThrowsWithOptions(const std::filesystem::path& path, const GltfLoadOptions& options, const std::string& part);
void ExpectThrowsWith(const std::filesystem::path& path, const std::string& part);

}  // namespace rigsim::gltf_test
