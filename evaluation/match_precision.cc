#include "evaluation/match_precision.h"

#include <algorithm>
#include <cmath>
#include <limits>
#include <stdexcept>

namespace rigsim {

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
  cross_class += o.cross_class;
  cross_class_correct += o.cross_class_correct;
  return *this;
}

std::vector<char> CrossClassMatches(const std::vector<Eigen::Vector2d>& px_a, const std::vector<Eigen::Vector2d>& px_b,
                                    const ImageU8& labels_a, const ImageU8& labels_b) {
  const auto label_at = [](const ImageU8& labels, const Eigen::Vector2d& px) -> int {
    const int x = static_cast<int>(std::lround(px.x())), y = static_cast<int>(std::lround(px.y()));
    if (x < 0 || y < 0 || x >= labels.width || y >= labels.height) return -1;
    return labels.at(x, y);
  };
  std::vector<char> cross(px_a.size(), 0);
  for (size_t i = 0; i < px_a.size(); ++i) cross[i] = label_at(labels_a, px_a[i]) != label_at(labels_b, px_b[i]);
  return cross;
}

std::vector<char> CheckMatches(const std::vector<Eigen::Vector2d>& px_a, const std::vector<Eigen::Vector2d>& px_b,
                               const Camera& cam_a, const ImageF& range_a, const ViewPose& pose_a, const Camera& cam_b,
                               const ImageF& range_b, const ViewPose& pose_b, const MatchPrecisionOptions& options,
                               int* num_at_infinity) {
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
      in_b = TransferPixel(px_a[i], cam_a, range_a, pose_a, cam_b, range_b, pose_b, options.transfer);
    } else {
      ++at_infinity;
      // A point at infinity moves with the rotation only, and B must see no surface there; each
      // view turned as at its keypoint's row (a correct match is captured at that row).
      const auto bearing_a = cam_a.CamFromImg(px_a[i]);
      if (bearing_a) {
        const Eigen::Quaterniond b_from_a = pose_b.Row(RowOfPixel(px_b[i], cam_b)).rotation *
                                            pose_a.Row(RowOfPixel(px_a[i], cam_a)).rotation.inverse();
        const auto px = cam_b.ImgFromCam(b_from_a * *bearing_a);
        if (px && cam_b.IsInImage(*px) && RangeAt(range_b, *px) <= 0.f) in_b = px;
      }
    }
    correct[i] = in_b && (*in_b - px_b[i]).norm() <= options.max_error_px;
  }
  if (num_at_infinity != nullptr) *num_at_infinity = at_infinity;
  return correct;
}

MatchPrecisionCounts MatchPrecision(const std::vector<Eigen::Vector2d>& px_a, const std::vector<Eigen::Vector2d>& px_b,
                                    const Camera& cam_a, const ImageF& range_a, const ViewPose& pose_a,
                                    const Camera& cam_b, const ImageF& range_b, const ViewPose& pose_b,
                                    const MatchPrecisionOptions& options) {
  MatchPrecisionCounts counts;
  const std::vector<char> ok =
      CheckMatches(px_a, px_b, cam_a, range_a, pose_a, cam_b, range_b, pose_b, options, &counts.at_infinity);
  counts.evaluated = static_cast<int>(ok.size());
  counts.correct = static_cast<int>(std::count(ok.begin(), ok.end(), 1));
  return counts;
}

}  // namespace rigsim
