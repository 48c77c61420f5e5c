// The glTF loader's working parts, internal to gltf/ (it includes tinygltf): the Loader that
// LoadGltf (gltf/gltf_loader.h) runs once per file, and the types its parts share. Loader::Load
// is the order of the steps; each group of members below lives in the file named above it.
#pragma once

#include <cstddef>
#include <cstdint>
#include <filesystem>
#include <map>
#include <optional>
#include <set>
#include <stdexcept>
#include <string>
#include <vector>

#include <Eigen/Core>
#include <tiny_gltf.h>

#include "gltf/gltf_compression.h"
#include "gltf/gltf_loader.h"
#include "gltf/readable_gltf.h"
#include "scene/scene.h"

namespace rigsim::gltf {

// A class given explicitly somewhere (node, mesh or material); nullopt = not specified there.
using ClassTag = std::optional<uint8_t>;

inline constexpr const char* kGpuInstancing = "EXT_mesh_gpu_instancing";

inline std::string Quote(const std::string& s) { return "'" + s + "'"; }

// What follows an object's index in messages: " 'wheel'" in "mesh 3 'wheel'"; "" when unnamed.
inline std::string NameSuffix(const std::string& name) {
  std::string suffix;
  if (!name.empty()) suffix.append(" '").append(name).append("'");
  return suffix;
}

// "mesh 3 'wheel' primitive 0", as every message names a primitive.
inline std::string MeshLabel(const tinygltf::Model& model, int mesh, int prim) {
  return PrimitiveLabel(size_t(mesh), model.meshes[mesh].name, size_t(prim));
}

// Components of an accessor type (VEC3: 3, MAT4: 16); -1 for an unknown type. (accessors.cc)
int NumComponents(int type);

// A node's local transform: its matrix, or T * R * S. (nodes.cc)
Eigen::Matrix4d LocalTransform(const tinygltf::Node& node);

// A quaternion too short to normalise into a rotation (glTF stores unit ones; exporters round).
inline bool IsZeroQuaternion(const Eigen::Vector4d& q) { return !(q.norm() > 1e-6); }

// What LoadCheckedImage is given and what it leaves for the loader: why each image it did not
// decode was refused. The loader fails on such an image only when a texture it uses samples it:
// an optional extension's image (KTX2 for KHR_texture_basisu, say) whose texture falls back to its
// PNG or JPEG `source` is skipped, as glTF asks of a client without the extension.
struct ImageChecks {
  uint64_t max_pixels = 0;
  std::map<int, std::string> refused;  // image index -> why it was not decoded
};

// tinygltf's image loader callback (tinygltf::LoadImageDataFunction), with ImageChecks as its
// user data. (images.cc)
bool LoadCheckedImage(tinygltf::Image* image, int index, std::string* err, std::string* warn, int req_width, int req_height,
                      const unsigned char* bytes, int size, void* user_data);

// The texture coordinates a material's texture samples: the TEXCOORD_<set> attribute, mapped by
// KHR_texture_transform (identity without it). Baked into SceneMesh::texcoords (base colour),
// emissive_texcoords and normal_texcoords, which is exact because a SceneMesh is one primitive
// with one material.
struct TextureUv {
  int set = 0;
  Eigen::Matrix<double, 2, 3> uv_from_texcoord = Eigen::Matrix<double, 2, 3>::Identity();
};

struct MaterialUvs {
  TextureUv base_color;
  std::optional<TextureUv> emissive;  // only with an emissive texture
  std::optional<TextureUv> normal;    // only with a normal texture
  std::optional<TextureUv> occlusion;  // only with an occlusion texture
};

class Loader {
 public:
  Loader(const std::filesystem::path& path, const GltfLoadOptions& options) : path_(path), options_(options) {}

  // Reads the file and flattens the scene; the steps, in order, are in gltf_loader.cc.
  Scene Load();

 private:
  // Where one copy of a node's mesh goes: the instance's transform in the node's frame (identity
  // without EXT_mesh_gpu_instancing), its instance id and its index among the node's instances
  // (-1 = not instanced).
  struct Placement {
    Eigen::Matrix4d node_from_instance = Eigen::Matrix4d::Identity();
    uint16_t instance_id = 0;
    int gpu_instance = -1;
  };

  // A primitive's vertices, decoded once for all its placements: node-frame positions and normals
  // (xyz triples, morphed at the rest weights).
  struct PrimitiveVertices {
    std::vector<double> positions, normals;
    size_t count = 0;
    int position_accessor = -1;
    bool posed_later = false;  // PoseSceneAt re-poses the mesh (animated, skinned or morph-animated)
  };

  [[noreturn]] void Fail(const std::string& what) const { throw std::runtime_error(path_.string() + ": " + what); }

  void Warn(const std::string& what) {
    if (options_.warnings_are_errors) Fail(what);
    scene_.warnings.push_back(what);
  }

  // Unsupported features that may occur many times are counted and reported once each.
  void Ignore(const std::string& what) { ++ignored_[what]; }

  void Summarise();

  // model_reading.cc: the file into model_, and what the file as a whole asks for.
  void ReadModel();
  void UndoReadableRewrites(const ReadableGltf& readable);
  void ReportFileLevelUnsupported();

  // classes.cc: semantic classes from extras.class and the label rules.
  ClassTag ParseClass(const tinygltf::Value& extras, const std::string& owner);
  void ParseClasses();
  ClassTag ClassFromLabelRules(int node_index, int mesh_index, int material_index);
  void ReportUnusedLabelRules();

  // materials.cc: materials and the texture coordinates their textures sample.
  void ConvertMaterials();
  template <typename TextureInfo>
  TextureUv ParseTextureInfoUv(const TextureInfo& info, const std::string& where);
  void ConvertEmission(const tinygltf::Material& m, const std::string& where, Material* out, MaterialUvs* uvs);
  TextureUv ParseTextureTransform(const tinygltf::Value& ext, const std::string& where, int texcoord_set);

  // images.cc: textures, from the images LoadCheckedImage decoded.
  int ConvertTexture(int index);

  // accessors.cc: accessor data, every byte bounds-checked.
  std::vector<double> ReadAccessor(int index, int expected_type, const std::string& use, size_t* count_out);
  void ApplySparse(const tinygltf::Accessor& a, int ncomp, int csize, const std::string& label, std::vector<double>* out);
  const unsigned char* CheckedView(int index, const std::string& label) const;

  // animation.cc: node animations, skins and morph targets.
  void ParseAnimations();
  void ParseSkins();
  void SkinAtRestPose();
  void ReadSkinning(const tinygltf::Primitive& prim, int skin, size_t nverts, const std::string& where, SceneMesh* out);
  size_t MorphTargetCount(int node) const;
  std::vector<double> RestMorphWeights(int node_index);
  std::vector<MorphTarget> ReadMorphTargets(const tinygltf::Primitive& prim, size_t nverts, const std::string& where);
  void Morph(const tinygltf::Primitive& prim, size_t nverts, const std::vector<double>& weights, bool keep, const std::string& where,
             std::vector<double>* pos, std::vector<double>* nrm, SceneMesh* out);

  // nodes.cc: the node tree, its cameras and the mesh instances it places.
  std::vector<int> RootNodes();
  void CheckNodeTransforms() const;
  void Traverse();
  void AddCamera(int node_index, const Eigen::Matrix4d& world, bool animated);
  std::string NodeLabel(int node_index) const;
  uint16_t NextInstanceId();
  void AddMeshInstance(int node_index, const Eigen::Matrix4d& world, ClassTag node_cls);

  // gpu_instancing.cc: EXT_mesh_gpu_instancing.
  std::vector<Placement> GpuInstances(int node_index);
  void CheckInstancedSize(int node_index, size_t count, const std::string& where);

  // primitives.cc: a mesh primitive's vertices, attributes and triangles, placed once per instance.
  void AddPrimitive(int node_index, int mesh_index, int prim_index, const Eigen::Matrix4d& world, ClassTag cls,
                    const std::vector<Placement>& placements, const std::vector<double>& morph_weights);
  void IgnoreUnreadAttributes(const tinygltf::Primitive& prim, const MaterialUvs& uvs, bool skinned);
  ClassTag PrimitiveClass(int node_index, int mesh_index, const tinygltf::Primitive& prim, ClassTag cls, const std::string& where,
                          SceneMesh* out);
  PrimitiveVertices DecodeVertices(int node_index, const tinygltf::Primitive& prim, bool skinned,
                                   const std::vector<double>& morph_weights, const std::string& where, SceneMesh* out);
  std::vector<Eigen::Vector2f> ReadTexcoords(const tinygltf::Primitive& prim, const TextureUv& uv, size_t nverts,
                                             const std::string& where);
  void ReadTexcoordSets(const tinygltf::Primitive& prim, const MaterialUvs& uvs, size_t nverts, const std::string& where,
                        SceneMesh* out);
  void ReadVertexColors(int accessor, const std::string& where, size_t nverts, SceneMesh* out);
  std::vector<uint32_t> VertexSequence(const tinygltf::Primitive& prim, size_t nverts, const std::string& where);
  void AssembleTriangles(int mode, const std::vector<uint32_t>& seq, const std::string& where, std::vector<uint32_t>* indices);
  void AddPlacedCopies(SceneMesh out, const std::vector<Placement>& placements, const Eigen::Matrix4d& world,
                       const PrimitiveVertices& vertices, bool labeled, const std::string& where);
  void PlacePrimitive(const Eigen::Matrix4d& world, const std::vector<double>& pos, const std::vector<double>& nrm, bool posed_later,
                      int pos_accessor, const std::string& where, size_t* singular, size_t* bad_normals, SceneMesh* out);

  std::filesystem::path path_;
  GltfLoadOptions options_;
  tinygltf::Model model_;
  Scene scene_;
  std::vector<ClassTag> node_class_, mesh_class_, material_class_;
  std::vector<MaterialUvs> material_uv_;  // per glTF material: its textures' coordinates
  std::map<int, int> texture_map_;  // glTF texture -> Scene::textures index
  ImageChecks image_checks_;        // filled by LoadCheckedImage while tinygltf reads the file
  std::set<int> dataless_buffers_;  // buffers without uri or data (gltf/readable_gltf.h)
  std::map<int, std::string> unknown_accessor_types_;  // accessor -> a type glTF does not define
  std::set<int> animated_nodes_;    // nodes targeted by a translation, rotation or scale channel
  std::set<int> morph_animated_nodes_;  // nodes whose morph weights a channel animates
  std::vector<bool> traversed_;                 // per glTF node: reached from the loaded scene's roots
  std::vector<Eigen::Matrix4d> rest_world_;     // per glTF node: world_from_node at rest (when traversed)
  bool current_mesh_animated_ = false;  // the node being traversed moves with an animation
  std::map<std::string, size_t> ignored_;
  uint32_t next_instance_ = 1;
  bool instance_overflow_warned_ = false;
  size_t unlabeled_triangles_ = 0;
  size_t unlabeled_meshes_ = 0;
  size_t decoded_elements_ = 0;  // accessor elements read so far (ReadAccessor's total bound)
  size_t instanced_elements_ = 0;  // vertices and indices of every GPU instance so far (CheckInstancedSize)
  std::vector<int> rule_parent_;  // parent node of each node, for label rules (built on first use)
  std::vector<size_t> rule_uses_;  // per label rule: primitives it classified
  size_t rule_lookups_ = 0;        // primitives the label rules were asked about
};

}  // namespace rigsim::gltf
