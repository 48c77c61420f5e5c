#include "dataset/ground_truth.h"

#include <algorithm>
#include <cmath>
#include <stdexcept>
#include <string>

namespace rigsim {

float RangeAt(const ImageF& range, const Eigen::Vector2d& px) {
  const int x = static_cast<int>(std::lround(px.x()));
  const int y = static_cast<int>(std::lround(px.y()));
  if (x < 0 || y < 0 || x >= range.width || y >= range.height) return 0.0f;
  const float r = range.at(x, y);
  return std::isfinite(r) && r > 0 ? r : 0.0f;
}

namespace {

// B's pixel where the point `x_in_b` (B's frame) appears, when it projects inside B's image and
// B's range image sees that surface there (not something nearer, or sky).
std::optional<Eigen::Vector2d> SeenInB(const Eigen::Vector3d& x_in_b, const Camera& cam_b, const ImageF& range_b,
                                       const DepthTransferOptions& options) {
  const auto px_b = cam_b.ImgFromCam(x_in_b);
  if (!px_b || !cam_b.IsInImage(*px_b)) return std::nullopt;
  const double expected = x_in_b.norm();
  const double tol = std::max(options.abs_tolerance_m, options.rel_tolerance * expected);
  // Visible when one of the four pixels around px_b sees this surface: the nearest pixel alone
  // fails on surfaces seen at grazing angles, where range changes fast from pixel to pixel.
  // Occluded when all of them see something else (nearer, or sky).
  const int x0 = static_cast<int>(std::floor(px_b->x()));
  const int y0 = static_cast<int>(std::floor(px_b->y()));
  for (int dy = 0; dy <= 1; ++dy) {
    for (int dx = 0; dx <= 1; ++dx) {
      const int x = x0 + dx, y = y0 + dy;
      if (x < 0 || y < 0 || x >= range_b.width || y >= range_b.height) continue;
      const float r_b = range_b.at(x, y);
      if (std::isfinite(r_b) && r_b > 0 && std::abs(r_b - expected) <= tol) return px_b;
    }
  }
  return std::nullopt;
}

}  // namespace

std::optional<Eigen::Vector2d> TransferPixel(const Eigen::Vector2d& px_a, const Camera& cam_a, const ImageF& range_a,
                                             const Camera& cam_b, const ImageF& range_b, const Rigid3d& b_from_a,
                                             const DepthTransferOptions& options) {
  const float r_a = RangeAt(range_a, px_a);
  if (r_a <= 0) return std::nullopt;
  const auto ray_a = cam_a.CamFromImg(px_a);
  if (!ray_a) return std::nullopt;
  return SeenInB(b_from_a * (*ray_a * r_a), cam_b, range_b, options);
}

CoVisibleCounts CountCoVisible(const Camera& cam_a, const ImageF& range_a, const std::vector<TransferTarget>& targets,
                               int y_begin, int y_end, const DepthTransferOptions& options,
                               const std::vector<Eigen::Vector3f>* bearings_a) {
  if (bearings_a && bearings_a->size() != size_t(range_a.width) * range_a.height) {
    throw std::invalid_argument("CountCoVisible: " + std::to_string(bearings_a->size()) + " bearings for a " +
                                std::to_string(range_a.width) + "x" + std::to_string(range_a.height) + " range image");
  }
  CoVisibleCounts counts;
  counts.visible.assign(targets.size(), 0);
  for (int y = std::max(y_begin, 0); y < std::min(y_end, range_a.height); ++y) {
    for (int x = 0; x < range_a.width; ++x) {
      const float r_a = range_a.at(x, y);
      if (!(r_a > 0)) continue;
      ++counts.surface;
      const std::optional<Eigen::Vector3d> ray_a =
          bearings_a ? std::optional<Eigen::Vector3d>((*bearings_a)[size_t(y) * range_a.width + x].cast<double>())
                     : cam_a.CamFromImg(Eigen::Vector2d(x, y));
      if (!ray_a || ray_a->isZero() || !std::isfinite(r_a)) continue;
      const Eigen::Vector3d x_in_a = *ray_a * r_a;
      for (size_t t = 0; t < targets.size(); ++t) {
        if (SeenInB(targets[t].b_from_a * x_in_a, *targets[t].camera, *targets[t].range, options)) ++counts.visible[t];
      }
    }
  }
  return counts;
}

double CoVisibleFraction(const Camera& cam_a, const ImageF& range_a, const Camera& cam_b, const ImageF& range_b,
                         const Rigid3d& b_from_a, const DepthTransferOptions& options) {
  const CoVisibleCounts counts = CountCoVisible(cam_a, range_a, {{&cam_b, &range_b, b_from_a}}, 0, range_a.height, options);
  return counts.surface == 0 ? 0.0 : double(counts.visible[0]) / double(counts.surface);
}

}  // namespace rigsim
