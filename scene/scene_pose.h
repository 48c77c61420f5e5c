// Time for animated scenes: poses the meshes of a Scene whose glTF nodes are animated
// (Scene::nodes, Scene::animation_channels, filled by gltf/gltf_loader.h) at a given time.
//
// Conventions: times in seconds on the glTF animation clock (frames.json timestamp_s + a camera's
// time_offset_s); before the first key the first value holds, after the last the last. LINEAR
// interpolates translation, scale and morph weights linearly and rotation by slerp; STEP holds the
// previous key.
// A node's local transform is T * R * S (or its matrix when it has one and is not animated).
// Posing is a pure function of (scene, time), so renders stay byte-identical across threads.
#pragma once

#include <vector>

#include <Eigen/Core>

#include "scene/scene.h"

namespace rigsim {

// world_from_node of every Scene::nodes entry at `time_s` (empty for a static scene).
std::vector<Eigen::Matrix4d> NodeWorldTransformsAt(const Scene& scene, double time_s);

// Morph weights (AnimationPath::kWeights) at `time_s`, per Scene::nodes entry; empty for a node
// whose weights are not animated. LINEAR blends each weight linearly, STEP holds.
std::vector<std::vector<double>> MorphWeightsAt(const Scene& scene, double time_s);

// Copies scene.meshes and re-poses the animated ones (SceneMesh::node >= 0) at `time_s`:
// a mesh with animated morph weights is morphed first (scene/morphing.h), then positions and
// normals are placed in world coordinates (by world_from_node * SceneMesh::node_from_instance, the
// latter identity but for EXT_mesh_gpu_instancing instances); a skinned mesh (SceneMesh::skin >= 0)
// follows its joints (scene/skinning.h). Static meshes are copied unchanged.
std::vector<SceneMesh> PoseMeshesAt(const Scene& scene, double time_s);

// The flat world-space scene at `time_s` (a copy of `scene`, textures included, with posed meshes).
Scene PoseSceneAt(const Scene& scene, double time_s);

}  // namespace rigsim
