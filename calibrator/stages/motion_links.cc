#include "calibrator/stages/motion_links.h"

#include <algorithm>
#include <chrono>
#include <set>
#include <stdexcept>
#include <string>
#include <tuple>

#include <tbb/parallel_for.h>

#include "calibrator/estimators/camera_trajectory.h"
#include "calibrator/estimators/two_view.h"
#include "calibrator/features/matching.h"
#include "calibrator/features/parallel_scope.h"
#include "calibrator/model/rig_state.h"
#include "calibrator/stages/stage_clock.h"

namespace rigsim {
namespace {

// Each camera's own trajectory over the frames, through its steps as the rig chose them; frame 0 is
// the identity by definition, also for a camera whose own motion the images do not fix.
std::vector<CameraTrajectory> CameraTrajectories(const RigObservations& obs, const RigTurns& turns,
                                                 const RigPositionOptions& options) {
  std::vector<CameraTrajectory> out;
  for (int c = 0; c < static_cast<int>(obs.cameras.size()); ++c) {
    out.push_back(EstimateCameraTrajectory(obs.cameras[c], c, obs.keypoints, obs.temporal, turns.step_rotation[c], options));
    if (!out.back().empty()) out.back()[0] = Rigid3d();
  }
  return out;
}

// The rotation of view (b, u) from view (a, t) that the rotations predict: Q_b R_u R_t^T Q_a^T.
std::optional<Eigen::Quaterniond> PredictedViewRotation(const CrossTimeCandidateInputs& in, const CrossTimeCandidate& c) {
  const auto &qa = in.cam_from_rig[c.cam_a], &qb = in.cam_from_rig[c.cam_b];
  const auto &rt = in.rig_from_world[c.frame_a], &ru = in.rig_from_world[c.frame_b];
  if (!qa || !qb || !rt || !ru) return std::nullopt;
  return *qb * *ru * rt->conjugate() * qa->conjugate();
}

// One view pair matched and estimated, with its matches; nullopt with fewer matches or inliers than
// an edge of the view graph needs.
struct ViewPairFit {
  std::vector<std::pair<int, int>> matches;
  TwoViewResult two_view;
};
std::optional<ViewPairFit> FitViewPair(const RigObservations& obs, const CrossTimeCandidate& c, const ViewPairMatcher& match,
                                       const RigCalibrationOptions& options) {
  ViewPairFit fit;
  fit.matches = match(c.cam_a, c.frame_a, c.cam_b, c.frame_b);
  if (static_cast<int>(fit.matches.size()) < options.view_graph.min_inliers) return std::nullopt;
  std::vector<Eigen::Vector2d> px_a, px_b;
  const auto& kp_a = obs.keypoints.at(c.frame_a).at(c.cam_a);
  const auto& kp_b = obs.keypoints.at(c.frame_b).at(c.cam_b);
  for (const auto& [a, b] : fit.matches) {
    px_a.push_back(kp_a.at(a));
    px_b.push_back(kp_b.at(b));
  }
  fit.two_view = EstimateRelativePose(obs.cameras[c.cam_a], px_a, obs.cameras[c.cam_b], px_b,
                                      WithoutRivalSearch(options.pairwise.two_view));
  const TwoViewEstimate& e = fit.two_view.estimate;
  if (!e.success || e.num_inliers < options.view_graph.min_inliers) return std::nullopt;
  return fit;
}

// One candidate matched and estimated; nullopt when it does not link the views (too few inliers,
// or a rotation far from the predicted one).
std::optional<CrossTimePairEstimate> LinkViews(const RigObservations& obs, const CrossTimeCandidate& c,
                                               const std::optional<Eigen::Quaterniond>& predicted,
                                               const ViewPairMatcher& match, const RigCalibrationOptions& options) {
  const std::optional<ViewPairFit> fit = FitViewPair(obs, c, match, options);
  if (!fit) return std::nullopt;
  const TwoViewResult& tv = fit->two_view;
  const std::vector<std::pair<int, int>>& matches = fit->matches;
  if (predicted && RotationDifferenceDeg(*predicted, tv.estimate.cam_b_from_cam_a.rotation) >
                       options.motion.max_prediction_disagreement_deg) {
    return std::nullopt;
  }
  CrossTimePairEstimate e{c.cam_a, c.frame_a, c.cam_b, c.frame_b, tv.estimate, {}};
  for (size_t i = 0; i < matches.size(); ++i) {
    if (tv.inlier_mask[i]) e.inliers.push_back(matches[i]);
  }
  return e;
}
}  // namespace

ViewPairMatcher MatcherOfViews(const RigViews& views, const MatchOptions& options) {
  return [&views, options](int cam_a, int frame_a, int cam_b, int frame_b) {
    std::vector<std::pair<int, int>> out;
    for (const Match& m : MatchFeatures(views.Of(cam_a, frame_a), views.Of(cam_b, frame_b), options)) {
      out.push_back({m.a, m.b});
    }
    return out;
  };
}

MotionLinks FindMotionLinks(const RigObservations& obs,
                            const PerCamera<Eigen::Quaterniond>& known_rotations,
                            const ViewPairMatcher& match, const RigCalibrationOptions& options) {
  const auto start = StageClock::now();
  const int n = static_cast<int>(obs.cameras.size());
  const int num_frames = static_cast<int>(obs.keypoints.size());
  if (static_cast<int>(known_rotations.size()) != n) throw std::invalid_argument("FindMotionLinks: one rotation entry per camera");
  MotionLinks out;
  out.rotation_start.assign(n, std::nullopt);
  out.hand_eye_rotation.assign(n, std::nullopt);
  out.open_axis.assign(n, std::nullopt);
  out.hand_eye.assign(n, HandEyeCamera{});
  out.placed_by_motion.assign(n, 0);
  out.temporal = obs.temporal;
  if (!options.motion.enabled || num_frames < options.motion.min_frames || obs.temporal.empty()) return out;

  // Each step between frames takes the pose the rig agrees with (a planar pair's other pose).
  const RigTurns turns = ResolveStepsByTheRig(obs.temporal, known_rotations, num_frames, options.motion.rig_turns);
  out.temporal = turns.temporal;
  out.temporal_alternatives_taken = turns.alternatives_taken;
  out.temporal_pairs_disagreeing = turns.pairs_disagreeing;
  // Starts: the rotations known, else hand-eye's (also an undetermined one: the averaging and the
  // cross-time pairs decide it).
  const HandEyeResult hand_eye = SolveHandEye(CameraTrajectories(obs, turns, options.positions), options.motion.hand_eye);
  out.motion = hand_eye.motion;
  out.hand_eye = hand_eye.cameras;
  CrossTimeCandidateInputs inputs;
  inputs.cameras = obs.cameras;
  inputs.cam_from_rig = known_rotations;
  inputs.rig_from_world = turns.rig_from_world;
  for (int c = 0; c < n; ++c) {
    const HandEyeCamera& h = hand_eye.cameras[c];
    const bool solved = h.status == HandEyeStatus::kSolved || h.status == HandEyeStatus::kReference;
    const bool start = solved || h.status == HandEyeStatus::kRotationUndetermined;
    out.rotation_start[c] = known_rotations[c] ? known_rotations[c]
                            : start && h.cam_from_rig ? std::optional<Eigen::Quaterniond>(h.cam_from_rig->rotation)
                                                      : std::nullopt;
    if (solved && h.cam_from_rig) out.hand_eye_rotation[c] = h.cam_from_rig->rotation;
    // Only a rotation hand-eye determined predicts where views meet; an open one is searched for.
    if (!inputs.cam_from_rig[c] && solved && h.cam_from_rig) inputs.cam_from_rig[c] = h.cam_from_rig->rotation;
    if (c > 0 && hand_eye.motion.kind == MotionKind::kPlanar) out.open_axis[c] = hand_eye.motion.axis.normalized();
  }

  // Candidates that involve a camera the same-instant pairs did not reach; matched in parallel,
  // kept in candidate order.
  std::vector<CrossTimeCandidate> candidates;
  for (const CrossTimeCandidate& c : SelectCrossTimeCandidates(inputs, options.motion.candidates)) {
    if (!known_rotations[c.cam_a] || !known_rotations[c.cam_b]) candidates.push_back(c);
  }
  out.num_candidates = static_cast<int>(candidates.size());
  out.matched = candidates;
  for (int c = 0; c < n; ++c) out.placed_by_motion[c] = !known_rotations[c];
  std::vector<std::optional<CrossTimePairEstimate>> linked(candidates.size());
  {
    const ParallelScope parallel(options.pairwise.num_threads);
    tbb::parallel_for(0, static_cast<int>(candidates.size()), [&](int i) {
      linked[i] = LinkViews(obs, candidates[i], PredictedViewRotation(inputs, candidates[i]), match, options);
    });
  }
  for (auto& e : linked) {
    if (e) out.cross_time.push_back(std::move(*e));
  }
  out.time_s = SecondsSince(start);
  return out;
}

bool PredictionCheck::AnyCameraContradicted() const {
  for (size_t c = 0; c < camera_contradicting.size(); ++c) {
    if (camera_contradicting[c] >= min_contradictions && camera_contradicting[c] > 2 * camera_agreeing[c]) return true;
  }
  return false;
}

PredictionCheck CheckPredictedViews(const RigObservations& obs, const MotionLinks& links, const RigCalibrationResult& result,
                                    const ViewPairMatcher& match, const RigCalibrationOptions& options) {
  const auto start = StageClock::now();
  const int n = static_cast<int>(obs.cameras.size());
  CrossTimeCandidateInputs inputs;
  inputs.cameras = obs.cameras;
  inputs.cam_from_rig = result.cam_from_rig_rotation;
  for (const auto& pose : result.rig_from_world) {
    inputs.rig_from_world.push_back(pose ? std::optional<Eigen::Quaterniond>(pose->rotation) : std::nullopt);
  }
  PredictionCheck out;
  out.min_contradictions = options.motion.min_prediction_contradictions;
  if (static_cast<int>(inputs.cam_from_rig.size()) != n || inputs.rig_from_world.empty()) return out;
  using ViewPair = std::tuple<int, int, int, int>;  // cam_a, frame_a, cam_b, frame_b
  std::set<ViewPair> matched_before;
  for (const CrossTimeCandidate& m : links.matched) matched_before.emplace(m.cam_a, m.frame_a, m.cam_b, m.frame_b);
  std::vector<CrossTimeCandidate> fresh;
  for (const CrossTimeCandidate& c : SelectCrossTimeCandidates(inputs, options.motion.candidates)) {
    if (c.cam_a == c.cam_b) continue;
    if (!links.placed_by_motion[c.cam_a] && !links.placed_by_motion[c.cam_b]) continue;
    if (!matched_before.count({c.cam_a, c.frame_a, c.cam_b, c.frame_b})) fresh.push_back(c);
  }
  std::vector<int> verdict(fresh.size(), 0);  // +1 agrees, -1 contradicts, 0 no estimate
  {
    const ParallelScope parallel(options.pairwise.num_threads);
    tbb::parallel_for(0, static_cast<int>(fresh.size()), [&](int i) {
      const CrossTimeCandidate& c = fresh[i];
      const std::optional<ViewPairFit> fit = FitViewPair(obs, c, match, options);
      if (!fit) return;
      const TwoViewResult& tv = fit->two_view;
      const Eigen::Quaterniond predicted = *PredictedViewRotation(inputs, c);
      double nearest = RotationDifferenceDeg(predicted, tv.estimate.cam_b_from_cam_a.rotation);
      for (const Rigid3d& other : tv.estimate.planar_alternatives) {
        nearest = std::min(nearest, RotationDifferenceDeg(predicted, other.rotation));
      }
      verdict[i] = nearest <= options.motion.max_prediction_check_deg ? 1 : -1;
    });
  }
  out.camera_agreeing.assign(n, 0);
  out.camera_contradicting.assign(n, 0);
  for (size_t i = 0; i < fresh.size(); ++i) {
    out.agreeing += verdict[i] > 0;
    out.contradicting += verdict[i] < 0;
    for (int c : {fresh[i].cam_a, fresh[i].cam_b}) {
      if (!links.placed_by_motion[c]) continue;
      out.camera_agreeing[c] += verdict[i] > 0;
      out.camera_contradicting[c] += verdict[i] < 0;
    }
  }
  out.time_s = SecondsSince(start);
  return out;
}
}  // namespace rigsim
