// A small writer for labelled glTF scenes, used by the procedural generators: collect textures,
// materials and nodes (one mesh each, with a Cityscapes class name), then write one self-contained
// binary glTF 2.0 (.glb) that LoadGltf reads back.
//
// Conventions: glTF world frame (+Y up, metres); pixels row 0 = top; texcoords (0, 0) = top-left.
// The class goes to the node's `extras.class`; each node becomes one instance on load.
// Textures are embedded, as JPEG when fully opaque (small files) and PNG when they carry alpha.
// Output is deterministic: the same calls give a byte-identical file.
#pragma once

#include <cstdint>
#include <filesystem>
#include <string>
#include <vector>

#include <Eigen/Core>
#include <Eigen/Geometry>

namespace rigsim {

// One triangle mesh in the node's local frame.
struct MeshData {
  std::vector<Eigen::Vector3f> positions;
  std::vector<Eigen::Vector3f> normals;    // empty or one per position
  std::vector<Eigen::Vector2f> texcoords;  // empty or one per position
  std::vector<uint32_t> indices;           // 3 per triangle, counter-clockwise seen from the front
};

// One primitive of a node: a mesh and its material (-1 = default).
struct MeshPart {
  MeshData mesh;
  int material = -1;
};

class SceneBuilder {
 public:
  // Adds an 8-bit texture with `channels` = 3 (RGB) or 4 (RGBA), row 0 = top. Returns its index.
  int AddTexture(const std::string& name, int width, int height, int channels, std::vector<uint8_t> pixels,
                 bool nearest = false);
  // Adds a material; `texture` = -1 for none. Colour factor is linear RGBA. Returns its index.
  int AddMaterial(const std::string& name, const Eigen::Vector4f& base_color_factor, int texture = -1,
                  bool double_sided = false);
  // Sets `material`'s pbrMetallicRoughness factors (each in [0, 1]; by default metallic 0 and
  // roughness 1, a diffuse surface). Throws std::invalid_argument on a bad index or factor.
  void SetMetallicRoughness(int material, float metallic, float roughness);
  // Makes `material` alpha-masked (glTF alphaMode MASK): texels with alpha < cutoff are cut out.
  void SetAlphaMask(int material, float cutoff = 0.5f);
  // Adds a root node carrying `mesh` with `material` (-1 = default) and class `class_name`
  // (a Cityscapes name; "" = no class). Throws std::invalid_argument on unknown classes, bad
  // indices or mismatched attribute sizes. Returns the node index.
  int AddNode(const std::string& name, const std::string& class_name, MeshData mesh, int material,
              const Eigen::Matrix4d& world_from_node = Eigen::Matrix4d::Identity());
  // The same with several primitives (e.g. materials) in one node, hence one instance.
  int AddNode(const std::string& name, const std::string& class_name, std::vector<MeshPart> parts,
              const Eigen::Matrix4d& world_from_node = Eigen::Matrix4d::Identity());

  // Animates `node`'s translation (glTF animation channel, LINEAR): at times_s[k] the node's origin
  // is at translations[k] (world, since nodes are roots). The node is written with TRS instead of
  // a matrix, as glTF requires for animated nodes. Throws std::invalid_argument on bad input.
  void AddTranslationAnimation(int node, std::vector<float> times_s, std::vector<Eigen::Vector3f> translations);
  // Animates `node`'s rotation the same way (LINEAR, i.e. slerp between keys): at times_s[k] the
  // node's world_from_node rotation is rotations[k] (normalised when written). A node may have one
  // translation and one rotation animation.
  void AddRotationAnimation(int node, std::vector<float> times_s, std::vector<Eigen::Quaternionf> rotations);

  // Writes a .glb; throws std::runtime_error("<path>: ...") on failure.
  void WriteGlb(const std::filesystem::path& path) const;
  // The bytes WriteGlb would write.
  std::vector<uint8_t> ToGlb() const;

  int jpeg_quality = 90;

  size_t num_nodes() const { return nodes_.size(); }

 private:
  struct TextureData {
    std::string name;
    int width, height, channels;
    std::vector<uint8_t> pixels;
    bool nearest;
  };
  struct MaterialData {
    std::string name;
    Eigen::Vector4f factor;
    int texture;
    bool double_sided;
    float alpha_cutoff = -1.f;  // < 0: opaque
    float metallic = 0.f, roughness = 1.f;
  };
  struct NodeData {
    std::string name, class_name;
    std::vector<MeshPart> parts;
    Eigen::Matrix4d world_from_node;
  };
  std::vector<TextureData> textures_;
  std::vector<MaterialData> materials_;
  std::vector<NodeData> nodes_;
  struct AnimationData {
    int node;
    std::string path;           // glTF target path: "translation" or "rotation"
    std::vector<float> times;
    std::vector<float> values;  // per key 3 (translation) or 4 (rotation x, y, z, w) floats
  };
  // Checks a new animation of `path` on `node` with `keys` values; throws std::invalid_argument.
  void CheckAnimation(const std::string& who, int node, const std::string& path, const std::vector<float>& times_s,
                      size_t keys) const;
  std::vector<AnimationData> animations_;
};

}  // namespace rigsim
