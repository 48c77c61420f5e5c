#include "scene/morphing.h"

#include <stdexcept>
#include <string>

namespace rigsim {

void MorphMesh(const std::vector<double>& weights, SceneMesh* mesh) {
  const std::string where = "morphed mesh '" + mesh->name + "'";
  if (weights.size() != mesh->morph_targets.size()) {
    throw std::invalid_argument(where + ": " + std::to_string(weights.size()) + " weights for " +
                                std::to_string(mesh->morph_targets.size()) + " morph targets");
  }
  const size_t n = mesh->morph_base_positions.size();
  const bool with_normals = !mesh->morph_base_normals.empty();
  if (with_normals && mesh->morph_base_normals.size() != n) {
    throw std::invalid_argument(where + ": base normals and positions differ in count");
  }
  // Accumulated in double: many small weighted displacements.
  std::vector<Eigen::Vector3d> p(n), nrm(with_normals ? n : 0);
  for (size_t i = 0; i < n; ++i) p[i] = mesh->morph_base_positions[i].cast<double>();
  for (size_t i = 0; i < nrm.size(); ++i) nrm[i] = mesh->morph_base_normals[i].cast<double>();
  for (size_t t = 0; t < weights.size(); ++t) {
    const MorphTarget& target = mesh->morph_targets[t];
    if ((!target.positions.empty() && target.positions.size() != n) || (!target.normals.empty() && target.normals.size() != n)) {
      throw std::invalid_argument(where + ": morph target " + std::to_string(t) + " does not have one displacement per vertex");
    }
    const double w = weights[t];
    if (w == 0.0) continue;
    for (size_t i = 0; i < target.positions.size(); ++i) p[i] += w * target.positions[i].cast<double>();
    if (with_normals) {
      for (size_t i = 0; i < target.normals.size(); ++i) nrm[i] += w * target.normals[i].cast<double>();
    }
  }
  mesh->local_positions.resize(n);
  for (size_t i = 0; i < n; ++i) mesh->local_positions[i] = p[i].cast<float>();
  mesh->local_normals.resize(nrm.size());
  for (size_t i = 0; i < nrm.size(); ++i) {
    const double len = nrm[i].norm();
    mesh->local_normals[i] = len > 1e-12 ? (nrm[i] / len).cast<float>() : mesh->morph_base_normals[i];
  }
}

}  // namespace rigsim
