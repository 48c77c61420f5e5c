#include "calibrator/estimators/camera_centres.h"

#include <algorithm>
#include <cmath>

#include <Eigen/SVD>

#include "calibrator/model/rig_state.h"
#include "calibrator/model/union_find.h"
#include "geometry/rigid3.h"

namespace rigsim {

CameraCentres EstimateCameraCentres(const ViewGraph& graph,
                                    const PerCamera<Eigen::Quaterniond>& cam_from_rig,
                                    int reference_camera, int reweighting_iterations) {
  const int n = graph.num_cameras;
  CameraCentres out;
  out.centre_in_rig.assign(n, std::nullopt);
  if (reference_camera < 0 || reference_camera >= n || !cam_from_rig.at(reference_camera)) return out;

  // Edges with a direction between cameras with rotations; the reference's component over them.
  std::vector<int> edges;
  UnionFind components(n);
  for (int e = 0; e < static_cast<int>(graph.edges.size()); ++e) {
    const ViewGraphEdge& g = graph.edges[e];
    if (!g.active || g.rotation_only || !cam_from_rig[g.cam_a] || !cam_from_rig[g.cam_b]) continue;
    edges.push_back(e);
    components.Join(g.cam_a, g.cam_b);
  }
  std::vector<int> unknown_of(n, -1);  // column block of each camera; the reference has none
  std::vector<int> cams;
  for (int c = 0; c < n; ++c) {
    if (c != reference_camera && cam_from_rig[c] && components.Find(c) == components.Find(reference_camera)) {
      unknown_of[c] = static_cast<int>(cams.size());
      cams.push_back(c);
    }
  }
  out.centre_in_rig[reference_camera] = Eigen::Vector3d::Zero();
  if (cams.empty()) return out;
  const int reference_root = components.Find(reference_camera);
  std::erase_if(edges, [&](int e) { return components.Find(graph.edges[e].cam_a) != reference_root; });
  out.edges_used = static_cast<int>(edges.size());

  // Direction of c_a - c_b in the rig frame, per edge.
  std::vector<Eigen::Vector3d> dir(edges.size());
  for (size_t k = 0; k < edges.size(); ++k) {
    const ViewGraphEdge& g = graph.edges[edges[k]];
    dir[k] = (cam_from_rig[g.cam_b]->conjugate() * g.direction).normalized();
  }
  const int cols = 3 * static_cast<int>(cams.size());
  std::vector<double> weight(edges.size(), 1.0);
  Eigen::VectorXd x;
  for (int iter = 0; iter <= reweighting_iterations; ++iter) {
    Eigen::MatrixXd a = Eigen::MatrixXd::Zero(3 * edges.size(), cols);
    for (size_t k = 0; k < edges.size(); ++k) {
      const ViewGraphEdge& g = graph.edges[edges[k]];
      const Eigen::Matrix3d s = weight[k] * CrossProductMatrix(dir[k]);
      if (unknown_of[g.cam_a] >= 0) a.block<3, 3>(3 * k, 3 * unknown_of[g.cam_a]) += s;
      if (unknown_of[g.cam_b] >= 0) a.block<3, 3>(3 * k, 3 * unknown_of[g.cam_b]) -= s;
    }
    const Eigen::JacobiSVD<Eigen::MatrixXd> svd(a, Eigen::ComputeFullV);
    x = svd.matrixV().col(cols - 1);
    const Eigen::VectorXd& sv = svd.singularValues();
    // Each edge is rank 2; a second (near) null vector means the shape is ambiguous.
    out.unique = cols < 2 || (sv.size() >= cols && sv(cols - 2) > 1e-6 * std::max(sv(0), 1e-300));
    auto centre = [&](int c) -> Eigen::Vector3d {
      return unknown_of[c] >= 0 ? Eigen::Vector3d(x.segment<3>(3 * unknown_of[c])) : Eigen::Vector3d::Zero();
    };
    double agree = 0.0;
    for (size_t k = 0; k < edges.size(); ++k) {
      agree += dir[k].dot(centre(graph.edges[edges[k]].cam_a) - centre(graph.edges[edges[k]].cam_b));
    }
    if (agree < 0) x = -x;
    // Re-weight by the inverse sine of each edge's angular residual (floored): an L1-like fit.
    for (size_t k = 0; k < edges.size(); ++k) {
      const Eigen::Vector3d d = centre(graph.edges[edges[k]].cam_a) - centre(graph.edges[edges[k]].cam_b);
      const double sin_residual = d.norm() > 1e-12 ? dir[k].cross(d.normalized()).norm() : 1.0;
      const double residual = dir[k].dot(d) < 0 ? 1.0 : sin_residual;  // pointing backwards: as bad as it gets
      weight[k] = 1.0 / std::max(residual, 1e-3);
    }
  }
  double mean_length = 0.0;
  for (int e : edges) {
    const ViewGraphEdge& g = graph.edges[e];
    const Eigen::Vector3d ca = unknown_of[g.cam_a] >= 0 ? Eigen::Vector3d(x.segment<3>(3 * unknown_of[g.cam_a]))
                                                        : Eigen::Vector3d::Zero();
    const Eigen::Vector3d cb = unknown_of[g.cam_b] >= 0 ? Eigen::Vector3d(x.segment<3>(3 * unknown_of[g.cam_b]))
                                                        : Eigen::Vector3d::Zero();
    mean_length += (ca - cb).norm() / edges.size();
  }
  const double scale = mean_length > 0 ? 1.0 / mean_length : 1.0;
  for (int c : cams) out.centre_in_rig[c] = scale * x.segment<3>(3 * unknown_of[c]);
  return out;
}

}  // namespace rigsim
