#include "dataset/ground_truth.h"

#include <algorithm>
#include <cmath>

namespace rigsim {

float RangeAt(const ImageF& range, const Eigen::Vector2d& px) {
  const int x = static_cast<int>(std::lround(px.x()));
  const int y = static_cast<int>(std::lround(px.y()));
  if (x < 0 || y < 0 || x >= range.width || y >= range.height) return 0.0f;
  const float r = range.at(x, y);
  return std::isfinite(r) && r > 0 ? r : 0.0f;
}

std::optional<Eigen::Vector2d> TransferPixel(const Eigen::Vector2d& px_a, const Camera& cam_a, const ImageF& range_a,
                                             const Camera& cam_b, const ImageF& range_b, const Rigid3d& b_from_a,
                                             const DepthTransferOptions& options) {
  const float r_a = RangeAt(range_a, px_a);
  if (r_a <= 0) return std::nullopt;
  const auto ray_a = cam_a.CamFromImg(px_a);
  if (!ray_a) return std::nullopt;
  const Eigen::Vector3d x_in_b = b_from_a * (*ray_a * r_a);
  const auto px_b = cam_b.ImgFromCam(x_in_b);
  if (!px_b || !cam_b.IsInImage(*px_b)) return std::nullopt;
  const double expected = x_in_b.norm();
  const double tol = std::max(options.abs_tolerance_m, options.rel_tolerance * expected);
  // Visible when one of the four pixels around px_b sees this surface: the nearest pixel alone
  // fails on surfaces seen at grazing angles, where range changes fast from pixel to pixel.
  // Occluded when all of them see something else (nearer, or sky).
  const int x0 = static_cast<int>(std::floor(px_b->x()));
  const int y0 = static_cast<int>(std::floor(px_b->y()));
  bool seen = false;
  for (int dy = 0; dy <= 1 && !seen; ++dy) {
    for (int dx = 0; dx <= 1 && !seen; ++dx) {
      const int x = x0 + dx, y = y0 + dy;
      if (x < 0 || y < 0 || x >= range_b.width || y >= range_b.height) continue;
      const float r_b = range_b.at(x, y);
      seen = std::isfinite(r_b) && r_b > 0 && std::abs(r_b - expected) <= tol;
    }
  }
  if (!seen) return std::nullopt;
  return px_b;
}

double CoVisibleFraction(const Camera& cam_a, const ImageF& range_a, const Camera& cam_b, const ImageF& range_b,
                         const Rigid3d& b_from_a, const DepthTransferOptions& options) {
  size_t surface = 0, visible = 0;
  for (int y = 0; y < range_a.height; ++y) {
    for (int x = 0; x < range_a.width; ++x) {
      if (!(range_a.at(x, y) > 0)) continue;
      ++surface;
      if (TransferPixel(Eigen::Vector2d(x, y), cam_a, range_a, cam_b, range_b, b_from_a, options)) ++visible;
    }
  }
  return surface == 0 ? 0.0 : double(visible) / double(surface);
}

}  // namespace rigsim
