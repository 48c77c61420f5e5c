#include "calibrator/evaluation.h"

#include <algorithm>
#include <cmath>
#include <limits>
#include <stdexcept>

namespace rigsim {

double RotationErrorDeg(const Rigid3d& est, const Rigid3d& gt) { return RotationDifferenceDeg(est.rotation, gt.rotation); }

std::optional<double> TranslationDirectionErrorDeg(const Rigid3d& est, const Rigid3d& gt, double min_norm) {
  if (est.translation.norm() <= min_norm || gt.translation.norm() <= min_norm) return std::nullopt;
  const Eigen::Vector3d a = est.translation.normalized();
  const Eigen::Vector3d b = gt.translation.normalized();
  // atan2 keeps precision near 0 and 180 degrees, where acos of the dot product does not.
  return RadToDeg(std::atan2(a.cross(b).norm(), a.dot(b)));
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

void MatchPrecisionOptions::Check() const {
  if (!(max_error_px > 0)) throw std::invalid_argument("MatchPrecisionOptions: max_error_px must be > 0");
  if (transfer.abs_tolerance_m < 0 || transfer.rel_tolerance < 0) {
    throw std::invalid_argument("MatchPrecisionOptions: transfer tolerances must be >= 0");
  }
}

double MatchPrecisionCounts::Precision() const {
  return evaluated > 0 ? static_cast<double>(correct) / evaluated : std::numeric_limits<double>::quiet_NaN();
}

MatchPrecisionCounts& MatchPrecisionCounts::operator+=(const MatchPrecisionCounts& o) {
  evaluated += o.evaluated;
  correct += o.correct;
  at_infinity += o.at_infinity;
  return *this;
}

std::vector<char> CheckMatches(const std::vector<Eigen::Vector2d>& px_a, const std::vector<Eigen::Vector2d>& px_b,
                               const Camera& cam_a, const ImageF& range_a, const Camera& cam_b,
                               const ImageF& range_b, const Rigid3d& cam_b_from_cam_a,
                               const MatchPrecisionOptions& options, int* num_at_infinity) {
  options.Check();
  if (px_a.size() != px_b.size()) throw std::invalid_argument("CheckMatches: size mismatch");
  if (!range_a.SameSize(cam_a.width(), cam_a.height()) || !range_b.SameSize(cam_b.width(), cam_b.height())) {
    throw std::invalid_argument("CheckMatches: range image size differs from its camera's");
  }
  std::vector<char> correct(px_a.size(), 0);
  int at_infinity = 0;
  for (size_t i = 0; i < px_a.size(); ++i) {
    std::optional<Eigen::Vector2d> in_b;
    if (RangeAt(range_a, px_a[i]) > 0.f) {
      in_b = TransferPixel(px_a[i], cam_a, range_a, cam_b, range_b, cam_b_from_cam_a, options.transfer);
    } else {
      ++at_infinity;
      // A point at infinity moves with the rotation only, and B must see no surface there.
      const auto bearing_a = cam_a.CamFromImg(px_a[i]);
      if (bearing_a) {
        const auto px = cam_b.ImgFromCam(cam_b_from_cam_a.rotation * *bearing_a);
        if (px && cam_b.IsInImage(*px) && RangeAt(range_b, *px) <= 0.f) in_b = px;
      }
    }
    correct[i] = in_b && (*in_b - px_b[i]).norm() <= options.max_error_px;
  }
  if (num_at_infinity != nullptr) *num_at_infinity = at_infinity;
  return correct;
}

MatchPrecisionCounts MatchPrecision(const std::vector<Eigen::Vector2d>& px_a, const std::vector<Eigen::Vector2d>& px_b,
                                    const Camera& cam_a, const ImageF& range_a, const Camera& cam_b,
                                    const ImageF& range_b, const Rigid3d& cam_b_from_cam_a,
                                    const MatchPrecisionOptions& options) {
  MatchPrecisionCounts counts;
  const std::vector<char> ok =
      CheckMatches(px_a, px_b, cam_a, range_a, cam_b, range_b, cam_b_from_cam_a, options, &counts.at_infinity);
  counts.evaluated = static_cast<int>(ok.size());
  counts.correct = static_cast<int>(std::count(ok.begin(), ok.end(), 1));
  return counts;
}

}  // namespace rigsim
