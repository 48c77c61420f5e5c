// glTF 2.0 loader: reads a .gltf (JSON + external or data-URI buffers/images) or .glb file and
// flattens the node tree of one scene into a rigsim Scene (world-space triangles with semantic
// class, instance id, material and decoded RGBA8 textures).
//
// Conventions relied on:
//  - World frame = glTF's (right-handed, +Y up, metres); node transforms are accumulated in double
//    precision and applied to the vertices, so Scene meshes need no further transform.
//  - Semantics come from `extras: {"class": "<cityscapes name>"}` on a node (inherited by its
//    subtree), a mesh (overrides the node) or a material (overrides both). Names are Cityscapes
//    class names (labels/cityscapes.h). Primitives without one are classified by the optional
//    label rules (gltf/label_rules.h); geometry still without a class is unlabeled (id 0) and one
//    warning counts it.
//  - Each node carrying a mesh is one instance; ids 1, 2, ... in depth-first traversal order. A
//    node with EXT_mesh_gpu_instancing is one instance per entry of its TRANSLATION / ROTATION /
//    SCALE accessors instead, each placed at world_from_node * T * R * S with its own id
//    (SceneMesh::gpu_instance, node_from_instance); a skinned one is drawn once, with a warning.
//  - Node animations (translation, rotation, scale, morph weights; LINEAR and STEP, CUBICSPLINE as
//    LINEAR with a warning) are kept in Scene::nodes / Scene::animation_channels, and meshes under
//    an animated node keep their node-frame vertices, so scene/scene_pose.h can re-pose them at
//    any time. Meshes are flattened at the rest pose (the nodes' own transforms).
//  - Morph targets (POSITION and NORMAL displacements) are applied at load with the rest weights
//    (node.weights, else mesh.weights, else 0), before skinning; a mesh whose node's weights are
//    animated also keeps its base vertices and targets (SceneMesh::morph_targets).
//  - baseColorTexture may sample any TEXCOORD_n set and carry KHR_texture_transform (offset,
//    rotation, scale, texCoord override); the transform is baked into SceneMesh::texcoords.
//  - Cameras on nodes of the loaded scene become Scene::cameras (node order), posed at rest with
//    their parents' transforms and converted to the OpenCV frame by CamFromWorldFromGltfCameraNode;
//    the others are warned about and counted in Scene::skipped_camera_nodes.
//  - Everything the loader cannot represent (extensions, extra attributes and textures, TANGENT
//    morph displacements, points/lines) is named in Scene::warnings.
//  - Malformed input (truncated file, out-of-range accessor, non-finite position, cyclic node graph)
//    and files for another glTF version (asset.version and minVersion, checked as glTF 2.0 asks)
//    throw std::runtime_error whose message starts with the file name.
#pragma once

#include <cstddef>
#include <cstdint>
#include <filesystem>

#include "scene/scene.h"

namespace rigsim {

class LabelRules;  // gltf/label_rules.h

struct GltfLoadOptions {
  // Index of the glTF scene to flatten; -1 = the file's `scene` (scene 0 when the file sets none).
  int scene = -1;
  // Upper bound on any accessor's element count, on the sum over every accessor read (a mesh
  // instanced by N nodes counts N times), and on the vertices and indices that EXT_mesh_gpu_instancing
  // instances copy, summed over the file. Checked before allocating, so that a corrupt or hostile
  // count fails with a message instead of exhausting memory.
  size_t max_accessor_count = size_t(1) << 26;
  // Upper bound on an image's width x height, read from its header before it is decoded (16384 x
  // 16384 by default: 1 GiB of RGBA), for the same reason.
  uint64_t max_image_pixels = uint64_t(1) << 28;
  // Throw on the first warning instead of collecting it (for pipelines that must not lose data).
  bool warnings_are_errors = false;
  // Classes by node, mesh and material names (gltf/label_rules.h) for primitives that get no
  // class from extras; nullptr = none. Must outlive the call.
  const LabelRules* label_rules = nullptr;
};

// Loads `path` (.gltf or .glb, chosen by the file's magic bytes). Throws std::runtime_error
// ("<path>: <what is wrong>") on I/O errors and malformed files.
Scene LoadGltf(const std::filesystem::path& path, const GltfLoadOptions& options = {});

}  // namespace rigsim
