#include "scene/skinning.h"

#include <cmath>
#include <stdexcept>
#include <string>

#include <Eigen/LU>

namespace rigsim {

void SkinMesh(const SceneSkin& skin, const std::vector<Eigen::Matrix4d>& world_from_node, SceneMesh* mesh) {
  const std::string where = "skinned mesh '" + mesh->name + "'";
  const size_t n = mesh->local_positions.size();
  if (mesh->joints.size() != n || mesh->weights.size() != n ||
      (!mesh->local_normals.empty() && mesh->local_normals.size() != n)) {
    throw std::invalid_argument(where + ": joints, weights and normals must have one entry per vertex");
  }
  if (skin.inverse_bind.size() != skin.joints.size()) {
    throw std::invalid_argument(where + ": the skin has " + std::to_string(skin.joints.size()) + " joints and " +
                                std::to_string(skin.inverse_bind.size()) + " inverse bind matrices");
  }
  // world_from_mesh of each joint at this pose.
  std::vector<Eigen::Matrix4d> joint_matrices(skin.joints.size());
  for (size_t j = 0; j < skin.joints.size(); ++j) {
    const int node = skin.joints[j];
    if (node < 0 || size_t(node) >= world_from_node.size()) {
      throw std::invalid_argument(where + ": joint " + std::to_string(j) + " is node " + std::to_string(node) +
                                  ", which has no transform");
    }
    joint_matrices[j] = world_from_node[node] * skin.inverse_bind[j];
  }
  mesh->positions.resize(n);
  mesh->normals.resize(mesh->local_normals.size());
  bool singular = false;
  for (size_t i = 0; i < n; ++i) {
    Eigen::Matrix4d blended = Eigen::Matrix4d::Zero();
    for (int k = 0; k < 4; ++k) {
      const float w = mesh->weights[i][k];
      if (w == 0.0f) continue;
      const uint16_t j = mesh->joints[i][k];
      if (j >= joint_matrices.size()) {
        throw std::invalid_argument(where + ": vertex " + std::to_string(i) + " names joint " + std::to_string(j) +
                                    " of a skin with " + std::to_string(joint_matrices.size()));
      }
      blended += double(w) * joint_matrices[j];
    }
    const Eigen::Matrix3d linear = blended.topLeftCorner<3, 3>();
    mesh->positions[i] = (linear * mesh->local_positions[i].cast<double>() + blended.topRightCorner<3, 1>()).cast<float>();
    if (mesh->local_normals.empty() || singular) continue;
    if (std::abs(linear.determinant()) < 1e-300) {
      singular = true;
      continue;
    }
    mesh->normals[i] = (linear.inverse().transpose() * mesh->local_normals[i].cast<double>()).normalized().cast<float>();
  }
  if (singular) mesh->normals.clear();
}

}  // namespace rigsim
