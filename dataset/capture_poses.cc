#include "dataset/capture_poses.h"

#include <cmath>
#include <cstdio>
#include <map>
#include <stdexcept>
#include <string>
#include <utility>

#include "geometry/pose_interpolation.h"

namespace rigsim {
namespace {

std::string Seconds(double t) {
  char text[32];
  std::snprintf(text, sizeof text, "%.9g", t);
  return text;
}

}  // namespace

RigTrajectory::RigTrajectory(const FramesFile& frames, const std::string& source) {
  const auto fail = [&](const std::string& why) { throw std::invalid_argument(source + ": " + why); };
  std::map<double, std::string> first_at;  // timestamp -> the first frame there
  for (const Frame& f : frames.frames) {
    if (!f.rig_from_world) fail("frame '" + f.name + "' has no rig_from_world");
    if (!std::isfinite(f.timestamp_s)) fail("frame '" + f.name + "' has a timestamp that is not finite");
    if (const auto [at, added] = first_at.emplace(f.timestamp_s, f.name); !added) {
      fail("frames '" + at->second + "' and '" + f.name + "' share timestamp_s " + Seconds(f.timestamp_s) +
           ": the rig's pose between frames (for cameras with a time offset, rolling shutter or exposure) needs "
           "distinct timestamps");
    }
    path_.push_back({f.timestamp_s, *f.rig_from_world});
  }
  if (path_.empty()) fail("no frames");
  path_ = SortedByTime(std::move(path_));
}

Rigid3d RigTrajectory::RigFromWorldAt(double time_s) const { return RigFromWorldOnPath(path_, time_s); }

bool CapturePoses::IsTimed(const RigCamera& camera) { return camera.time_offset_s != 0 || camera.CaptureSpansTime(); }

CapturePoses::CapturePoses(const std::vector<RigCamera>& cameras, const FramesFile& frames, const std::string& source) {
  for (const RigCamera& camera : cameras) {
    if (IsTimed(camera) && !trajectory_) trajectory_.emplace(frames, source);
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
