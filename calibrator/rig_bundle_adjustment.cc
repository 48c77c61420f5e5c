#include "calibrator/rig_bundle_adjustment.h"

#include <algorithm>
#include <cmath>
#include <map>
#include <numeric>
#include <stdexcept>

#include <Eigen/SVD>
#include <ceres/ceres.h>
#include <ceres/manifold.h>
#include <ceres/sphere_manifold.h>

namespace rigsim {
namespace {

Eigen::Matrix3d Skew(const Eigen::Vector3d& v) {
  Eigen::Matrix3d m;
  m << 0, -v.z(), v.y(), v.z(), 0, -v.x(), -v.y(), v.x(), 0;
  return m;
}

using ReprojectionCost = ceres::AutoDiffCostFunction<RigReprojectionResidual, 2, 4, 3, 3>;

struct Point {
  int track = -1;
  Eigen::Vector3d x = Eigen::Vector3d::Zero();
  std::vector<TrackObservation> observations;  // kept ones
};

// Plain reprojection error (px) of one observation; nullopt when the point does not project.
std::optional<double> ReprojectionError(const Camera& camera, const Rigid3d& cam_from_rig, const Eigen::Vector3d& x,
                                        const Eigen::Vector2d& observed) {
  const auto px = camera.ImgFromCam(cam_from_rig * x);
  if (!px) return std::nullopt;
  return (*px - observed).norm();
}

}  // namespace

std::vector<Track> BuildTracks(int num_cameras, int num_frames, const std::vector<PairMatches>& pairs,
                               int* num_conflicting) {
  for (const PairMatches& p : pairs) {
    if (p.cam_a < 0 || p.cam_b < 0 || p.cam_a >= num_cameras || p.cam_b >= num_cameras || p.cam_a == p.cam_b) {
      throw std::invalid_argument("BuildTracks: bad camera pair (" + std::to_string(p.cam_a) + ", " +
                                  std::to_string(p.cam_b) + ")");
    }
    if (static_cast<int>(p.per_frame.size()) != num_frames) {
      throw std::invalid_argument("BuildTracks: pair has " + std::to_string(p.per_frame.size()) + " frames, expected " +
                                  std::to_string(num_frames));
    }
  }
  std::vector<Track> tracks;
  int conflicting = 0;
  for (int f = 0; f < num_frames; ++f) {
    // Nodes: (camera, keypoint) -> dense id.
    std::map<std::pair<int, int>, int> node_of;
    std::vector<std::pair<int, int>> nodes;
    std::vector<int> parent;
    auto node = [&](int cam, int kp) {
      const auto [it, inserted] = node_of.try_emplace({cam, kp}, static_cast<int>(nodes.size()));
      if (inserted) {
        nodes.push_back({cam, kp});
        parent.push_back(it->second);
      }
      return it->second;
    };
    auto find = [&](int x) {
      while (parent[x] != x) x = parent[x] = parent[parent[x]];
      return x;
    };
    for (const PairMatches& p : pairs) {
      for (const auto& [ka, kb] : p.per_frame[f]) {
        const int a = find(node(p.cam_a, ka)), b = find(node(p.cam_b, kb));
        if (a != b) parent[std::max(a, b)] = std::min(a, b);
      }
    }
    // Group by root in node order (deterministic), observations sorted by camera.
    std::map<int, std::vector<TrackObservation>> groups;
    for (int i = 0; i < static_cast<int>(nodes.size()); ++i) groups[find(i)].push_back({nodes[i].first, nodes[i].second});
    for (auto& [root, obs] : groups) {
      std::sort(obs.begin(), obs.end(), [](const TrackObservation& x, const TrackObservation& y) {
        return x.camera < y.camera || (x.camera == y.camera && x.keypoint < y.keypoint);
      });
      bool conflict = false;
      for (size_t i = 1; i < obs.size(); ++i) conflict = conflict || obs[i].camera == obs[i - 1].camera;
      if (conflict) {
        ++conflicting;
        continue;
      }
      if (obs.size() >= 2) tracks.push_back({f, std::move(obs)});
    }
  }
  if (num_conflicting) *num_conflicting = conflicting;
  return tracks;
}

CameraCentres EstimateCameraCentres(const ViewGraph& graph,
                                    const std::vector<std::optional<Eigen::Quaterniond>>& cam_from_rig,
                                    int reference_camera, int reweighting_iterations) {
  const int n = graph.num_cameras;
  CameraCentres out;
  out.centre_in_rig.assign(n, std::nullopt);
  if (reference_camera < 0 || reference_camera >= n || !cam_from_rig.at(reference_camera)) return out;

  // Edges with a direction between cameras with rotations; the reference's component over them.
  std::vector<int> edges;
  std::vector<int> parent(n);
  std::iota(parent.begin(), parent.end(), 0);
  auto find = [&](int x) {
    while (parent[x] != x) x = parent[x] = parent[parent[x]];
    return x;
  };
  for (int e = 0; e < static_cast<int>(graph.edges.size()); ++e) {
    const ViewGraphEdge& g = graph.edges[e];
    if (!g.active || g.rotation_only || !cam_from_rig[g.cam_a] || !cam_from_rig[g.cam_b]) continue;
    edges.push_back(e);
    parent[find(g.cam_a)] = find(g.cam_b);
  }
  std::vector<int> unknown_of(n, -1);  // column block of each camera; the reference has none
  std::vector<int> cams;
  for (int c = 0; c < n; ++c) {
    if (c != reference_camera && cam_from_rig[c] && find(c) == find(reference_camera)) {
      unknown_of[c] = static_cast<int>(cams.size());
      cams.push_back(c);
    }
  }
  out.centre_in_rig[reference_camera] = Eigen::Vector3d::Zero();
  if (cams.empty()) return out;
  std::erase_if(edges, [&](int e) { return find(graph.edges[e].cam_a) != find(reference_camera); });
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
      const Eigen::Matrix3d s = weight[k] * Skew(dir[k]);
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

std::optional<Eigen::Vector3d> TriangulateTrack(const std::vector<Camera>& cameras, const FrameKeypoints& keypoints,
                                                const Track& track,
                                                const std::vector<std::optional<Rigid3d>>& cam_from_rig,
                                                double min_angle_rad) {
  std::vector<Eigen::Vector3d> origins, dirs;
  for (const TrackObservation& o : track.observations) {
    if (!cam_from_rig[o.camera]) continue;
    const auto f = cameras[o.camera].CamFromImg(keypoints[track.frame][o.camera][o.keypoint]);
    if (!f) continue;
    const Rigid3d rig_from_cam = cam_from_rig[o.camera]->Inverse();
    origins.push_back(rig_from_cam.translation);
    dirs.push_back((rig_from_cam.rotation * *f).normalized());
  }
  if (dirs.size() < 2) return std::nullopt;
  double max_angle = 0.0;
  for (size_t i = 0; i < dirs.size(); ++i) {
    for (size_t j = i + 1; j < dirs.size(); ++j) {
      max_angle = std::max(max_angle, std::atan2(dirs[i].cross(dirs[j]).norm(), dirs[i].dot(dirs[j])));
    }
  }
  if (max_angle < min_angle_rad) return std::nullopt;
  // Point closest to all rays: sum (I - d d^T)(X - o) = 0.
  Eigen::Matrix3d a = Eigen::Matrix3d::Zero();
  Eigen::Vector3d b = Eigen::Vector3d::Zero();
  for (size_t i = 0; i < dirs.size(); ++i) {
    const Eigen::Matrix3d p = Eigen::Matrix3d::Identity() - dirs[i] * dirs[i].transpose();
    a += p;
    b += p * origins[i];
  }
  const Eigen::Vector3d x = a.ldlt().solve(b);
  if (!x.allFinite()) return std::nullopt;
  // In front of every ray (the midpoint of two diverging rays lies behind them).
  for (size_t i = 0; i < dirs.size(); ++i) {
    if (dirs[i].dot(x - origins[i]) <= 0) return std::nullopt;
  }
  return x;
}

RigReprojectionResidual::RigReprojectionResidual(const Camera& camera, const Eigen::Vector2d& observed_px)
    : model(camera.model()), num_params(static_cast<int>(camera.params().size())), params_{}, observed(observed_px) {
  std::copy(camera.params().begin(), camera.params().end(), params_);
}

bool EvaluateRigReprojection(const Camera& camera, const Eigen::Vector2d& observed, const Eigen::Vector4d& rotation_xyzw,
                             const Eigen::Vector3d& translation, const Eigen::Vector3d& point_in_rig,
                             Eigen::Vector2d* residual, Eigen::Matrix<double, 2, 4>* d_rotation,
                             Eigen::Matrix<double, 2, 3>* d_translation, Eigen::Matrix<double, 2, 3>* d_point) {
  const ReprojectionCost cost(new RigReprojectionResidual(camera, observed));
  const double* params[3] = {rotation_xyzw.data(), translation.data(), point_in_rig.data()};
  Eigen::Matrix<double, 2, 4, Eigen::RowMajor> jq;
  Eigen::Matrix<double, 2, 3, Eigen::RowMajor> jt, jx;
  double* jacobians[3] = {jq.data(), jt.data(), jx.data()};
  double r[2];
  if (!cost.Evaluate(params, r, jacobians)) return false;
  if (residual) *residual = Eigen::Vector2d(r[0], r[1]);
  if (d_rotation) *d_rotation = jq;
  if (d_translation) *d_translation = jt;
  if (d_point) *d_point = jx;
  return true;
}

void RigBundleAdjustmentOptions::Check() const {
  auto fail = [](const std::string& why) { throw std::invalid_argument("RigBundleAdjustmentOptions: " + why); };
  if (!(min_triangulation_angle_deg >= 0)) fail("min_triangulation_angle_deg must be >= 0");
  if (!(loss_scale_px > 0)) fail("loss_scale_px must be > 0");
  if (!(max_reprojection_error_px > 0)) fail("max_reprojection_error_px must be > 0");
  if (filter_rounds < 0) fail("filter_rounds must be >= 0");
  if (max_iterations < 1) fail("max_iterations must be >= 1");
  if (num_threads < 1) fail("num_threads must be >= 1");
}

RigBundleAdjustmentResult RigBundleAdjust(const std::vector<Camera>& cameras, const FrameKeypoints& keypoints,
                                          const std::vector<Track>& tracks,
                                          const std::vector<std::optional<Rigid3d>>& initial_cam_from_rig,
                                          int reference_camera, int scale_camera,
                                          const RigBundleAdjustmentOptions& options) {
  options.Check();
  const int n = static_cast<int>(cameras.size());
  if (static_cast<int>(initial_cam_from_rig.size()) != n || reference_camera < 0 || reference_camera >= n ||
      !initial_cam_from_rig[reference_camera]) {
    throw std::invalid_argument("RigBundleAdjust: one initial pose per camera, the reference camera's given");
  }
  RigBundleAdjustmentResult result;
  result.num_tracks = static_cast<int>(tracks.size());
  result.cam_from_rig = initial_cam_from_rig;
  result.observations_per_camera.assign(n, 0);

  // Parameter blocks: quaternion (x, y, z, w) and translation per posed camera.
  std::vector<Eigen::Vector4d> q(n, Eigen::Vector4d(0, 0, 0, 1));
  std::vector<Eigen::Vector3d> t(n, Eigen::Vector3d::Zero());
  for (int c = 0; c < n; ++c) {
    if (!initial_cam_from_rig[c]) continue;
    q[c] = initial_cam_from_rig[c]->rotation.coeffs();
    t[c] = initial_cam_from_rig[c]->translation;
  }
  auto pose = [&](int c) { return Rigid3d(Eigen::Quaterniond(q[c].data()), t[c]); };
  auto observed = [&](int frame, const TrackObservation& o) -> const Eigen::Vector2d& {
    return keypoints[frame][o.camera][o.keypoint];
  };

  std::vector<Point> points;
  const double min_angle = DegToRad(options.min_triangulation_angle_deg);
  for (int i = 0; i < static_cast<int>(tracks.size()); ++i) {
    const auto x = TriangulateTrack(cameras, keypoints, tracks[i], initial_cam_from_rig, min_angle);
    if (!x) continue;
    Point p;
    p.track = i;
    p.x = *x;
    for (const TrackObservation& o : tracks[i].observations) {
      if (initial_cam_from_rig[o.camera] &&
          ReprojectionError(cameras[o.camera], *initial_cam_from_rig[o.camera], *x, observed(tracks[i].frame, o))) {
        p.observations.push_back(o);
      }
    }
    if (p.observations.size() >= 2) points.push_back(std::move(p));
  }

  // RMS of the plain reprojection errors over the kept observations.
  auto rms = [&]() {
    double sum = 0.0;
    int count = 0;
    for (const Point& p : points) {
      for (const TrackObservation& o : p.observations) {
        const auto e = ReprojectionError(cameras[o.camera], pose(o.camera), p.x, observed(tracks[p.track].frame, o));
        sum += e ? *e * *e : 0.0;
        ++count;
      }
    }
    return count > 0 ? std::sqrt(sum / count) : 0.0;
  };
  result.initial_rms_px = rms();

  for (int round = 0; round <= options.filter_rounds; ++round) {
    if (round > 0) {
      // Filter at the current solution; stop once nothing changes.
      int removed = 0;
      for (Point& p : points) {
        const size_t before = p.observations.size();
        std::erase_if(p.observations, [&](const TrackObservation& o) {
          const auto e = ReprojectionError(cameras[o.camera], pose(o.camera), p.x, observed(tracks[p.track].frame, o));
          return !e || *e > options.max_reprojection_error_px;
        });
        removed += static_cast<int>(before - p.observations.size());
      }
      std::erase_if(points, [](const Point& p) {
        return p.observations.size() < 2;
      });
      result.num_filtered_observations += removed;
      if (removed == 0) break;
    }
    if (points.empty()) break;

    ceres::Problem::Options problem_options;
    problem_options.manifold_ownership = ceres::TAKE_OWNERSHIP;
    problem_options.loss_function_ownership = ceres::TAKE_OWNERSHIP;
    ceres::Problem problem(problem_options);
    ceres::LossFunction* loss = new ceres::HuberLoss(options.loss_scale_px);
    for (Point& p : points) {
      for (const TrackObservation& o : p.observations) {
        problem.AddResidualBlock(
            new ReprojectionCost(new RigReprojectionResidual(cameras[o.camera], observed(tracks[p.track].frame, o))),
            loss, q[o.camera].data(), t[o.camera].data(), p.x.data());
      }
    }
    for (int c = 0; c < n; ++c) {
      if (!problem.HasParameterBlock(q[c].data())) continue;
      if (c == reference_camera) {
        problem.SetParameterBlockConstant(q[c].data());  // the gauge: camera 0 is the rig frame
        problem.SetParameterBlockConstant(t[c].data());
        continue;
      }
      problem.SetManifold(q[c].data(), new ceres::EigenQuaternionManifold);
      // The scale: its distance from the reference camera stays as given (|t| = |centre|).
      if (c == scale_camera && t[c].norm() > 0) problem.SetManifold(t[c].data(), new ceres::SphereManifold<3>);
    }
    ceres::Solver::Options solver_options;
    solver_options.linear_solver_type = ceres::SPARSE_SCHUR;
    solver_options.max_num_iterations = options.max_iterations;
    solver_options.function_tolerance = 1e-10;
    solver_options.parameter_tolerance = 1e-10;
    solver_options.num_threads = options.num_threads;
    solver_options.logging_type = ceres::SILENT;
    ceres::Solver::Summary summary;
    ceres::Solve(solver_options, &problem, &summary);
    result.iterations += static_cast<int>(summary.iterations.size());
  }

  for (int c = 0; c < n; ++c) {
    if (initial_cam_from_rig[c]) result.cam_from_rig[c] = pose(c);
  }
  result.num_points = static_cast<int>(points.size());
  for (const Point& p : points) {
    for (const TrackObservation& o : p.observations) ++result.observations_per_camera[o.camera];
    result.num_observations += static_cast<int>(p.observations.size());
  }
  result.reprojection_rms_px = rms();
  return result;
}

}  // namespace rigsim
