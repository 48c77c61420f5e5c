#include "evaluation/verdicts.h"

#include <algorithm>
#include <cmath>
#include <limits>

namespace rigsim {

std::optional<bool> WithinTolerance(const std::optional<double>& rotation_error_deg,
                                    const std::optional<double>& direction_error_deg, const PoseTolerance& tolerance) {
  if (!rotation_error_deg) return std::nullopt;
  return *rotation_error_deg <= tolerance.rotation_deg && direction_error_deg.value_or(0.0) <= tolerance.direction_deg;
}

double PoseErrorDeg(bool full_pose, const std::optional<double>& rotation_error_deg,
                    const std::optional<double>& direction_error_deg, bool truth_has_direction) {
  const double inf = std::numeric_limits<double>::infinity();
  if (!full_pose || !rotation_error_deg) return inf;
  if (!truth_has_direction) return *rotation_error_deg;
  return direction_error_deg ? std::max(*rotation_error_deg, *direction_error_deg) : inf;
}

bool RigSucceeds(bool reference_posed, const std::vector<double>& other_camera_pose_errors_deg, double limit_deg) {
  return reference_posed && std::all_of(other_camera_pose_errors_deg.begin(), other_camera_pose_errors_deg.end(),
                                        [&](double e) { return e <= limit_deg; });
}

double OpenAxisErrorDeg(const std::optional<double>& rotation_error_deg,
                        const std::optional<double>& across_axis_direction_error_deg, bool truth_has_across_direction) {
  return PoseErrorDeg(true, rotation_error_deg, across_axis_direction_error_deg, truth_has_across_direction);
}

bool ConfidentlyWrong(bool reported_placed, double error_deg) {
  return reported_placed && error_deg > kConfidentlyWrongDeg;
}

std::optional<double> StatedError::JudgedSd() const {
  if (!stated_sd_deg) return std::nullopt;
  return truth_sd_deg > 0.0 ? std::hypot(*stated_sd_deg, truth_sd_deg) : *stated_sd_deg;
}

std::optional<double> StatedError::Ratio() const {
  const std::optional<double> sd = JudgedSd();
  if (!error_deg || !sd) return std::nullopt;
  if (*sd <= 0.0) return std::numeric_limits<double>::infinity();
  return *error_deg / *sd;
}

bool StatedError::Beyond() const {
  const std::optional<double> sd = JudgedSd();
  if (!error_deg || !sd) return false;
  return *error_deg > std::max(kOverconfidentSigmas * *sd, kOverconfidentFloorDeg);
}

std::optional<bool> Overconfident(const std::vector<StatedError>& errors) {
  std::optional<bool> out;
  for (const StatedError& e : errors) {
    if (!e.error_deg || !e.stated_sd_deg) continue;
    out = out.value_or(false) || e.Beyond();
  }
  return out;
}

}  // namespace rigsim
