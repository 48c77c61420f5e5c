#include "calibrator/estimators/multi_frame_rig.h"

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
#include <tbb/parallel_invoke.h>

#include "calibrator/estimators/bundle_covariance.h"
#include "calibrator/estimators/cost_functions.h"
#include "calibrator/model/rig_state.h"
#include "common/format.h"
#include "geometry/pose_interpolation.h"

namespace rigsim {
namespace {

// Projection onto SO(3) of a 3x3 matrix (the chordal mean of rotations summed into it).
Eigen::Matrix3d ProjectToRotation(const Eigen::Matrix3d& m) {
  const Eigen::JacobiSVD<Eigen::Matrix3d> svd(m, Eigen::ComputeFullU | Eigen::ComputeFullV);
  Eigen::Matrix3d d = Eigen::Matrix3d::Identity();
  d(2, 2) = (svd.matrixU() * svd.matrixV().transpose()).determinant() < 0 ? -1.0 : 1.0;
  return svd.matrixU() * d * svd.matrixV().transpose();
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

void RigBundleAdjustmentOptions::Check() const {
  auto fail = [](const std::string& why) { throw std::invalid_argument("RigBundleAdjustmentOptions: " + why); };
  if (!(min_triangulation_angle_deg >= 0)) fail("min_triangulation_angle_deg must be >= 0");
  if (!(loss_scale_px > 0)) fail("loss_scale_px must be > 0");
  if (!(max_reprojection_error_px > 0)) fail("max_reprojection_error_px must be > 0");
  if (filter_rounds < 0) fail("filter_rounds must be >= 0");
  if (coarse_points < 0) fail("coarse_points must be >= 0");
  if (max_iterations < 1) fail("max_iterations must be >= 1");
  if (num_threads < 1) fail("num_threads must be >= 1");
  if (intrinsics_passes < 1) fail("intrinsics_passes must be >= 1");
  intrinsics_priors.Check();
  if (given_intrinsics_sd) given_intrinsics_sd->Check();
  if (given_intrinsics_sd && refine_intrinsics) fail("given_intrinsics_sd is for held intrinsics, not refine_intrinsics");
  if (!(inter_camera_weight > 0)) fail("inter_camera_weight must be > 0");
  for (const auto& axis : held_centre_axis) {
    if (axis && std::abs(axis->norm() - 1.0) > 1e-6) fail("held_centre_axis must hold unit directions");
  }
}

PerFrame<Eigen::Quaterniond> EstimateRigRotations(
    int num_frames, const PerCamera<Eigen::Quaterniond>& cam_from_rig,
    const std::vector<TemporalPairEstimate>& temporal) {
  PerFrame<Eigen::Quaterniond> out(std::max(num_frames, 0));
  if (num_frames < 1) return out;
  out[0] = Eigen::Quaterniond::Identity();
  for (int k = 0; k + 1 < num_frames; ++k) {
    std::vector<Eigen::Matrix3d> motions;  // R_{k+1} R_k^T seen by each camera
    for (const TemporalPairEstimate& t : temporal) {
      if (t.frame != k || !t.PoseUsable() || t.camera < 0 || t.camera >= static_cast<int>(cam_from_rig.size()) ||
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

// The bundle adjustment's unknowns as Ceres parameter blocks: per camera cam_from_rig (rotation
// x, y, z, w; translation) and its intrinsics (held constant unless refined), per frame
// rig_from_world; and what the observations refer to.
struct BundleProblem {
  const std::vector<Camera>& given;  // the intrinsics as given: the priors' centres
  std::vector<Camera> cameras;       // the current intrinsics
  const FrameKeypoints& keypoints;
  const std::vector<ViewTrack>& tracks;
  const PerCamera<Rigid3d>& initial_cam_from_rig;
  const PerFrame<Rigid3d>& initial_rig_from_world;
  const CaptureTiming* timing;  // nullptr: every camera captures at its frame's timestamp
  std::vector<Eigen::Vector4d> cq, rq;
  std::vector<Eigen::Vector3d> ct, rt;
  std::vector<std::vector<double>> intrinsics;
  std::vector<Eigen::Vector2d> time;  // per camera (offset, readout), with a timing model

  BundleProblem(const std::vector<Camera>& cameras, const FrameKeypoints& keypoints, const std::vector<ViewTrack>& tracks,
                const PerCamera<Rigid3d>& initial_cam_from_rig,
                const PerFrame<Rigid3d>& initial_rig_from_world, const CaptureTiming* timing)
      : given(cameras),
        cameras(cameras),
        keypoints(keypoints),
        tracks(tracks),
        initial_cam_from_rig(initial_cam_from_rig),
        initial_rig_from_world(initial_rig_from_world),
        timing(timing),
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
    if (timing) {
      for (size_t c = 0; c < cameras.size(); ++c) time.emplace_back(timing->time_offset_s[c], timing->readout_s[c]);
    }
  }

  // With a timing model: the observation's row in readout order over the image height.
  double RowFraction(const ViewObservation& o) const {
    const double h = cameras[o.camera].height();
    const double y = Observed(o).y();
    const bool up = !timing->readout_bottom_to_top.empty() && timing->readout_bottom_to_top[o.camera];
    return (up ? h - 1 - y : y) / h;
  }
  // With a timing model: the two posed frames (a, b) around the observation's capture time at the
  // current timing, and that time relative to frame a's; a == b when fewer than two are posed.
  struct Bracket {
    int a = 0, b = 0;
  };
  Bracket Around(const ViewObservation& o) const {
    const std::vector<double>& times = timing->frame_times_s;
    const double capture = times[o.frame] + time[o.camera][0] + RowFraction(o) * time[o.camera][1];
    std::vector<int> posed;
    for (size_t k = 0; k < times.size(); ++k) {
      if (initial_rig_from_world[k]) posed.push_back(static_cast<int>(k));
    }
    std::sort(posed.begin(), posed.end(), [&](int x, int y) { return times[x] < times[y]; });
    if (posed.size() < 2) return {o.frame, o.frame};
    size_t i = 0;  // the last posed frame at or before the capture, within [0, size - 2]
    while (i + 2 < posed.size() && times[posed[i + 1]] <= capture) ++i;
    return {posed[i], posed[i + 1]};
  }
  Rigid3d RigAt(const ViewObservation& o) const {
    const Rigid3d frame(Eigen::Quaterniond(rq[o.frame].data()), rt[o.frame]);
    if (!timing) return frame;
    const Bracket br = Around(o);
    if (br.a == br.b) return frame;
    const std::vector<double>& times = timing->frame_times_s;
    const double s = (times[o.frame] - times[br.a] + time[o.camera][0] + RowFraction(o) * time[o.camera][1]) /
                     (times[br.b] - times[br.a]);
    Rigid3d out;
    InterpolateRigFromWorld<double>(Eigen::Quaterniond(rq[br.a].data()), rt[br.a], Eigen::Quaterniond(rq[br.b].data()),
                                    rt[br.b], s, &out.rotation, &out.translation);
    return out;
  }

  // Takes the intrinsics blocks into `cameras`. A block the solver moved to parameters the model
  // rejects (a distortion that folds inside the image) goes back to the camera's last valid ones;
  // returns the cameras that did.
  std::vector<int> UpdateCameras() {
    std::vector<int> rejected;
    for (size_t c = 0; c < cameras.size(); ++c) {
      if (intrinsics[c] == cameras[c].params()) continue;
      try {
        cameras[c] = Camera(cameras[c].model(), cameras[c].width(), cameras[c].height(), intrinsics[c]);
      } catch (const std::invalid_argument&) {
        intrinsics[c] = cameras[c].params();
        rejected.push_back(static_cast<int>(c));
      }
    }
    return rejected;
  }

  bool Posed(const ViewObservation& o) const { return initial_cam_from_rig[o.camera] && initial_rig_from_world[o.frame]; }
  Rigid3d ViewPose(const ViewObservation& o) const {
    return Rigid3d(Eigen::Quaterniond(cq[o.camera].data()), ct[o.camera]) * RigAt(o);
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

  // The median distance (along the optical axis) of the points from the views that see them.
  double MedianDepth(const std::vector<WorldPoint>& points) const {
    std::vector<double> depths;
    for (const WorldPoint& p : points) {
      for (const ViewObservation& o : p.observations) depths.push_back((ViewPose(o) * p.x).z());
    }
    if (depths.empty()) return 0.0;
    std::nth_element(depths.begin(), depths.begin() + depths.size() / 2, depths.end());
    return depths[depths.size() / 2];
  }

  // Every observation's reprojection residual with its view and place in the image
  // (CorrelatedResidualFactor); observations that do not project are left out.
  std::vector<LocatedResidual> LocatedResiduals(const std::vector<WorldPoint>& points) const {
    std::vector<LocatedResidual> out;
    const int num_frames = static_cast<int>(keypoints.size());
    for (const WorldPoint& p : points) {
      for (const ViewObservation& o : p.observations) {
        const auto px = cameras[o.camera].ImgFromCam(ViewPose(o) * p.x);
        if (!px) continue;
        const Camera& cam = cameras[o.camera];
        const Eigen::Vector2d at(Observed(o).x() / cam.width(), Observed(o).y() / cam.height());
        out.push_back({o.camera * num_frames + o.frame, at, *px - Observed(o)});
      }
    }
    return out;
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

// The weight of a held centre component (px per unit of length): a shift of a thousandth of the
// scale camera's distance costs as much as a pixel of reprojection error.
constexpr double kHeldCentreWeightPx = 1e3;

// How one solve of SolveBundle is set up.
struct BundleRound {
  size_t point_stride = 1;  // every point, or an even subsample (the coarse first solve)
  bool final_round = false;
  bool refine_intrinsics = false;  // free the intrinsics, under their priors
  bool covariance = false;         // compute the covariances (the very last solve)
  int scale_camera = -1;
  bool hold_frames = false;
};

// Where each reprojection cost comes from: its image's frame and its point's index.
struct CostSource {
  int frame = 0;
  int point = 0;
};

struct BundleRoundResult {
  int iterations = 0;
  // With BundleRound::covariance only.
  PerCamera<Eigen::Matrix3d> centre_covariance;
  PerCamera<double> rotation_stddev_deg;
  std::vector<std::vector<double>> intrinsics_stddev;  // per camera; empty when not refined
  PerCamera<double> time_offset_stddev_s, readout_stddev_s;  // per camera, where estimated
  double residual_correlation = 1.0;  // CorrelatedResidualFactor, by which the variance was scaled
  JackknifeSpread frame_jackknife, point_jackknife;
  PerCamera<Eigen::Matrix3d> centre_covariance_of_intrinsics;  // with given_intrinsics_sd
  PerCamera<double> rotation_stddev_of_intrinsics_deg;
};

// One Levenberg-Marquardt solve over the points (every `point_stride`-th) and the poses they see,
// updating the poses in `bp` and the points in place; the final round also yields the camera
// centres' covariances (and with refined intrinsics, their standard deviations).
// The reprojection costs of every point of the round: observations of points that two or more
// cameras see weigh options.inter_camera_weight times the others.
// Returns where each cost comes from.
std::map<ceres::ResidualBlockId, CostSource> AddReprojectionCosts(BundleProblem& bp, std::vector<WorldPoint>& points,
                                                                  const BundleRound& round,
                                                                  const RigBundleAdjustmentOptions& options,
                                                                  ceres::Problem& problem) {
  std::map<ceres::ResidualBlockId, CostSource> sources;
  ceres::LossFunction* own_loss = new ceres::HuberLoss(options.loss_scale_px);
  ceres::LossFunction* shared_loss =
      options.inter_camera_weight == 1.0
          ? own_loss
          : new ceres::ScaledLoss(new ceres::HuberLoss(options.loss_scale_px), options.inter_camera_weight,
                                  ceres::TAKE_OWNERSHIP);
  bool own_used = false, shared_used = false;  // the problem deletes only the losses it was given
  for (size_t i = 0; i < points.size(); i += round.point_stride) {
    WorldPoint& p = points[i];
    const bool shared = std::any_of(p.observations.begin(), p.observations.end(),
                                    [&](const ViewObservation& o) { return o.camera != p.observations[0].camera; });
    ceres::LossFunction* loss = shared ? shared_loss : own_loss;
    (shared ? shared_used : own_used) = true;
    for (const ViewObservation& o : p.observations) {
      const BundleProblem::Bracket br = bp.timing ? bp.Around(o) : BundleProblem::Bracket{o.frame, o.frame};
      if (br.a != br.b) {
        const std::vector<double>& times = bp.timing->frame_times_s;
        sources[problem.AddResidualBlock(
            TimedRigReprojectionCost::Create(bp.cameras[o.camera], bp.Observed(o), times[o.frame] - times[br.a],
                                             times[br.b] - times[br.a], bp.RowFraction(o)),
            loss,
            {bp.cq[o.camera].data(), bp.ct[o.camera].data(), bp.rq[br.a].data(), bp.rt[br.a].data(), bp.rq[br.b].data(),
             bp.rt[br.b].data(), bp.time[o.camera].data(), p.x.data()})] = {o.frame, static_cast<int>(i)};
        continue;
      }
      const ceres::ResidualBlockId cost = problem.AddResidualBlock(
          CreateRigReprojectionCost(bp.cameras[o.camera], bp.Observed(o)), loss,
          {bp.cq[o.camera].data(), bp.ct[o.camera].data(), bp.rq[o.frame].data(), bp.rt[o.frame].data(), p.x.data(),
           bp.intrinsics[o.camera].data()});
      sources[cost] = {o.frame, static_cast<int>(i)};
    }
  }
  if (own_loss == shared_loss) {
    if (!own_used && !shared_used) delete own_loss;
  } else {
    if (!own_used) delete own_loss;
    if (!shared_used) delete shared_loss;
  }
  return sources;
}

// What the round holds and how the poses move: capture times estimated or held, intrinsics refined
// under their priors or held, camera 0 and frame 0 as the gauge, held centre axes, the scale
// camera on the sphere.
void HoldAndBoundParameters(BundleProblem& bp, const BundleRound& round, const RigBundleAdjustmentOptions& options,
                            ceres::Problem& problem) {
  const int n = static_cast<int>(bp.cameras.size());
  const int num_frames = static_cast<int>(bp.keypoints.size());
  for (int c = 0; c < n && bp.timing; ++c) {
    double* block = bp.time[c].data();
    if (!problem.HasParameterBlock(block)) continue;
    const bool held = !bp.timing->offset_held.empty() && bp.timing->offset_held[c];
    const bool offset = bp.timing->estimate_offsets && c > 0 && !held, readout = bp.timing->estimate_readout;
    if (!offset && !readout) {
      problem.SetParameterBlockConstant(block);
    } else if (!offset || !readout) {
      problem.SetManifold(block, new ceres::SubsetManifold(2, {offset ? 1 : 0}));
    }
    // A readout takes time: a global shutter's comes out at zero, not below it by the noise.
    if (readout) problem.SetParameterLowerBound(block, 1, 0.0);
  }
  for (int c = 0; c < n; ++c) {
    if (!problem.HasParameterBlock(bp.cq[c].data())) continue;
    if (round.refine_intrinsics) {
      const std::vector<Camera>& centres = options.intrinsics_priors.centres;
      const Camera& given = centres.empty() ? bp.given[c] : centres.at(c);
      const std::vector<double> sigma = IntrinsicsPriorSigmas(given, options.intrinsics_priors);
      std::vector<double> weights;
      for (double s : sigma) weights.push_back(options.intrinsics_priors.pixel_noise_px / s);
      const double aspect_weight =
          options.intrinsics_priors.pixel_noise_px / (options.intrinsics_priors.aspect_fraction * std::abs(given.fx()));
      problem.AddResidualBlock(new IntrinsicsPriorCost(given.params(), weights, aspect_weight), nullptr,
                               bp.intrinsics[c].data());
    } else if (problem.HasParameterBlock(bp.intrinsics[c].data())) {  // timed costs hold intrinsics themselves
      problem.SetParameterBlockConstant(bp.intrinsics[c].data());
    }
    if (c == 0) {  // camera 0 is the rig frame
      problem.SetParameterBlockConstant(bp.cq[c].data());
      problem.SetParameterBlockConstant(bp.ct[c].data());
      continue;
    }
    if (c < static_cast<int>(options.held_centre_axis.size()) && options.held_centre_axis[c]) {
      // At the start's value: the images say nothing of it, so it stays what the caller chose.
      const Eigen::Vector3d& axis = *options.held_centre_axis[c];
      const double held = axis.dot(bp.initial_cam_from_rig[c]->SourceOriginInTarget());
      problem.AddResidualBlock(HeldCentreAxisCost::Create(axis, held, kHeldCentreWeightPx), nullptr,
                               {bp.cq[c].data(), bp.ct[c].data()});
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
}

// The cameras' spread over the steps of the linearised adjustment without each group
// (StepsWithoutGroups, CameraSpread).
JackknifeSpread SpreadWithoutGroups(const BundleProblem& bp, ceres::Problem& problem,
                                    const BundleLinearisation& linearised, const NormalEquations& normal,
                                    const std::vector<int>& block_group, int groups,
                                    const std::vector<std::vector<int>>& held) {
  return CameraSpread(problem, linearised, StepsWithoutGroups(linearised, normal, block_group, groups, held), bp.cq,
                      bp.ct);
}

// The jackknife over frames (JackknifeFrameGroups); `source_of_block`: per residual block of the
// linearisation, where it comes from (nullptr: a block that always stays).
JackknifeSpread FrameJackknife(const BundleProblem& bp, ceres::Problem& problem, const BundleLinearisation& linearised,
                               const NormalEquations& normal, const std::vector<const CostSource*>& source_of_block) {
  const int num_frames = static_cast<int>(bp.keypoints.size());
  std::vector<int> posed;
  for (int k = 0; k < num_frames; ++k) {
    if (bp.initial_rig_from_world[k]) posed.push_back(k);
  }
  const std::vector<std::vector<int>> groups = JackknifeFrameGroups(posed);
  if (groups.empty()) {
    JackknifeSpread none;
    none.rotation_std_deg.assign(bp.cameras.size(), std::nullopt);
    none.direction_std_deg.assign(bp.cameras.size(), std::nullopt);
    return none;
  }
  std::vector<int> group_of_frame(num_frames, -1);
  for (size_t g = 0; g < groups.size(); ++g) {
    for (const int k : groups[g]) group_of_frame[k] = static_cast<int>(g);
  }
  std::vector<int> block_group(source_of_block.size(), -1);
  for (size_t b = 0; b < source_of_block.size(); ++b) {
    if (source_of_block[b]) block_group[b] = group_of_frame[source_of_block[b]->frame];
  }
  // Frame 0 holds the gauge: without it, the first frame of the next group holds it, where the
  // solution put it.
  std::vector<std::vector<int>> held(groups.size());
  const int gauge = groups[1].front();
  for (const double* block : {bp.rq[gauge].data(), bp.rt[gauge].data()}) {
    const auto it = linearised.offset.find(block);
    if (it == linearised.offset.end()) continue;
    for (int i = 0; i < problem.ParameterBlockTangentSize(block); ++i) held[0].push_back(it->second + i);
  }
  return SpreadWithoutGroups(bp, problem, linearised, normal, block_group, static_cast<int>(groups.size()), held);
}

// The jackknives (jackknife.h) over points and over frames of the solved problem.
void ReadJackknives(const BundleProblem& bp, const std::vector<WorldPoint>& points, ceres::Problem& problem,
                    const BundleLinearisation& linearised, const NormalEquations& normal,
                    const std::vector<ceres::ResidualBlockId>& blocks,
                    const std::map<ceres::ResidualBlockId, CostSource>& sources, BundleRoundResult* out) {
  std::vector<const CostSource*> source_of_block(blocks.size(), nullptr);
  for (size_t b = 0; b < blocks.size(); ++b) {
    if (const auto it = sources.find(blocks[b]); it != sources.end()) source_of_block[b] = &it->second;
  }
  // The two jackknives read the same linearisation and write apart: side by side they give the
  // same bits as one after the other.
  tbb::parallel_invoke(
      [&] {
        std::vector<int> point_group(blocks.size(), -1);
        for (size_t b = 0; b < blocks.size(); ++b) {
          if (source_of_block[b]) point_group[b] = JackknifePointGroup(source_of_block[b]->point);
        }
        const JackknifeSpread every_tenth =
            SpreadWithoutGroups(bp, problem, linearised, normal, point_group, kJackknifePointGroups, {});
        // And by region: the larger of the two spreads is the points'.
        std::vector<Eigen::Vector3d> positions;
        positions.reserve(points.size());
        for (const WorldPoint& p : points) positions.push_back(p.x);
        const std::vector<int> region = JackknifeRegionGroups(positions);
        for (size_t b = 0; b < blocks.size(); ++b) {
          if (source_of_block[b]) point_group[b] = region[source_of_block[b]->point];
        }
        out->point_jackknife = LargerSpread(
            every_tenth, SpreadWithoutGroups(bp, problem, linearised, normal, point_group, kJackknifePointGroups, {}));
      },
      [&] { out->frame_jackknife = FrameJackknife(bp, problem, linearised, normal, source_of_block); });
}

// The poses', capture times' and intrinsics' standard deviations from the solved problem's
// covariance, at the points' reprojection RMS.
void ReadCovariances(BundleProblem& bp, const std::vector<WorldPoint>& points, const RigBundleAdjustmentOptions& options,
                     const std::map<ceres::ResidualBlockId, CostSource>& sources,
                     ceres::Problem& problem, BundleRoundResult* result) {
  BundleRoundResult& out = *result;
  const int n = static_cast<int>(bp.cameras.size());
  const int num_frames = static_cast<int>(bp.keypoints.size());
  std::vector<double*> pose_blocks;
  for (int c = 0; c < n; ++c) pose_blocks.insert(pose_blocks.end(), {bp.cq[c].data(), bp.ct[c].data()});
  for (int k = 0; k < num_frames; ++k) pose_blocks.insert(pose_blocks.end(), {bp.rq[k].data(), bp.rt[k].data()});
  for (int c = 0; c < n; ++c) pose_blocks.push_back(bp.intrinsics[c].data());
  for (Eigen::Vector2d& t : bp.time) pose_blocks.push_back(t.data());
  std::vector<ceres::ResidualBlockId> blocks;
  problem.GetResidualBlocks(&blocks);
  const BundleLinearisation linearised = Linearise(problem, pose_blocks, blocks);
  const NormalEquations normal = NormalEquationsOf(linearised);
  ReducedCovariance reduced;
  // The covariance and the jackknives read the same linearisation and write apart.
  tbb::parallel_invoke([&] { reduced = PoseCovariance(linearised, normal); },
                       [&] { ReadJackknives(bp, points, problem, linearised, normal, blocks, sources, &out); });
  const double rms_px = bp.RmsPx(points);
  // Per image coordinate, over the coordinates the fit leaves free, and as many times that as the
  // residuals of one image region move together.
  int observations = 0;
  for (const WorldPoint& p : points) observations += static_cast<int>(p.observations.size());
  out.residual_correlation = ResidualDegreesOfFreedomFactor(2 * observations, FreeParameterCount(problem)) *
                             CorrelatedResidualFactor(bp.LocatedResiduals(points));
  const double variance = 0.5 * rms_px * rms_px * out.residual_correlation;
  // Observations weighed up (inter_camera_weight) are no more precise than the others: the
  // covariance of what they alone fix is scaled back, and of the rest over-stated (the safe side).
  out.centre_covariance = CentreCovariances(problem, reduced, bp.cq, bp.ct, variance * options.inter_camera_weight);
  out.rotation_stddev_deg = RotationStdDevsDeg(problem, reduced, bp.cq, variance * options.inter_camera_weight);
  if (options.given_intrinsics_sd) {  // what the given intrinsics' own uncertainty moves the poses by
    std::vector<HeldBlock> held;
    for (int c = 0; c < n; ++c) held.push_back({bp.intrinsics[c].data(), options.given_intrinsics_sd->OfCamera(c, bp.given[c])});
    const HeldShare share = HeldBlocksShare(problem, reduced, held, bp.cq, bp.ct);
    out.centre_covariance_of_intrinsics = share.centre_covariance;
    AddHeldShare(problem, reduced, bp.cq, variance * options.inter_camera_weight, share, &out.centre_covariance,
                 &out.rotation_stddev_deg, &out.rotation_stddev_of_intrinsics_deg);
  }
  out.time_offset_stddev_s.assign(n, std::nullopt);
  out.readout_stddev_s.assign(n, std::nullopt);
  for (int c = 0; c < n && bp.timing; ++c) {
    double* block = bp.time[c].data();
    const auto it = reduced.offset.find(block);
    if (it == reduced.offset.end()) continue;
    const int size = problem.ParameterBlockTangentSize(block);
    Eigen::Matrix2d cov = Eigen::Matrix2d::Zero();
    if (const ceres::Manifold* manifold = problem.GetManifold(block)) {
      Eigen::Matrix<double, 2, Eigen::Dynamic, Eigen::RowMajor> plus(2, size);
      manifold->PlusJacobian(block, plus.data());
      cov = plus * reduced.covariance.block(it->second, it->second, size, size) * plus.transpose();
    } else {
      cov = reduced.covariance.block<2, 2>(it->second, it->second);
    }
    cov *= variance;
    const bool held = !bp.timing->offset_held.empty() && bp.timing->offset_held[c];
    if (bp.timing->estimate_offsets && c > 0 && !held) out.time_offset_stddev_s[c] = std::sqrt(std::max(cov(0, 0), 0.0));
    if (bp.timing->estimate_readout) out.readout_stddev_s[c] = std::sqrt(std::max(cov(1, 1), 0.0));
  }
  out.intrinsics_stddev.assign(n, {});
  for (int c = 0; c < n; ++c) {
    const auto it = reduced.offset.find(bp.intrinsics[c].data());
    if (it == reduced.offset.end()) continue;
    for (size_t i = 0; i < bp.intrinsics[c].size(); ++i) {
      out.intrinsics_stddev[c].push_back(std::sqrt(variance * reduced.covariance(it->second + i, it->second + i)));
    }
  }
}

BundleRoundResult SolveBundleOnce(BundleProblem& bp, std::vector<WorldPoint>& points, const BundleRound& round,
                                  const RigBundleAdjustmentOptions& options) {
  ceres::Problem::Options problem_options;
  problem_options.manifold_ownership = ceres::TAKE_OWNERSHIP;
  problem_options.loss_function_ownership = ceres::TAKE_OWNERSHIP;
  ceres::Problem problem(problem_options);
  const std::map<ceres::ResidualBlockId, CostSource> sources = AddReprojectionCosts(bp, points, round, options, problem);
  HoldAndBoundParameters(bp, round, options, problem);
  ceres::Solver::Options solver_options;
  // A few poses and many points: the reduced camera system is small and dense.
  solver_options.linear_solver_type = ceres::DENSE_SCHUR;
  solver_options.max_num_iterations = options.max_iterations;
  // The rounds before the last only decide which observations to filter: a coarse solve is
  // enough there. The last stops at a relative cost change of 1e-6: beyond it Levenberg-Marquardt
  // crawls for many iterations without changing the poses (BENCHMARKS.md, "Calibration").
  solver_options.function_tolerance = round.final_round ? 1e-6 : 1e-5;
  solver_options.parameter_tolerance = round.final_round ? 1e-10 : 1e-5;
  solver_options.num_threads = options.num_threads;
  solver_options.logging_type = ceres::SILENT;
  ceres::Solver::Summary summary;
  ceres::Solve(solver_options, &problem, &summary);
  BundleRoundResult out;
  out.iterations = static_cast<int>(summary.iterations.size());
  if (round.refine_intrinsics) bp.UpdateCameras();
  if (round.covariance) ReadCovariances(bp, points, options, sources, problem, &out);
  return out;
}

// The frames around each capture time as the timing currently places them, in observation order.
std::vector<std::pair<int, int>> Brackets(const BundleProblem& bp, const std::vector<WorldPoint>& points, int stride) {
  std::vector<std::pair<int, int>> out;
  for (size_t i = 0; i < points.size(); i += stride) {
    for (const ViewObservation& o : points[i].observations) {
      const BundleProblem::Bracket br = bp.Around(o);
      out.emplace_back(br.a, br.b);
    }
  }
  return out;
}

// SolveBundleOnce, repeated with a timing model while the solved offsets move captures across a
// frame: each cost interpolates between the frames chosen when it was built.
BundleRoundResult SolveBundle(BundleProblem& bp, std::vector<WorldPoint>& points, const BundleRound& round,
                              const RigBundleAdjustmentOptions& options) {
  if (!bp.timing) return SolveBundleOnce(bp, points, round, options);
  constexpr int kMaxRebrackets = 4;
  BundleRoundResult out;
  for (int pass = 0; pass <= kMaxRebrackets; ++pass) {
    const std::vector<std::pair<int, int>> before = Brackets(bp, points, round.point_stride);
    const int iterations = out.iterations;
    out = SolveBundleOnce(bp, points, round, options);
    out.iterations += iterations;
    if (Brackets(bp, points, round.point_stride) == before) break;
  }
  return out;
}

}  // namespace

void CaptureTiming::Check(int cameras, int frames) const {
  auto fail = [](const std::string& why) { throw std::invalid_argument("CaptureTiming: " + why); };
  if (static_cast<int>(frame_times_s.size()) != frames) fail("frame_times_s needs one time per frame");
  if (static_cast<int>(time_offset_s.size()) != cameras || static_cast<int>(readout_s.size()) != cameras) {
    fail("time_offset_s and readout_s need one value per camera");
  }
  if (!readout_bottom_to_top.empty() && static_cast<int>(readout_bottom_to_top.size()) != cameras) {
    fail("readout_bottom_to_top needs one flag per camera, or none");
  }
  if (!offset_held.empty() && static_cast<int>(offset_held.size()) != cameras) {
    fail("offset_held needs one flag per camera, or none");
  }
  std::vector<double> sorted = frame_times_s;
  std::sort(sorted.begin(), sorted.end());
  for (size_t k = 0; k < sorted.size(); ++k) {
    if (!std::isfinite(sorted[k]) || (k > 0 && sorted[k] == sorted[k - 1])) fail("frame times must be finite and distinct");
  }
  for (int c = 0; c < cameras; ++c) {
    if (!std::isfinite(time_offset_s[c]) || !std::isfinite(readout_s[c]) || readout_s[c] < 0) {
      fail("offsets must be finite and readout times finite and >= 0");
    }
  }
}

MultiFrameBundleAdjustmentResult MultiFrameRigBundleAdjust(
    const std::vector<Camera>& cameras, const FrameKeypoints& keypoints, const std::vector<ViewTrack>& tracks,
    const RigPoses& initial, int scale_camera,
    const RigBundleAdjustmentOptions& options, bool hold_frames, const CaptureTiming* timing) {
  const PerCamera<Rigid3d>& initial_cam_from_rig = initial.cam_from_rig;
  const PerFrame<Rigid3d>& initial_rig_from_world = initial.rig_from_world;
  options.Check();
  QuietCeresLogs();
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
  result.poses = initial;
  result.observations_per_camera.assign(n, 0);
  result.cameras = cameras;

  if (timing) {
    timing->Check(n, num_frames);
    if (options.refine_intrinsics || options.given_intrinsics_sd) {
      throw std::invalid_argument(
          "MultiFrameRigBundleAdjust: neither refine_intrinsics nor given_intrinsics_sd combines with a timing model");
    }
  }
  BundleProblem bp(cameras, keypoints, tracks, initial_cam_from_rig, initial_rig_from_world, timing);
  const double min_angle = DegToRad(options.min_triangulation_angle_deg);
  std::vector<WorldPoint> points = bp.Triangulate(min_angle, std::numeric_limits<double>::infinity());
  result.initial_rms_px = bp.RmsPx(points);
  if (options.keep_points) result.initial_residuals_px = bp.Residuals(points);

  // Round -1 (coarse): the linear initial poses can be far off (hundreds of px RMS on the demo
  // ring), and converging from there takes ~80 iterations over every point. Poses are fixed by far
  // fewer points: solve on an even subsample, then re-triangulate every track from those poses,
  // keeping the observations within max_reprojection_error_px (the poses now tell outliers).
  const bool coarse_first = options.coarse_points > 0 && static_cast<int>(points.size()) > 2 * options.coarse_points;
  // Solve-and-filter rounds from `first_round` (-1: the coarse one first) until nothing is left to
  // filter or the rounds run out; `last`: the result's final solve (covariances).
  auto adjust = [&](int first_round, bool refine, bool last) {
    for (int round = first_round; round <= options.filter_rounds; ++round) {
      BundleRound setup;
      setup.final_round = round == options.filter_rounds;
      setup.scale_camera = scale_camera;
      setup.hold_frames = hold_frames;
      setup.refine_intrinsics = refine;
      if (round == 0 && first_round < 0) points = bp.Triangulate(min_angle, options.max_reprojection_error_px);
      if (round > 0) {
        const int removed = bp.Filter(&points, options.max_reprojection_error_px);
        result.num_filtered_observations += removed;
        if (removed == 0) setup.final_round = true;  // nothing left to filter: converge and stop
      }
      if (points.empty()) break;
      setup.point_stride = round < 0 ? points.size() / options.coarse_points : 1;
      setup.covariance = setup.final_round && last && options.covariance;
      BundleRoundResult solved = SolveBundle(bp, points, setup, options);
      result.iterations += solved.iterations;
      if (setup.final_round) {
        if (last) {
          result.centre_covariance = std::move(solved.centre_covariance);
          result.rotation_stddev_deg = std::move(solved.rotation_stddev_deg);
          result.time_offset_stddev_s = std::move(solved.time_offset_stddev_s);
          result.readout_stddev_s = std::move(solved.readout_stddev_s);
          result.residual_correlation = solved.residual_correlation;
          result.frame_jackknife = std::move(solved.frame_jackknife);
          result.point_jackknife = std::move(solved.point_jackknife);
          result.centre_covariance_of_intrinsics = std::move(solved.centre_covariance_of_intrinsics);
          result.rotation_stddev_of_intrinsics_deg = std::move(solved.rotation_stddev_of_intrinsics_deg);
          if (refine) result.intrinsics_stddev = std::move(solved.intrinsics_stddev);
        }
        break;
      }
    }
  };
  adjust(coarse_first ? -1 : 0, false, !options.refine_intrinsics);
  // Refining the intrinsics: from the poses the given intrinsics led to, each pass triangulates
  // every track again (observations the better intrinsics now explain return) and adjusts with
  // the intrinsics free. The filter's count is the last pass's.
  for (int pass = 0; options.refine_intrinsics && pass < options.intrinsics_passes; ++pass) {
    points = bp.Triangulate(min_angle, options.max_reprojection_error_px);
    result.num_filtered_observations = 0;
    adjust(0, true, pass + 1 == options.intrinsics_passes);
  }
  result.cameras = bp.cameras;
  result.timing = bp.time;

  for (int c = 0; c < n; ++c) {
    if (initial_cam_from_rig[c]) result.poses.cam_from_rig[c] = Rigid3d(Eigen::Quaterniond(bp.cq[c].data()), bp.ct[c]);
  }
  for (int k = 0; k < num_frames; ++k) {
    if (initial_rig_from_world[k]) result.poses.rig_from_world[k] = Rigid3d(Eigen::Quaterniond(bp.rq[k].data()), bp.rt[k]);
  }
  result.num_points = static_cast<int>(points.size());
  for (const WorldPoint& p : points) {
    for (const ViewObservation& o : p.observations) ++result.observations_per_camera[o.camera];
    result.num_observations += static_cast<int>(p.observations.size());
  }
  result.reprojection_rms_px = bp.RmsPx(points);
  result.median_depth = bp.MedianDepth(points);
  if (options.keep_points) {
    result.final_residuals_px = bp.Residuals(points);
    for (const WorldPoint& p : points) {
      result.points.push_back(p.x);
      result.point_observations.push_back(static_cast<int>(p.observations.size()));
    }
  }
  return result;
}

double TruncatedReprojectionCost(const std::vector<Camera>& cameras, const FrameKeypoints& keypoints,
                                 const std::vector<ViewTrack>& tracks,
                                 const RigPoses& poses, double max_error_px,
                                 double min_angle_deg, int* observations) {
  const PerCamera<Rigid3d>& cam_from_rig = poses.cam_from_rig;
  const PerFrame<Rigid3d>& rig_from_world = poses.rig_from_world;
  auto posed = [&](const ViewObservation& o) { return poses.Posed(o.camera, o.frame); };
  auto view_pose = [&](const ViewObservation& o) { return poses.CamFromWorld(o.camera, o.frame); };
  double far = 0.0;  // the largest distance between two posed views' centres
  {
    std::vector<Eigen::Vector3d> centres;
    for (const auto& r : rig_from_world) {
      for (const auto& c : cam_from_rig) {
        if (r && c) centres.push_back((*c * *r).Inverse().translation);
      }
    }
    for (const Eigen::Vector3d& a : centres) {
      for (const Eigen::Vector3d& b : centres) far = std::max(far, (a - b).norm());
    }
    far = 1e6 * std::max(far, 1e-9);
  }
  const double cap = max_error_px * max_error_px;
  const double min_angle = DegToRad(min_angle_deg);
  double cost = 0.0;
  int count = 0;
  for (const ViewTrack& t : tracks) {
    std::vector<Eigen::Vector3d> origins, dirs;
    std::vector<const ViewObservation*> used;
    for (const ViewObservation& o : t.observations) {
      if (!posed(o)) continue;
      const auto f = cameras[o.camera].CamFromImg(keypoints[o.frame][o.camera][o.keypoint]);
      if (!f) continue;
      const Rigid3d world_from_cam = view_pose(o).Inverse();
      origins.push_back(world_from_cam.translation);
      dirs.push_back((world_from_cam.rotation * *f).normalized());
      used.push_back(&o);
    }
    if (used.size() < 2) continue;
    std::optional<Eigen::Vector3d> x = TriangulateRays(origins, dirs, min_angle);
    if (!x) {
      Eigen::Vector3d mean = Eigen::Vector3d::Zero();
      for (const Eigen::Vector3d& d : dirs) mean += d;
      x = origins[0] + far * mean.normalized();
    }
    for (const ViewObservation* o : used) {
      const auto e = ReprojectionError(cameras[o->camera], view_pose(*o), *x, keypoints[o->frame][o->camera][o->keypoint]);
      cost += e ? std::min(*e * *e, cap) : cap;
      ++count;
    }
  }
  if (observations) *observations = count;
  return cost;
}

}  // namespace rigsim
