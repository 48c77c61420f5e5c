#include "calibrator/motion_links.h"

#include <algorithm>
#include <chrono>
#include <set>
#include <stdexcept>
#include <string>
#include <tuple>

#include <tbb/parallel_for.h>

#include "calibrator/camera_trajectory.h"
#include "calibrator/format.h"
#include "calibrator/matching.h"
#include "calibrator/multi_frame_rig.h"
#include "calibrator/parallel_scope.h"
#include "calibrator/two_view.h"

namespace rigsim {
namespace {

using MotionClock = std::chrono::steady_clock;

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
  fit.two_view = EstimateRelativePose(obs.cameras[c.cam_a], px_a, obs.cameras[c.cam_b], px_b, options.pairwise.two_view);
  if (!fit.two_view.success || fit.two_view.num_inliers < options.view_graph.min_inliers) return std::nullopt;
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
  if (predicted && RotationDifferenceDeg(*predicted, tv.cam_b_from_cam_a.rotation) >
                       options.motion.max_prediction_disagreement_deg) {
    return std::nullopt;
  }
  CrossTimePairEstimate e{c.cam_a, c.frame_a, c.cam_b, c.frame_b, ToEstimate(tv, static_cast<int>(matches.size())), {}};
  for (size_t i = 0; i < matches.size(); ++i) {
    if (tv.inlier_mask[i]) e.inliers.push_back(matches[i]);
  }
  return e;
}

// The motion stage is on and the rig moved over enough frames, and `obs` has no links yet.
bool MotionCanLink(const RigObservations& obs, const RigCalibrationOptions& options) {
  return options.motion.enabled && !obs.HasMotionLinks() && !obs.temporal.empty() &&
         static_cast<int>(obs.keypoints.size()) >= options.motion.min_frames;
}

// A camera the same-instant pairs left without a full pose: what the motion stage is for.
bool NeedsMotionLinks(const RigCalibrationResult& r, const RigObservations& obs, const RigCalibrationOptions& options) {
  if (!MotionCanLink(obs, options)) return false;
  return std::any_of(r.camera_status.begin(), r.camera_status.end(), [](const CameraStatus& s) {
    return s.outcome == CameraOutcome::kNotConnected || s.outcome == CameraOutcome::kRotationOnly;
  });
}

// Cameras with a full pose, or one but for an axis the motion leaves open.
int CamerasPlaced(const RigCalibrationResult& r) {
  return static_cast<int>(std::count_if(r.camera_status.begin(), r.camera_status.end(), [](const CameraStatus& s) {
    return HasFullPose(s.outcome) || s.outcome == CameraOutcome::kOpenAlongAxis;
  }));
}

// Cameras joined with camera 0 by active same-instant edges of `graph`.
std::vector<char> ReachedByEdges(const ViewGraph& graph, int n) {
  std::vector<char> reached(n, 0);
  reached[0] = 1;
  for (bool grew = true; grew;) {
    grew = false;
    for (const ViewGraphEdge& e : graph.edges) {
      if (!e.active || reached[e.cam_a] == reached[e.cam_b]) continue;
      reached[e.cam_a] = reached[e.cam_b] = 1;
      grew = true;
    }
  }
  return reached;
}

// One joint averaging of every rotation, leaving out the cross-time pairs of `dropped` cameras.
JointRotations AverageJointly(const RigObservations& obs, const ViewGraph& graph, const std::vector<char>& dropped,
                              const RigCalibrationOptions& options) {
  const int n = static_cast<int>(obs.cameras.size());
  const int num_frames = static_cast<int>(obs.keypoints.size());
  std::vector<ViewPairRotation> measurements;
  for (const ViewGraphEdge& e : graph.edges) {
    if (e.active) measurements.push_back({e.cam_a, e.cam_b, -1, -1, e.rotation, std::max(e.weight, 1)});
  }
  for (const TemporalPairEstimate& t : obs.temporal) {
    if (!t.PoseUsable()) continue;
    measurements.push_back({t.camera, t.camera, t.frame, t.frame + 1, t.two_view.cam_b_from_cam_a.rotation,
                            std::max(t.two_view.num_inliers, 1)});
  }
  std::vector<int> measurement_of(obs.cross_time.size(), -1);  // per cross-time pair
  for (size_t i = 0; i < obs.cross_time.size(); ++i) {
    const CrossTimePairEstimate& x = obs.cross_time[i];
    if (dropped[x.cam_a] || dropped[x.cam_b]) continue;
    measurement_of[i] = static_cast<int>(measurements.size());
    measurements.push_back({x.cam_a, x.cam_b, x.frame_a, x.frame_b, x.two_view.cam_b_from_cam_a.rotation,
                            std::max(x.two_view.num_inliers, 1)});
  }
  std::vector<std::optional<Eigen::Quaterniond>> starts = obs.rotation_start;
  for (int c = 0; c < n && !starts.empty(); ++c) {
    if (dropped[c]) starts[c].reset();
  }
  JointRotations out;
  out.rotations = AverageRigRotations(n, num_frames, measurements, starts, options.motion.rotation_averaging);
  for (int c = 0; c < n; ++c) {
    if (dropped[c]) out.rotations.cam_from_rig[c].reset();
  }
  const auto& q = out.rotations.cam_from_rig;
  const auto& r = out.rotations.rig_from_world;
  for (size_t i = 0; i < obs.cross_time.size(); ++i) {
    const CrossTimePairEstimate& x = obs.cross_time[i];
    const int m = measurement_of[i];
    out.cross_time_used.push_back(m >= 0 && !out.rotations.outlier[m] && q[x.cam_a] && q[x.cam_b] && r[x.frame_a] &&
                                  r[x.frame_b]);
  }
  return out;
}

// Marks in `dropped` the cameras outside `reached` whose rotation no two things agree on: hand-eye
// within MotionLinkOptions::max_hand_eye_disagreement_deg counts as two, each used cross-time pair
// with another camera still kept as one; and those no used pair joins with an anchored camera.
void DropUnsupportedCameras(const RigObservations& obs, const std::vector<char>& reached,
                            const RigCalibrationOptions& options, JointRotations* joint, std::vector<char>* dropped) {
  const int n = static_cast<int>(obs.cameras.size());
  auto& q = joint->rotations.cam_from_rig;
  for (bool changed = true; changed;) {
    changed = false;
    for (int c = 1; c < n; ++c) {
      if (reached[c] || !q[c]) continue;
      int support = 0;
      const auto& he = obs.hand_eye_rotation.empty() ? std::nullopt : obs.hand_eye_rotation[c];
      if (he && RotationDifferenceDeg(*he, *q[c]) <= options.motion.max_hand_eye_disagreement_deg) support += 2;
      for (size_t i = 0; i < obs.cross_time.size(); ++i) {
        const CrossTimePairEstimate& x = obs.cross_time[i];
        const int other = x.cam_a == c ? x.cam_b : x.cam_b == c ? x.cam_a : c;
        support += joint->cross_time_used[i] && other != c && q[other];
      }
      if (support >= 2) continue;
      q[c].reset();
      (*dropped)[c] = 1;
      changed = true;
      for (size_t i = 0; i < obs.cross_time.size(); ++i) {
        if (obs.cross_time[i].cam_a == c || obs.cross_time[i].cam_b == c) joint->cross_time_used[i] = 0;
      }
    }
  }
  // Two cameras that agree only with each other hang on hand-eye starts that did not determine
  // them: kept are the cameras used cross-time pairs join with camera 0's part or hand-eye's.
  std::vector<char> anchored = reached;
  for (int c = 1; c < n; ++c) {
    const auto& he = obs.hand_eye_rotation.empty() ? std::nullopt : obs.hand_eye_rotation[c];
    if (q[c] && he && RotationDifferenceDeg(*he, *q[c]) <= options.motion.max_hand_eye_disagreement_deg) anchored[c] = 1;
  }
  for (bool grew = true; grew;) {
    grew = false;
    for (size_t i = 0; i < obs.cross_time.size(); ++i) {
      const CrossTimePairEstimate& x = obs.cross_time[i];
      if (!joint->cross_time_used[i] || anchored[x.cam_a] == anchored[x.cam_b]) continue;
      anchored[x.cam_a] = anchored[x.cam_b] = 1;
      grew = true;
    }
  }
  for (int c = 1; c < n; ++c) {
    if (anchored[c] || !q[c]) continue;
    q[c].reset();
    (*dropped)[c] = 1;
  }
  for (size_t i = 0; i < obs.cross_time.size(); ++i) {
    const CrossTimePairEstimate& x = obs.cross_time[i];
    if (!q[x.cam_a] || !q[x.cam_b]) joint->cross_time_used[i] = 0;
  }
}

// True when a camera `result` calibrated kept under a quarter as many bundle-adjustment
// observations as its own motion has inliers: links that turn the rig wrongly make a camera's own
// tracks stop fitting (a reference camera kept 5 of its observations under a rig turned 50 deg by
// consistent wrong matches of a facade).
bool LosesOwnTracks(const RigObservations& obs, const RigCalibrationResult& result) {
  std::vector<int> own(obs.cameras.size(), 0);
  for (const TemporalPairEstimate& t : obs.temporal) {
    if (t.two_view.success) own[t.camera] += static_cast<int>(t.inliers.size());
  }
  for (size_t c = 0; c < own.size(); ++c) {
    if (!HasFullPose(result.camera_status[c].outcome)) continue;
    if (4 * result.camera_stats[c].observations < own[c]) return true;
  }
  return false;
}

RigCalibrationResult::MotionLinkSummary SummaryOf(const MotionLinks& links, bool kept, int pairs_used,
                                                  const PredictionCheck& check) {
  RigCalibrationResult::MotionLinkSummary summary;
  summary.predicted_views_agreeing = check.agreeing;
  summary.predicted_views_contradicting = check.contradicting;
  summary.kept = kept;
  summary.motion = links.motion.kind;
  summary.candidates = links.num_candidates;
  summary.pairs = static_cast<int>(links.cross_time.size());
  summary.pairs_used = pairs_used;
  summary.temporal_alternatives_taken = links.temporal_alternatives_taken;
  summary.temporal_pairs_disagreeing = links.temporal_pairs_disagreeing;
  summary.time_s = links.time_s + check.time_s;
  return summary;
}

// A camera the motion stage did not place either: its status says what the rig's motion gave for
// it (hand-eye's finding, the view pairs matched with it across time), so that a user sees why.
void SayWhatTheMotionFound(const MotionLinks& links, const PredictionCheck& check, RigCalibrationResult* result) {
  result->motion_links = SummaryOf(links, false, 0, check);
  for (size_t c = 1; c < result->camera_status.size() && c < links.hand_eye.size(); ++c) {
    CameraStatus& s = result->camera_status[c];
    if (s.outcome != CameraOutcome::kNotConnected && s.outcome != CameraOutcome::kRotationOnly) continue;
    const int cam = static_cast<int>(c);
    const auto pairs = std::count_if(links.cross_time.begin(), links.cross_time.end(),
                                     [&](const CrossTimePairEstimate& x) { return x.cam_a == cam || x.cam_b == cam; });
    const HandEyeCamera& h = links.hand_eye[c];
    const std::string hand_eye =
        h.status == HandEyeStatus::kSolved ? "solved, but the joint solution did not hold" : h.reason;
    s.reason += "; nor did the rig's motion place it (hand-eye: " + hand_eye + "; " + std::to_string(pairs) +
                " view pair(s) matched with it across time";
    if (check.AnyCameraContradicted()) {
      s.reason += "; the rig they made predicts views that the images contradict (wrong matches of repeated "
                  "structure): of the view pairs it predicts for this camera, matched afresh, " +
                  std::to_string(check.camera_agreeing[c]) + " agree and " + std::to_string(check.camera_contradicting[c]) +
                  " contradict; of all, " + std::to_string(check.agreeing) + " and " + std::to_string(check.contradicting);
    }
    s.reason += ")";
  }
}

// Hand-eye solved no camera and no view pair linked across time: nothing for a pass with links.
bool FoundNothing(const MotionLinks& links) {
  return links.cross_time.empty() && std::none_of(links.hand_eye.begin() + 1, links.hand_eye.end(),
                                                  [](const HandEyeCamera& h) { return h.status == HandEyeStatus::kSolved; });
}

// The rig stages on `obs` with the motion stage's links.
RigCalibrationResult EstimateRigWithLinks(const RigObservations& obs, const MotionLinks& links,
                                          const RigCalibrationOptions& options) {
  RigObservations linked = obs;
  linked.temporal = links.temporal;
  linked.cross_time = links.cross_time;
  linked.rotation_start = links.rotation_start;
  linked.hand_eye_rotation = links.hand_eye_rotation;
  linked.open_axis = links.open_axis;
  return EstimateRig(linked, options);
}

// Whether `second` (with the links) keeps its own tracks and is contradicted for none of its
// cameras by the views it predicts (`check`, of `second`).
bool Holds(const RigObservations& obs, const RigCalibrationResult& second, const PredictionCheck& check) {
  return !LosesOwnTracks(obs, second) && !check.AnyCameraContradicted();
}

// `second` (with the links) where it places more cameras than `first` (without), keeps its own
// tracks and is contradicted for none of its cameras by the views it predicts (`check`); `first`
// otherwise; either counts the work of both.
RigCalibrationResult TheBetterPass(const RigObservations& obs, RigCalibrationResult first, RigCalibrationResult second,
                                   const MotionLinks& links, const PredictionCheck& check) {
  if (CamerasPlaced(second) <= CamerasPlaced(first) || !Holds(obs, second, check)) {
    SayWhatTheMotionFound(links, check, &first);
    AddRigWork(second, &first);
    return first;
  }
  second.motion_links = SummaryOf(links, true, second.num_cross_time_pairs_used, check);
  AddRigWork(first, &second);
  return second;
}

// After the full pass without links, `first`: the motion stage only where it leaves a camera
// without a full pose.
RigCalibrationResult LinkWhereTheFullPassNeedsIt(const RigObservations& obs, RigCalibrationResult first,
                                                 const ViewPairMatcher& match, const RigCalibrationOptions& options) {
  if (!NeedsMotionLinks(first, obs, options)) return first;
  const MotionLinks links = FindMotionLinks(obs, first.cam_from_rig_rotation, match, options);
  if (FoundNothing(links)) {
    SayWhatTheMotionFound(links, {}, &first);
    return first;
  }
  RigCalibrationResult second = EstimateRigWithLinks(obs, links, options);
  const PredictionCheck check = CheckPredictedViews(obs, links, second, match, options);
  return TheBetterPass(obs, std::move(first), std::move(second), links, check);
}

// The motion stage first, from the rotations where the pass without links stopped
// (EstimateRigUnlessUnplaced): a pass with the links that places every camera, keeps its own
// tracks and holds against the views it predicts is the result, and the full pass without them runs
// only otherwise, to compare as LinkWhereTheFullPassNeedsIt does.
RigCalibrationResult LinkBeforeTheFullPass(const RigObservations& obs,
                                           const std::vector<std::optional<Eigen::Quaterniond>>& known_rotations,
                                           const ViewPairMatcher& match, const RigCalibrationOptions& options) {
  const MotionLinks links = FindMotionLinks(obs, known_rotations, match, options);
  std::optional<RigCalibrationResult> second;
  PredictionCheck check;
  if (!FoundNothing(links)) {
    second = EstimateRigWithLinks(obs, links, options);
    check = CheckPredictedViews(obs, links, *second, match, options);
    if (CamerasPlaced(*second) == static_cast<int>(obs.cameras.size()) && Holds(obs, *second, check)) {
      second->motion_links = SummaryOf(links, true, second->num_cross_time_pairs_used, check);
      return *std::move(second);
    }
  }
  RigCalibrationResult first = EstimateRig(obs, options);
  // Where the full pass leaves no camera without a full pose after all (a pair a later round
  // rejected had left it out of rotation averaging), the motion stage was not needed: it ran, not
  // kept.
  if (!second || !NeedsMotionLinks(first, obs, options)) {
    SayWhatTheMotionFound(links, check, &first);
    if (second) AddRigWork(*second, &first);
    return first;
  }
  return TheBetterPass(obs, std::move(first), *std::move(second), links, check);
}

}  // namespace

void MotionLinkOptions::Check() const {
  auto fail = [](const std::string& why) { throw std::invalid_argument("MotionLinkOptions: " + why); };
  if (min_frames < 3) fail("min_frames must be >= 3");
  hand_eye.Check();
  rig_turns.Check();
  candidates.Check();
  rotation_averaging.Check();
  if (!(max_prediction_disagreement_deg > 0)) fail("max_prediction_disagreement_deg must be > 0");
  if (!(max_hand_eye_disagreement_deg > 0)) fail("max_hand_eye_disagreement_deg must be > 0");
  if (!(max_prediction_check_deg > 0)) fail("max_prediction_check_deg must be > 0");
  if (min_prediction_contradictions < 1) fail("min_prediction_contradictions must be >= 1");
  if (!(max_inter_camera_weight >= 1)) fail("max_inter_camera_weight must be >= 1");
}

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
                            const std::vector<std::optional<Eigen::Quaterniond>>& known_rotations,
                            const ViewPairMatcher& match, const RigCalibrationOptions& options) {
  const auto start = MotionClock::now();
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
  out.time_s = std::chrono::duration<double>(MotionClock::now() - start).count();
  return out;
}

RigCalibrationResult EstimateRigWithMotionLinks(const RigObservations& obs, const ViewPairMatcher& match,
                                                const RigCalibrationOptions& options) {
  if (!MotionCanLink(obs, options)) return EstimateRig(obs, options);
  RigPreCheck stop;
  std::optional<RigCalibrationResult> first = EstimateRigUnlessUnplaced(obs, options, &stop);
  if (first) return LinkWhereTheFullPassNeedsIt(obs, *std::move(first), match, options);
  RigCalibrationResult result = LinkBeforeTheFullPass(obs, stop.cam_from_rig_rotation, match, options);
  AddRigWork(stop.work, &result);
  return result;
}

// For the rig stages (rig_calibration.cc).

bool PredictionCheck::AnyCameraContradicted() const {
  for (size_t c = 0; c < camera_contradicting.size(); ++c) {
    if (camera_contradicting[c] >= min_contradictions && camera_contradicting[c] > 2 * camera_agreeing[c]) return true;
  }
  return false;
}

PredictionCheck CheckPredictedViews(const RigObservations& obs, const MotionLinks& links, const RigCalibrationResult& result,
                                    const ViewPairMatcher& match, const RigCalibrationOptions& options) {
  const auto start = MotionClock::now();
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
      double nearest = RotationDifferenceDeg(predicted, tv.cam_b_from_cam_a.rotation);
      for (const Rigid3d& other : tv.planar_alternatives) nearest = std::min(nearest, RotationDifferenceDeg(predicted, other.rotation));
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
  out.time_s = std::chrono::duration<double>(MotionClock::now() - start).count();
  return out;
}

JointRotations AverageRotationsWithMotionLinks(const RigObservations& obs, const ViewGraph& graph,
                                               const RigCalibrationOptions& options) {
  const int n = static_cast<int>(obs.cameras.size());
  const std::vector<char> reached = ReachedByEdges(graph, n);
  std::vector<char> dropped(n, 0);  // cameras without two agreeing supports
  JointRotations out;
  for (int round = 0; round < 2; ++round) {
    out = AverageJointly(obs, graph, dropped, options);
    std::vector<char> more = dropped;
    DropUnsupportedCameras(obs, reached, options, &out, &more);
    if (more == dropped) break;
    dropped = more;
  }
  return out;
}

std::vector<std::optional<Eigen::Vector3d>> HeldCentreAxes(const RigObservations& obs, const std::vector<ViewTrack>& tracks) {
  const int n = static_cast<int>(obs.cameras.size());
  std::vector<std::optional<Eigen::Vector3d>> held(n);
  if (obs.open_axis.empty()) return held;
  std::vector<char> shares(n, 0);  // a track joins the camera with another one
  for (const ViewTrack& t : tracks) {
    for (const ViewObservation& o : t.observations) {
      if (o.camera != t.observations[0].camera) {
        for (const ViewObservation& p : t.observations) shares[p.camera] = 1;
        break;
      }
    }
  }
  for (int c = 1; c < n; ++c) {
    if (obs.open_axis[c] && !shares[c]) held[c] = obs.open_axis[c];
  }
  return held;
}

std::string OpenAxisReason(const Eigen::Vector3d& axis) {
  return "its offset along the turn axis of the rig's planar motion (" + Fixed(axis.x(), 2) + ", " +
         Fixed(axis.y(), 2) + ", " + Fixed(axis.z(), 2) +
         " in the rig: its height when the rig turns about the vertical) is not determined: no point joins it with "
         "another camera, and a motion about one axis leaves it open; to place it: a path that also pitches or rolls, "
         "or more overlap with a placed camera";
}

double InterCameraWeight(const std::vector<ViewTrack>& tracks, double max_weight) {
  double all = 0.0, shared = 0.0;
  for (const ViewTrack& t : tracks) {
    all += t.observations.size();
    const bool joins = std::any_of(t.observations.begin(), t.observations.end(),
                                   [&](const ViewObservation& o) { return o.camera != t.observations[0].camera; });
    if (joins) shared += t.observations.size();
  }
  if (shared <= 0.0) return 1.0;
  return std::clamp(0.25 * all / shared, 1.0, max_weight);
}

}  // namespace rigsim
