// Small glTF 2.0 files for tests, written by hand so that a test controls every byte:
//
//   GltfBuilder g;
//   const int pos = g.Positions(kUnitQuad);                  // accessor 0 over bufferView 0 of `bin`
//   g.Node({{"mesh", g.Mesh({{"POSITION", pos}}, -1, 6)}});  // a TRIANGLE_FAN primitive
//   g.Scene({0});
//   g.doc["extensionsUsed"] = {"KHR_materials_unlit"};       // anything else: edit `doc`
//   LoadGltf(g.Write(dir, "quad"));                          // quad.gltf + quad.bin; or WriteEmbedded, WriteGlb
//
// `doc` is the document without its buffers; buffer 0 holds `bin`, buffers 1, 2, ... are
// `extra_buffers` as given. Write and WriteGlb add the buffers unless `doc` has its own "buffers"
// (a test that corrupts them). Shapes (Triangle, Quad, Square) add a mesh and a classed node and
// list it among the scene's roots. DataUri and TinyPngUri embed data in a document.
#pragma once

#include <array>
#include <cstddef>
#include <cstdint>
#include <cstring>
#include <filesystem>
#include <string>
#include <string_view>
#include <vector>

#include <Eigen/Core>
#include <nlohmann/json.hpp>

namespace rigsim {

// accessor.componentType values.
inline constexpr int kGltfByte = 5120, kGltfUByte = 5121, kGltfShort = 5122, kGltfUShort = 5123, kGltfUInt = 5125,
                     kGltfFloat = 5126;

// The corners (0,0,0) (1,0,0) (1,1,0) (0,1,0) of a unit quad in the z = 0 plane, xyz each.
inline const std::vector<float> kUnitQuad = {0, 0, 0, 1, 0, 0, 1, 1, 0, 0, 1, 0};

// A base64 data URI.
std::string DataUri(std::string_view mime_type, const std::vector<uint8_t>& data);
// A 2x2 PNG as a data URI, for materials whose texture content does not matter.
std::string TinyPngUri();

// A document of glTF cameras only, for the tests of glTF cameras as a rig:
//  - node 0 "front": perspective (yfov 60 deg), at (1, 2, 3), turned +90 deg about +Y;
//  - node 2 "back": perspective (yfov 60 deg, aspectRatio 2), at local (2, 0, 0) on node 1 "mount"
//    (translation (0, 0, -10), 180 deg about +Y, scale 2);
//  - node 3 "top": orthographic (camera 2 "plan"), at (0, 50, 0).
// The scene lists nodes 1, 0, 3: traversal meets "back" before "front".
nlohmann::json GltfCamerasDocument();

class GltfBuilder {
 public:
  using json = nlohmann::json;

  json doc = {{"asset", {{"version", "2.0"}}}, {"bufferViews", json::array()}, {"accessors", json::array()},
              {"nodes", json::array()}, {"meshes", json::array()}};
  std::vector<uint8_t> bin;
  json extra_buffers = json::array();

  // An accessor of `count` elements of `type` ("SCALAR", "VEC3", ...) over a new bufferView holding
  // `values` (4-byte aligned in `bin`); `component_type` need not match T, so that tests can lie.
  template <typename T>
  int Accessor(const std::vector<T>& values, int component_type, const std::string& type, size_t count,
               bool normalized = false) {
    const size_t offset = AppendToBin(values.empty() ? nullptr : values.data(), values.size() * sizeof(T));
    doc["bufferViews"].push_back({{"buffer", 0}, {"byteOffset", offset}, {"byteLength", values.size() * sizeof(T)}});
    json a = {{"bufferView", doc["bufferViews"].size() - 1}, {"componentType", component_type}, {"count", count}, {"type", type}};
    if (normalized) a["normalized"] = true;
    doc["accessors"].push_back(a);
    return int(doc["accessors"].size()) - 1;
  }
  // FLOAT accessors: VEC3 positions, and any type with the count the values give.
  int Positions(const std::vector<float>& xyz) { return Accessor(xyz, kGltfFloat, "VEC3", xyz.size() / 3); }
  int Floats(const std::vector<float>& values, const std::string& type);

  // kUnitQuad's positions, TEXCOORD_0 on its corners' unit square and TEXCOORD_1 on the square's
  // middle quarter: the accessors of (POSITION, TEXCOORD_0, TEXCOORD_1).
  struct TwoSets {
    int pos, uv0, uv1;
  };
  TwoSets QuadWithTwoTexcoordSets();
  // textures[0]: a 2 x 2 PNG (TinyPngUri) as images[0].
  void TinyTexture();

  // A mesh with one primitive (mode 4: triangles); returns the mesh index.
  int Mesh(json attributes, int indices = -1, int mode = 4, int material = -1, json extras = nullptr);
  // Appends a node; returns its index.
  int Node(json node);
  // Scene 0, the default scene, with these root nodes.
  void Scene(std::vector<int> roots);
  // Appends `node` to scene 0's roots (making scene 0 if there is none).
  void AddRoot(int node);

  // A non-indexed triangle `xyz` (9 floats) as its own mesh and root node of class `cls`; returns
  // the node.
  int Triangle(const std::vector<float>& xyz, const std::string& cls);
  // A quad with corners `c` in order around it, as two non-indexed triangles, its own mesh and root
  // node of class `cls`; returns the node. With a material, TEXCOORD_0 puts (0,0) (1,0) (1,1) (0,1)
  // at the corners; `rgba` (per corner) adds COLOR_0.
  int Quad(const std::array<Eigen::Vector3d, 4>& c, const std::string& cls, int material = -1,
           const std::vector<Eigen::Vector4f>& rgba = {});
  // A square of side `size` centred at `centre`, spanned by unit vectors `right` and `up`; uv (0, 0)
  // at its top-left corner as seen with `right` to the right and `up` up.
  int Square(const Eigen::Vector3d& centre, const Eigen::Vector3d& right, const Eigen::Vector3d& up, double size,
             const std::string& cls, int material = -1);

  // The document with its buffers: buffer 0 as a data URI, or as the file `bin_uri`.
  json Document(const std::string& bin_uri = "") const;
  // Writes `name`.gltf into `dir` with buffer 0 in `name`.bin beside it; returns the .gltf's path.
  std::filesystem::path Write(const std::filesystem::path& dir, const std::string& name) const;
  // Writes `name`.gltf into `dir` with buffer 0 in it as a data URI.
  std::filesystem::path WriteEmbedded(const std::filesystem::path& dir, const std::string& name) const;
  // Writes `name`.glb: the document and buffer 0 in one binary file.
  std::filesystem::path WriteGlb(const std::filesystem::path& dir, const std::string& name) const;

 private:
  size_t AppendToBin(const void* data, size_t bytes);
};

}  // namespace rigsim
