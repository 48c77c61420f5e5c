#include "scenes/rig_generators.h"

#include <cmath>
#include <cstdio>
#include <stdexcept>

namespace rigsim {

void RingRigOptions::Check() const {
  auto fail = [](const std::string& why) { throw std::invalid_argument("ring rig: " + why); };
  if (num_cameras < 1) fail("needs at least one camera");
  if (!(hfov_deg > 1 && hfov_deg < 179)) fail("hfov_deg must be in (1, 179) for perspective cameras");
  if (!(radius_m >= 0)) fail("radius_m must be >= 0");
  if (width < 16 || height < 16) fail("image size must be at least 16x16");
  if (distorted_camera >= num_cameras) fail("distorted_camera is not a camera index");
}

Rig MakeRingRig(const RingRigOptions& o) {
  o.Check();
  Rig rig;
  const double r = std::tan(DegToRad(0.5 * o.hfov_deg));  // normalised radius at the image's side edge
  for (int i = 0; i < o.num_cameras; ++i) {
    const double yaw = DegToRad((i - 0.5 * (o.num_cameras - 1)) * o.yaw_spacing_deg);
    const Eigen::Matrix3d rig_from_cam_r = Eigen::AngleAxisd(yaw, Eigen::Vector3d::UnitY()).toRotationMatrix();
    const Eigen::Vector3d centre_in_rig = o.radius_m * Eigen::Vector3d(std::sin(yaw), 0.0, std::cos(yaw));
    const Rigid3d rig_from_cam(rig_from_cam_r, centre_in_rig);
    const double half_w = 0.5 * o.width;
    const double cx = 0.5 * (o.width - 1), cy = 0.5 * (o.height - 1);
    Camera cam;
    if (i == o.distorted_camera) {
      // Same horizontal field of view: the side edge images the ray at hfov/2 after distortion.
      const double rd = r * (1.0 + o.k1 * r * r + o.k2 * r * r * r * r);
      if (!(rd > 0)) throw std::invalid_argument("ring rig: distortion folds inside the field of view");
      const double f = half_w / rd;
      cam = Camera(CameraModelId::kOpenCV, o.width, o.height, {f, f, cx, cy, o.k1, o.k2, 0.0, 0.0});
    } else {
      const double f = half_w / r;
      cam = Camera(CameraModelId::kPinhole, o.width, o.height, {f, f, cx, cy});
    }
    char name[32];
    std::snprintf(name, sizeof(name), "cam%d", i);
    rig.cameras.push_back(RigCamera{name, cam, rig_from_cam.Inverse(), 0.0});
  }
  return rig;
}

Rigid3d RigFromWorldAt(const Eigen::Vector3d& position_world, double heading_deg) {
  const double h = DegToRad(heading_deg);
  Eigen::Matrix3d world_from_rig;
  world_from_rig.col(0) = Eigen::Vector3d(std::cos(h), 0.0, std::sin(h));   // right
  world_from_rig.col(1) = Eigen::Vector3d(0.0, -1.0, 0.0);                  // down
  world_from_rig.col(2) = Eigen::Vector3d(std::sin(h), 0.0, -std::cos(h));  // forward
  return Rigid3d(world_from_rig, position_world).Inverse();
}

FramesFile MakeStraightTrajectory(const Eigen::Vector3d& start_world, double heading_deg, int num_frames,
                                  double step_m, double frame_interval_s) {
  if (num_frames < 1) throw std::invalid_argument("trajectory: needs at least one frame");
  const double h = DegToRad(heading_deg);
  const Eigen::Vector3d forward(std::sin(h), 0.0, -std::cos(h));
  FramesFile frames;
  for (int k = 0; k < num_frames; ++k) {
    char name[32];
    std::snprintf(name, sizeof(name), "%06d", k);
    frames.frames.push_back(Frame{name, RigFromWorldAt(start_world + k * step_m * forward, heading_deg),
                                  k * frame_interval_s});
  }
  return frames;
}

}  // namespace rigsim
