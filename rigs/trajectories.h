// Rig poses and trajectories (straight, circle, polyline): where a rig stands in a scene, frame
// by frame, as frames.json holds it.
//
// World: glTF's (+Y up, metres). Headings: 0 = world -Z, 90 = world +X. The rig stands upright
// (rig y = world -Y) and looks along its heading (rig z).
#pragma once

#include <string_view>
#include <vector>

#include <Eigen/Core>

#include "dataset/dataset.h"
#include "geometry/rigid3.h"

namespace rigsim {

// The horizontal unit direction (world) of `heading_deg`.
Eigen::Vector3d HeadingDirection(double heading_deg);

// The pose of a rig standing at `position_world` and looking horizontally along `heading_deg`.
Rigid3d RigFromWorldAt(const Eigen::Vector3d& position_world, double heading_deg);

// `num_frames` frames, the rig moving forward by `step_m` per frame from `start_world`,
// `frame_interval_s` apart in time.
FramesFile MakeStraightTrajectory(const Eigen::Vector3d& start_world, double heading_deg, int num_frames,
                                  double step_m, double frame_interval_s = 0.1);

enum class TrajectoryKind { kStraight, kCircle, kPolyline };

// The paths a rig's options choose by name (a polyline needs its waypoints).
inline constexpr TrajectoryKind kNamedTrajectoryKinds[] = {TrajectoryKind::kStraight, TrajectoryKind::kCircle};

// "straight", "circle", "polyline".
std::string_view TrajectoryKindName(TrajectoryKind kind);
// Inverse of TrajectoryKindName for kNamedTrajectoryKinds; throws std::invalid_argument naming them.
TrajectoryKind TrajectoryKindFromName(std::string_view name);

struct TrajectoryOptions {
  TrajectoryKind kind = TrajectoryKind::kStraight;
  Eigen::Vector3d start_world = Eigen::Vector3d(0, 1.6, 0);  // frame 0's rig position
  double heading_deg = 0.0;        // frame 0's heading (straight, circle)
  int num_frames = 1;
  double step_m = 2.0;             // distance travelled between frames (arc length on curves)
  double frame_interval_s = 0.1;
  // circle: radius of the path; the rig drives along it, turning left (> 0) or right (< 0).
  double circle_radius_m = 10.0;
  // polyline: waypoints after start_world (x, y, z world); the rig follows start -> waypoints,
  // heading along the current segment, and stops at the last one.
  std::vector<Eigen::Vector3d> waypoints;
  void Check() const;              // throws std::invalid_argument
};
FramesFile MakeTrajectory(const TrajectoryOptions& options);

// The rig's pose at any time, from the poses and timestamps of a trajectory's frames: between two
// frames the rig's centre moves on the straight line and its orientation turns by slerp, at
// constant speed over the time between them; before the first frame and after the last it goes on
// with the velocity (linear and angular) of the nearest pair of frames. A single frame stands
// still. At a frame's timestamp the pose is that frame's rig_from_world exactly.
class RigTrajectory {
 public:
  // Throws std::invalid_argument when a frame has no rig_from_world, a timestamp is not finite,
  // or two frames share a timestamp (the speed between them would be infinite). Frames may come
  // in any order of time.
  explicit RigTrajectory(const FramesFile& frames);

  Rigid3d RigFromWorldAt(double time_s) const;

 private:
  struct Key {
    double time_s;
    Rigid3d rig_from_world;
    Eigen::Quaterniond world_from_rig;  // rotation
    Eigen::Vector3d centre;             // the rig's origin in the world
  };
  std::vector<Key> keys_;  // by time
};

// The demo's path on the built-in street: from the middle of the street at eye height, 2 m per
// frame along a gentle left turn (12 m radius, 9.5 deg per frame). The turn is what makes each
// camera's place in the rig visible in its own images (hand-eye style); on a straight path only
// the narrow overlaps between neighbours carry it (VALIDATION.md, "A straight path against a
// turning one").
FramesFile MakeDemoTrajectory(int num_frames);

}  // namespace rigsim
