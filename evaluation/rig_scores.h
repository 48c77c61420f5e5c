// Scores an estimate of a rig's extrinsics against the truth, the same way whichever tool made it
// (rigsim's calibrate, COLMAP, Kalibr, a hand-written rig.json).
//
// Gauge: both rigs are expressed with their first camera (camera 0 of the truth) as the rig frame,
// so an estimate in any rig frame compares. Per camera c > 0:
//   rotation error           angle of R_est R_true^T, R = cam_c_from_cam0's rotation;
//   direction error          angle between the estimated and true directions of c's centre seen
//                            from camera 0's (what images fix without a known distance);
//   position error (m)       |s C_est - C_true| with the scale s fitted by least squares over the
//                            cameras with a position (s = 1 when the estimate is metric); the
//                            rotation and origin are fixed by the shared gauge, so this is the
//                            similarity alignment of the two rigs;
//   across-axis direction    of a camera placed but for one axis (RigEstimate::open_axis, no full
//   error                    pose): angle between its estimated centre across the axis and its
//                            true centre with the component along the same axis removed, both in
//                            camera 0's frame (pose_errors.h AcrossAxisDirectionErrorDeg); none
//                            where that true component is (near) zero (a camera on the axis);
//   pose error               max(rotation error, direction error); infinite for a camera without
//                            a full pose (a rotation-only camera has a rotation error only; one
//                            placed but for one axis is judged confidently wrong on its rotation
//                            and across-axis direction, verdicts.h OpenAxisErrorDeg).
// Per camera pair (a < b): the same errors of cam_b_from_cam_a (direction of its translation).
// AUC of the pose errors at 1, 2, 5 and 10 deg (missing poses count as failures), over cameras
// and over pairs. The pose error, success and confidently wrong are evaluation/verdicts.h's.
#pragma once

#include <optional>
#include <string>
#include <vector>

#include <Eigen/Geometry>
#include <nlohmann/json.hpp>

#include "evaluation/rig_estimate.h"
#include "geometry/rig.h"
#include "geometry/rigid3.h"

namespace rigsim {

struct CameraScore {
  std::string name;
  bool posed = false;          // full pose
  bool has_rotation = false;   // full pose or rotation only
  bool open_axis = false;      // placed but for one axis: a rotation and the centre across the axis
  bool if_synchronised = false;  // the full pose holds only if the camera captured with camera 0
  // Overconfident (verdicts.h) on its rotation error or, with a full pose, its direction error
  // against the standard deviations the estimate states; nullopt where it states none for an error
  // the camera has (a peer, camera 0), and for a camera posed if synchronised that the truth has
  // capture at another time than camera 0 (the condition its deviations hold under is false).
  std::optional<bool> overconfident;
  // Those errors over their stated standard deviations, with the truth's own (TruthAccuracy)
  // counted (+inf for 0); nullopt as above.
  std::optional<double> rotation_sd_ratio, direction_sd_ratio;
  std::optional<double> rotation_error_deg;
  std::optional<double> direction_error_deg;
  std::optional<double> across_axis_direction_error_deg;  // open_axis cameras
  std::optional<double> position_error_m;
  double pose_error_deg = 0.0;  // +inf when not posed; 0 for camera 0
};

struct PairScore {
  std::string cam_a, cam_b;
  std::optional<double> rotation_error_deg;
  std::optional<double> direction_error_deg;
  double pose_error_deg = 0.0;  // +inf without both full poses
};

// How well the truth itself is known, one standard deviation: each camera's orientation (deg)
// and its position along each axis (m). 0 for a render's truth; a surveyed rig's otherwise.
struct TruthAccuracy {
  double rotation_deg = 0.0;
  double position_m = 0.0;
  bool Exact() const { return rotation_deg == 0.0 && position_m == 0.0; }
};

struct RigScores {
  std::string method;
  TruthAccuracy truth_accuracy;  // what the overconfident verdicts counted of the truth's own error
  std::vector<CameraScore> cameras;  // truth order; camera 0 is the reference
  std::vector<PairScore> pairs;      // a < b in truth order
  double scale = 1.0;                // s of the position errors
  bool metric = false;
  int cameras_posed = 0;             // camera 0 included
  int cameras_rotation_only = 0;     // a rotation and nothing of the position
  int cameras_open_axis = 0;         // placed but for one axis
  // Of the cameras posed, those whose pose holds only if synchronised, and of those the ones more
  // than kConfidentlyWrongDeg off (confidently wrong too where the truth's camera captured with
  // camera 0: the condition the estimate stated holds there).
  int cameras_if_synchronised = 0;
  int wrong_if_synchronised = 0;
  std::optional<double> max_rotation_error_deg, median_rotation_error_deg;
  std::optional<double> max_direction_error_deg, median_direction_error_deg;
  std::optional<double> max_position_error_m;
  std::optional<double> max_across_axis_direction_error_deg;
  double auc_cameras[4] = {0, 0, 0, 0};  // at 1, 2, 5, 10 deg
  double auc_pairs[4] = {0, 0, 0, 0};
  bool success_1deg = false, success_2deg = false;  // RigSucceeds at kSuccessLimitsDeg
  // Cameras ConfidentlyWrong (verdicts.h), placed but for one axis ones included, and those whose
  // pose holds only if synchronised where the truth's camera captured with camera 0.
  int confidently_wrong = 0;
  int overconfident = 0;        // cameras CameraScore::overconfident
  int cameras_stating_sd = 0;   // cameras judged on it (CameraScore::overconfident not nullopt)
  std::vector<std::string> notes;
};

// Whether camera `c` of `truth` captures when camera 0 does (same time offset and readout): the
// condition under which an estimate "calibrated if synchronised" holds.
bool CapturesWithReference(const Rig& truth, size_t c);

// The thresholds of RigScores::auc_*.
inline constexpr double kAucThresholdsDeg[4] = {1.0, 2.0, 5.0, 10.0};

// `truth` must give every camera's cam_from_rig (std::invalid_argument otherwise); `estimate`
// has one entry per truth camera.
// Each camera's errors are judged against its stated deviations together with what `accuracy`
// gives the same errors: a relative rotation sqrt(2) rotation_deg, a direction from camera 0
// sqrt(2) position_m over the cameras' true distance.
RigScores ScoreRig(const Rig& truth, const RigEstimate& estimate, const TruthAccuracy& accuracy = {});

// A camera's errors as evaluation.json and the calibrate tables give them, for an estimate whose
// own camera 0 is its rig frame (a rigsim calibration): the rotation error of a full pose or a
// rotation only (geometry/rigid3.h RotationDifferenceDeg against the truth with camera 0 as the
// rig frame), the direction error when both centres are away from camera 0's (1e-9), the
// position error of a metric estimate (no scale fitted; camera 0's included), and of a camera placed
// but for one axis the across-axis direction error (the estimate's axis and centre across it taken
// in camera 0's frame, as ScoreRig).
// ScoreRig measures the same errors another way (any estimate re-expressed in its camera 0's
// frame, rotations by Eigen's angularDistance, which does not normalise): they agree to about
// 1e-15 deg, not to the last digit, so one cannot replace the other without changing what
// evaluation.json or evaluate, the report and the sweep write.
struct CameraErrors {
  std::optional<double> rotation_error_deg;
  std::optional<double> direction_error_deg;
  std::optional<double> position_error_m;
  std::optional<double> across_axis_direction_error_deg;
};
// One per camera of `truth`; std::invalid_argument unless the truth has every cam_from_rig and
// the estimate one entry per camera.
std::vector<CameraErrors> CalibrationCameraErrors(const Rig& truth, const RigEstimate& estimate);

nlohmann::json RigScoresToJson(const RigScores& scores);
// The camera and pair tables and a summary line, for a terminal.
std::string FormatRigScores(const std::vector<RigScores>& scores);

}  // namespace rigsim
