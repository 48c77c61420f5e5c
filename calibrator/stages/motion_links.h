// Links between cameras from the rig's motion, for rigs whose cameras share little or nothing of
// their views at the same instant (a ring at low overlap): the same-instant view graph leaves them
// out of camera 0's part, but as the rig turns, camera b at frame t' sees what camera a saw at t.
//
// Stages (FindMotionLinks): each step between frames takes the pose the rig agrees with
// (rig_turns.h) -> each camera's own trajectory from those steps (camera_trajectory.h) -> hand-eye calibration against camera 0's (hand_eye.h): a start of every
// camera's rotation in the rig, and the axis of a planar motion -> which views to match across time
// (cross_time_candidates.h: predicted from the rotations known, a search by the rig's turn for the
// others) -> those view pairs matched (with the pairwise stage's matcher and semantic mode) and
// estimated (two_view.h). The rig stage (rig_calibration.h, with rig_motion_links.h) then averages
// every rotation jointly (rig_rotation_averaging.h), extends the tracks with the cross-time inliers
// and adjusts the rig over all frames, weighing the few observations shared by two cameras up; the
// controller (motion_passes.h) decides which pass is kept.
//
// What the motion leaves open is said, never guessed: a camera that no track joins with another
// camera is placed by its own motion alone, and a planar motion does not fix its centre along the
// turn axis (rig_calibration.h PositionOutcome::kOpenAlongTurnAxis).
#pragma once

#include <functional>
#include <optional>
#include <string>
#include <utility>
#include <vector>

#include <Eigen/Core>
#include <Eigen/Geometry>

#include "calibrator/estimators/cross_time_candidates.h"
#include "calibrator/estimators/hand_eye.h"
#include "calibrator/estimators/rig_rotation_averaging.h"
#include "calibrator/estimators/rig_turns.h"
#include "calibrator/features/matching.h"
#include "calibrator/model/rig_observations.h"
#include "calibrator/model/rig_state.h"
#include "calibrator/stages/pairwise.h"
#include "calibrator/stages/rig_options.h"
#include "calibrator/stages/rig_result.h"

namespace rigsim {

// The matches (keypoint index in view a, in view b) of view (cam_a, frame_a) with view (cam_b,
// frame_b). Called from several threads at once.
using ViewPairMatcher = std::function<std::vector<std::pair<int, int>>(int cam_a, int frame_a, int cam_b, int frame_b)>;

// The pairwise stage's matcher and semantic mode (pairwise.h) on `views`' features. `views` must
// outlive the matcher.
ViewPairMatcher MatcherOfViews(const RigViews& views, const MatchOptions& options);

// What the motion stage found, for the rig stages (RigObservations) and a report.
struct MotionLinks {
  MotionClass motion;  // how camera 0's trajectory turns
  // Per camera: its hand-eye result (camera 0: the reference).
  std::vector<HandEyeCamera> hand_eye;
  // Per camera: the start of its rotation in the rig (the rotation already known, or hand-eye's).
  PerCamera<Eigen::Quaterniond> rotation_start;
  // Per camera: the rotation hand-eye calibration determined (kSolved), nullopt otherwise.
  PerCamera<Eigen::Quaterniond> hand_eye_rotation;
  // Per camera: with a planar motion, the turn axis in the rig, along which the motion does not
  // fix its centre; nullopt otherwise.
  PerCamera<Eigen::Vector3d> open_axis;
  // The temporal pairs with the poses the rig agrees with (rig_turns.h), for the rig stages, and how
  // many took their planar alternative or disagree with every pose (failed).
  std::vector<TemporalPairEstimate> temporal;
  int temporal_alternatives_taken = 0;
  int temporal_pairs_disagreeing = 0;
  int num_candidates = 0;  // view pairs matched
  std::vector<CrossTimeCandidate> matched;  // those view pairs
  // Per camera: 1 when the same-instant pairs gave it no rotation (the motion stage is to place it).
  std::vector<char> placed_by_motion;
  std::vector<CrossTimePairEstimate> cross_time;  // the successful ones
  double time_s = 0.0;
};

// The motion stage on `obs` (which needs temporal pairs and options.min_frames frames; otherwise
// nothing is found). `known_rotations` (per camera, nullopt where unknown) are the rotations in the
// rig that the same-instant pairs already gave.
MotionLinks FindMotionLinks(const RigObservations& obs,
                            const PerCamera<Eigen::Quaterniond>& known_rotations,
                            const ViewPairMatcher& match, const RigCalibrationOptions& options);

// The rig `result` that the motion links `links` made, checked on view pairs it predicts to meet
// (cross_time_candidates.h, from its rotations) that involve a camera the motion stage placed and
// that the motion stage did not match, between two cameras (a camera's pairs with itself predict
// the same rotation whatever its turn about the axis of a planar motion, the turn cross-time links
// can get wrong, and measure only its own matching): each, matched and estimated now, agrees with
// the rig's rotation between its two views (within MotionLinkOptions::max_prediction_check_deg, by
// its pose or a planar alternative) or contradicts it. Cross-time matches of repeated structure can
// agree with each other on a wrong rig where the motion leaves a camera's turn open; the views that
// rig predicts then do not show what it says.
// Counted per camera (a pair counts for each of its cameras the motion stage placed) and in all. A
// camera is contradicted when at least `min_contradictions`
// (MotionLinkOptions::min_prediction_contradictions) of its pairs contradict the rig and more
// than twice as many contradict as agree: a right camera's predicted views mostly agree (a wrong
// match or a degenerate pair contradicts now and then); a camera a few degrees wrong has none that
// agree.
struct PredictionCheck {
  int agreeing = 0;
  int contradicting = 0;
  std::vector<int> camera_agreeing, camera_contradicting;
  double time_s = 0.0;
  int min_contradictions = 1;

  bool AnyCameraContradicted() const;
};
PredictionCheck CheckPredictedViews(const RigObservations& obs, const MotionLinks& links, const RigCalibrationResult& result,
                                    const ViewPairMatcher& match, const RigCalibrationOptions& options);

}  // namespace rigsim
