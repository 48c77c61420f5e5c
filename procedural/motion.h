// Keyframed motion for the procedural worlds' animated objects (gltf/scene_builder.h writes the
// keys as glTF LINEAR channels): people pacing along a path with a walking gait, vehicles driving
// a lane in a loop whose jump back happens under the ground, a bus driving to its stop, and
// vegetation swaying about its base.
//
// Conventions: glTF world (+Y up, metres); a node's heading is where its +z axis points, yaw about
// +Y (yaw 0 = +z, yaw pi/2 = +x); times in seconds from 0 to kMotionDuration_s, after which glTF
// holds the last key. Every function is a pure function of its arguments.
#pragma once

#include <vector>

#include <Eigen/Core>
#include <Eigen/Geometry>

#include "gltf/scene_builder.h"
#include "procedural/textures.h"

namespace rigsim::procedural {

// How long the animations run: longer than a sweep's longest capture (100 frames of 0.1 s plus
// offsets up to 1 s).
inline constexpr float kMotionDuration_s = 60.f;

// Vehicles on `lane_length_m` of lane at `traffic` vehicles per 100 m (rounded to the nearest whole vehicle).
int VehiclesOnLanes(double traffic, double lane_length_m);

struct MotionKeys {
  std::vector<float> times_s;
  std::vector<Eigen::Vector3f> translations;  // empty: translation not animated
  std::vector<Eigen::Quaternionf> rotations;  // empty: rotation not animated
};

// Rotation by `yaw` about +Y.
Eigen::Quaternionf Heading(float yaw);

// A person pacing back and forth: out `leg_m` along `yaw` from `start` (the feet) and back, at
// `speed_mps`, turning on the spot for kTurn_s at each end. The gait: steps of 0.7 m, the body
// rising by up to kBob_m at every step and rolling by up to kRoll_rad once per stride (two steps);
// `phase` in [0, 1) shifts the gait so that people do not step in unison.
struct Walk {
  static constexpr float kTurn_s = 0.6f;
  static constexpr float kStep_m = 0.7f;
  static constexpr float kBob_m = 0.03f;
  static constexpr float kRoll_rad = 0.035f;  // 2 degrees
  Eigen::Vector3f start = Eigen::Vector3f::Zero();
  float yaw = 0;
  float leg_m = 10;
  float speed_mps = 1.4f;
  float phase = 0;
};
MotionKeys WalkKeys(const Walk& walk);
// Where a walker's feet are at `time_s` on its path (without the gait's bob): what WalkKeys samples.
Eigen::Vector3f WalkPosition(const Walk& walk, float time_s);

// A vehicle driving from `from` to `to` and on again from `from`, looping, at `speed_mps`, heading
// along the lane; `offset_m` is how far along the lane it is at time 0. At each loop it sinks 10 m
// under `to`, drives back under the ground and rises at `from` within 3 ms: place both ends out of
// sight (behind a facade, inside a building) and the lane over opaque ground.
struct LaneDrive {
  Eigen::Vector3f from = Eigen::Vector3f::Zero(), to = Eigen::Vector3f::UnitZ();
  float offset_m = 0;
  float speed_mps = 8;
};
MotionKeys LaneDriveKeys(const LaneDrive& drive);
// Where the vehicle is at `time_s` (on the lane; during the 3 ms jump, at `from`).
Eigen::Vector3f LaneDrivePosition(const LaneDrive& drive, float time_s);

// `vehicles` spread over `lanes` (vehicle k on lane k mod lanes, the first lanes taking one more
// when they do not divide evenly), evenly spaced along each lane from the lane's own offset_m.
std::vector<LaneDrive> SpreadOnLanes(int vehicles, const std::vector<LaneDrive>& lanes);

// A vehicle driving straight from `start` along `yaw` for `distance_m` at `speed_mps`, then
// standing (a bus at its stop). Translation keys only: the heading is the node's own.
MotionKeys DriveToStopKeys(const Eigen::Vector3f& start, float yaw, float distance_m, float speed_mps);

// Vegetation swaying in the wind about its base (the node's origin): its rest heading `yaw` tilted
// towards `wind` (a horizontal direction) by amplitude_rad * sin(2 pi (t / period_s + phase)).
struct Sway {
  float yaw = 0;
  Eigen::Vector3f wind = Eigen::Vector3f::UnitX();
  float amplitude_rad = 0.04f;
  float period_s = 3.5f;
  float phase = 0;
};
MotionKeys SwayKeys(const Sway& sway);
// A scene's wind: a random horizontal direction. A tree's sway in it: 1.5 to 3 degrees, a period of
// 2.5 to 4.5 s, a random phase.
Eigen::Vector3f RandomWind(Rng& rng);
Sway RandomSway(float yaw, const Eigen::Vector3f& wind, Rng& rng);

// Writes `keys` as `node`'s translation and rotation animations (those present).
void AddMotion(SceneBuilder* builder, int node, const MotionKeys& keys);

// A disc on the ground (x, z) that walkers keep clear of.
struct Obstacle {
  float x, z, radius;
};
// How far a walker of radius `clearance` can go from `start` (x, z) along `dir` (unit, x z), up to
// `max_m`, before it touches an obstacle or leaves the box |x| <= half_x, |z| <= half_z. 0 when
// the start itself is blocked.
float ClearLength(const Eigen::Vector2f& start, const Eigen::Vector2f& dir, float max_m, float clearance,
                  const std::vector<Obstacle>& obstacles, float half_x, float half_z);

}  // namespace rigsim::procedural
