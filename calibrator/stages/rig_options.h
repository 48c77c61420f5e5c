// The options of the rig stages (rig_calibration.h) and of the motion stage (motion_links.h), and
// the known distance that gives a result metric scale.
#pragma once

#include <functional>
#include <optional>
#include <string>
#include <utility>
#include <vector>

#include "calibrator/estimators/capture_time.h"
#include "calibrator/estimators/cross_time_candidates.h"
#include "calibrator/estimators/hand_eye.h"
#include "calibrator/estimators/multi_frame_rig.h"
#include "calibrator/estimators/rig_positions.h"
#include "calibrator/estimators/rig_resection.h"
#include "calibrator/estimators/rig_rotation_averaging.h"
#include "calibrator/estimators/rig_turns.h"
#include "calibrator/estimators/rotation_averaging.h"
#include "calibrator/model/view_graph.h"
#include "calibrator/stages/pairwise.h"

namespace rigsim {

// The distance between two cameras' centres, the only source of metric scale.
struct KnownDistance {
  std::string cam_a;
  std::string cam_b;
  double metres = 0.0;
};

// The indices in `names` of the known distance's two cameras. Throws std::invalid_argument starting
// with `where` when it names a camera that is not there, listing the cameras that are.
std::pair<int, int> KnownDistanceCameras(const KnownDistance& known, const std::vector<std::string>& names,
                                         const std::string& where);

// The motion stage (motion_links.h): links between cameras that share little or nothing of their
// views at the same instant, from the rig's motion.
struct MotionLinkOptions {
  // Run it when the same-instant pairs leave a camera without a full pose and the rig moved over
  // at least min_frames frames (temporal pairs).
  bool enabled = true;
  int min_frames = 3;
  HandEyeOptions hand_eye;
  RigTurnOptions rig_turns;
  CrossTimeCandidateOptions candidates;
  // The joint averaging of every rotation (same-instant, temporal and cross-time pairs).
  RigRotationAveragingOptions rotation_averaging;
  // A view pair matched because the rotations predicted that the views meet, whose two-view
  // rotation is farther than this (deg) from the predicted one, is not used: a wrong match of
  // repeated structure (the joint averaging drops the rest).
  double max_prediction_disagreement_deg = 10.0;
  // A camera the same-instant pairs do not reach keeps the rotation the motion links give it only
  // when two things agree on it: its hand-eye rotation within this (deg), or two cross-time pairs
  // with cameras that are kept. One pair alone could be a wrong match nothing would contradict.
  double max_hand_eye_disagreement_deg = 2.0;
  // The rig the motion links made is checked on view pairs it predicts to meet that were not matched
  // to make it: one whose rotation is within this (deg) of the rig's agrees, a farther one
  // contradicts; the rig is not kept when, for one of its cameras, at least
  // min_prediction_contradictions contradict and more than twice as many as agree
  // (PredictionCheck; the figures behind the rule are in BENCHMARKS.md).
  double max_prediction_check_deg = 3.0;
  int min_prediction_contradictions = 2;
  // The bundle adjustment weighs the observations of points that two or more cameras see up, by a
  // quarter of the ratio of all observations to theirs, at most this much
  // (RigBundleAdjustmentOptions::inter_camera_weight).
  double max_inter_camera_weight = 10.0;

  // Throws std::invalid_argument naming the first bad field.
  void Check() const;
};

// Registration through tracks (track_registration.h) of the cameras the rig stage left without a
// full pose.
struct TrackRegistrationOptions {
  // Registration runs after the rig stage where a camera is left without a full pose.
  bool enabled = true;
  // A camera's view at frame f is matched with the placed cameras' views of frames f - reach ..
  // f + reach: a moving rig brings one camera to look where another looked a frame before.
  int frame_reach = 1;
  // At most this many view pairs per camera, spread over the frames.
  int max_view_pairs_per_camera = 48;
  // Points from tracks whose rays meet at under this angle (deg) are too far to place anything, and
  // a track any of whose views its point misses by more than max_track_error_px is not used.
  double min_triangulation_angle_deg = 0.5;
  double max_track_error_px = 3.0;
  RigResectionOptions resection;
  // A camera with a rotation already (rotation only) is registered only where the resection's
  // rotation agrees with it within this (deg).
  double max_rotation_disagreement_deg = 3.0;
  // A view pair passes its inliers on to the rig stage when it has at least this many.
  int min_view_pair_inliers = 3;

  // Throws std::invalid_argument naming the first bad field.
  void Check() const;
};

struct RigCalibrationOptions {
  // Matching and two-view estimation of every pair (pairwise.h).
  PairwiseOptions pairwise;
  // Which pairs become edges.
  ViewGraphOptions view_graph;
  // Robust rotation averaging and its outlier threshold.
  RotationAveragingOptions rotation_averaging;
  // Positions from the tracks (one of the bundle adjustment's starts, rig_positions.h).
  RigPositionOptions positions;
  // Triangulation, bundle adjustment and its outlier filter.
  RigBundleAdjustmentOptions bundle_adjustment;
  // Metric scale; without it the result has unit scale.
  std::optional<KnownDistance> known_distance;
  // A camera whose direction from camera 0 the bundle adjustment's covariance leaves more
  // uncertain than this (standard deviation, deg) is reported "rotation only", not placed. The
  // covariance is optimistic (correlated feature errors): the real direction errors of the target
  // rigs (bench/calibrator_targets.sh) are several times it, so the bound sits where they stay
  // within the 5 deg direction tolerance, above well-fixed cameras and far below cameras that sit
  // (next to) together (VALIDATION.md, "Where the calibrator's thresholds come from"). Held
  // against the deviation that counts every residual as independent, on which it was measured (the
  // stated one is wider by the square root of MultiFrameBundleAdjustmentResult::residual_correlation).
  double max_direction_std_deg = 0.5;
  // The bundle adjustment runs from every initial position estimate (rig_positions.h) and keeps
  // the result the images agree with best. A camera that another start puts more than
  // max_start_disagreement_deg (direction from camera 0) away is reported ambiguous, not placed,
  // unless the other start's cost is more than min_start_cost_ratio times the best: then that
  // start ended in a minimum the images do not support: on the target rigs where the starts ended
  // apart, the other start cost clearly more than the best, and the best's cameras that the
  // covariance kept were within tolerance (VALIDATION.md, "Where the calibrator's thresholds come from"). A wrong pair that makes a wrong
  // rig fit best is left to the pair checks (cheirality, the pair-vs-rig check).
  double max_start_disagreement_deg = 2.0;
  double min_start_cost_ratio = 1.5;
  // A camera placed by one pair only, whose matches fit a rival pose as well (two_view.h), is not
  // placed; its rotation is kept only when the rival's is at most this far (deg) from the pair's.
  double max_rival_rotation_deg = 1.0;
  // A used pair whose two-view rotation is more than max_pair_rotation_disagreement_deg from the
  // rig's, or whose baseline direction is more than max_pair_direction_disagreement_deg from the
  // rig's, is left out and the rig made again without it (at most max_rejected_pairs times, the
  // worst first): a wrong pair agrees with the rest only by chance. The rotation bound is loose: a
  // right fisheye pair's two-view rotation can be a degree or two off a rig that the tracks make
  // right, and a wrong pair shows in its direction, far beyond the direction bound
  // (VALIDATION.md, "Where the calibrator's thresholds come from").
  double max_pair_rotation_disagreement_deg = 3.0;
  double max_pair_direction_disagreement_deg = 10.0;
  int max_rejected_pairs = 3;
  // A pair whose rotation agrees with the rig's within half max_pair_rotation_disagreement_deg and
  // whose baseline direction is off by no more than this keeps its rotation and its matches in the
  // rig, only its direction is left out: a few percent of wrong inliers bias a direction beyond
  // max_pair_direction_disagreement_deg (the parking surround rig without masks) while its rotation
  // and matches still serve; leaving the whole pair out there cut the reference camera off. Farther
  // off, near a mirror pose of repeated structure, the whole pair goes
  // (VALIDATION.md, "Where the calibrator's thresholds come from").
  double max_direction_only_disagreement_deg = 30.0;
  // Keep what a report shows of every stage in RigCalibrationResult::details (matches with their
  // flags, rotations after rotation averaging, points, reprojection errors). Costs memory only.
  bool keep_details = false;
  // Capture times: offsets and rolling-shutter readouts estimated, or checked (capture_time.h).
  // Uses RigObservations::frame_times_s.
  CaptureTimeOptions capture_time;
  // Links between cameras from the rig's motion (motion_links.h; EstimateRigFromPairs only).
  MotionLinkOptions motion;
  // Registration through tracks of the cameras left without a full pose (EstimateRigFromPairs only).
  TrackRegistrationOptions registration;
  // Told, in a user's words, as each long stage begins ("matching the camera pairs", "placing the
  // rig", ...), for a progress display; null: nothing is told. Called from the stage's thread, so
  // from several at once where semantic modes run side by side.
  std::function<void(const std::string& stage)> progress;

  // Throws std::invalid_argument naming the first bad field.
  void Check() const;
  // `progress` told `stage`, when there is a progress.
  void Tell(const std::string& stage) const {
    if (progress) progress(stage);
  }
};

}  // namespace rigsim
