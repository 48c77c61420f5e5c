#include "renderer/camera_rays.h"

#include <algorithm>
#include <cmath>
#include <optional>
#include <utility>

#include <tbb/parallel_for.h>

#include "common/splitmix64.h"
#include "renderer/tiles.h"

namespace rigsim {
namespace {

// Counter-based random numbers: a pure function of (seed, pixel, sample), so the image does not
// depend on which thread renders which tile.

// The hash of (seed, x, y), from which each sample's numbers are one more mix.
uint64_t PixelHash(uint64_t seed, int x, int y) { return SplitMix64(SplitMix64(seed) ^ (uint64_t(uint32_t(x)) << 32 | uint32_t(y))); }

uint64_t SampleHash(uint64_t pixel_hash, int sample, int stream) {
  return SplitMix64(pixel_hash ^ (uint64_t(uint32_t(sample)) << 8 | uint32_t(stream)));
}

float UnitFloat(uint64_t h) { return float(h >> 40) * 0x1p-24f; }  // [0, 1)

// Sub-pixel offset in [-0.5, 0.5)^2 of sample `s` of the pixel with hash `pixel_hash`: both
// jitters from one 64-bit hash (its top and middle 24 bits).
Eigen::Vector2d SampleOffset(uint64_t pixel_hash, int s, int spp, int grid, const std::vector<int>& rooks) {
  const uint64_t h = SampleHash(pixel_hash, s, 0);
  const float jx = UnitFloat(h);
  const float jy = float((h >> 16) & 0xFFFFFF) * 0x1p-24f;
  if (grid > 0) {
    return Eigen::Vector2d((s % grid + jx) / grid - 0.5, (s / grid + jy) / grid - 0.5);
  }
  return Eigen::Vector2d((s + jx) / spp - 0.5, (rooks[s] + jy) / spp - 0.5);
}

PixelCentreRays ComputePixelCentreRays(const Camera& camera) {
  const int width = camera.width(), height = camera.height();
  PixelCentreRays rays;
  rays.width = width;
  rays.interpolate_samples = !IsFisheyeModel(camera.model());
  rays.bearings.assign(size_t(width) * height, Eigen::Vector3f::Zero());
  rays.valid.assign(rays.bearings.size(), 0);
  rays.angle.assign(rays.bearings.size(), 0.0f);
  tbb::parallel_for(0, height, [&](int y) {
    for (int x = 0; x < width; ++x) {
      if (const auto b = camera.CamFromImg(Eigen::Vector2d(x, y))) {
        rays.bearings[size_t(y) * width + x] = b->normalized().cast<float>();
        rays.valid[size_t(y) * width + x] = 1;
      }
    }
  });
  const float fallback = float(1.0 / std::max(camera.fx(), camera.fy()));
  tbb::parallel_for(0, height, [&](int y) {
    for (int x = 0; x < width; ++x) {
      const size_t idx = size_t(y) * width + x;
      if (!rays.valid[idx]) continue;
      float a = 0.0f;
      auto neighbour = [&](int nx, int ny) {
        if (nx < 0 || ny < 0 || nx >= width || ny >= height) return;
        const size_t n = size_t(ny) * width + nx;
        if (rays.valid[n]) a = std::max(a, float((rays.bearings[n] - rays.bearings[idx]).norm()));
      };
      neighbour(x + 1, y);
      neighbour(x - 1, y);
      neighbour(x, y + 1);
      neighbour(x, y - 1);
      rays.angle[idx] = a > 0.0f ? a : fallback;
    }
  });
  return rays;
}

// The unit bearing of image point (px, py) from the four pixel centres around it (bilinear, then
// normalised), when they all lie in the image and inside the lens; else nullopt. Between pixel
// centres the bearing is a smooth function of the image point, so the interpolation's error is of
// second order in the pixel size: below 1e-6 rad (1/1000 px) for every camera model in the tests,
// while undistorting each sample exactly (Newton iterations for a distorted lens) would cost a
// quarter of the instructions of a 4-spp render of the demo rig.
[[gnu::always_inline]] inline std::optional<Eigen::Vector3f> InterpolatedBearing(const PixelCentreRays& c, int height,
                                                                                double px, double py) {
  if (!(px >= 0.0 && py >= 0.0)) return std::nullopt;  // (also NaN) the top-left pixel's centre is (0, 0)
  const int x0 = int(px), y0 = int(py);                  // floor, as px, py >= 0
  const double fx = x0, fy = y0;
  if (x0 + 1 >= c.width || y0 + 1 >= height) return std::nullopt;
  const size_t i00 = size_t(y0) * c.width + x0, i01 = i00 + c.width;
  if (!(c.valid[i00] & c.valid[i00 + 1] & c.valid[i01] & c.valid[i01 + 1])) return std::nullopt;
  const float ax = float(px - fx), ay = float(py - fy);
  const Eigen::Vector3f top = c.bearings[i00] + ax * (c.bearings[i00 + 1] - c.bearings[i00]);
  const Eigen::Vector3f bottom = c.bearings[i01] + ax * (c.bearings[i01 + 1] - c.bearings[i01]);
  return (top + ay * (bottom - top)).normalized();
}

}  // namespace

std::optional<Eigen::Vector3f> SampleBearing(const Camera& camera, const PixelCentreRays& centres, const Eigen::Vector2d& point) {
  if (centres.interpolate_samples) {
    if (const auto b = InterpolatedBearing(centres, camera.height(), point.x(), point.y())) return b;
  }
  const auto exact = camera.CamFromImg(point);  // at the image's border or the lens's
  if (!exact) return std::nullopt;
  return exact->normalized().cast<float>();
}

std::shared_ptr<const PixelCentreRays> PixelCentreRayCache::For(const Camera& camera) const {
  std::vector<double> key = {double(int(camera.model())), double(camera.width()), double(camera.height())};
  key.insert(key.end(), camera.params().begin(), camera.params().end());
  {
    std::lock_guard<std::mutex> lock(mutex_);
    if (auto it = rays_.find(key); it != rays_.end()) return it->second;
  }
  auto rays = std::make_shared<const PixelCentreRays>(ComputePixelCentreRays(camera));
  std::lock_guard<std::mutex> lock(mutex_);
  if (rays_.size() >= kMaxCachedCameras) rays_.clear();
  rays_.emplace(std::move(key), rays);
  return rays;
}

ViewPoses ViewPoses::Still(const Rigid3d& cam_from_world) {
  ViewPoses poses;
  RowPose& row = poses.rows.emplace_back();
  row.world_from_cam = cam_from_world.rotation.conjugate();
  row.world_from_cam_f = row.world_from_cam.toRotationMatrix().cast<float>();
  row.origin = cam_from_world.SourceOriginInTarget().cast<float>();
  row.begin_rotation = row.end_rotation = row.world_from_cam.cast<float>();
  row.begin_origin = row.end_origin = row.origin;
  return poses;
}

CameraRays::CameraRays(const Camera& camera, const PixelCentreRays& centres, const ViewPoses& poses,
                       const RenderOptions& options)
    : camera_(camera), centres_(centres), poses_(poses), spp_(options.samples_per_pixel), seed_(options.seed) {
  grid_ = int(std::lround(std::sqrt(double(spp_))));
  if (grid_ * grid_ != spp_) grid_ = 0;  // n-rooks
  rooks_.resize(grid_ > 0 ? 0 : spp_);
  if (poses_.exposure) time_strata_.resize(spp_);
}

void CameraRays::Batch(const Eigen::Vector2i& tile_corner, int y, int x_begin, int x_end, std::vector<RTCRayHit>* rays,
                       std::vector<CameraRayInfo>* info, std::vector<Eigen::Vector3f>* bearings) {
  rays->clear();
  info->clear();
  if (bearings != nullptr) bearings->clear();
  const int width = centres_.width;
  const RowPose& pose = poses_.Row(y);
  for (int x = x_begin; x < x_end; ++x) {
    const size_t idx = size_t(y) * width + x;
    if (!centres_.valid[idx]) continue;
    const int pixel = (y - tile_corner.y()) * kTileSize + (x - tile_corner.x());
    rays->push_back(CameraRay(pose.origin, pose.world_from_cam_f * centres_.bearings[idx]));
    rays->back().ray.time = pose.ray_time;
    info->push_back({pixel, centres_.angle[idx], true});
    if (bearings != nullptr) bearings->push_back(centres_.bearings[idx]);
    if (spp_ == 1) continue;
    const uint64_t pixel_hash = PixelHash(seed_, x, y);
    if (grid_ == 0) {  // n-rooks: a per-pixel random permutation of the y strata
      for (int i = 0; i < spp_; ++i) rooks_[i] = i;
      for (int i = spp_ - 1; i > 0; --i) {
        const int j = int(SampleHash(pixel_hash, i, 2) % uint64_t(i + 1));
        std::swap(rooks_[i], rooks_[j]);
      }
    }
    if (poses_.exposure) {  // the samples' times: one per stratum of the exposure, strata shuffled per pixel
      for (int i = 0; i < spp_; ++i) time_strata_[i] = i;
      for (int i = spp_ - 1; i > 0; --i) {
        const int j = int(SampleHash(pixel_hash, i, 3) % uint64_t(i + 1));
        std::swap(time_strata_[i], time_strata_[j]);
      }
    }
    const float sample_angle = centres_.angle[idx] / std::sqrt(float(spp_));
    for (int s = 0; s < spp_; ++s) {
      const Eigen::Vector2d point = Eigen::Vector2d(x, y) + SampleOffset(pixel_hash, s, spp_, grid_, rooks_);
      const std::optional<Eigen::Vector3f> bearing = SampleBearing(camera_, centres_, point);
      if (!bearing) continue;  // part of the pixel lies outside the lens
      if (poses_.exposure) {
        const float a = (float(time_strata_[s]) + UnitFloat(SampleHash(pixel_hash, s, 4))) / float(spp_);
        const Eigen::Quaternionf rotation(Eigen::Vector4f((1 - a) * pose.begin_rotation.coeffs() + a * pose.end_rotation.coeffs()));
        const Eigen::Vector3f origin = (1 - a) * pose.begin_origin + a * pose.end_origin;
        rays->push_back(CameraRay(origin, (rotation.normalized() * *bearing).normalized()));
        rays->back().ray.time = (1 - a) * pose.begin_ray_time + a * pose.end_ray_time;
      } else {
        rays->push_back(CameraRay(pose.origin, (pose.world_from_cam_f * *bearing).normalized()));
        rays->back().ray.time = pose.ray_time;
      }
      info->push_back({pixel, sample_angle, false});
      if (bearings != nullptr) bearings->push_back(*bearing);
    }
  }
}

}  // namespace rigsim
