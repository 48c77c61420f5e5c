// Every verdict on an estimate against the truth, defined once: within tolerance, the pose error
// that success and the AUC are measured on, success, and confidently wrong. evaluation.json,
// pairs.json, the calibrate and evaluate tables, the report, the sweep's rows (and through them
// the thesis claims) take their verdicts from here.
//
// The verdicts answer different questions and so have different bounds:
//   within tolerance    one pose: rotation and (where the estimate has one) direction each within
//                       its bound; a camera 1 and 5 deg, a camera pair's two-view estimate 2 and
//                       5 deg. What evaluation.json's "within_tolerance" and the tables' "(outside
//                       tolerance against the truth)" say.
//   pose error          one pose: max(rotation error, direction error); +inf without a full pose.
//   success at N deg    a whole rig: the reference camera posed and every other camera's pose
//                       error at most N (the sweep's success_1deg and success_2deg).
//   confidently wrong   one camera reported placed whose error exceeds 5 deg: with a full pose, its
//                       pose error; placed but for one axis (no full pose, so never a success),
//                       its rotation or the direction of its centre across the axis.
//   overconfident       one camera whose error, in its rotation or (with a full pose) the direction
//                       of its centre, exceeds both 3 times the standard deviation the estimate
//                       states for it and a floor of 0.05 deg; not judged where nothing is stated
//                       (nor, rig_scores.h, a pose stated to hold if synchronised when it was not).
#pragma once

#include <optional>
#include <vector>

namespace rigsim {

// The bounds of "within tolerance" (deg).
struct PoseTolerance {
  double rotation_deg = 0.0;
  double direction_deg = 0.0;  // of a camera's centre seen from camera 0, or of a pair's baseline
};
inline constexpr PoseTolerance kCameraTolerance{1.0, 5.0};  // a camera's pose in the rig
inline constexpr PoseTolerance kPairTolerance{2.0, 5.0};    // a camera pair's two-view estimate

// True when the rotation error and, when given, the direction error are within `tolerance` (a
// direction the estimate does not have is not judged); nullopt without a rotation error (no truth,
// or no estimate).
std::optional<bool> WithinTolerance(const std::optional<double>& rotation_error_deg,
                                    const std::optional<double>& direction_error_deg, const PoseTolerance& tolerance);

// The pose error (deg) of an estimate: +inf without a full pose or a rotation error; the rotation
// error alone when the truth has no direction to judge (a camera at camera 0's centre, a pair
// without a baseline); otherwise max(rotation, direction), +inf when the direction is missing.
double PoseErrorDeg(bool full_pose, const std::optional<double>& rotation_error_deg,
                    const std::optional<double>& direction_error_deg, bool truth_has_direction);

// The limits (deg) of the sweep's success_1deg and success_2deg.
inline constexpr double kSuccessLimitsDeg[2] = {1.0, 2.0};

// Success of a whole rig at `limit_deg`: the reference camera has a full pose and every other
// camera's pose error (PoseErrorDeg) is at most the limit.
bool RigSucceeds(bool reference_posed, const std::vector<double>& other_camera_pose_errors_deg, double limit_deg);

// The error (deg) of what a camera placed but for one axis claims, its rotation and the direction
// of its centre across the axis: max of the two, as PoseErrorDeg of a full pose; the rotation
// error alone when the truth has no direction across the axis (a camera on it).
double OpenAxisErrorDeg(const std::optional<double>& rotation_error_deg,
                        const std::optional<double>& across_axis_direction_error_deg, bool truth_has_across_direction);

// A camera reported placed (`reported_placed`: a full pose, or placed but for one axis) whose
// error (PoseErrorDeg, or OpenAxisErrorDeg) exceeds this (deg) is confidently wrong.
inline constexpr double kConfidentlyWrongDeg = 5.0;
bool ConfidentlyWrong(bool reported_placed, double error_deg);

// An error beyond this many stated standard deviations is overconfident (a Gaussian gets there
// once in 370).
inline constexpr double kOverconfidentSigmas = 3.0;
// Below this error (deg) no camera is overconfident, however small its stated deviation: it is
// about how well the best real truths are known (a factory calibration or a rectified stereo pair
// is good to a few hundredths of a degree), so an error below it says as much about the truth as
// about the estimate; and a deviation of 0.001 deg would otherwise flag an error no one can act on.
inline constexpr double kOverconfidentFloorDeg = 0.05;

// One error against the standard deviation stated for it (deg).
struct StatedError {
  std::optional<double> error_deg;
  std::optional<double> stated_sd_deg;
  // The truth's own standard deviation in the same error (deg): 0 for a render's exact truth; a
  // survey's otherwise. The error is judged against both deviations together.
  double truth_sd_deg = 0.0;
  // sqrt(stated sd^2 + truth sd^2); nullopt without a stated sd.
  std::optional<double> JudgedSd() const;
  // error / JudgedSd; nullopt without both, +inf for a judged sd of 0.
  std::optional<double> Ratio() const;
  // Both known and the error beyond max(kOverconfidentSigmas * JudgedSd, kOverconfidentFloorDeg).
  bool Beyond() const;
};

// Whether a camera is overconfident: one of its errors Beyond() what is stated for it; nullopt when
// no error has a stated deviation (a peer's estimate, a camera without a stated deviation: not
// judged, and not counted).
std::optional<bool> Overconfident(const std::vector<StatedError>& errors);

}  // namespace rigsim
