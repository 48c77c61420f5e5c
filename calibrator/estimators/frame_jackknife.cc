#include "calibrator/estimators/frame_jackknife.h"

#include <algorithm>
#include <cmath>
#include <utility>

#include <Eigen/Eigenvalues>
#include <tbb/parallel_for.h>

#include "calibrator/estimators/bundle_covariance.h"
#include "geometry/rigid3.h"

namespace rigsim {
namespace {

constexpr int kMinFrames = 3;
// Beyond this many posed frames, runs of consecutive frames are left out together (a delete-a-group
// jackknife): the cost stays that of this many adjustments, and neighbouring frames, which share
// most of their scene, leave together.
constexpr int kMaxGroups = 10;
constexpr int kMaxIterations = 15;

// The problem without the observations and poses of the frames in `left_out` (sorted). Frame 0
// holds the gauge, so when it is left out, frames 0 and `gauge` (posed, kept) swap places (every
// frame index, time and keypoint list).
struct LeftOut {
  FrameKeypoints swapped_keypoints;  // empty unless frame 0 is left out
  std::vector<ViewTrack> tracks;
  RigPoses start;
  std::optional<CaptureTiming> timing;
};

LeftOut WithoutFrames(const RigAdjustmentProblem& problem, const std::vector<int>& left_out, int gauge) {
  const bool swap = left_out.front() == 0;
  const auto frame_of = [&](int k) { return !swap ? k : k == 0 ? gauge : k == gauge ? 0 : k; };
  std::vector<char> removed(problem.keypoints.size(), 0);
  LeftOut out;
  out.start = problem.solution;
  out.timing = problem.timing;
  if (swap) {
    out.swapped_keypoints = problem.keypoints;
    std::swap(out.swapped_keypoints[0], out.swapped_keypoints[gauge]);
    std::swap(out.start.rig_from_world[0], out.start.rig_from_world[gauge]);
    if (out.timing) std::swap(out.timing->frame_times_s[0], out.timing->frame_times_s[gauge]);
  }
  for (int k : left_out) {
    removed[frame_of(k)] = 1;
    out.start.rig_from_world[frame_of(k)].reset();
  }
  for (const ViewTrack& t : problem.tracks) {
    ViewTrack kept;
    for (ViewObservation o : t.observations) {
      o.frame = frame_of(o.frame);
      if (!removed[o.frame]) kept.observations.push_back(o);
    }
    if (kept.observations.size() < 2) continue;
    std::sort(kept.observations.begin(), kept.observations.end(), [](const ViewObservation& a, const ViewObservation& b) {
      return std::pair(a.frame, a.camera) < std::pair(b.frame, b.camera);
    });
    out.tracks.push_back(std::move(kept));
  }
  return out;
}

// The posed frames in at most kMaxGroups runs of consecutive ones, as even as they divide.
std::vector<std::vector<int>> FrameGroups(const std::vector<int>& posed) {
  const int m = static_cast<int>(posed.size()), g = std::min(m, kMaxGroups);
  std::vector<std::vector<int>> groups(g);
  for (int i = 0; i < m; ++i) groups[static_cast<size_t>(i) * g / m].push_back(posed[i]);
  return groups;
}

// (m - 1) / m times the scatter of `samples` about their mean.
Eigen::Matrix3d JackknifeCovariance(const std::vector<Eigen::Vector3d>& samples) {
  const double m = static_cast<double>(samples.size());
  Eigen::Vector3d mean = Eigen::Vector3d::Zero();
  for (const Eigen::Vector3d& x : samples) mean += x / m;
  Eigen::Matrix3d scatter = Eigen::Matrix3d::Zero();
  for (const Eigen::Vector3d& x : samples) scatter += (x - mean) * (x - mean).transpose();
  return (m - 1.0) / m * scatter;
}

double WorstAxisStdDeg(const Eigen::Matrix3d& cov) {
  const Eigen::SelfAdjointEigenSolver<Eigen::Matrix3d> eig(cov, Eigen::EigenvaluesOnly);
  return RadToDeg(std::sqrt(std::max(eig.eigenvalues().maxCoeff(), 0.0)));
}

}  // namespace

RigAdjustmentProblem SolvedProblem(const std::vector<Camera>& cameras, const FrameKeypoints& keypoints,
                                   const std::vector<ViewTrack>& tracks, int scale_camera,
                                   const RigBundleAdjustmentOptions& options, bool hold_frames,
                                   const CaptureTiming* timing, const MultiFrameBundleAdjustmentResult& solved) {
  RigAdjustmentProblem p{cameras, keypoints, tracks, solved.poses, scale_camera, options, hold_frames, std::nullopt};
  if (timing) {
    p.timing = *timing;
    for (size_t c = 0; c < solved.timing.size() && c < cameras.size(); ++c) {
      p.timing->time_offset_s[c] = solved.timing[c][0];
      p.timing->readout_s[c] = solved.timing[c][1];
    }
  }
  return p;
}

FrameJackknife JackknifeOverFrames(const RigAdjustmentProblem& problem) {
  const int n = static_cast<int>(problem.cameras.size());
  FrameJackknife out;
  out.rotation_std_deg.assign(n, std::nullopt);
  out.direction_std_deg.assign(n, std::nullopt);
  std::vector<int> posed;
  for (int k = 0; k < static_cast<int>(problem.solution.rig_from_world.size()); ++k) {
    if (problem.solution.rig_from_world[k]) posed.push_back(k);
  }
  if (static_cast<int>(posed.size()) < kMinFrames) return out;

  RigBundleAdjustmentOptions options = problem.options;
  options.covariance = false;
  options.keep_points = false;
  options.coarse_points = 0;  // it starts at the solution
  options.num_threads = 1;
  // From the solution a run without a tenth to a third of the frames moves little: one filter
  // round and a few iterations per solve give the spread of full runs within 1 % at 40 % of the
  // time (BENCHMARKS.md); without the filter round, outliers of the left-out frames' neighbours
  // stay and the spread moves by up to 25 %.
  options.filter_rounds = std::min(options.filter_rounds, 1);
  options.max_iterations = std::min(options.max_iterations, kMaxIterations);
  const std::vector<std::vector<int>> groups = FrameGroups(posed);
  std::vector<MultiFrameBundleAdjustmentResult> adjusted(groups.size());
  tbb::parallel_for(0, static_cast<int>(groups.size()), [&](int i) {
    const LeftOut left = WithoutFrames(problem, groups[i], groups[i].front() == 0 ? groups[1].front() : 0);
    adjusted[i] = MultiFrameRigBundleAdjust(problem.cameras,
                                            left.swapped_keypoints.empty() ? problem.keypoints : left.swapped_keypoints,
                                            left.tracks, left.start, problem.scale_camera, options, problem.hold_frames,
                                            left.timing ? &*left.timing : nullptr);
  });
  out.groups_left_out = static_cast<int>(groups.size());

  for (int c = 1; c < n; ++c) {
    const std::optional<Rigid3d>& solved = problem.solution.cam_from_rig[c];
    if (!solved) continue;
    std::vector<Eigen::Vector3d> turns, centres;
    for (const MultiFrameBundleAdjustmentResult& a : adjusted) {
      if (a.observations_per_camera[c] == 0 || !a.poses.cam_from_rig[c]) continue;
      const Eigen::AngleAxisd turn(a.poses.cam_from_rig[c]->rotation * solved->rotation.inverse());
      turns.push_back(turn.angle() * turn.axis());
      centres.push_back(a.poses.cam_from_rig[c]->SourceOriginInTarget());
    }
    if (turns.size() < 2) continue;
    out.rotation_std_deg[c] = WorstAxisStdDeg(JackknifeCovariance(turns));
    out.direction_std_deg[c] = DirectionStdDeg(solved->SourceOriginInTarget(), JackknifeCovariance(centres));
  }
  return out;
}

}  // namespace rigsim
