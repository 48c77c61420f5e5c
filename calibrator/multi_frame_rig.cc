#include "calibrator/multi_frame_rig.h"

#include <algorithm>
#include <functional>
#include <cmath>
#include <limits>
#include <map>
#include <numeric>
#include <stdexcept>

#include <Eigen/Eigenvalues>
#include <Eigen/SVD>
#include <ceres/ceres.h>
#include <ceres/manifold.h>
#include <ceres/sphere_manifold.h>
#include <glog/logging.h>

#include "calibrator/cost_functions.h"
#include "calibrator/format.h"

namespace rigsim {
namespace {

// Union-find over dense ids.
struct UnionFind {
  std::vector<int> parent;
  int Add() {
    parent.push_back(static_cast<int>(parent.size()));
    return parent.back();
  }
  int Find(int x) {
    while (parent[x] != x) x = parent[x] = parent[parent[x]];
    return x;
  }
  void Join(int a, int b) {
    a = Find(a);
    b = Find(b);
    if (a != b) parent[std::max(a, b)] = std::min(a, b);
  }
};

// Projection onto SO(3) of a 3x3 matrix (the chordal mean of rotations summed into it).
Eigen::Matrix3d ProjectToRotation(const Eigen::Matrix3d& m) {
  const Eigen::JacobiSVD<Eigen::Matrix3d> svd(m, Eigen::ComputeFullU | Eigen::ComputeFullV);
  Eigen::Matrix3d d = Eigen::Matrix3d::Identity();
  d(2, 2) = (svd.matrixU() * svd.matrixV().transpose()).determinant() < 0 ? -1.0 : 1.0;
  return svd.matrixU() * d * svd.matrixV().transpose();
}

// Least-squares point closest to the rays; nullopt when the rays span less than min_angle_rad or
// the point lies behind one of them.
std::optional<Eigen::Vector3d> TriangulateRays(const std::vector<Eigen::Vector3d>& origins,
                                               const std::vector<Eigen::Vector3d>& dirs, double min_angle_rad) {
  if (dirs.size() < 2) return std::nullopt;
  double max_angle = 0.0;
  for (size_t i = 0; i < dirs.size(); ++i) {
    for (size_t j = i + 1; j < dirs.size(); ++j) {
      max_angle = std::max(max_angle, std::atan2(dirs[i].cross(dirs[j]).norm(), dirs[i].dot(dirs[j])));
    }
  }
  if (max_angle < min_angle_rad) return std::nullopt;
  Eigen::Matrix3d a = Eigen::Matrix3d::Zero();
  Eigen::Vector3d b = Eigen::Vector3d::Zero();
  for (size_t i = 0; i < dirs.size(); ++i) {
    const Eigen::Matrix3d p = Eigen::Matrix3d::Identity() - dirs[i] * dirs[i].transpose();
    a += p;
    b += p * origins[i];
  }
  const Eigen::Vector3d x = a.ldlt().solve(b);
  if (!x.allFinite()) return std::nullopt;
  for (size_t i = 0; i < dirs.size(); ++i) {
    if (dirs[i].dot(x - origins[i]) <= 0) return std::nullopt;
  }
  return x;
}

std::optional<double> ReprojectionError(const Camera& camera, const Rigid3d& cam_from_world, const Eigen::Vector3d& x,
                                        const Eigen::Vector2d& observed) {
  const auto px = camera.ImgFromCam(cam_from_world * x);
  if (!px) return std::nullopt;
  return (*px - observed).norm();
}

struct WorldPoint {
  int track = -1;
  Eigen::Vector3d x = Eigen::Vector3d::Zero();
  std::vector<ViewObservation> observations;
};

}  // namespace

void RigBundleAdjustmentOptions::Check() const {
  auto fail = [](const std::string& why) { throw std::invalid_argument("RigBundleAdjustmentOptions: " + why); };
  if (!(min_triangulation_angle_deg >= 0)) fail("min_triangulation_angle_deg must be >= 0");
  if (!(loss_scale_px > 0)) fail("loss_scale_px must be > 0");
  if (!(max_reprojection_error_px > 0)) fail("max_reprojection_error_px must be > 0");
  if (filter_rounds < 0) fail("filter_rounds must be >= 0");
  if (coarse_points < 0) fail("coarse_points must be >= 0");
  if (max_iterations < 1) fail("max_iterations must be >= 1");
  if (num_threads < 1) fail("num_threads must be >= 1");
}

std::vector<ViewTrack> BuildViewTracks(int num_cameras, int num_frames, const std::vector<PairMatches>& pairs,
                                       const std::vector<TemporalPairEstimate>& temporal, int* num_conflicting) {
  for (const PairMatches& p : pairs) {
    if (p.cam_a < 0 || p.cam_b < 0 || p.cam_a >= num_cameras || p.cam_b >= num_cameras || p.cam_a == p.cam_b ||
        static_cast<int>(p.per_frame.size()) != num_frames) {
      throw std::invalid_argument("BuildViewTracks: bad camera pair (" + std::to_string(p.cam_a) + ", " +
                                  std::to_string(p.cam_b) + ") or number of frames");
    }
  }
  for (const TemporalPairEstimate& t : temporal) {
    if (t.camera < 0 || t.camera >= num_cameras || t.frame < 0 || t.frame + 1 >= num_frames) {
      throw std::invalid_argument("BuildViewTracks: temporal pair (camera " + std::to_string(t.camera) + ", frame " +
                                  std::to_string(t.frame) + ") out of range");
    }
  }
  std::map<std::tuple<int, int, int>, int> node_of;  // (frame, camera, keypoint) -> id
  std::vector<ViewObservation> nodes;
  UnionFind uf;
  auto node = [&](int cam, int frame, int kp) {
    const auto [it, inserted] = node_of.try_emplace({frame, cam, kp}, static_cast<int>(nodes.size()));
    if (inserted) {
      nodes.push_back({cam, frame, kp});
      uf.Add();
    }
    return it->second;
  };
  for (const PairMatches& p : pairs) {
    for (int f = 0; f < num_frames; ++f) {
      for (const auto& [ka, kb] : p.per_frame[f]) uf.Join(node(p.cam_a, f, ka), node(p.cam_b, f, kb));
    }
  }
  for (const TemporalPairEstimate& t : temporal) {
    if (!t.two_view.success) continue;
    for (const auto& [ka, kb] : t.inliers) uf.Join(node(t.camera, t.frame, ka), node(t.camera, t.frame + 1, kb));
  }
  // Nodes are ids in creation order; group by root, observations sorted by (frame, camera, kp).
  std::map<int, std::vector<ViewObservation>> groups;
  for (const auto& [key, id] : node_of) groups[uf.Find(id)].push_back(nodes[id]);
  std::vector<ViewTrack> tracks;
  int conflicting = 0;
  for (auto& [root, obs] : groups) {
    bool conflict = false;
    for (size_t i = 1; i < obs.size(); ++i) {
      conflict = conflict || (obs[i].frame == obs[i - 1].frame && obs[i].camera == obs[i - 1].camera);
    }
    if (conflict) {
      ++conflicting;
      continue;
    }
    if (obs.size() >= 2) tracks.push_back({std::move(obs)});
  }
  if (num_conflicting) *num_conflicting = conflicting;
  return tracks;
}

std::vector<std::optional<Eigen::Quaterniond>> EstimateRigRotations(
    int num_frames, const std::vector<std::optional<Eigen::Quaterniond>>& cam_from_rig,
    const std::vector<TemporalPairEstimate>& temporal) {
  std::vector<std::optional<Eigen::Quaterniond>> out(std::max(num_frames, 0));
  if (num_frames < 1) return out;
  out[0] = Eigen::Quaterniond::Identity();
  for (int k = 0; k + 1 < num_frames; ++k) {
    std::vector<Eigen::Matrix3d> motions;  // R_{k+1} R_k^T seen by each camera
    for (const TemporalPairEstimate& t : temporal) {
      if (t.frame != k || !t.two_view.success || t.camera < 0 || t.camera >= static_cast<int>(cam_from_rig.size()) ||
          !cam_from_rig[t.camera]) {
        continue;
      }
      const Eigen::Matrix3d q = cam_from_rig[t.camera]->toRotationMatrix();
      motions.push_back(q.transpose() * t.two_view.cam_b_from_cam_a.RotationMatrix() * q);
    }
    if (motions.empty()) break;  // frame k+1 and after: not chained
    // Robust: the motion closest to all others (sum of angles), then the chordal mean of those
    // within 2 deg of it.
    auto angle = [](const Eigen::Matrix3d& a, const Eigen::Matrix3d& b) {
      return Eigen::AngleAxisd(a * b.transpose()).angle();
    };
    size_t best = 0;
    double best_sum = std::numeric_limits<double>::infinity();
    for (size_t i = 0; i < motions.size(); ++i) {
      double sum = 0.0;
      for (const Eigen::Matrix3d& m : motions) sum += angle(motions[i], m);
      if (sum < best_sum) {
        best_sum = sum;
        best = i;
      }
    }
    Eigen::Matrix3d sum = Eigen::Matrix3d::Zero();
    for (const Eigen::Matrix3d& m : motions) {
      if (angle(motions[best], m) < DegToRad(2.0)) sum += m;
    }
    out[k + 1] = Eigen::Quaterniond(ProjectToRotation(sum) * out[k]->toRotationMatrix()).normalized();
  }
  return out;
}

namespace {

// A track's observation as a ray in the world, through its view's known rotation.
struct Ray {
  int camera, frame;
  Eigen::Vector3d dir;
};

// The rays of each track with >= 2 posed views spanning at least `min_angle` (rad): the tracks
// whose point, hence whose constraint on the positions, has a determined depth.
std::vector<std::vector<Ray>> UsableRays(const std::vector<Camera>& cameras, const FrameKeypoints& keypoints,
                                         const std::vector<ViewTrack>& tracks,
                                         const std::vector<std::optional<Eigen::Quaterniond>>& cam_from_rig,
                                         const std::vector<std::optional<Eigen::Quaterniond>>& rig_from_world,
                                         double min_angle) {
  std::vector<std::vector<Ray>> rays;
  for (const ViewTrack& t : tracks) {
    std::vector<Ray> r;
    for (const ViewObservation& o : t.observations) {
      if (!cam_from_rig[o.camera] || !rig_from_world[o.frame]) continue;
      const auto f = cameras[o.camera].CamFromImg(keypoints[o.frame][o.camera][o.keypoint]);
      if (!f) continue;
      const Eigen::Quaterniond world_from_cam = (*cam_from_rig[o.camera] * *rig_from_world[o.frame]).conjugate();
      r.push_back({o.camera, o.frame, (world_from_cam * *f).normalized()});
    }
    if (r.size() < 2) continue;
    double max_angle = 0.0;
    for (size_t i = 0; i < r.size() && max_angle < min_angle; ++i) {
      for (size_t j = i + 1; j < r.size(); ++j) {
        max_angle = std::max(max_angle, std::atan2(r[i].dir.cross(r[j].dir).norm(), r[i].dir.dot(r[j].dir)));
      }
    }
    if (max_angle >= min_angle) rays.push_back(std::move(r));
  }
  return rays;
}

// The unknowns of the linear position system: the cameras and frames whose views the rays link to
// view (camera 0, frame 0), and their 3-column blocks in x (frames k > 0 first, then cameras
// c > 0; -1 for the references and the ones left out).
struct PositionUnknowns {
  std::vector<char> cam_in, frame_in;
  std::vector<int> frame_block, cam_block;
  int blocks = 0;
  int cams_solved = 0;  // cameras other than camera 0
};

PositionUnknowns ChooseUnknowns(int n, int num_frames, const std::vector<std::vector<Ray>>& rays,
                                const std::vector<std::optional<Eigen::Quaterniond>>& cam_from_rig,
                                const std::vector<std::optional<Eigen::Quaterniond>>& rig_from_world, bool static_rig) {
  UnionFind uf;
  for (int i = 0; i < n * num_frames; ++i) uf.Add();
  for (const auto& r : rays) {
    for (size_t i = 1; i < r.size(); ++i) uf.Join(r[0].frame * n + r[0].camera, r[i].frame * n + r[i].camera);
  }
  if (static_rig) {  // every frame's rig is at the origin: a camera's views are one
    for (int k = 1; k < num_frames; ++k) {
      for (int c = 0; c < n; ++c) uf.Join(c, k * n + c);
    }
  }
  PositionUnknowns u;
  u.cam_in.assign(n, 0);
  u.frame_in.assign(num_frames, 0);
  for (int k = 0; k < num_frames; ++k) {
    for (int c = 0; c < n; ++c) {
      if (uf.Find(k * n + c) == uf.Find(0) && cam_from_rig[c] && rig_from_world[k]) u.cam_in[c] = u.frame_in[k] = 1;
    }
  }
  u.frame_block.assign(num_frames, -1);
  u.cam_block.assign(n, -1);
  for (int k = 1; k < num_frames; ++k) {
    if (u.frame_in[k] && !static_rig) u.frame_block[k] = u.blocks++;
  }
  for (int c = 1; c < n; ++c) {
    if (u.cam_in[c]) u.cam_block[c] = u.blocks++;
  }
  for (int c = 1; c < n; ++c) u.cams_solved += u.cam_in[c];
  return u;
}

// The solution of the position system: x (up to scale) and the eigenvalues of its quadratic form.
struct PositionSolution {
  Eigen::VectorXd x;
  Eigen::VectorXd eigenvalues;
};

// centre(c, k) = C_k + R_k^T o_c is linear in x; each track's point is eliminated in closed form
// (a Schur complement per track), leaving a quadratic form whose smallest eigenvector is x. Then
// re-weighted by depth (the ray constraint's size is depth x angle) and robustly (Cauchy on a
// track's RMS angular residual), `options.reweighting_iterations` times.
PositionSolution SolvePositionSystem(const std::vector<std::vector<Ray>>& rays, const PositionUnknowns& u,
                                     const std::vector<std::optional<Eigen::Quaterniond>>& rig_from_world,
                                     const RigPositionOptions& options) {
  const int num_frames = static_cast<int>(rig_from_world.size());
  const int dim = 3 * u.blocks;
  std::vector<Eigen::Matrix3d> rig_t(num_frames, Eigen::Matrix3d::Identity());  // R_k^T
  for (int k = 0; k < num_frames; ++k) {
    if (rig_from_world[k]) rig_t[k] = rig_from_world[k]->toRotationMatrix().transpose();
  }
  // centre(c, k) = sum over its (at most two) blocks of M * x_block.
  struct Term {
    int block;
    Eigen::Matrix3d m;
  };
  auto centre_terms = [&](int c, int k) {
    std::vector<Term> terms;
    if (u.frame_block[k] >= 0) terms.push_back({u.frame_block[k], Eigen::Matrix3d::Identity()});
    if (u.cam_block[c] >= 0) terms.push_back({u.cam_block[c], rig_t[k]});
    return terms;
  };
  auto centre_of = [&](const Eigen::VectorXd& x, int c, int k) {
    Eigen::Vector3d v = Eigen::Vector3d::Zero();
    for (const Term& t : centre_terms(c, k)) v += t.m * x.segment<3>(3 * t.block);
    return v;
  };

  std::vector<std::vector<double>> weight(rays.size());
  for (size_t i = 0; i < rays.size(); ++i) weight[i].assign(rays[i].size(), 1.0);
  PositionSolution out;
  out.x = Eigen::VectorXd::Zero(dim);
  Eigen::VectorXd& x = out.x;
  for (int iter = 0; iter <= options.reweighting_iterations; ++iter) {
    Eigen::MatrixXd q = Eigen::MatrixXd::Zero(dim, dim);
    for (size_t i = 0; i < rays.size(); ++i) {
      const auto& r = rays[i];
      // A = sum w P, B = sum w P J (per block), q += sum w J^T P J - B^T A^-1 B.
      Eigen::Matrix3d a = Eigen::Matrix3d::Zero();
      std::map<int, Eigen::Matrix3d> b;
      for (size_t j = 0; j < r.size(); ++j) {
        const Eigen::Matrix3d p = weight[i][j] * (Eigen::Matrix3d::Identity() - r[j].dir * r[j].dir.transpose());
        a += p;
        const std::vector<Term> terms = centre_terms(r[j].camera, r[j].frame);
        for (const Term& t1 : terms) {
          auto [it, inserted] = b.try_emplace(t1.block, Eigen::Matrix3d::Zero());
          it->second += p * t1.m;
          for (const Term& t2 : terms) {
            q.block<3, 3>(3 * t1.block, 3 * t2.block) += t1.m.transpose() * p * t2.m;
          }
        }
      }
      const Eigen::Matrix3d a_inv = a.inverse();
      if (!a_inv.allFinite()) continue;
      for (const auto& [b1, m1] : b) {
        for (const auto& [b2, m2] : b) q.block<3, 3>(3 * b1, 3 * b2) -= m1.transpose() * a_inv * m2;
      }
    }
    q = 0.5 * (q + q.transpose());
    const Eigen::SelfAdjointEigenSolver<Eigen::MatrixXd> eig(q);
    out.eigenvalues = eig.eigenvalues();
    x = eig.eigenvectors().col(0);

    // Points, sign (in front of the rays) and the next weights.
    double front = 0.0;
    std::vector<std::vector<double>> depth(rays.size()), residual(rays.size());
    for (size_t i = 0; i < rays.size(); ++i) {
      const auto& r = rays[i];
      Eigen::Matrix3d a = Eigen::Matrix3d::Zero();
      Eigen::Vector3d rhs = Eigen::Vector3d::Zero();
      std::vector<Eigen::Vector3d> centres;
      for (size_t j = 0; j < r.size(); ++j) {
        const Eigen::Matrix3d p = weight[i][j] * (Eigen::Matrix3d::Identity() - r[j].dir * r[j].dir.transpose());
        centres.push_back(centre_of(x, r[j].camera, r[j].frame));
        a += p;
        rhs += p * centres.back();
      }
      const Eigen::Vector3d pt = a.ldlt().solve(rhs);
      for (size_t j = 0; j < r.size(); ++j) {
        const Eigen::Vector3d d = pt - centres[j];
        front += r[j].dir.dot(d) > 0 ? 1.0 : -1.0;
        depth[i].push_back(d.norm());
        residual[i].push_back(d.norm() > 1e-12 ? r[j].dir.cross(d / d.norm()).norm() : 1.0);
      }
    }
    if (front < 0) x = -x;
    for (size_t i = 0; i < rays.size(); ++i) {
      double sq = 0.0;
      for (double e : residual[i]) sq += e * e;
      const double rms = std::sqrt(sq / residual[i].size());
      const double robust = 1.0 / (1.0 + (rms / options.loss_scale_rad) * (rms / options.loss_scale_rad));
      for (size_t j = 0; j < rays[i].size(); ++j) {
        // Angular residuals: the ray constraint's size is depth x angle.
        weight[i][j] = robust / std::max(depth[i][j] * depth[i][j], 1e-12);
      }
    }
  }
  return out;
}

}  // namespace

void RigPositionOptions::Check() const {
  auto fail = [](const std::string& why) { throw std::invalid_argument("RigPositionOptions: " + why); };
  if (!(min_ray_angle_deg >= 0)) fail("min_ray_angle_deg must be >= 0");
  if (!(loss_scale_rad > 0)) fail("loss_scale_rad must be > 0");
  if (reweighting_iterations < 0) fail("reweighting_iterations must be >= 0");
  if (!(min_eigenvalue_ratio >= 1)) fail("min_eigenvalue_ratio must be >= 1");
}

RigPositions EstimateRigPositions(const std::vector<Camera>& cameras, const FrameKeypoints& keypoints,
                                  const std::vector<ViewTrack>& tracks,
                                  const std::vector<std::optional<Eigen::Quaterniond>>& cam_from_rig,
                                  const std::vector<std::optional<Eigen::Quaterniond>>& rig_from_world,
                                  const RigPositionOptions& options, bool static_rig) {
  options.Check();
  const int n = static_cast<int>(cameras.size());
  const int num_frames = static_cast<int>(keypoints.size());
  if (static_cast<int>(cam_from_rig.size()) != n || static_cast<int>(rig_from_world.size()) != num_frames) {
    throw std::invalid_argument("EstimateRigPositions: one rotation per camera and per frame");
  }
  RigPositions out;
  out.centre_in_rig.assign(n, std::nullopt);
  out.rig_centre_in_world.assign(num_frames, std::nullopt);
  if (n == 0 || num_frames == 0 || !cam_from_rig[0] || !rig_from_world[0]) {
    out.reason = "camera 0 or frame 0 has no rotation";
    return out;
  }
  std::vector<std::vector<Ray>> rays =
      UsableRays(cameras, keypoints, tracks, cam_from_rig, rig_from_world, DegToRad(options.min_ray_angle_deg));
  const PositionUnknowns u = ChooseUnknowns(n, num_frames, rays, cam_from_rig, rig_from_world, static_rig);
  out.centre_in_rig[0] = Eigen::Vector3d::Zero();
  out.rig_centre_in_world[0] = Eigen::Vector3d::Zero();
  if (u.cams_solved == 0) {
    out.reason = "no track links another camera to camera 0";
    return out;
  }
  std::erase_if(rays, [&](const std::vector<Ray>& r) { return !u.cam_in[r[0].camera] || !u.frame_in[r[0].frame]; });
  for (auto& r : rays) {
    std::erase_if(r, [&](const Ray& x) { return !u.cam_in[x.camera] || !u.frame_in[x.frame]; });
  }
  std::erase_if(rays, [](const std::vector<Ray>& r) { return r.size() < 2; });
  out.tracks_used = static_cast<int>(rays.size());
  const PositionSolution solution = SolvePositionSystem(rays, u, rig_from_world, options);
  const Eigen::VectorXd& x = solution.x;
  const Eigen::VectorXd& eigenvalues = solution.eigenvalues;

  const double l0_raw = eigenvalues.size() > 0 ? eigenvalues(0) : 0.0;
  const double l1 = eigenvalues.size() > 1 ? eigenvalues(1) : std::numeric_limits<double>::infinity();
  const double lmax = eigenvalues.size() > 0 ? eigenvalues(eigenvalues.size() - 1) : 0.0;
  // The matrix is positive semi-definite in exact arithmetic; rounding moves its eigenvalues by
  // about 2e-16 x lmax. A smallest eigenvalue far below zero means near-singular points broke the
  // elimination, and the system decides nothing (measured: -0.009 against lmax 6e9 on a
  // forward-moving ring whose positions then came out 57-117 deg wrong; clamped to 0, it had
  // passed as infinitely determined).
  const double noise = 1e-13 * lmax;
  const double l0 = std::max(l0_raw, 0.0);
  out.eigenvalue_ratio = l0 > 0 ? l1 / l0 : std::numeric_limits<double>::infinity();
  out.unique = u.blocks > 0 && l0_raw >= -noise && l1 >= options.min_eigenvalue_ratio * l0 && l1 > 1e-12 * lmax;
  if (!out.unique) {
    out.reason = l0_raw < -noise ? "the tracks leave the positions undetermined (the linear system is indefinite: "
                                   "smallest eigenvalue " + std::to_string(l0_raw) + ")"
                                 : !(l1 > 1e-12 * lmax)
                                     ? "the tracks leave the positions ambiguous (the two smallest eigenvalues of "
                                       "the linear system are both next to zero: more than one direction is free)"
                                     : "the tracks leave the positions ambiguous (the second smallest eigenvalue of "
                                       "the linear system is " + Fixed(out.eigenvalue_ratio, 1) +
                                           " times the smallest; determined positions need " +
                                           Fixed(options.min_eigenvalue_ratio, 1) + ")";
    return out;
  }
  double mean = 0.0;
  for (int c = 1; c < n; ++c) {
    if (u.cam_block[c] >= 0) mean += x.segment<3>(3 * u.cam_block[c]).norm() / u.cams_solved;
  }
  if (!(mean > 1e-12)) {
    out.unique = false;
    out.reason = "every camera centre coincides with camera 0's";
    return out;
  }
  for (int c = 1; c < n; ++c) {
    if (u.cam_block[c] >= 0) out.centre_in_rig[c] = x.segment<3>(3 * u.cam_block[c]) / mean;
  }
  for (int k = 1; k < num_frames; ++k) {
    if (u.frame_block[k] >= 0) out.rig_centre_in_world[k] = x.segment<3>(3 * u.frame_block[k]) / mean;
    if (static_rig && u.frame_in[k]) out.rig_centre_in_world[k] = Eigen::Vector3d::Zero();
  }
  return out;
}

namespace {

// Covariance of each camera's centre in the rig (C = -R^T t of cam_from_rig, whose translation
// block is `ct[c]`) at the solution: the inverse of J^T J (robustified Jacobian, in the tangent
// spaces of the manifolds) over the poses after the points are eliminated (Schur complement),
// scaled by the variance of one residual coordinate estimated from the reprojection RMS. The
// gauge is fixed by the problem itself (camera 0 and frame 0 constant, the scale camera's |t|).
// Directions the data barely fix have tiny eigenvalues in the reduced system and come out with a
// huge variance (a pseudo-inverse, not a failure: a camera next to camera 0 must read as
// uncertain, not as missing). nullopt for cameras not adjusted.
std::vector<std::optional<Eigen::Matrix3d>> CentreCovariances(ceres::Problem& problem,
                                                              const std::vector<double*>& pose_blocks,
                                                              const std::vector<Eigen::Vector4d>& cq,
                                                              const std::vector<Eigen::Vector3d>& ct, double rms_px) {
  std::vector<std::optional<Eigen::Matrix3d>> out(ct.size());
  // The adjusted pose blocks first, in `pose_blocks` order, then the points. Ceres lists its
  // blocks in the order of their addresses, which differ from run to run: summed in that order
  // the reduced system, and so the covariance, would change in its last bits between runs. The
  // points live in one array, so their address order is their order there.
  std::vector<double*> all, poses, points;
  problem.GetParameterBlocks(&all);
  for (double* block : pose_blocks) {
    if (problem.HasParameterBlock(block) && !problem.IsParameterBlockConstant(block)) poses.push_back(block);
  }
  for (double* block : all) {
    if (problem.IsParameterBlockConstant(block)) continue;
    if (std::find(pose_blocks.begin(), pose_blocks.end(), block) == pose_blocks.end()) points.push_back(block);
  }
  std::sort(points.begin(), points.end(), std::less<double*>());
  std::map<const double*, int> offset;  // tangent column of each pose block
  int pose_dim = 0;
  for (double* block : poses) {
    offset[block] = pose_dim;
    pose_dim += problem.ParameterBlockTangentSize(block);
  }
  if (pose_dim == 0) return out;
  std::vector<double*> ordered = poses;
  ordered.insert(ordered.end(), points.begin(), points.end());
  ceres::Problem::EvaluateOptions evaluate;
  evaluate.parameter_blocks = ordered;
  ceres::CRSMatrix jacobian;
  if (!problem.Evaluate(evaluate, nullptr, nullptr, nullptr, &jacobian)) return out;

  // Rows of one point's observations touch its 3 columns and some pose columns.
  const int num_points = static_cast<int>(points.size());
  Eigen::MatrixXd h_poses = Eigen::MatrixXd::Zero(pose_dim, pose_dim);
  std::vector<Eigen::Matrix3d> h_point(num_points, Eigen::Matrix3d::Zero());
  std::vector<Eigen::MatrixXd> h_cross(num_points);  // pose_dim x 3
  for (int row = 0; row < jacobian.num_rows; ++row) {
    Eigen::VectorXd jp = Eigen::VectorXd::Zero(pose_dim);
    Eigen::Vector3d jx = Eigen::Vector3d::Zero();
    int point = -1;
    for (int k = jacobian.rows[row]; k < jacobian.rows[row + 1]; ++k) {
      const int col = jacobian.cols[k];
      if (col < pose_dim) {
        jp[col] = jacobian.values[k];
      } else {
        point = (col - pose_dim) / 3;
        jx[(col - pose_dim) % 3] = jacobian.values[k];
      }
    }
    h_poses.noalias() += jp * jp.transpose();
    if (point < 0) continue;
    if (h_cross[point].size() == 0) h_cross[point] = Eigen::MatrixXd::Zero(pose_dim, 3);
    h_point[point] += jx * jx.transpose();
    h_cross[point].noalias() += jp * jx.transpose();
  }
  // Eliminate the points: S = H_cc - sum_p H_cp H_pp^+ H_pc.
  Eigen::MatrixXd reduced = h_poses;
  for (int p = 0; p < num_points; ++p) {
    if (h_cross[p].size() == 0) continue;
    const Eigen::SelfAdjointEigenSolver<Eigen::Matrix3d> eig(h_point[p]);
    const double top = eig.eigenvalues().maxCoeff();
    Eigen::Vector3d inv = Eigen::Vector3d::Zero();
    for (int i = 0; i < 3; ++i) {
      if (eig.eigenvalues()[i] > 1e-12 * top) inv[i] = 1.0 / eig.eigenvalues()[i];
    }
    const Eigen::Matrix3d h_point_inv = eig.eigenvectors() * inv.asDiagonal() * eig.eigenvectors().transpose();
    reduced.noalias() -= h_cross[p] * h_point_inv * h_cross[p].transpose();
  }
  // Pseudo-inverse of the reduced system: directions with (next to) no information get a variance
  // 1e12 times the best determined one's, instead of an infinity or a failure.
  const Eigen::SelfAdjointEigenSolver<Eigen::MatrixXd> eig(0.5 * (reduced + reduced.transpose()));
  const double top = std::max(eig.eigenvalues().maxCoeff(), 1e-300);
  Eigen::VectorXd inv(pose_dim);
  for (int i = 0; i < pose_dim; ++i) inv[i] = 1.0 / std::max(eig.eigenvalues()[i], 1e-12 * top);
  const Eigen::MatrixXd covariance = eig.eigenvectors() * inv.asDiagonal() * eig.eigenvectors().transpose();

  const double variance = 0.5 * rms_px * rms_px;  // per image coordinate
  for (size_t c = 0; c < ct.size(); ++c) {
    const auto it = offset.find(ct[c].data());
    if (it == offset.end()) continue;
    const int size = problem.ParameterBlockTangentSize(ct[c].data());
    const Eigen::MatrixXd tangent = covariance.block(it->second, it->second, size, size);
    Eigen::Matrix3d t_cov = Eigen::Matrix3d::Zero();
    if (const ceres::Manifold* manifold = problem.GetManifold(ct[c].data())) {  // the scale camera: |t| held
      Eigen::Matrix<double, 3, Eigen::Dynamic, Eigen::RowMajor> plus(3, size);
      manifold->PlusJacobian(ct[c].data(), plus.data());
      t_cov = plus * tangent * plus.transpose();
    } else {
      t_cov = tangent;
    }
    const Eigen::Matrix3d r = Eigen::Quaterniond(cq[c].data()).toRotationMatrix();
    out[c] = variance * r.transpose() * t_cov * r;  // C = -R^T t; R's own uncertainty is far smaller
  }
  return out;
}

}  // namespace

namespace {

// The bundle adjustment's unknowns as Ceres parameter blocks: per camera cam_from_rig (rotation
// x, y, z, w; translation) and its intrinsics (held constant), per frame rig_from_world; and
// what the observations refer to.
struct BundleProblem {
  const std::vector<Camera>& cameras;
  const FrameKeypoints& keypoints;
  const std::vector<ViewTrack>& tracks;
  const std::vector<std::optional<Rigid3d>>& initial_cam_from_rig;
  const std::vector<std::optional<Rigid3d>>& initial_rig_from_world;
  std::vector<Eigen::Vector4d> cq, rq;
  std::vector<Eigen::Vector3d> ct, rt;
  std::vector<std::vector<double>> intrinsics;

  BundleProblem(const std::vector<Camera>& cameras, const FrameKeypoints& keypoints, const std::vector<ViewTrack>& tracks,
                const std::vector<std::optional<Rigid3d>>& initial_cam_from_rig,
                const std::vector<std::optional<Rigid3d>>& initial_rig_from_world)
      : cameras(cameras),
        keypoints(keypoints),
        tracks(tracks),
        initial_cam_from_rig(initial_cam_from_rig),
        initial_rig_from_world(initial_rig_from_world),
        cq(cameras.size(), Eigen::Vector4d(0, 0, 0, 1)),
        rq(keypoints.size(), Eigen::Vector4d(0, 0, 0, 1)),
        ct(cameras.size(), Eigen::Vector3d::Zero()),
        rt(keypoints.size(), Eigen::Vector3d::Zero()) {
    for (size_t c = 0; c < cameras.size(); ++c) {
      intrinsics.push_back(cameras[c].params());
      if (!initial_cam_from_rig[c]) continue;
      cq[c] = initial_cam_from_rig[c]->rotation.coeffs();
      ct[c] = initial_cam_from_rig[c]->translation;
    }
    for (size_t k = 0; k < keypoints.size(); ++k) {
      if (!initial_rig_from_world[k]) continue;
      rq[k] = initial_rig_from_world[k]->rotation.coeffs();
      rt[k] = initial_rig_from_world[k]->translation;
    }
  }

  bool Posed(const ViewObservation& o) const { return initial_cam_from_rig[o.camera] && initial_rig_from_world[o.frame]; }
  Rigid3d ViewPose(const ViewObservation& o) const {
    return Rigid3d(Eigen::Quaterniond(cq[o.camera].data()), ct[o.camera]) *
           Rigid3d(Eigen::Quaterniond(rq[o.frame].data()), rt[o.frame]);
  }
  const Eigen::Vector2d& Observed(const ViewObservation& o) const { return keypoints[o.frame][o.camera][o.keypoint]; }
  std::optional<double> Error(const WorldPoint& p, const ViewObservation& o) const {
    return ReprojectionError(cameras[o.camera], ViewPose(o), p.x, Observed(o));
  }

  // Points triangulated from the current poses (rays spanning at least `min_angle_rad`), each
  // keeping the observations that reproject within `max_error_px`.
  std::vector<WorldPoint> Triangulate(double min_angle_rad, double max_error_px) const {
    std::vector<WorldPoint> points;
    for (int i = 0; i < static_cast<int>(tracks.size()); ++i) {
      std::vector<Eigen::Vector3d> origins, dirs;
      for (const ViewObservation& o : tracks[i].observations) {
        if (!Posed(o)) continue;
        const auto f = cameras[o.camera].CamFromImg(Observed(o));
        if (!f) continue;
        const Rigid3d world_from_cam = ViewPose(o).Inverse();
        origins.push_back(world_from_cam.translation);
        dirs.push_back((world_from_cam.rotation * *f).normalized());
      }
      const auto x = TriangulateRays(origins, dirs, min_angle_rad);
      if (!x) continue;
      WorldPoint p;
      p.track = i;
      p.x = *x;
      for (const ViewObservation& o : tracks[i].observations) {
        if (!Posed(o)) continue;
        const auto e = Error(p, o);
        if (e && *e <= max_error_px) p.observations.push_back(o);
      }
      if (p.observations.size() >= 2) points.push_back(std::move(p));
    }
    return points;
  }

  double RmsPx(const std::vector<WorldPoint>& points) const {
    double sum = 0.0;
    int count = 0;
    for (const WorldPoint& p : points) {
      for (const ViewObservation& o : p.observations) {
        const auto e = Error(p, o);
        sum += e ? *e * *e : 0.0;
        ++count;
      }
    }
    return count > 0 ? std::sqrt(sum / count) : 0.0;
  }

  // Every observation's reprojection error (px); behind the camera counts as infinite.
  std::vector<double> Residuals(const std::vector<WorldPoint>& points) const {
    std::vector<double> out;
    for (const WorldPoint& p : points) {
      for (const ViewObservation& o : p.observations) {
        const auto e = Error(p, o);
        out.push_back(e ? *e : std::numeric_limits<double>::infinity());
      }
    }
    return out;
  }

  // Removes the observations reprojecting beyond `max_error_px` (or behind their camera), then
  // the points left with fewer than two. Returns the observations removed.
  int Filter(std::vector<WorldPoint>* points, double max_error_px) const {
    int removed = 0;
    for (WorldPoint& p : *points) {
      const size_t before = p.observations.size();
      std::erase_if(p.observations, [&](const ViewObservation& o) {
        const auto e = Error(p, o);
        return !e || *e > max_error_px;
      });
      removed += static_cast<int>(before - p.observations.size());
    }
    std::erase_if(*points, [](const WorldPoint& p) { return p.observations.size() < 2; });
    return removed;
  }
};

// How one solve of SolveBundle is set up.
struct BundleRound {
  size_t point_stride = 1;  // every point, or an even subsample (the coarse first solve)
  bool final_round = false;
  int scale_camera = -1;
  bool hold_frames = false;
};

struct BundleRoundResult {
  int iterations = 0;
  std::vector<std::optional<Eigen::Matrix3d>> centre_covariance;  // final round only
};

// One Levenberg-Marquardt solve over the points (every `point_stride`-th) and the poses they see,
// updating the poses in `bp` and the points in place; the final round also yields the camera
// centres' covariances.
BundleRoundResult SolveBundle(BundleProblem& bp, std::vector<WorldPoint>& points, const BundleRound& round,
                              const RigBundleAdjustmentOptions& options) {
  const int n = static_cast<int>(bp.cameras.size());
  const int num_frames = static_cast<int>(bp.keypoints.size());
  ceres::Problem::Options problem_options;
  problem_options.manifold_ownership = ceres::TAKE_OWNERSHIP;
  problem_options.loss_function_ownership = ceres::TAKE_OWNERSHIP;
  ceres::Problem problem(problem_options);
  ceres::LossFunction* loss = new ceres::HuberLoss(options.loss_scale_px);
  for (size_t i = 0; i < points.size(); i += round.point_stride) {
    WorldPoint& p = points[i];
    for (const ViewObservation& o : p.observations) {
      problem.AddResidualBlock(CreateRigReprojectionCost(bp.cameras[o.camera], bp.Observed(o)), loss,
                               {bp.cq[o.camera].data(), bp.ct[o.camera].data(), bp.rq[o.frame].data(),
                                bp.rt[o.frame].data(), p.x.data(), bp.intrinsics[o.camera].data()});
    }
  }
  for (int c = 0; c < n; ++c) {
    if (!problem.HasParameterBlock(bp.cq[c].data())) continue;
    problem.SetParameterBlockConstant(bp.intrinsics[c].data());  // the intrinsics are not refined
    if (c == 0) {  // camera 0 is the rig frame
      problem.SetParameterBlockConstant(bp.cq[c].data());
      problem.SetParameterBlockConstant(bp.ct[c].data());
      continue;
    }
    problem.SetManifold(bp.cq[c].data(), new ceres::EigenQuaternionManifold);
    if (c == round.scale_camera && bp.ct[c].norm() > 0) problem.SetManifold(bp.ct[c].data(), new ceres::SphereManifold<3>);
  }
  for (int k = 0; k < num_frames; ++k) {
    if (!problem.HasParameterBlock(bp.rq[k].data())) continue;
    if (k == 0 || round.hold_frames) {  // frame 0's rig frame is the world
      problem.SetParameterBlockConstant(bp.rq[k].data());
      problem.SetParameterBlockConstant(bp.rt[k].data());
      continue;
    }
    problem.SetManifold(bp.rq[k].data(), new ceres::EigenQuaternionManifold);
  }
  ceres::Solver::Options solver_options;
  // A few poses and many points: the reduced camera system is small and dense.
  solver_options.linear_solver_type = ceres::DENSE_SCHUR;
  solver_options.max_num_iterations = options.max_iterations;
  // The rounds before the last only decide which observations to filter: a coarse solve is
  // enough there (with the final tolerance it takes 150 of 155 iterations on the demo ring).
  // The last stops at a relative cost change of 1e-6: beyond it Levenberg-Marquardt crawls
  // 100 iterations (4.6 s on a 6-camera ring) for 3e-5 of the cost and no change in the
  // poses at 0.001 deg.
  solver_options.function_tolerance = round.final_round ? 1e-6 : 1e-5;
  solver_options.parameter_tolerance = round.final_round ? 1e-10 : 1e-5;
  solver_options.num_threads = options.num_threads;
  solver_options.logging_type = ceres::SILENT;
  ceres::Solver::Summary summary;
  ceres::Solve(solver_options, &problem, &summary);
  BundleRoundResult out;
  out.iterations = static_cast<int>(summary.iterations.size());
  if (round.final_round) {
    std::vector<double*> pose_blocks;
    for (int c = 0; c < n; ++c) pose_blocks.insert(pose_blocks.end(), {bp.cq[c].data(), bp.ct[c].data()});
    for (int k = 0; k < num_frames; ++k) pose_blocks.insert(pose_blocks.end(), {bp.rq[k].data(), bp.rt[k].data()});
    out.centre_covariance = CentreCovariances(problem, pose_blocks, bp.cq, bp.ct, bp.RmsPx(points));
  }
  return out;
}

}  // namespace

MultiFrameBundleAdjustmentResult MultiFrameRigBundleAdjust(
    const std::vector<Camera>& cameras, const FrameKeypoints& keypoints, const std::vector<ViewTrack>& tracks,
    const std::vector<std::optional<Rigid3d>>& initial_cam_from_rig,
    const std::vector<std::optional<Rigid3d>>& initial_rig_from_world, int scale_camera,
    const RigBundleAdjustmentOptions& options, bool hold_frames) {
  options.Check();
  // Ceres reports through glog a failed Cholesky step that Levenberg-Marquardt then recovers from
  // by itself (a larger damping); that is not for the user's terminal. Errors still show.
  static const bool glog_quiet = [] {
    FLAGS_minloglevel = std::max(FLAGS_minloglevel, int(google::GLOG_ERROR));
    return true;
  }();
  (void)glog_quiet;
  const int n = static_cast<int>(cameras.size());
  const int num_frames = static_cast<int>(keypoints.size());
  if (static_cast<int>(initial_cam_from_rig.size()) != n ||
      static_cast<int>(initial_rig_from_world.size()) != num_frames || n == 0 || num_frames == 0 ||
      !initial_cam_from_rig[0] || !initial_rig_from_world[0]) {
    throw std::invalid_argument(
        "MultiFrameRigBundleAdjust: one initial pose per camera and per frame, camera 0's and frame 0's given");
  }
  MultiFrameBundleAdjustmentResult result;
  result.num_tracks = static_cast<int>(tracks.size());
  result.cam_from_rig = initial_cam_from_rig;
  result.rig_from_world = initial_rig_from_world;
  result.observations_per_camera.assign(n, 0);

  BundleProblem bp(cameras, keypoints, tracks, initial_cam_from_rig, initial_rig_from_world);
  const double min_angle = DegToRad(options.min_triangulation_angle_deg);
  std::vector<WorldPoint> points = bp.Triangulate(min_angle, std::numeric_limits<double>::infinity());
  result.initial_rms_px = bp.RmsPx(points);
  if (options.keep_points) result.initial_residuals_px = bp.Residuals(points);

  // Round -1 (coarse): the linear initial poses can be far off (hundreds of px RMS on the demo
  // ring), and converging from there takes ~80 iterations over every point. Poses are fixed by far
  // fewer points: solve on an even subsample, then re-triangulate every track from those poses,
  // keeping the observations within max_reprojection_error_px (the poses now tell outliers).
  const bool coarse_first = options.coarse_points > 0 && static_cast<int>(points.size()) > 2 * options.coarse_points;
  const int first_round = coarse_first ? -1 : 0;
  for (int round = first_round; round <= options.filter_rounds; ++round) {
    BundleRound setup;
    setup.final_round = round == options.filter_rounds;
    setup.scale_camera = scale_camera;
    setup.hold_frames = hold_frames;
    if (round == 0 && first_round < 0) points = bp.Triangulate(min_angle, options.max_reprojection_error_px);
    if (round > 0) {
      const int removed = bp.Filter(&points, options.max_reprojection_error_px);
      result.num_filtered_observations += removed;
      if (removed == 0) setup.final_round = true;  // nothing left to filter: converge and stop
    }
    if (points.empty()) break;
    setup.point_stride = round < 0 ? points.size() / options.coarse_points : 1;
    BundleRoundResult solved = SolveBundle(bp, points, setup, options);
    result.iterations += solved.iterations;
    if (setup.final_round) {
      result.centre_covariance = std::move(solved.centre_covariance);
      break;
    }
  }

  for (int c = 0; c < n; ++c) {
    if (initial_cam_from_rig[c]) result.cam_from_rig[c] = Rigid3d(Eigen::Quaterniond(bp.cq[c].data()), bp.ct[c]);
  }
  for (int k = 0; k < num_frames; ++k) {
    if (initial_rig_from_world[k]) result.rig_from_world[k] = Rigid3d(Eigen::Quaterniond(bp.rq[k].data()), bp.rt[k]);
  }
  result.num_points = static_cast<int>(points.size());
  for (const WorldPoint& p : points) {
    for (const ViewObservation& o : p.observations) ++result.observations_per_camera[o.camera];
    result.num_observations += static_cast<int>(p.observations.size());
  }
  result.reprojection_rms_px = bp.RmsPx(points);
  if (options.keep_points) {
    result.final_residuals_px = bp.Residuals(points);
    for (const WorldPoint& p : points) {
      result.points.push_back(p.x);
      result.point_observations.push_back(static_cast<int>(p.observations.size()));
    }
  }
  return result;
}

}  // namespace rigsim
