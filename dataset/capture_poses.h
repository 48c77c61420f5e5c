// Where each camera is when it captures: the rig between its frames as the renderer moves it, and
// each camera's pose at its capture time (frame timestamp + time_offset_s, + its row's share of
// readout_s for a rolling shutter, geometry/rig.h). The renderer renders with these poses and the
// evaluation checks matches with them, so a camera that captures while the rig moves is judged
// where it was.
#pragma once

#include <optional>
#include <string>
#include <vector>

#include "dataset/dataset.h"
#include "dataset/ground_truth.h"
#include "geometry/pose_interpolation.h"
#include "geometry/rig.h"
#include "geometry/rigid3.h"

namespace rigsim {

// The rig's pose at any time, from the poses and timestamps of a trajectory's frames
// (geometry/pose_interpolation.h RigFromWorldOnPath, which the calibrator shares).
class RigTrajectory {
 public:
  // Throws std::invalid_argument, its message starting with `source` (the frames' file), when a
  // frame has no rig_from_world, a timestamp is not finite, or two frames share a timestamp (the
  // speed between them would be infinite). Frames may come in any order of time.
  explicit RigTrajectory(const FramesFile& frames, const std::string& source = "trajectory");

  Rigid3d RigFromWorldAt(double time_s) const;

 private:
  std::vector<TimedPose> path_;  // by time
};

// Each camera's pose at its capture times. A camera without a time offset, readout or exposure
// sees from its frame's rig_from_world exactly as given (a frame without one, as photographs have,
// stands at the world's origin: the poses within the frame hold); the others from the
// RigTrajectory, built only when some camera needs it.
class CapturePoses {
 public:
  // Throws std::invalid_argument as RigTrajectory does, when some camera is timed.
  CapturePoses(const std::vector<RigCamera>& cameras, const FramesFile& frames, const std::string& source = "trajectory");

  // Whether some camera captures away from its frame's timestamp.
  bool timed() const { return trajectory_.has_value(); }
  Rigid3d CamFromWorld(const RigCamera& camera, const Frame& frame, double time_s) const;
  // Every row's pose for a rolling shutter, else one.
  ViewPose Of(const RigCamera& camera, const Frame& frame) const;

  // Whether a camera's capture depends on where the rig is between frames.
  static bool IsTimed(const RigCamera& camera);

 private:
  std::optional<RigTrajectory> trajectory_;
};

}  // namespace rigsim
