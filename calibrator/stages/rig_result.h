// What the rig stages make of a rig: the rig, each camera's outcome and statistics, each pair's
// edge, the rig's poses per frame, the motion stage's summary and the stage times.
#pragma once

#include <algorithm>
#include <memory>
#include <optional>
#include <string>
#include <string_view>
#include <vector>

#include <Eigen/Core>
#include <Eigen/Geometry>

#include "calibrator/estimators/hand_eye.h"
#include "calibrator/estimators/intrinsics_refinement.h"
#include "calibrator/estimators/rig_turns.h"
#include "calibrator/model/camera_status.h"
#include "calibrator/model/rig_state.h"
#include "calibrator/model/two_view_geometry.h"
#include "calibrator/stages/pairwise.h"
#include "geometry/rig.h"
#include "geometry/rigid3.h"

namespace rigsim {

struct RigCameraStats {
  int observations = 0;  // bundle-adjustment observations kept
  // Standard deviation of the direction of the camera's centre from camera 0's (deg): how well the
  // images fix where the camera is, without truth. The larger of the bundle adjustment's
  // covariance's and the frame jackknife's (below) where that ran.
  std::optional<double> direction_std_deg;
  // Standard deviation of its rotation in the rig (deg, worst axis), the same way.
  std::optional<double> rotation_std_deg;
  // The same two from the adjustment without each frame, to first order (jackknife.h);
  // nullopt with fewer than 3 posed frames or where the camera had no deviation to state.
  std::optional<double> direction_jackknife_std_deg, rotation_jackknife_std_deg;
  // With RigBundleAdjustmentOptions::given_intrinsics_sd: the given intrinsics' share of the two
  // deviations above alone (in them already); the jackknives' spreads, the data's alone, are
  // widened by it in quadrature where they state the deviation.
  std::optional<double> direction_intrinsics_std_deg, rotation_intrinsics_std_deg;
  // With RigBundleAdjustmentOptions::refine_intrinsics, for a camera in the bundle adjustment: its
  // given and refined intrinsics and their standard deviations.
  std::optional<RefinedIntrinsics> intrinsics;
  // Relative to camera 0's (s), with their standard deviations: estimated with
  // CaptureTimeOptions::estimate_offsets / estimate_readout, or, for the offset, measured by the
  // synchronisation check; nullopt otherwise.
  std::optional<double> time_offset_s, time_offset_stddev_s;
  // The check's offset is where the solve stopped, not a measurement: other offsets fit the images
  // as well (CameraSynchronisation::offset_undetermined); time_offset_stddev_s is then nullopt.
  bool time_offset_undetermined = false;
  // Then, where a solve from moved offsets ended, fitting the images as well or better: the
  // offsets between the two are what the images leave open.
  std::optional<double> time_offset_also_fits_s;
  std::optional<double> readout_s, readout_stddev_s;
  // With the synchronisation check or offsets estimated: how much an offset of one frame interval
  // would change the camera's view on the rig's path (px, capture_time.h IntervalVisibilityPx);
  // below CaptureTimeOptions::min_interval_visibility_px the images cannot show its capture time.
  std::optional<double> interval_visibility_px;
};

// What the rig stage made of a camera pair's edge; RigEdgeStats::status says it in words.
enum class EdgeOutcome {
  kUsed,                 // "used"
  kUsedRotationOnly,     // "used (rotation only)": a camera of it has no position
  kDirectionLeftOut,     // used for its rotation only: its baseline direction disagreed with the rig
  kCameraNotCalibrated,  // active, but a camera of it has no rotation
  kTwoViewFailed,        // no two-view estimate ("two-view failed: ...")
  kTooFewInliers,        // below ViewGraphOptions::min_inliers
  kRotationOutlier,      // rotation averaging found its rotation an outlier
  kRejected,             // left out for disagreeing with the rig (status says by how much)
};

struct RigEdgeStats {
  std::string cam_a, cam_b;
  int inliers = 0;
  EdgeOutcome outcome = EdgeOutcome::kTwoViewFailed;
  bool rotation_only = false;  // no translation direction
  std::optional<double> rotation_residual_deg;  // R_b R_a^T vs the pair's rotation at the solution
  // The pair's two-view estimate against the final rig: rotation (deg) and, when both cameras
  // have a position, baseline direction (deg).
  std::optional<double> rotation_disagreement_deg;
  std::optional<double> direction_disagreement_deg;
  // A round of the rig stage left its baseline direction out (kDirectionLeftOut while it stays used).
  bool direction_left_out = false;
  std::string status;  // "used" or why not

  // Active after rotation averaging.
  bool Used() const {
    return outcome == EdgeOutcome::kUsed || outcome == EdgeOutcome::kUsedRotationOnly ||
           outcome == EdgeOutcome::kDirectionLeftOut;
  }
};

// One start of the bundle adjustment (RigCalibrationOptions::max_start_disagreement_deg).
struct RigStartSummary {
  std::string source;  // "two-view directions", "tracks"
  double cost = 0.0;   // TruncatedReprojectionCost after the adjustment (px^2)
  int observations = 0;
  bool chosen = false;
  // Per camera c > 0: the angle between this start's and the chosen one's direction of c from
  // camera 0 after the adjustment; nullopt where either has no position.
  PerCamera<double> direction_difference_deg;
};

// The stages of one calibration as a report shows them (RigCalibrationOptions::keep_details).
struct RigCalibrationDetails {
  // The pairwise stage's keypoints, every match with its inlier flag (pairwise.h, kept with
  // PairwiseOptions::keep_match_details); empty for EstimateRig on given observations.
  PairwiseMatchData matches;
  // Per camera: cam_from_rig's rotation after rotation averaging, before the bundle adjustment.
  PerCamera<Eigen::Quaterniond> rotation_averaging;
  // The bundle adjustment's points in the result's world (frame 0's rig frame, the result's
  // scale), how many views see each, and the reprojection errors (px) of every observation at
  // the initial poses and at the end (multi_frame_rig.h).
  std::vector<Eigen::Vector3d> points;
  std::vector<int> point_observations;
  std::vector<double> initial_residuals_px, final_residuals_px;
};

// The work that made a rig result: full runs of the rig stages (EstimateRig, its pair-rejection
// rounds included; 2 where a pass with the motion links and one without both ran, or intrinsics
// were refined) and the wall time of each stage (the pairwise ones are in
// RigCalibrationResult::pairwise), summed over the passes and the rounds of a pass stopped before
// its bundle adjustment (EstimateRigUnlessUnplaced).
struct RigWork {
  int rig_passes = 0;
  double rotation_averaging_time_s = 0.0;
  double positions_time_s = 0.0;
  double tracks_time_s = 0.0;
  double bundle_adjustment_time_s = 0.0;
  double synchronisation_check_time_s = 0.0;  // CaptureTimeOptions::check_synchronisation
  // Rounds whose capture times were checked: the one a pass keeps, not those with a pair to leave out.
  int rounds_checked_for_capture_times = 0;
  // Bundle adjustments from a start (one per start and round): those solved, and those given back
  // because an earlier round had solved identical inputs (rig_adjustment_cache.h).
  int start_adjustments_solved = 0;
  int start_adjustments_reused = 0;

  RigWork& operator+=(const RigWork& other);
};

struct RigCalibrationResult {
  std::string semantic_mode;
  // Intrinsics as given (refined with RigBundleAdjustmentOptions::refine_intrinsics); cam_from_rig
  // estimated for calibrated cameras, nullopt otherwise.
  Rig rig;
  // Per camera: the estimated cam_from_rig rotation of calibrated and "rotation only" cameras;
  // nullopt for cameras not connected.
  PerCamera<Eigen::Quaterniond> cam_from_rig_rotation;
  // Per camera with CameraOutcome::kOpenAlongAxis: the axis (unit, in the rig) along which its
  // centre is not determined, and its centre in the rig without that component (the part the
  // images determine, in the result's unit); nullopt otherwise.
  PerCamera<Eigen::Vector3d> open_axis;
  PerCamera<Eigen::Vector3d> partial_centre;
  // Per camera: what the calibration made of it, and why.
  std::vector<CameraStatus> camera_status;
  std::vector<RigCameraStats> camera_stats;
  std::vector<RigEdgeStats> edges;  // per camera pair
  // With refine_intrinsics (rig_intrinsics.h): each pair's two-view estimate made again with the
  // refined intrinsics, which the rig used (RigObservations::pairs order); empty otherwise.
  std::vector<TwoViewEstimate> reestimated_pairs;
  // How the unit of length was fixed, and in words, e.g. "unit scale: |centre of cam1| = 1".
  ScaleKind scale_kind = ScaleKind::kNone;
  std::string scale;
  // The camera whose distance from camera 0 was made the unit (before a known distance made the
  // result metric); -1 with ScaleKind::kNone.
  int unit_camera = -1;
  std::vector<std::string> warnings;
  double initial_reprojection_rms_px = 0.0;
  double reprojection_rms_px = 0.0;
  // How many residuals of one image region count as one independent residual in the stated
  // deviations (bundle_covariance.h CorrelatedResidualFactor): 1 when they scatter independently.
  double residual_correlation = 1.0;
  int num_tracks = 0;
  int num_conflicting_tracks = 0;  // dropped: two keypoints of one camera
  int num_points = 0;
  int num_observations = 0;
  int num_filtered_observations = 0;
  int num_rotation_outliers = 0;
  // Rig motion: frames with a rig pose (all frames when static), and whether the rig was tracked
  // between frames (temporal pairs used) or taken as static.
  int num_frames = 0;
  int num_frames_posed = 0;
  // Per frame: the rig's pose, rig_from_world, with the rig frame at frame 0 as the world and in
  // the scale of cam_from_rig (the identity for every frame of a static rig); nullopt for a frame
  // without one. Empty when the camera positions are not observable.
  PerFrame<Rigid3d> rig_from_world;
  bool rig_motion_estimated = false;
  int num_temporal_pairs_used = 0;  // successful temporal pairs between cameras with a rotation
  int num_cross_time_pairs_used = 0;  // cross-time pairs (motion_links.h) rotation averaging kept
  // How clearly the tracks single out one set of positions (RigPositions::eigenvalue_ratio).
  double position_eigenvalue_ratio = 0.0;
  // The bundle adjustment's starts and how each ended.
  std::vector<RigStartSummary> position_starts;
  // The motion stage (motion_links.h) when it ran: whether its result was kept (it placed more
  // cameras), the motion's kind, the view pairs matched across time, the successful ones, those
  // rotation averaging kept, the temporal pairs that took their planar alternative or failed
  // against the rig's turns (rig_turns.h), the view pairs its rig predicts that agree with it and
  // contradict it, and its time.
  struct MotionLinkSummary {
    bool kept = false;
    MotionKind motion = MotionKind::kStraight;
    int candidates = 0;
    int pairs = 0;
    int pairs_used = 0;
    int temporal_alternatives_taken = 0;
    int temporal_pairs_disagreeing = 0;
    int predicted_views_agreeing = 0;
    int predicted_views_contradicting = 0;
    double time_s = 0.0;
  };
  std::optional<MotionLinkSummary> motion_links;
  CalibrationReport pairwise;
  RigWork work;
  // With RigCalibrationOptions::keep_details only; shared, so copies of a result stay cheap.
  std::shared_ptr<RigCalibrationDetails> details;
};

// Removes the result's warnings that start with `prefix`.
inline void DropWarnings(RigCalibrationResult* result, std::string_view prefix) {
  auto& w = result->warnings;
  w.erase(std::remove_if(w.begin(), w.end(), [prefix](const std::string& s) { return s.rfind(prefix, 0) == 0; }), w.end());
}

}  // namespace rigsim
