#include "calibrator/estimators/rig_positions.h"

#include <algorithm>
#include <cmath>
#include <limits>
#include <map>
#include <stdexcept>
#include <utility>

#include <Eigen/Eigenvalues>

#include "calibrator/estimators/translation_averaging.h"
#include "calibrator/model/rig_state.h"
#include "calibrator/model/union_find.h"
#include "common/format.h"

namespace rigsim {
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
                                         const PerCamera<Eigen::Quaterniond>& cam_from_rig,
                                         const PerFrame<Eigen::Quaterniond>& rig_from_world,
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

// The unknowns of a position system: the cameras and frames that the constraints link to the
// references (camera 0, frame 0), and their 3-column blocks in x (frames k > 0 first, then
// cameras c > 0; -1 for the references and the ones left out). Nodes: camera c is c, frame k is
// n + k; a link joins two nodes that appear in one constraint.
struct PositionUnknowns {
  std::vector<char> cam_in, frame_in;
  std::vector<int> frame_block, cam_block;
  int blocks = 0;
  int cams_solved = 0;  // cameras other than camera 0
};

PositionUnknowns ChooseUnknowns(int n, int num_frames, const std::vector<std::pair<int, int>>& links,
                                const PerCamera<Eigen::Quaterniond>& cam_from_rig,
                                const PerFrame<Eigen::Quaterniond>& rig_from_world, bool static_rig) {
  UnionFind uf;
  for (int i = 0; i < n + num_frames; ++i) uf.Add();
  for (const auto& [a, b] : links) uf.Join(a, b);
  uf.Join(0, n);  // the references
  if (static_rig) {  // every frame's rig is at the origin, given
    for (int k = 1; k < num_frames; ++k) uf.Join(n, n + k);
  }
  PositionUnknowns u;
  u.cam_in.assign(n, 0);
  u.frame_in.assign(num_frames, 0);
  for (int c = 0; c < n; ++c) u.cam_in[c] = uf.Find(c) == uf.Find(0) && cam_from_rig[c];
  for (int k = 0; k < num_frames; ++k) u.frame_in[k] = uf.Find(n + k) == uf.Find(0) && rig_from_world[k];
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

// Writes a solution x of the unknowns `u` into `out`, scaled so that the mean distance of the
// solved cameras' centres from camera 0 is 1; not solved when they all sit at camera 0's.
void SetPositions(const Eigen::VectorXd& x, const PositionUnknowns& u, bool static_rig, RigPositions* out) {
  const int n = static_cast<int>(u.cam_in.size()), num_frames = static_cast<int>(u.frame_in.size());
  double mean = 0.0;
  for (int c = 1; c < n; ++c) {
    if (u.cam_block[c] >= 0) mean += x.segment<3>(3 * u.cam_block[c]).norm() / u.cams_solved;
  }
  if (!(mean > 1e-12) || !x.allFinite()) {
    out->solved = false;
    out->reason = "every camera centre coincides with camera 0's";
    return;
  }
  out->solved = true;
  for (int c = 1; c < n; ++c) {
    if (u.cam_block[c] >= 0) out->centre_in_rig[c] = x.segment<3>(3 * u.cam_block[c]) / mean;
  }
  for (int k = 1; k < num_frames; ++k) {
    if (u.frame_block[k] >= 0) out->rig_centre_in_world[k] = x.segment<3>(3 * u.frame_block[k]) / mean;
    if (static_rig && u.frame_in[k]) out->rig_centre_in_world[k] = Eigen::Vector3d::Zero();
  }
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
                                     const PerFrame<Eigen::Quaterniond>& rig_from_world,
                                     const RigPositionOptions& options,
                                     const PerCamera<Eigen::Vector3d>& held_axis = {}) {
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
    // A camera whose centre the data leave open along an axis is held at camera 0's along it: the
    // open direction would otherwise be a second smallest eigenvector, mixed into the solution.
    const double typical = dim > 0 ? q.trace() / dim : 0.0;
    for (size_t c = 0; c < held_axis.size(); ++c) {
      if (!held_axis[c] || u.cam_block[c] < 0) continue;
      q.block<3, 3>(3 * u.cam_block[c], 3 * u.cam_block[c]) += typical * *held_axis[c] * held_axis[c]->transpose();
    }
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
    // Depths far below the scene's come from points that the current x puts next to a camera:
    // weighted by 1 / depth^2 they would outweigh every other track (and drive the second
    // smallest eigenvalue down to rounding next to the largest).
    std::vector<double> all_depths;
    for (const auto& d : depth) all_depths.insert(all_depths.end(), d.begin(), d.end());
    double min_depth = 1e-6;
    if (!all_depths.empty()) {
      std::nth_element(all_depths.begin(), all_depths.begin() + all_depths.size() / 2, all_depths.end());
      min_depth = std::max(min_depth, 0.05 * all_depths[all_depths.size() / 2]);
    }
    for (size_t i = 0; i < rays.size(); ++i) {
      double sq = 0.0;
      for (double e : residual[i]) sq += e * e;
      const double rms = std::sqrt(sq / residual[i].size());
      const double robust = 1.0 / (1.0 + (rms / options.loss_scale_rad) * (rms / options.loss_scale_rad));
      for (size_t j = 0; j < rays[i].size(); ++j) {
        // Angular residuals: the ray constraint's size is depth x angle.
        const double d = std::max(depth[i][j], min_depth);
        weight[i][j] = robust / (d * d);
      }
    }
  }
  return out;
}

// No camera or frame placed yet: the result both estimates start from.
RigPositions NoPositions(int num_cameras, int num_frames) {
  RigPositions out;
  out.centre_in_rig.assign(num_cameras, std::nullopt);
  out.rig_centre_in_world.assign(num_frames, std::nullopt);
  return out;
}

}  // namespace

void RigPositionOptions::Check() const {
  auto fail = [](const std::string& why) { throw std::invalid_argument("RigPositionOptions: " + why); };
  if (!(min_ray_angle_deg >= 0)) fail("min_ray_angle_deg must be >= 0");
  if (!(loss_scale_rad > 0)) fail("loss_scale_rad must be > 0");
  if (reweighting_iterations < 0) fail("reweighting_iterations must be >= 0");
}

RigPositions EstimateRigPositions(const std::vector<Camera>& cameras, const FrameKeypoints& keypoints,
                                  const std::vector<ViewTrack>& tracks,
                                  const PerCamera<Eigen::Quaterniond>& cam_from_rig,
                                  const PerFrame<Eigen::Quaterniond>& rig_from_world,
                                  const RigPositionOptions& options, bool static_rig,
                                  const PerCamera<Eigen::Vector3d>& held_axis) {
  options.Check();
  const int n = static_cast<int>(cameras.size());
  if (!held_axis.empty() && static_cast<int>(held_axis.size()) != n) {
    throw std::invalid_argument("EstimateRigPositions: held_axis needs one entry per camera");
  }
  const int num_frames = static_cast<int>(keypoints.size());
  if (static_cast<int>(cam_from_rig.size()) != n || static_cast<int>(rig_from_world.size()) != num_frames) {
    throw std::invalid_argument("EstimateRigPositions: one rotation per camera and per frame");
  }
  RigPositions out = NoPositions(n, num_frames);
  if (n == 0 || num_frames == 0 || !cam_from_rig[0] || !rig_from_world[0]) {
    out.reason = "camera 0 or frame 0 has no rotation";
    return out;
  }
  std::vector<std::vector<Ray>> rays =
      UsableRays(cameras, keypoints, tracks, cam_from_rig, rig_from_world, DegToRad(options.min_ray_angle_deg));
  std::vector<std::pair<int, int>> links;  // a track ties the cameras and frames of all its views
  for (const auto& r : rays) {
    for (const Ray& x : r) {
      links.emplace_back(r[0].camera, x.camera);
      links.emplace_back(r[0].camera, n + x.frame);
    }
  }
  const PositionUnknowns u = ChooseUnknowns(n, num_frames, links, cam_from_rig, rig_from_world, static_rig);
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
  out.constraints_used = static_cast<int>(rays.size());
  const PositionSolution solution = SolvePositionSystem(rays, u, rig_from_world, options, held_axis);
  const Eigen::VectorXd& eigenvalues = solution.eigenvalues;
  const double l0_raw = eigenvalues.size() > 0 ? eigenvalues(0) : 0.0;
  const double l1 = eigenvalues.size() > 1 ? eigenvalues(1) : std::numeric_limits<double>::infinity();
  const double lmax = eigenvalues.size() > 0 ? eigenvalues(eigenvalues.size() - 1) : 0.0;
  const double l0 = std::max(l0_raw, 0.0);
  out.eigenvalue_ratio = l0 > 0 ? l1 / l0 : std::numeric_limits<double>::infinity();
  // The matrix is positive semi-definite in exact arithmetic; rounding moves its eigenvalues by
  // about 2e-16 x lmax. A smallest eigenvalue far below zero means near-singular points broke the
  // elimination, and the solution means nothing (VALIDATION.md, "Where the calibrator's
  // thresholds come from").
  if (l0_raw < -1e-13 * lmax) {
    out.reason = "the tracks' linear system is indefinite (smallest eigenvalue " + Fixed(l0_raw, 6) + ")";
    return out;
  }
  SetPositions(solution.x, u, static_rig, &out);
  return out;
}

PerFrame<Eigen::Vector3d> EstimateTrajectoryCentres(
    const Camera& camera, const std::vector<std::vector<Eigen::Vector2d>>& keypoints,
    const std::vector<ViewTrack>& tracks, const PerCamera<Eigen::Quaterniond>& rotations,
    const RigPositionOptions& options) {
  options.Check();
  const int num_frames = static_cast<int>(keypoints.size());
  if (static_cast<int>(rotations.size()) != num_frames) {
    throw std::invalid_argument("EstimateTrajectoryCentres: one rotation per frame");
  }
  PerFrame<Eigen::Vector3d> centres(num_frames);
  if (num_frames == 0 || !rotations[0]) return centres;
  // A rig of this one camera at the rig frame: the frames' rig centres are the camera's.
  FrameKeypoints one_camera(num_frames);
  for (int k = 0; k < num_frames; ++k) one_camera[k] = {keypoints[k]};
  const PerCamera<Eigen::Quaterniond> identity{Eigen::Quaterniond::Identity()};
  std::vector<std::vector<Ray>> rays =
      UsableRays({camera}, one_camera, tracks, identity, rotations, DegToRad(options.min_ray_angle_deg));
  std::vector<std::pair<int, int>> links;
  for (const auto& r : rays) {
    for (const Ray& x : r) links.emplace_back(1 + r[0].frame, 1 + x.frame);
  }
  const PositionUnknowns u = ChooseUnknowns(1, num_frames, links, identity, rotations, false);
  std::erase_if(rays, [&](const std::vector<Ray>& r) { return !u.frame_in[r[0].frame]; });
  for (auto& r : rays) std::erase_if(r, [&](const Ray& x) { return !u.frame_in[x.frame]; });
  std::erase_if(rays, [](const std::vector<Ray>& r) { return r.size() < 2; });
  if (u.blocks == 0 || rays.empty()) return centres;
  const PositionSolution solution = SolvePositionSystem(rays, u, rotations, options);
  double mean = 0.0;
  int solved = 0;
  for (int k = 1; k < num_frames; ++k) {
    if (u.frame_block[k] < 0) continue;
    mean += solution.x.segment<3>(3 * u.frame_block[k]).norm();
    ++solved;
  }
  mean /= std::max(solved, 1);
  if (!(mean > 1e-12) || !solution.x.allFinite()) return centres;
  centres[0] = Eigen::Vector3d::Zero();
  for (int k = 1; k < num_frames; ++k) {
    if (u.frame_block[k] >= 0) centres[k] = solution.x.segment<3>(3 * u.frame_block[k]) / mean;
  }
  return centres;
}

RigPositions EstimateRigPositionsFromDirections(const ViewGraph& graph, const std::vector<TemporalPairEstimate>& temporal,
                                                const PerCamera<Eigen::Quaterniond>& cam_from_rig,
                                                const PerFrame<Eigen::Quaterniond>& rig_from_world,
                                                bool static_rig) {
  const int n = graph.num_cameras;
  const int num_frames = static_cast<int>(rig_from_world.size());
  if (static_cast<int>(cam_from_rig.size()) != n) {
    throw std::invalid_argument("EstimateRigPositionsFromDirections: one rotation per camera");
  }
  RigPositions out = NoPositions(n, num_frames);
  if (n == 0 || num_frames == 0 || !cam_from_rig[0] || !rig_from_world[0]) {
    out.reason = "camera 0 or frame 0 has no rotation";
    return out;
  }
  auto rotated = [&](int c) { return c >= 0 && c < n && cam_from_rig[c].has_value(); };
  auto framed = [&](int k) { return k >= 0 && k < num_frames && rig_from_world[k].has_value(); };
  // What each direction links: a pair's two cameras in every frame, a temporal pair's two views.
  std::vector<int> edges, steps;
  std::vector<std::pair<int, int>> links;
  for (int e = 0; e < static_cast<int>(graph.edges.size()); ++e) {
    const ViewGraphEdge& g = graph.edges[e];
    if (!g.active || g.rotation_only || !rotated(g.cam_a) || !rotated(g.cam_b)) continue;
    edges.push_back(e);
    links.emplace_back(g.cam_a, g.cam_b);
  }
  for (int i = 0; i < static_cast<int>(temporal.size()) && !static_rig; ++i) {
    const TemporalPairEstimate& t = temporal[i];
    if (!t.PoseUsable() || t.two_view.rotation_only || !rotated(t.camera) || !framed(t.frame) ||
        !framed(t.frame + 1)) {
      continue;
    }
    steps.push_back(i);
    links.emplace_back(n + t.frame, n + t.frame + 1);
    links.emplace_back(n + t.frame, t.camera);
  }
  const PositionUnknowns u = ChooseUnknowns(n, num_frames, links, cam_from_rig, rig_from_world, static_rig);
  out.centre_in_rig[0] = Eigen::Vector3d::Zero();
  out.rig_centre_in_world[0] = Eigen::Vector3d::Zero();
  if (u.cams_solved == 0) {
    out.reason = "no two-view direction links another camera to camera 0";
    return out;
  }
  std::vector<DirectionConstraint> constraints;
  for (int e : edges) {  // o_b - o_a is parallel to -R_b^T t_ab (two_view.h: t_ab = t of cam_b_from_cam_a)
    const ViewGraphEdge& g = graph.edges[e];
    if (!u.cam_in[g.cam_a] || !u.cam_in[g.cam_b]) continue;
    DirectionConstraint c;
    if (u.cam_block[g.cam_b] >= 0) c.terms.emplace_back(u.cam_block[g.cam_b], Eigen::Matrix3d::Identity());
    if (u.cam_block[g.cam_a] >= 0) c.terms.emplace_back(u.cam_block[g.cam_a], -Eigen::Matrix3d::Identity());
    c.direction = -(cam_from_rig[g.cam_b]->conjugate() * g.direction).normalized();
    constraints.push_back(std::move(c));
  }
  for (int i : steps) {  // centre(c, k+1) - centre(c, k) is parallel to -(Q_c R_{k+1})^T t
    const TemporalPairEstimate& t = temporal[i];
    const int c = t.camera, k = t.frame;
    if (!u.cam_in[c] || !u.frame_in[k] || !u.frame_in[k + 1]) continue;
    DirectionConstraint dc;
    dc.terms.emplace_back(u.frame_block[k + 1], Eigen::Matrix3d::Identity());
    if (u.frame_block[k] >= 0) dc.terms.emplace_back(u.frame_block[k], -Eigen::Matrix3d::Identity());
    if (u.cam_block[c] >= 0) {
      const Eigen::Matrix3d m = rig_from_world[k + 1]->toRotationMatrix().transpose() -
                                rig_from_world[k]->toRotationMatrix().transpose();
      dc.terms.emplace_back(u.cam_block[c], m);
    }
    const Eigen::Quaterniond world_from_cam = (*cam_from_rig[c] * *rig_from_world[k + 1]).conjugate();
    dc.direction = -(world_from_cam * t.two_view.cam_b_from_cam_a.translation).normalized();
    constraints.push_back(std::move(dc));
  }
  out.constraints_used = static_cast<int>(constraints.size());
  const TranslationAveragingResult ta = AverageTranslations(u.blocks, constraints);
  SetPositions(ta.x, u, static_rig, &out);
  return out;
}

}  // namespace rigsim
