// Rig generators (ring, stereo, surround, wide-baseline), trajectories (straight, circle, polyline)
// and automatic placement of a rig in a loaded scene. Everything random takes an explicit seed.
//
// Rig frame: x right, y down, z forward (like a camera). Yaw turns a camera to the right
// (from +z towards +x) about the rig's y axis. World: glTF's (+Y up, metres). Headings: 0 = world
// -Z, 90 = world +X. Angles are degrees in options (user-facing), radians inside.
#pragma once

#include <cstdint>
#include <optional>
#include <string>
#include <vector>

#include <Eigen/Core>

#include "dataset/dataset.h"
#include "geometry/rig.h"
#include "scenes/scene.h"

namespace rigsim {

// ---- Rigs ---------------------------------------------------------------------------------------

struct RingRigOptions {
  int num_cameras = 4;           // cameras on the ring, named cam0..cam{N-1} from left to right
  double yaw_spacing_deg = 60.0; // yaw between neighbours; with hfov 95: 29-34% ground-truth overlap on the street
  double hfov_deg = 95.0;        // horizontal field of view of every camera (distorted ones too)
  double radius_m = 0.5;         // camera centres lie on this circle around the rig origin
  int width = 1280;
  int height = 720;
  int distorted_camera = 1;      // index of the camera with barrel distortion; -1 = none
  double k1 = -0.25;             // its OPENCV radial distortion
  double k2 = 0.06;
  // When in (0, 1): choose the yaw spacing so that neighbours share this fraction of their image
  // (overrides yaw_spacing_deg; see RingSpacingForOverlap). <= 0: use yaw_spacing_deg.
  double target_overlap = 0.0;
  void Check() const;            // throws std::invalid_argument
};

// N cameras on a horizontal circle, facing outwards, centred on the rig's forward direction.
Rig MakeRingRig(const RingRigOptions& options);

// Fraction of camera a's pixels whose rays, seen from b (pure rotation, points at infinity),
// land inside b's image. The exact ground-truth overlap also depends on depth (parallax from the
// ring radius) and on how much sky a view sees; the renderer measures it (overlap.json).
double AngularOverlap(const Camera& a, const Camera& b, const Eigen::Matrix3d& b_from_a_rotation);

// Yaw spacing (deg) at which neighbouring ring cameras overlap by `overlap` (mean over both
// directions and all neighbour pairs, AngularOverlap). Throws when unreachable.
double RingSpacingForOverlap(const RingRigOptions& options, double overlap);

// Ring rig whose neighbours share `options.target_overlap` of their surface pixels as the
// renderer's ground truth counts it (overlap.json: sky excluded, depth-tested), predicted by ray
// casting in `scene` with the rig at `rig_from_world`: cam0 keeps the yaw of the angular solution
// and each next camera's yaw is solved in turn, so spacings differ where the scene does (more sky
// or near occluders on one side). Costs a few seconds of ray casting.
Rig MakeRingRigInScene(const RingRigOptions& options, const Scene& scene, const Rigid3d& rig_from_world);

// Predicted ground-truth overlap of cameras a and b of `rig` at `rig_from_world` in `scene`
// (mean of both directions; see MakeRingRigInScene).
double PredictedOverlap(const Scene& scene, const Rig& rig, int a, int b, const Rigid3d& rig_from_world);

struct StereoRigOptions {
  double baseline_m = 0.12;  // distance between the two camera centres along the rig's x axis
  double hfov_deg = 80.0;    // horizontal field of view (pinhole)
  int width = 1280;
  int height = 720;
  void Check() const;
};
// "left" and "right", parallel optical axes along the rig's +z, centres at x = -+baseline/2.
Rig MakeStereoRig(const StereoRigOptions& options);

struct SurroundRigOptions {
  double length_m = 4.0;         // front and back cameras at z = +-length/2 (vehicle-like)
  double width_m = 1.8;          // side cameras at x = +-width/2
  double front_hfov_deg = 100.0; // front camera: OPENCV with mild barrel distortion
  double back_hfov_deg = 90.0;   // back camera: PINHOLE
  double side_fov_deg = 190.0;   // side cameras: OPENCV_FISHEYE, horizontal field of view (> 180 ok)
  double side_pitch_deg = 0.0;   // side cameras look down by this much (positive = down)
  int width = 1280;
  int height = 720;
  void Check() const;
};
// "front" (OPENCV), "right" (OPENCV_FISHEYE), "back" (PINHOLE), "left" (OPENCV_FISHEYE).
Rig MakeSurroundRig(const SurroundRigOptions& options);

struct WideBaselineRigOptions {
  double baseline_m = 2.0;       // distance between the two camera centres
  double convergence_deg = 30.0; // angle between the optical axes; each camera toes in by half
  double hfov_deg = 70.0;        // horizontal field of view (pinhole)
  int width = 1280;
  int height = 720;
  void Check() const;
};
// "cam0" at x = -baseline/2 and "cam1" at +baseline/2, both turned towards the rig's +z axis.
Rig MakeWideBaselineRig(const WideBaselineRigOptions& options);

// Mounting errors: every camera's cam_from_rig is perturbed by a random rotation of up to
// `rotation_deg` and a translation of up to `translation_m` (uniform, seeded).
struct RigPerturbation {
  double rotation_deg = 0.0;
  double translation_m = 0.0;
  uint64_t seed = 1;
};
void PerturbRig(Rig& rig, const RigPerturbation& perturbation);

// ---- Poses and trajectories ---------------------------------------------------------------------

// The pose of a rig standing at `position_world` and looking horizontally along `heading_deg`
// (0 = world -Z, 90 = world +X), upright (rig y = world -Y).
Rigid3d RigFromWorldAt(const Eigen::Vector3d& position_world, double heading_deg);

// `num_frames` frames, the rig moving forward by `step_m` per frame from `start_world`,
// `frame_interval_s` apart in time.
FramesFile MakeStraightTrajectory(const Eigen::Vector3d& start_world, double heading_deg, int num_frames,
                                  double step_m, double frame_interval_s = 0.1);

enum class TrajectoryKind { kStraight, kCircle, kPolyline };

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
  void Check() const;
};
FramesFile MakeTrajectory(const TrajectoryOptions& options);

// The demo's path on the built-in street: from the middle of the street at eye height, 2 m per
// frame along a gentle left turn (12 m radius, 9.5 deg per frame). The turn is what makes each
// camera's place in the rig visible in its own images (hand-eye style); on a straight path only
// the narrow overlaps between neighbours carry it. Measured on the demo ring, 4 frames, every
// semantic mode: worst camera 0.021 deg / 0.21 deg (rotation / translation direction) against
// 0.033 deg / 0.35 deg straight, where the gated mode's linear position step also failed.
FramesFile MakeDemoTrajectory(int num_frames);

// ---- Automatic placement --------------------------------------------------------------------

struct PlacementOptions {
  double height_m = 1.6;          // rig origin above the ground under it
  double min_clearance_m = 2.0;   // no surface closer than this along any camera's central rays
  double travel_m = 0.0;          // free distance needed straight ahead (for a straight trajectory)
  double max_range_m = 80.0;      // hits further than this do not count as structure
  int num_candidates = 300;       // random positions tried (seeded)
  int num_headings = 24;          // headings tried at each position
  uint64_t seed = 1;
  void Check() const;
};

struct RigPlacement {
  Eigen::Vector3d position_world;
  double heading_deg = 0.0;
  double score = 0.0;  // fraction of probe rays of all cameras that hit structure in range
};

// Picks a position on the ground (the surface seen from above must be the lowest level of the
// scene, so not a roof or a car) and a heading such that the rig is not inside geometry, every
// camera's central rays see no surface closer than min_clearance_m, and as many probe rays as
// possible hit structure. Uses brute-force ray casting over a coarse grid, not the renderer.
// nullopt when no candidate qualifies.
std::optional<RigPlacement> PlaceRig(const Scene& scene, const Rig& rig, const PlacementOptions& options);

// Distance to the first surface along a ray (unit direction), or nullopt. For tests and tools;
// builds the grid on each call, so use PlaceRig for many rays.
std::optional<double> CastRay(const Scene& scene, const Eigen::Vector3d& origin, const Eigen::Vector3d& direction);

}  // namespace rigsim
