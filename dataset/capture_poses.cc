#include "dataset/capture_poses.h"

#include <cmath>
#include <stdexcept>
#include <string>
#include <utility>

#include "geometry/pose_interpolation.h"

namespace rigsim {
namespace {

[[noreturn]] void Fail(const std::string& why) { throw std::invalid_argument("trajectory: " + why); }

}  // namespace

RigTrajectory::RigTrajectory(const FramesFile& frames) {
  for (const Frame& f : frames.frames) {
    if (!f.rig_from_world) Fail("frame '" + f.name + "' has no rig_from_world");
    if (!std::isfinite(f.timestamp_s)) Fail("frame '" + f.name + "' has a timestamp that is not finite");
    path_.push_back({f.timestamp_s, *f.rig_from_world});
  }
  if (path_.empty()) Fail("no frames");
  path_ = SortedByTime(std::move(path_));
  for (size_t k = 1; k < path_.size(); ++k) {
    if (path_[k].time_s == path_[k - 1].time_s) {
      Fail("two frames share timestamp_s " + std::to_string(path_[k].time_s) +
           ": the rig's pose between frames (for cameras with a time offset, rolling shutter or exposure) needs "
           "distinct timestamps");
    }
  }
}

Rigid3d RigTrajectory::RigFromWorldAt(double time_s) const { return RigFromWorldOnPath(path_, time_s); }

bool CapturePoses::IsTimed(const RigCamera& camera) { return camera.time_offset_s != 0 || camera.CaptureSpansTime(); }

CapturePoses::CapturePoses(const std::vector<RigCamera>& cameras, const FramesFile& frames) {
  for (const RigCamera& camera : cameras) {
    if (IsTimed(camera) && !trajectory_) trajectory_.emplace(frames);
  }
}

Rigid3d CapturePoses::CamFromWorld(const RigCamera& camera, const Frame& frame, double time_s) const {
  if (!IsTimed(camera)) return *camera.cam_from_rig * frame.rig_from_world.value_or(Rigid3d());
  return *camera.cam_from_rig * trajectory_->RigFromWorldAt(time_s);
}

ViewPose CapturePoses::Of(const RigCamera& camera, const Frame& frame) const {
  ViewPose pose;
  const int rows = camera.readout_s > 0 ? camera.camera.height() : 1;
  for (int y = 0; y < rows; ++y) {
    pose.cam_from_world_rows.push_back(CamFromWorld(camera, frame, frame.timestamp_s + camera.RowTime(y)));
  }
  return pose;
}

}  // namespace rigsim
