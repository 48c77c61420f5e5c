// A flat, renderer-ready world: triangle meshes already transformed to world coordinates, each
// carrying its semantic class and instance, plus materials and decoded textures.
//
// World frame: glTF's (right-handed, +Y up, metres). Texture pixels are stored as in the file
// (8-bit RGBA, base colour in sRGB encoding); the renderer linearises them for shading.
// Texture coordinates follow glTF: (0, 0) is the top-left corner of the image's first pixel.
#pragma once

#include <cstdint>
#include <string>
#include <vector>

#include <Eigen/Core>

namespace rigsim {

enum class WrapMode { kRepeat, kClampToEdge, kMirroredRepeat };

struct Texture {
  std::string name;
  int width = 0;
  int height = 0;
  std::vector<uint8_t> rgba;  // width * height * 4, row 0 = top of the image
  WrapMode wrap_s = WrapMode::kRepeat;
  WrapMode wrap_t = WrapMode::kRepeat;
  bool nearest = false;  // magnification filter NEAREST
};

enum class AlphaMode { kOpaque, kMask, kBlend };

struct Material {
  std::string name;
  Eigen::Vector4f base_color_factor = Eigen::Vector4f::Ones();  // linear RGBA
  int base_color_texture = -1;                                  // index into Scene::textures
  AlphaMode alpha_mode = AlphaMode::kOpaque;
  float alpha_cutoff = 0.5f;
  bool double_sided = false;
};

struct SceneMesh {
  std::string name;         // node name (or mesh name when the node has none)
  uint8_t class_id = 0;     // Cityscapes label id (labels/cityscapes.h); 0 = unlabeled
  uint16_t instance_id = 0; // 1.. per glTF node carrying geometry; 0 = none
  int material = -1;        // index into Scene::materials; -1 = default grey
  std::vector<Eigen::Vector3f> positions;  // world
  std::vector<Eigen::Vector3f> normals;    // world, unit; empty = use the face normal
  std::vector<Eigen::Vector2f> texcoords;  // TEXCOORD_0; empty = none
  std::vector<uint32_t> indices;           // 3 per triangle, into positions
};

struct Scene {
  std::string source;  // file it came from, for messages
  std::vector<SceneMesh> meshes;
  std::vector<Material> materials;
  std::vector<Texture> textures;
  std::vector<std::string> warnings;  // everything the loader skipped or guessed, human readable

  size_t NumTriangles() const {
    size_t n = 0;
    for (const SceneMesh& m : meshes) n += m.indices.size() / 3;
    return n;
  }
};

}  // namespace rigsim
