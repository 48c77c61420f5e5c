// Seeded-free, closed-form rig generators and rig placements in a scene.
//
// Rig frame: x right, y down, z forward (like a camera). Yaw turns a camera to the right
// (from +z towards +x) about the rig's y axis.
#pragma once

#include <string>

#include <Eigen/Core>

#include "dataset/dataset.h"
#include "geometry/rig.h"

namespace rigsim {

struct RingRigOptions {
  int num_cameras = 4;           // cameras on the ring, named cam0..cam{N-1} from left to right
  double yaw_spacing_deg = 65.0; // yaw between neighbours; with hfov 95 about 30% overlap
  double hfov_deg = 95.0;        // horizontal field of view of every camera (distorted ones too)
  double radius_m = 0.5;         // camera centres lie on this circle around the rig origin
  int width = 1280;
  int height = 720;
  int distorted_camera = 1;      // index of the camera with barrel distortion; -1 = none
  double k1 = -0.25;             // its OPENCV radial distortion
  double k2 = 0.06;
  void Check() const;            // throws std::invalid_argument
};

// N cameras on a horizontal circle, facing outwards, centred on the rig's forward direction.
Rig MakeRingRig(const RingRigOptions& options);

// The pose of a rig standing at `position_world` and looking horizontally along `heading_deg`
// (0 = world -Z, 90 = world +X), upright (rig y = world -Y).
Rigid3d RigFromWorldAt(const Eigen::Vector3d& position_world, double heading_deg);

// `num_frames` frames, the rig moving forward by `step_m` per frame from `start_world`,
// `frame_interval_s` apart in time.
FramesFile MakeStraightTrajectory(const Eigen::Vector3d& start_world, double heading_deg, int num_frames,
                                  double step_m, double frame_interval_s = 0.1);

}  // namespace rigsim
