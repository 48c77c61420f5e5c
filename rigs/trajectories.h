// Rig poses and trajectories (straight, circle, polyline, loop, figure eight, handheld): where a
// rig stands in a scene, frame by frame, as frames.json holds it. Every path is a continuous
// function of the distance travelled (RigFromWorldAlongPath) that the frames sample, so the
// renderer's interpolation between frames (dataset/capture_poses.h) follows the same path.
//
// World: glTF's (+Y up, metres). Headings: 0 = world -Z, 90 = world +X. The rig stands upright
// (rig y = world -Y) and looks along its heading (rig z); only the handheld path tilts it:
// pitch > 0 raises the view (rig z towards world up), roll > 0 dips the rig's right side (rig x
// towards world down), world_from_rig = upright * Rx(pitch) * Rz(roll).
#pragma once

#include <string>
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

// What each path fixes of a rig by hand-eye calibration (each camera's own motion against the
// rig's): straight links nothing without overlap; circle and loop turn about one axis (planar), so
// each camera's offset along it (its height) stays open; figure-eight turns both ways but still
// about one axis; handheld turns about three (yaw, pitch, roll), which fixes every offset.
enum class TrajectoryKind { kStraight, kCircle, kPolyline, kLoop, kFigureEight, kHandheld };

// The paths a rig's options choose by name (a polyline needs its waypoints).
inline constexpr TrajectoryKind kNamedTrajectoryKinds[] = {TrajectoryKind::kStraight, TrajectoryKind::kCircle,
                                                           TrajectoryKind::kLoop, TrajectoryKind::kFigureEight,
                                                           TrajectoryKind::kHandheld};

// "straight", "circle", "polyline", "loop", "figure-eight", "handheld".
std::string_view TrajectoryKindName(TrajectoryKind kind);
// Inverse of TrajectoryKindName for kNamedTrajectoryKinds; throws std::invalid_argument naming them.
TrajectoryKind TrajectoryKindFromName(std::string_view name);

struct TrajectoryOptions {
  TrajectoryKind kind = TrajectoryKind::kStraight;
  Eigen::Vector3d start_world = Eigen::Vector3d(0, 1.6, 0);  // frame 0's rig position
  double heading_deg = 0.0;        // frame 0's heading (every path but the polyline)
  int num_frames = 1;
  // Distance travelled between frames (arc length on curves). Loop and figure-eight spread their
  // frames evenly over the whole closed path instead (PathStep).
  double step_m = 2.0;
  double frame_interval_s = 0.1;
  // circle, handheld: radius of the path; the rig drives along it, turning left (> 0) or right (< 0).
  // loop: one whole lap of this circle. figure-eight: a lap of this circle, then a lap of its mirror
  // image, turning the other way (both through the start, where the rig's heading is the same).
  double circle_radius_m = 10.0;
  // handheld: the amplitude of pitch and roll (deg). Both start at 0 and swing as sines of the
  // distance travelled, pitch over kHandheldPitchWavelengthM, roll over kHandheldRollWavelengthM,
  // so that no two frame-to-frame rotations share an axis.
  double tilt_deg = 10.0;
  // polyline: waypoints after start_world (x, y, z world); the rig follows start -> waypoints,
  // heading along the current segment, and stops at the last one.
  std::vector<Eigen::Vector3d> waypoints;
  void Check() const;              // throws std::invalid_argument
};
FramesFile MakeTrajectory(const TrajectoryOptions& options);

inline constexpr double kHandheldPitchWavelengthM = 7.0;
inline constexpr double kHandheldRollWavelengthM = 11.0;

// The whole length of a closed path (loop, figure-eight; m); 0 for open paths.
double ClosedPathLength(const TrajectoryOptions& options);
// The distance between frames: step_m, or a closed path's length over the frames (the frame after
// the last would be back at the start).
double PathStep(const TrajectoryOptions& options);
// The rig's pose after travelling `distance_m` along the path (frame k is at k * PathStep); closed
// paths repeat. Continuous in distance_m.
Rigid3d RigFromWorldAlongPath(const TrajectoryOptions& options, double distance_m);

// The path in words for messages: "circle of 12 frames (radius 8 m, 2 m per frame)".
std::string DescribePath(const TrajectoryOptions& options);

// The demo's path on the built-in street: from the middle of the street at eye height, 2 m per
// frame along a gentle left turn (12 m radius, 9.5 deg per frame). The turn is what makes each
// camera's place in the rig visible in its own images (hand-eye style); on a straight path only
// the narrow overlaps between neighbours carry it (VALIDATION.md, "A straight path against a
// turning one"). The rig slows into the turn (frames 0.2 s apart, then 0.02 s more each frame:
// 10 m/s, 8.3 m/s, 7.1 m/s, ...): at a steady speed and turn rate a time offset between cameras
// would look like a different mounting, and the calibration could not check that they capture
// together.
FramesFile MakeDemoTrajectory(int num_frames);

}  // namespace rigsim
