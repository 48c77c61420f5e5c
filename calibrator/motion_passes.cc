#include "calibrator/motion_passes.h"

#include <algorithm>
#include <optional>
#include <utility>

#include "calibrator/model/rig_state.h"
#include "calibrator/stages/registered_rig_adjustment.h"
#include "calibrator/stages/rig_calibration.h"
#include "calibrator/stages/rig_capture_times.h"
#include "calibrator/stages/track_registration.h"
#include "common/format.h"

namespace rigsim {
namespace {

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

// `obs` with the motion stage's links.
RigObservations Linked(const RigObservations& obs, const MotionLinks& links) {
  RigObservations linked = obs;
  linked.temporal = links.temporal;
  linked.cross_time = links.cross_time;
  linked.rotation_start = links.rotation_start;
  linked.hand_eye_rotation = links.hand_eye_rotation;
  linked.open_axis = links.open_axis;
  return linked;
}

// The rig stages on `obs` with the motion stage's links.
RigCalibrationResult EstimateRigWithLinks(const RigObservations& obs, const MotionLinks& links,
                                          const RigCalibrationOptions& options) {
  return EstimateRig(Linked(obs, links), options);
}

// Whether `second` (with the links) keeps its own tracks and is contradicted for none of its
// cameras by the views it predicts (`check`, of `second`).
bool Holds(const RigObservations& obs, const RigCalibrationResult& second, const PredictionCheck& check) {
  return !LosesOwnTracks(obs, second) && !check.AnyCameraContradicted();
}

// `second` (with the links) where it places more cameras than `first` (without), keeps its own
// tracks and is contradicted for none of its cameras by the views it predicts (`check`); `first`
// otherwise; either counts the work of both. `used` becomes the observations of the one kept.
RigCalibrationResult TheBetterPass(const RigObservations& obs, RigCalibrationResult first, RigCalibrationResult second,
                                   const MotionLinks& links, const PredictionCheck& check, RigObservations* used) {
  if (CamerasPlaced(second) <= CamerasPlaced(first) || !Holds(obs, second, check)) {
    SayWhatTheMotionFound(links, check, &first);
    first.work += second.work;
    return first;
  }
  second.motion_links = SummaryOf(links, true, second.num_cross_time_pairs_used, check);
  second.work += first.work;
  *used = Linked(obs, links);
  return second;
}

// After the full pass without links, `first`: the motion stage only where it leaves a camera
// without a full pose.
RigCalibrationResult LinkWhereTheFullPassNeedsIt(const RigObservations& obs, RigCalibrationResult first,
                                                 const ViewPairMatcher& match, const RigCalibrationOptions& options,
                                                 RigObservations* used) {
  if (!NeedsMotionLinks(first, obs, options)) return first;
  options.Tell("linking cameras through the rig's motion");
  const MotionLinks links = FindMotionLinks(obs, first.cam_from_rig_rotation, match, options);
  if (FoundNothing(links)) {
    SayWhatTheMotionFound(links, {}, &first);
    return first;
  }
  RigCalibrationResult second = EstimateRigWithLinks(obs, links, options);
  const PredictionCheck check = CheckPredictedViews(obs, links, second, match, options);
  return TheBetterPass(obs, std::move(first), std::move(second), links, check, used);
}

// The motion stage first, from the rotations where the pass without links stopped
// (EstimateRigUnlessUnplaced): a pass with the links that places every camera, keeps its own
// tracks and holds against the views it predicts is the result, and the full pass without them runs
// only otherwise (resumed where it stopped), to compare as LinkWhereTheFullPassNeedsIt does.
RigCalibrationResult LinkBeforeTheFullPass(const RigObservations& obs, const RigPreCheck& stop,
                                           const ViewPairMatcher& match, const RigCalibrationOptions& options,
                                           RigObservations* used) {
  options.Tell("linking cameras through the rig's motion");
  const MotionLinks links = FindMotionLinks(obs, stop.cam_from_rig_rotation, match, options);
  std::optional<RigCalibrationResult> second;
  PredictionCheck check;
  if (!FoundNothing(links)) {
    second = EstimateRigWithLinks(obs, links, options);
    check = CheckPredictedViews(obs, links, *second, match, options);
    if (CamerasPlaced(*second) == static_cast<int>(obs.cameras.size()) && Holds(obs, *second, check)) {
      second->motion_links = SummaryOf(links, true, second->num_cross_time_pairs_used, check);
      *used = Linked(obs, links);
      return *std::move(second);
    }
  }
  RigCalibrationResult first = EstimateRigFrom(obs, options, stop);
  // Where the full pass leaves no camera without a full pose after all (a pair a later round
  // rejected had left it out of rotation averaging), the motion stage was not needed: it ran, not
  // kept.
  if (!second || !NeedsMotionLinks(first, obs, options)) {
    SayWhatTheMotionFound(links, check, &first);
    if (second) first.work += second->work;
    return first;
  }
  return TheBetterPass(obs, std::move(first), *std::move(second), links, check, used);
}

// The motion passes of EstimateRigWithMotionLinks; `used` becomes the observations of the result.
RigCalibrationResult MotionPasses(const RigObservations& obs, const ViewPairMatcher& match,
                                  const RigCalibrationOptions& options, RigObservations* used) {
  if (!MotionCanLink(obs, options)) return EstimateRig(obs, options);
  RigPreCheck stop;
  std::optional<RigCalibrationResult> first = EstimateRigUnlessUnplaced(obs, options, &stop);
  if (first) return LinkWhereTheFullPassNeedsIt(obs, *std::move(first), match, options, used);
  RigCalibrationResult result = LinkBeforeTheFullPass(obs, stop, match, options, used);
  result.work += stop.work;
  return result;
}

bool SomeCameraUnplaced(const RigCalibrationResult& r) {
  return std::any_of(r.camera_status.begin(), r.camera_status.end(), [](const CameraStatus& s) {
    return s.outcome == CameraOutcome::kNotConnected || s.outcome == CameraOutcome::kRotationOnly;
  });
}

// A registration may add cameras, not move the ones placed without it: a camera placed before
// that loses its pose or turns by more than this (deg) means the registered camera's matches pull
// the rig somewhere its own pairs do not put it.
constexpr double kMaxPlacedRotationChangeDeg = 1.0;

// Why the rig adjusted with the registered cameras, `after`, is not kept over `before`: it places no
// more cameras, moves or un-places one `before` placed, or loses a camera's own tracks
// (LosesOwnTracks). Empty when it is kept.
std::string WhyNotKept(const RigObservations& obs, const RigCalibrationResult& before, const RegisteredRig& registered) {
  const RigCalibrationResult& after = registered.result;
  for (size_t c = 0; c < before.camera_status.size(); ++c) {
    if (!HasFullPose(before.camera_status[c].outcome)) continue;
    const std::string& name = before.rig.cameras[c].name;
    if (!HasFullPose(after.camera_status[c].outcome)) return "the rig adjusted with it leaves " + name + " unplaced";
    const auto& a = before.cam_from_rig_rotation[c];
    const auto& b = after.cam_from_rig_rotation[c];
    const double turn = a && b ? RotationDifferenceDeg(*a, *b) : 0.0;
    if (turn > kMaxPlacedRotationChangeDeg) {
      return "the rig adjusted with it turns " + name + " by " + Fixed(turn, 2) + " deg from where its pairs put it";
    }
  }
  if (LosesOwnTracks(obs, after)) return "the rig adjusted with it no longer fits a placed camera's own tracks";
  if (CamerasPlaced(after) > CamerasPlaced(before)) return "";
  std::string why = "the rig adjusted with it places no more cameras";
  for (const std::string& camera_why : registered.not_placed) why += "; " + camera_why;
  return why;
}

// Says, for each camera the registration did not place, why: in its status.
void SayWhyNotRegistered(const TrackRegistration& reg, const std::string& why_not_kept, RigCalibrationResult* result) {
  if (reg.cameras.empty() && !reg.why_none.empty()) {
    for (CameraStatus& s : result->camera_status) {
      if (s.outcome == CameraOutcome::kNotConnected || s.outcome == CameraOutcome::kRotationOnly) {
        s.reason += "; nor was it registered through tracks (" + reg.why_none + ")";
      }
    }
    return;
  }
  for (const CameraRegistration& r : reg.cameras) {
    CameraStatus& s = result->camera_status[r.camera];
    if (HasFullPose(s.outcome)) continue;
    s.reason += "; nor was it registered through tracks (" +
                (r.registered ? why_not_kept : r.reason + ", over " + std::to_string(r.view_pairs_matched) +
                                                   " view pairs with placed cameras") +
                ")";
  }
}

void SayWhatWasRegistered(const TrackRegistration& reg, RigCalibrationResult* result) {
  for (const CameraRegistration& r : reg.cameras) {
    if (!r.registered || !HasFullPose(result->camera_status[r.camera].outcome)) continue;
    result->warnings.push_back(result->rig.cameras[r.camera].name + " is placed through tracks: " +
                               std::to_string(r.inliers) + " of its " + std::to_string(r.correspondences) +
                               " matches with points the other cameras placed fit one pose (chance: 10^" +
                               Fixed(r.log10_false_alarms, 0) + "), over " + std::to_string(r.view_pairs.size()) +
                               " view pairs; no pair of it placed it alone");
  }
}

// Registration through tracks (track_registration.h) of the cameras `result` leaves without a full
// pose, round after round while it places more: the rig stage on `used` with the registered
// cameras' matches, kept when it places more cameras, keeps the placed ones where they were and
// keeps their own tracks.
RigCalibrationResult RegisterWhereUnplaced(RigObservations used, RigCalibrationResult result,
                                           const ViewPairMatcher& match, const RigCalibrationOptions& options) {
  constexpr int kMaxRounds = 3;
  for (int round = 0; round < kMaxRounds && options.registration.enabled && SomeCameraUnplaced(result); ++round) {
    options.Tell("registering the unplaced cameras through tracks");
    const TrackRegistration reg = RegisterCamerasThroughTracks(used, result, match, options.registration);
    if (!reg.AnyRegistered()) {
      SayWhyNotRegistered(reg, "", &result);
      break;
    }
    RigObservations next = WithRegisteredViewPairs(used, reg);
    options.Tell("adjusting the rig with the registered cameras");
    RegisteredRig second = AdjustRegisteredRig(next, result, reg, options);
    const std::string why_not = WhyNotKept(used, result, second);
    if (!why_not.empty()) {
      SayWhyNotRegistered(reg, "a pose fits its matches with placed points, but " + why_not, &result);
      result.work.bundle_adjustment_time_s = second.result.work.bundle_adjustment_time_s;  // `second` is `result` adjusted
      break;
    }
    SayWhatWasRegistered(reg, &second.result);
    PutHiddenTimeWarningLast(&second.result);
    result = std::move(second.result);
    used = std::move(next);
  }
  return result;
}

}  // namespace

RigCalibrationResult EstimateRigWithMotionLinks(const RigObservations& obs, const ViewPairMatcher& match,
                                                const RigCalibrationOptions& options) {
  RigObservations used = obs;
  RigCalibrationResult result = MotionPasses(obs, match, options, &used);
  return RegisterWhereUnplaced(std::move(used), std::move(result), match, options);
}

}  // namespace rigsim
