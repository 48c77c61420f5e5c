// Linear blend skinning (glTF 2.0, "Skins"): a skinned mesh's vertex is placed by the weighted sum
// of its joints' world_from_joint * inverse_bind matrices; the mesh node's own transform is not
// used. The loader skins at the rest pose, PoseSceneAt (scene/scene_pose.h) at any time.
#pragma once

#include <vector>

#include <Eigen/Core>

#include "scene/scene.h"

namespace rigsim {

// Sets mesh->positions (and mesh->normals, from local_normals) from mesh->local_positions, its
// joints and weights, and world_from_node of every glTF node. Normals use the inverse transpose of
// each vertex's blended matrix; a vertex whose matrix is singular drops the mesh's normals (face
// normals are used). Throws std::invalid_argument naming the mesh when the data do not fit
// together (sizes, a joint index beyond the skin, a joint node without a transform).
void SkinMesh(const SceneSkin& skin, const std::vector<Eigen::Matrix4d>& world_from_node, SceneMesh* mesh);

}  // namespace rigsim
