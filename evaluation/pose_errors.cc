#include "evaluation/pose_errors.h"

#include <algorithm>
#include <cmath>
#include <limits>

namespace rigsim {

double RotationErrorDeg(const Rigid3d& est, const Rigid3d& gt) { return RotationDifferenceDeg(est.rotation, gt.rotation); }

std::optional<double> TranslationDirectionErrorDeg(const Rigid3d& est, const Rigid3d& gt, double min_norm) {
  if (est.translation.norm() <= min_norm || gt.translation.norm() <= min_norm) return std::nullopt;
  const Eigen::Vector3d a = est.translation.normalized();
  const Eigen::Vector3d b = gt.translation.normalized();
  // atan2 keeps precision near 0 and 180 degrees, where acos of the dot product does not.
  return RadToDeg(std::atan2(a.cross(b).norm(), a.dot(b)));
}

Eigen::Vector3d AcrossAxis(const Eigen::Vector3d& axis, const Eigen::Vector3d& v) {
  const Eigen::Vector3d a = axis.normalized();
  return v - a * a.dot(v);
}

std::optional<double> AcrossAxisDirectionErrorDeg(const Eigen::Vector3d& axis, const Eigen::Vector3d& est_centre_across,
                                                  const Eigen::Vector3d& true_centre, double min_norm) {
  const Eigen::Vector3d est = AcrossAxis(axis, est_centre_across), truth = AcrossAxis(axis, true_centre);
  if (est.norm() <= min_norm || truth.norm() <= min_norm) return std::nullopt;
  return RadToDeg(std::atan2(est.cross(truth).norm(), est.dot(truth)));
}

double PoseAuc(const std::vector<double>& errors_deg, double threshold_deg) {
  if (errors_deg.empty() || !(threshold_deg > 0)) return 0.0;
  std::vector<double> e;
  for (double x : errors_deg) e.push_back(std::isnan(x) ? std::numeric_limits<double>::infinity() : x);
  std::sort(e.begin(), e.end());
  const double n = static_cast<double>(e.size());
  // Recall curve through (0, 0), (e_i, i/n) for the errors below the threshold, then flat to the
  // threshold; trapezoidal area, as SuperGlue's pose_auc computes it.
  double area = 0.0, prev_e = 0.0, prev_r = 0.0;
  for (size_t i = 0; i < e.size() && e[i] < threshold_deg; ++i) {
    const double r = (i + 1) / n;
    area += 0.5 * (prev_r + r) * (e[i] - prev_e);
    prev_e = e[i];
    prev_r = r;
  }
  area += prev_r * (threshold_deg - prev_e);
  return area / threshold_deg;
}

}  // namespace rigsim
