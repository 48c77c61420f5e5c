#include "testing/rendered_yard.h"

#include <algorithm>
#include <cmath>
#include <cstdint>
#include <limits>

namespace rigsim {
namespace {

// Smooth value noise in [0, 1] on a plane: blobs of about `cell` metres.
double ValueNoise(double u, double v, double cell, uint32_t salt) {
  auto hash = [salt](int64_t i, int64_t j) {
    uint64_t h = static_cast<uint64_t>(i) * 0x9E3779B97F4A7C15ull ^ static_cast<uint64_t>(j) * 0xC2B2AE3D27D4EB4Full ^ salt;
    h ^= h >> 31;
    h *= 0xBF58476D1CE4E5B9ull;
    h ^= h >> 29;
    return static_cast<double>(h & 0xFFFF) / 65535.0;
  };
  const double x = u / cell, y = v / cell;
  const int64_t i = static_cast<int64_t>(std::floor(x)), j = static_cast<int64_t>(std::floor(y));
  double fx = x - i, fy = y - j;
  fx = fx * fx * (3 - 2 * fx);
  fy = fy * fy * (3 - 2 * fy);
  const double a = hash(i, j) + fx * (hash(i + 1, j) - hash(i, j));
  const double b = hash(i, j + 1) + fx * (hash(i + 1, j + 1) - hash(i, j + 1));
  return a + fy * (b - a);
}

// A walled yard (frame: x right, y down, z forward): floor (road) at y = 1.6, back wall
// (building) at z = 9, left wall (vegetation) at x = -4, right wall (building) at x = 5; walls end
// at y = -3, above them is sky.
struct Hit {
  double range = 0.0;
  uint8_t label = 23;  // sky
  double shade = 0.75;
};

Hit Trace(const Eigen::Vector3d& o, const Eigen::Vector3d& d) {
  Hit best;
  best.range = std::numeric_limits<double>::infinity();
  auto consider = [&](double t, uint8_t label, double u, double v, uint32_t salt, bool ok) {
    if (!ok || !(t > 1e-6) || t >= best.range) return;
    best.range = t;
    best.label = label;
    best.shade = 0.15 + 0.55 * ValueNoise(u, v, 0.25, salt) + 0.3 * ValueNoise(u, v, 0.07, salt + 1);
  };
  auto at = [&](double t) { return o + t * d; };
  if (d.y() > 0) {
    const double t = (1.6 - o.y()) / d.y();
    consider(t, 7, at(t).x(), at(t).z(), 11, true);
  }
  if (d.z() > 0) {
    const double t = (9.0 - o.z()) / d.z();
    consider(t, 11, at(t).x(), at(t).y(), 22, at(t).y() > -3);
  }
  if (d.x() < 0) {
    const double t = (-4.0 - o.x()) / d.x();
    consider(t, 21, at(t).z(), at(t).y(), 33, at(t).y() > -3);
  }
  if (d.x() > 0) {
    const double t = (5.0 - o.x()) / d.x();
    consider(t, 11, at(t).z(), at(t).y(), 44, at(t).y() > -3);
  }
  if (!std::isfinite(best.range)) return Hit{};
  return best;
}

Rigid3d CamFromRig(double yaw_deg, const Eigen::Vector3d& centre_in_rig) {
  const Eigen::Matrix3d r = Eigen::AngleAxisd(DegToRad(yaw_deg), Eigen::Vector3d::UnitY()).toRotationMatrix();
  return Rigid3d(r, -r * centre_in_rig);
}

RenderedYard Render() {
  RenderedYard yard;
  Rig& rig = yard.rig;
  rig.cameras.push_back({"cam0", Camera(CameraModelId::kPinhole, 320, 240, {220, 220, 159.5, 119.5}),
                         CamFromRig(0, Eigen::Vector3d::Zero()), 0.0});
  rig.cameras.push_back({"cam1", Camera(CameraModelId::kOpenCV, 320, 240, {210, 211, 161, 118, -0.08, 0.01, 0, 0}),
                         CamFromRig(20, Eigen::Vector3d(0.6, 0.05, 0.1)), 0.0});
  for (int f = 0; f < 2; ++f) {
    yard.rig_from_world.emplace_back(
        Eigen::Quaterniond(Eigen::AngleAxisd(DegToRad(-6.0 * f), Eigen::Vector3d::UnitY())),
        Eigen::Vector3d(0.3 * f, 0, -0.8 * f));
  }
  for (const RigCamera& rc : rig.cameras) {
    yard.rgb.emplace_back();
    yard.labels.emplace_back();
    yard.range.emplace_back();
    for (const Rigid3d& rig_from_world : yard.rig_from_world) {
      const Rigid3d world_from_cam = (*rc.cam_from_rig * rig_from_world).Inverse();
      const Camera& cam = rc.camera;
      ImageU8 rgb(cam.width(), cam.height(), 3), labels(cam.width(), cam.height(), 1);
      ImageF range(cam.width(), cam.height(), 1, 0.f);
      for (int y = 0; y < cam.height(); ++y) {
        for (int x = 0; x < cam.width(); ++x) {
          double shade = 0.0;
          for (int s = 0; s < 4; ++s) {  // 2x2 supersampling
            const Eigen::Vector2d px(x - 0.25 + 0.5 * (s % 2), y - 0.25 + 0.5 * (s / 2));
            const auto f = cam.CamFromImg(px);
            shade += f ? Trace(world_from_cam.translation, world_from_cam.rotation * *f).shade / 4 : 0.0;
          }
          const auto f = cam.CamFromImg(Eigen::Vector2d(x, y));
          const Hit h = Trace(world_from_cam.translation, world_from_cam.rotation * *f);
          range.at(x, y) = static_cast<float>(h.range);
          labels.at(x, y) = h.label;
          for (int c = 0; c < 3; ++c) rgb.at(x, y, c) = static_cast<uint8_t>(std::clamp(255.0 * shade, 0.0, 255.0));
        }
      }
      yard.rgb.back().push_back(std::move(rgb));
      yard.labels.back().push_back(std::move(labels));
      yard.range.back().push_back(std::move(range));
    }
  }
  return yard;
}

}  // namespace

const RenderedYard& TwoCameraYard() {
  static const RenderedYard yard = Render();
  return yard;
}

}  // namespace rigsim
