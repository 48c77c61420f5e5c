// A flat, renderer-ready world: triangle meshes already transformed to world coordinates, each
// carrying its semantic class and instance, plus materials and decoded textures.
//
// World frame: glTF's (right-handed, +Y up, metres). Texture pixels are stored as in the file
// (8-bit RGBA, base colour in sRGB encoding); the renderer linearises them for shading.
// Texture coordinates follow glTF: (0, 0) is the top-left corner of the image's first pixel.
#pragma once

#include <array>
#include <cstdint>
#include <string>
#include <vector>

#include <Eigen/Core>

#include "geometry/rigid3.h"

namespace rigsim {

enum class WrapMode { kRepeat, kClampToEdge, kMirroredRepeat };

// The mip levels a minified texture is read from (the second half of a glTF minFilter): level 0
// only (NEAREST, LINEAR), the nearest level (*_MIPMAP_NEAREST) or a blend of the two nearest
// (*_MIPMAP_LINEAR, and rigsim's choice when the file leaves minFilter undefined).
enum class MipFilter { kNone, kNearest, kLinear };

struct Texture {
  std::string name;
  int width = 0;
  int height = 0;
  std::vector<uint8_t> rgba;  // width * height * 4, row 0 = top of the image
  WrapMode wrap_s = WrapMode::kRepeat;
  WrapMode wrap_t = WrapMode::kRepeat;
  bool nearest = false;      // magnification filter NEAREST (else LINEAR)
  bool min_nearest = false;  // minification takes a level's nearest texel (minFilter NEAREST, NEAREST_MIPMAP_*)
  MipFilter mip = MipFilter::kLinear;
};

enum class AlphaMode { kOpaque, kMask, kBlend };

struct Material {
  std::string name;
  Eigen::Vector4f base_color_factor = Eigen::Vector4f::Ones();  // linear RGBA
  int base_color_texture = -1;                                  // index into Scene::textures
  AlphaMode alpha_mode = AlphaMode::kOpaque;
  float alpha_cutoff = 0.5f;
  bool double_sided = false;
  bool unlit = false;  // KHR_materials_unlit: the base colour is what the camera sees
  // Light the surface gives off itself, added to what it reflects and cast on nothing else:
  // glTF's emissiveFactor times KHR_materials_emissive_strength, linear RGB (1 shows white at
  // exposure 1).
  Eigen::Vector3f emissive = Eigen::Vector3f::Zero();
  int emissive_texture = -1;  // index into Scene::textures; multiplies `emissive`
  // Tangent-space normal map (glTF normalTexture: linear RGB, +X along u, +Y towards the image's
  // top, i.e. decreasing v) and its scale on X and Y.
  int normal_texture = -1;  // index into Scene::textures
  float normal_scale = 1.0f;
  // Ambient occlusion (glTF occlusionTexture: linear, red channel, 1 = open) and its strength:
  // the sky light is scaled by 1 + strength * (occlusion - 1). The sun is not, as glTF applies
  // occlusion to indirect light only.
  int occlusion_texture = -1;  // index into Scene::textures
  float occlusion_strength = 1.0f;
  // glTF pbrMetallicRoughness factors, in [0, 1], glTF's defaults: a surface rougher than the
  // renderer's glossy threshold (renderer/shading.h kGlossyRoughness) is shaded as before, one
  // below it also reflects the world (one specular bounce).
  float metallic = 1.0f;
  float roughness = 1.0f;
};

// One glTF morph target of a mesh: the displacement of every vertex, in the mesh's own frame.
struct MorphTarget {
  std::vector<Eigen::Vector3f> positions;  // one per vertex; empty = the target moves no position
  std::vector<Eigen::Vector3f> normals;    // one per vertex; empty = the target turns no normal
};

struct SceneMesh {
  std::string name;         // node name (or mesh name when the node has none)
  uint8_t class_id = 0;     // Cityscapes label id (labels/cityscapes.h); 0 = unlabeled
  uint16_t instance_id = 0; // 1.. per glTF node carrying geometry (per instance of it, below); 0 = none
  int material = -1;        // index into Scene::materials; -1 = default grey
  std::vector<Eigen::Vector3f> positions;  // world
  std::vector<Eigen::Vector3f> normals;    // world, unit; empty = use the face normal
  // What the material's base colour texture samples: the TEXCOORD_n set it names (TEXCOORD_0
  // without a texture), with its KHR_texture_transform already applied; empty = none.
  std::vector<Eigen::Vector2f> texcoords;
  // What the material's emissive texture samples (its own TEXCOORD_n and KHR_texture_transform);
  // empty = none.
  std::vector<Eigen::Vector2f> emissive_texcoords;
  // What the material's normal texture samples; empty = none. The tangent frame is derived per
  // triangle from the positions and these coordinates (a file's TANGENT attribute is not used).
  std::vector<Eigen::Vector2f> normal_texcoords;
  // What the material's occlusion texture samples; empty = none.
  std::vector<Eigen::Vector2f> occlusion_texcoords;
  // COLOR_0: linear RGBA per vertex, which multiplies the material's base colour (glTF 2.0);
  // empty = none.
  std::vector<Eigen::Vector4f> colors;
  std::vector<uint32_t> indices;           // 3 per triangle, into positions
  // Animated (node or morph weights) and skinned meshes only: the glTF node carrying the mesh
  // (index into the file's nodes, and into Scene::nodes when animated) and the vertices in the
  // mesh's own frame (morphed at the rest weights), from which PoseSceneAt
  // (scene/scene_pose.h) recomputes `positions` and `normals` at any time.
  int node = -1;
  std::vector<Eigen::Vector3f> local_positions;
  std::vector<Eigen::Vector3f> local_normals;
  // Skinned meshes only: index into Scene::skins, and per vertex JOINTS_0 (indices into the skin's
  // joints) and WEIGHTS_0 (summing to 1). Such a mesh is placed by its joints, not by its node.
  int skin = -1;
  std::vector<std::array<uint16_t, 4>> joints;
  std::vector<Eigen::Vector4f> weights;
  // How many morph targets the glTF primitive has (0 = none). Their rest weights (node.weights,
  // else mesh.weights) are already applied to every vertex above.
  int num_morph_targets = 0;
  // Only when the node's morph weights are animated (a kWeights channel): the node-frame vertices
  // before morphing and the targets, from which PoseSceneAt recomputes local_positions and
  // local_normals (scene/morphing.h) before placing or skinning the mesh. Empty otherwise, so
  // that static meshes carry no copy.
  std::vector<Eigen::Vector3f> morph_base_positions;
  std::vector<Eigen::Vector3f> morph_base_normals;
  std::vector<MorphTarget> morph_targets;
  // EXT_mesh_gpu_instancing: which instance of its node this mesh is (-1 = the node is not
  // instanced), and the instance's T * R * S in the node's frame. Each instance is its own set of
  // meshes with its own instance_id; an animated one is placed at world_from_node(t) *
  // node_from_instance (the instance transform comes first, glTF "Transformation Order").
  int gpu_instance = -1;
  Eigen::Matrix4d node_from_instance = Eigen::Matrix4d::Identity();
};

// A glTF skin: the nodes (joints) that move a skinned mesh's vertices, each with its inverse bind
// matrix (joint_from_mesh at bind time).
struct SceneSkin {
  std::vector<int> joints;  // glTF node indices
  std::vector<Eigen::Matrix4d> inverse_bind;
};

// A glTF node's rest transform and parent; filled by the loader only for animated scenes.
struct SceneNode {
  std::string name;
  int parent = -1;                      // index into Scene::nodes; -1 = root
  bool has_matrix = false;              // node.matrix given (glTF: such nodes are not animated)
  Eigen::Matrix4d matrix = Eigen::Matrix4d::Identity();
  Eigen::Vector3d translation = Eigen::Vector3d::Zero();
  Eigen::Vector4d rotation_xyzw = Eigen::Vector4d(0, 0, 0, 1);  // glTF order (x, y, z, w)
  Eigen::Vector3d scale = Eigen::Vector3d::Ones();
};

enum class AnimationPath { kTranslation, kRotation, kScale, kWeights };
enum class AnimationInterpolation { kLinear, kStep };  // CUBICSPLINE is loaded as LINEAR (warned)

// One glTF animation channel with its sampler: keyframes of one property of one node. Before the
// first key the first value holds, after the last the last (glTF clamps).
struct AnimationChannel {
  int node = -1;                       // index into Scene::nodes
  AnimationPath path = AnimationPath::kTranslation;
  AnimationInterpolation interpolation = AnimationInterpolation::kLinear;
  std::vector<double> times_s;         // increasing
  std::vector<Eigen::Vector4d> values; // translation / scale in xyz; rotation quaternion (x, y, z, w)
  // kWeights only (`values` is then empty): per key, one weight per morph target of the node's mesh.
  std::vector<Eigen::VectorXd> weights;
};

// A glTF camera placed by a node of the loaded scene, at the node's rest pose (parents included).
// Only what a rig camera needs; projection into pixels is decided by whoever picks an image size
// (gltf/scene_cameras.h).
struct SceneCamera {
  std::string name;          // the node's name, else the camera's, else "camera<node index>"
  int node = -1;             // glTF node index (Scene::cameras is sorted by it: file order)
  int camera = -1;           // glTF camera index
  bool orthographic = false; // orthographic cameras are kept so that tools can name them
  double yfov_rad = 0.0;     // perspective: vertical field of view
  double aspect_ratio = 0.0; // perspective: width / height; 0 = not given in the file
  double znear_m = 0.0;
  double zfar_m = 0.0;       // 0 = infinite
  // OpenCV-frame pose (x right, y down, z forward), converted from glTF's -Z-forward, +Y-up camera
  // frame by CamFromWorldFromGltfCameraNode (geometry/rigid3.h); node scale removed.
  Rigid3d cam_from_world;
};

struct Scene {
  std::string source;  // file it came from, for messages
  std::vector<SceneMesh> meshes;
  std::vector<Material> materials;
  std::vector<Texture> textures;
  std::vector<std::string> warnings;  // everything the loader skipped or guessed, human readable
  std::vector<SceneCamera> cameras;   // glTF cameras on nodes of the loaded scene, in node order
  // Camera nodes not in `cameras`: outside the loaded scene, or not usable as a camera (mirrored,
  // yfov out of range, ...); the warnings say which and why.
  size_t skipped_camera_nodes = 0;
  std::vector<SceneSkin> skins;       // glTF skins (SceneMesh::skin)
  // Node animation (empty for a static scene): the node tree and the channels that move it.
  std::vector<SceneNode> nodes;
  std::vector<AnimationChannel> animation_channels;
  // What the loader decompressed (for `rigsim inspect`): KHR_draco_mesh_compression primitives
  // and EXT_meshopt_compression buffer views.
  size_t draco_primitives = 0;
  size_t meshopt_views = 0;

  bool IsAnimated() const { return !animation_channels.empty(); }

  size_t NumTriangles() const {
    size_t n = 0;
    for (const SceneMesh& m : meshes) n += m.indices.size() / 3;
    return n;
  }
};

}  // namespace rigsim
