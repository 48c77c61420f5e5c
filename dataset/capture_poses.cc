#include "dataset/capture_poses.h"

#include <algorithm>
#include <cmath>
#include <stdexcept>
#include <string>

#include "geometry/pose_interpolation.h"

namespace rigsim {
namespace {

[[noreturn]] void Fail(const std::string& why) { throw std::invalid_argument("trajectory: " + why); }

}  // namespace

RigTrajectory::RigTrajectory(const FramesFile& frames) {
  for (const Frame& f : frames.frames) {
    if (!f.rig_from_world) Fail("frame '" + f.name + "' has no rig_from_world");
    if (!std::isfinite(f.timestamp_s)) Fail("frame '" + f.name + "' has a timestamp that is not finite");
    keys_.push_back({f.timestamp_s, *f.rig_from_world});
  }
  if (keys_.empty()) Fail("no frames");
  std::stable_sort(keys_.begin(), keys_.end(), [](const Key& a, const Key& b) { return a.time_s < b.time_s; });
  for (size_t k = 1; k < keys_.size(); ++k) {
    if (keys_[k].time_s == keys_[k - 1].time_s) {
      Fail("two frames share timestamp_s " + std::to_string(keys_[k].time_s) +
           ": the rig's pose between frames (for cameras with a time offset, rolling shutter or exposure) needs "
           "distinct timestamps");
    }
  }
}

Rigid3d RigTrajectory::RigFromWorldAt(double time_s) const {
  if (keys_.size() == 1) return keys_[0].rig_from_world;
  // The segment [k, k + 1] that holds time_s, or the first or last one outside.
  size_t k = size_t(std::upper_bound(keys_.begin(), keys_.end(), time_s,
                                     [](double t, const Key& key) { return t < key.time_s; }) -
                    keys_.begin());
  if (k > 0 && keys_[k - 1].time_s == time_s) return keys_[k - 1].rig_from_world;
  k = std::clamp<size_t>(k, 1, keys_.size() - 1) - 1;
  const Key& a = keys_[k];
  const Key& b = keys_[k + 1];
  const double s = (time_s - a.time_s) / (b.time_s - a.time_s);  // < 0 or > 1 outside: extrapolation
  Rigid3d out;
  InterpolateRigFromWorld<double>(a.rig_from_world.rotation, a.rig_from_world.translation, b.rig_from_world.rotation,
                                  b.rig_from_world.translation, s, &out.rotation, &out.translation);
  out.rotation.normalize();
  return out;
}

bool CapturePoses::IsTimed(const RigCamera& camera) { return camera.time_offset_s != 0 || camera.CaptureSpansTime(); }

CapturePoses::CapturePoses(const std::vector<RigCamera>& cameras, const FramesFile& frames) {
  for (const RigCamera& camera : cameras) {
    if (IsTimed(camera) && !trajectory_) trajectory_.emplace(frames);
  }
}

Rigid3d CapturePoses::CamFromWorld(const RigCamera& camera, const Frame& frame, double time_s) const {
  if (!IsTimed(camera)) return *camera.cam_from_rig * *frame.rig_from_world;
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
