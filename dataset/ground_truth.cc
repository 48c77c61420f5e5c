#include "dataset/ground_truth.h"

#include <algorithm>
#include <cmath>
#include <limits>
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

// Whether the point `x_in_b` (B's frame), which projects to `px_b`, lies in B's image and B's
// range image sees that surface there (not something nearer, or sky).
bool VisibleInB(const Eigen::Vector3d& x_in_b, const Eigen::Vector2d& px_b, const Camera& cam_b, const ImageF& range_b,
                const DepthTransferOptions& options) {
  if (!cam_b.IsInImage(px_b)) return false;
  const double expected = x_in_b.norm();
  const double tol = std::max(options.abs_tolerance_m, options.rel_tolerance * expected);
  // Visible when one of the four pixels around px_b sees this surface: the nearest pixel alone
  // fails on surfaces seen at grazing angles, where range changes fast from pixel to pixel.
  // Occluded when all of them see something else (nearer, or sky).
  const int x0 = static_cast<int>(std::floor(px_b.x()));
  const int y0 = static_cast<int>(std::floor(px_b.y()));
  for (int dy = 0; dy <= 1; ++dy) {
    for (int dx = 0; dx <= 1; ++dx) {
      const int x = x0 + dx, y = y0 + dy;
      if (x < 0 || y < 0 || x >= range_b.width || y >= range_b.height) continue;
      const float r_b = range_b.at(x, y);
      if (std::isfinite(r_b) && r_b > 0 && std::abs(r_b - expected) <= tol) return true;
    }
  }
  return false;
}

// B's pixel where the point `x_in_b` (B's frame) appears, when it is visible there (VisibleInB).
std::optional<Eigen::Vector2d> SeenInB(const Eigen::Vector3d& x_in_b, const Camera& cam_b, const ImageF& range_b,
                                       const DepthTransferOptions& options) {
  const auto px_b = cam_b.ImgFromCam(x_in_b);
  if (!px_b || !VisibleInB(x_in_b, *px_b, cam_b, range_b, options)) return std::nullopt;
  return px_b;
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

std::optional<ViewProjection> ProjectIntoView(const Eigen::Vector3d& x_in_world, const Camera& camera, const ViewPose& pose,
                                              int first_row_guess) {
  if (!pose.Rolling()) {
    const Eigen::Vector3d x_in_cam = pose.Row(0) * x_in_world;
    const auto px = camera.ImgFromCam(x_in_cam);
    if (!px) return std::nullopt;
    return ViewProjection{*px, x_in_cam};
  }
  const int last = camera.height() - 1;
  int row = first_row_guess >= 0 ? std::min(first_row_guess, last) : last / 2;
  std::optional<ViewProjection> found;
  for (int step = 0; step < 8; ++step) {
    const Eigen::Vector3d x_in_cam = pose.Row(row) * x_in_world;
    const auto px = camera.ImgFromCam(x_in_cam);
    if (!px) return found;
    found = ViewProjection{*px, x_in_cam};
    const int next = RowOfPixel(*px, camera);
    if (next == row) break;
    row = next;
  }
  return found;
}

int RowOfPixel(const Eigen::Vector2d& px, const Camera& camera) {
  return int(std::clamp<long>(std::lround(px.y()), 0, camera.height() - 1));
}

std::optional<Eigen::Vector2d> TransferPixel(const Eigen::Vector2d& px_a, const Camera& cam_a, const ImageF& range_a,
                                             const ViewPose& pose_a, const Camera& cam_b, const ImageF& range_b,
                                             const ViewPose& pose_b, const DepthTransferOptions& options) {
  const float r_a = RangeAt(range_a, px_a);
  if (r_a <= 0) return std::nullopt;
  const auto ray_a = cam_a.CamFromImg(px_a);
  if (!ray_a) return std::nullopt;
  const int row_a = RowOfPixel(px_a, cam_a);
  const auto in_b = ProjectIntoView(pose_a.Row(row_a).Inverse() * (*ray_a * r_a), cam_b, pose_b, row_a);
  if (!in_b || !VisibleInB(in_b->x_in_cam, in_b->px, cam_b, range_b, options)) return std::nullopt;
  return in_b->px;
}

CorrespondenceMap ComputeCorrespondence(const Camera& cam_a, const ImageF& range_a, const ViewPose& pose_a,
                                        const std::vector<Eigen::Vector3f>& bearings_a, const Camera& cam_b,
                                        const ImageF& range_b, const ViewPose& pose_b, const DepthTransferOptions& options) {
  const int width = range_a.width, height = range_a.height;
  if (bearings_a.size() != size_t(width) * height) {
    throw std::invalid_argument("ComputeCorrespondence: " + std::to_string(bearings_a.size()) + " bearings for a " +
                                std::to_string(width) + "x" + std::to_string(height) + " range image");
  }
  CorrespondenceMap out;
  const float nan = std::numeric_limits<float>::quiet_NaN();
  out.map = ImageF(width, height, 3, nan);
  // Both global shutters: one transform, the same arithmetic as CountCoVisible.
  const bool still = !pose_a.Rolling() && !pose_b.Rolling();
  const Rigid3d b_from_a = pose_b.Row(0) * pose_a.Row(0).Inverse();
  for (int y = 0; y < height; ++y) {
    const Rigid3d world_from_a = pose_a.Row(y).Inverse();
    for (int x = 0; x < width; ++x) {
      out.map.at(x, y, 2) = 0.0f;
      const float r_a = range_a.at(x, y);
      if (!(r_a > 0)) continue;
      ++out.surface;
      const Eigen::Vector3d ray_a = bearings_a[size_t(y) * width + x].cast<double>();
      if (ray_a.isZero() || !std::isfinite(r_a)) continue;
      const Eigen::Vector3d x_in_a = ray_a * r_a;
      std::optional<ViewProjection> in_b;
      if (still) {
        const Eigen::Vector3d x_in_b = b_from_a * x_in_a;
        if (const auto px = cam_b.ImgFromCam(x_in_b)) in_b = ViewProjection{*px, x_in_b};
      } else {
        in_b = ProjectIntoView(world_from_a * x_in_a, cam_b, pose_b, y);
      }
      if (!in_b) continue;
      out.map.at(x, y, 0) = float(in_b->px.x());
      out.map.at(x, y, 1) = float(in_b->px.y());
      if (VisibleInB(in_b->x_in_cam, in_b->px, cam_b, range_b, options)) {
        out.map.at(x, y, 2) = 1.0f;
        ++out.visible;
      }
    }
  }
  return out;
}

double CoVisibleFraction(const Camera& cam_a, const ImageF& range_a, const Camera& cam_b, const ImageF& range_b,
                         const Rigid3d& b_from_a, const DepthTransferOptions& options) {
  const CoVisibleCounts counts = CountCoVisible(cam_a, range_a, {{&cam_b, &range_b, b_from_a}}, 0, range_a.height, options);
  return counts.surface == 0 ? 0.0 : double(counts.visible[0]) / double(counts.surface);
}

}  // namespace rigsim
