#include "procedural/motion.h"

#include <algorithm>
#include <cmath>

namespace rigsim::procedural {
namespace {

constexpr float kTwoPi = 2 * kPi;
constexpr float kJumpStep_s = 0.001f;  // each of the three moves of a lane drive's jump back
constexpr float kUnderground_m = 10.f;

// Appends `q` with the sign nearer the previous key, so that LINEAR (slerp) keys never take the
// long way round.
void PushRotation(std::vector<Eigen::Quaternionf>* keys, Eigen::Quaternionf q) {
  if (!keys->empty() && keys->back().dot(q) < 0) q.coeffs() = -q.coeffs();
  keys->push_back(q);
}

// The walker's heading and feet (no bob) at `time_s`.
struct WalkState {
  float yaw;
  Eigen::Vector3f feet;
};

WalkState WalkStateAt(const Walk& w, float time_s) {
  const float leg_s = w.leg_m / w.speed_mps, cycle = 2 * (leg_s + Walk::kTurn_s);
  const float s = std::fmod(time_s, cycle);
  const Eigen::Vector3f dir(std::sin(w.yaw), 0, std::cos(w.yaw));
  if (s < leg_s) return {w.yaw, w.start + dir * (w.speed_mps * s)};
  if (s < leg_s + Walk::kTurn_s) return {w.yaw + kPi * (s - leg_s) / Walk::kTurn_s, w.start + dir * w.leg_m};
  if (s < 2 * leg_s + Walk::kTurn_s) return {w.yaw + kPi, w.start + dir * (w.leg_m - w.speed_mps * (s - leg_s - Walk::kTurn_s))};
  return {w.yaw + kPi * (1 + (s - 2 * leg_s - Walk::kTurn_s) / Walk::kTurn_s), w.start};
}

}  // namespace

int VehiclesOnLanes(double traffic, double lane_length_m) { return int(std::lround(traffic * lane_length_m / 100.0)); }

Eigen::Quaternionf Heading(float yaw) { return Eigen::Quaternionf(Eigen::AngleAxisf(yaw, Eigen::Vector3f::UnitY())); }

Eigen::Vector3f WalkPosition(const Walk& walk, float time_s) { return WalkStateAt(walk, time_s).feet; }

MotionKeys WalkKeys(const Walk& w) {
  const float step_s = Walk::kStep_m / w.speed_mps, stride_s = 2 * step_s;
  const float dt = step_s / 8;  // eight keys a step: the bob's rise and fall, and the turns, in small pieces
  MotionKeys keys;
  for (int k = 0;; ++k) {
    const float t = std::min(k * dt, kMotionDuration_s);
    const WalkState state = WalkStateAt(w, t);
    const float gait = t / stride_s + w.phase;
    const float bob = Walk::kBob_m * 0.5f * (1 - std::cos(2 * kTwoPi * gait));  // up twice a stride
    const float roll = Walk::kRoll_rad * std::sin(kTwoPi * gait);                // side to side once
    keys.times_s.push_back(t);
    keys.translations.push_back(state.feet + Eigen::Vector3f(0, bob, 0));
    PushRotation(&keys.rotations, Heading(state.yaw) * Eigen::Quaternionf(Eigen::AngleAxisf(roll, Eigen::Vector3f::UnitZ())));
    if (t >= kMotionDuration_s) break;
  }
  return keys;
}

Eigen::Vector3f LaneDrivePosition(const LaneDrive& d, float time_s) {
  const float length = (d.to - d.from).norm(), drive_s = length / d.speed_mps, cycle = drive_s + 3 * kJumpStep_s;
  const float p = std::fmod(std::fmod(d.offset_m, length) / d.speed_mps + time_s, cycle);
  if (p >= drive_s) return d.from;
  return d.from + (d.to - d.from) * (p / drive_s);
}

MotionKeys LaneDriveKeys(const LaneDrive& d) {
  const Eigen::Vector3f lane = d.to - d.from, down(0, -kUnderground_m, 0);
  const float length = lane.norm(), drive_s = length / d.speed_mps, cycle = drive_s + 3 * kJumpStep_s;
  const float start_s = std::fmod(d.offset_m, length) / d.speed_mps;  // time into the first cycle
  MotionKeys keys;
  auto key = [&keys](float t, const Eigen::Vector3f& p) {
    if (!keys.times_s.empty() && !(t > keys.times_s.back())) return;  // float rounding at a cycle's ends
    keys.times_s.push_back(t);
    keys.translations.push_back(p);
  };
  key(0, LaneDrivePosition(d, 0));
  for (float end = drive_s - start_s; end < kMotionDuration_s; end += cycle) {
    key(end, d.to);
    key(end + kJumpStep_s, d.to + down);
    key(end + 2 * kJumpStep_s, d.from + down);
    key(end + 3 * kJumpStep_s, d.from);
  }
  key(kMotionDuration_s, LaneDrivePosition(d, kMotionDuration_s));
  const Eigen::Quaternionf heading = Heading(std::atan2(lane.x(), lane.z()));
  keys.rotations.assign(keys.times_s.size(), heading);
  return keys;
}

std::vector<LaneDrive> SpreadOnLanes(int vehicles, const std::vector<LaneDrive>& lanes) {
  std::vector<LaneDrive> out;
  const int n_lanes = int(lanes.size());
  for (int k = 0; k < vehicles && n_lanes > 0; ++k) {
    const int lane = k % n_lanes, index = k / n_lanes;
    const int on_lane = vehicles / n_lanes + (lane < vehicles % n_lanes ? 1 : 0);
    LaneDrive d = lanes[lane];
    d.offset_m += index * (d.to - d.from).norm() / on_lane;
    out.push_back(d);
  }
  return out;
}

MotionKeys DriveToStopKeys(const Eigen::Vector3f& start, float yaw, float distance_m, float speed_mps) {
  const Eigen::Vector3f dir(std::sin(yaw), 0, std::cos(yaw));
  MotionKeys keys;
  keys.times_s = {0.f, distance_m / speed_mps};
  keys.translations = {start, start + dir * distance_m};
  return keys;
}

MotionKeys SwayKeys(const Sway& s) {
  const Eigen::Vector3f axis = Eigen::Vector3f::UnitY().cross(s.wind).normalized();  // tilts +Y towards the wind
  const float dt = s.period_s / 16;
  MotionKeys keys;
  for (int k = 0;; ++k) {
    const float t = std::min(k * dt, kMotionDuration_s);
    const float angle = s.amplitude_rad * std::sin(kTwoPi * (t / s.period_s + s.phase));
    keys.times_s.push_back(t);
    PushRotation(&keys.rotations, Eigen::Quaternionf(Eigen::AngleAxisf(angle, axis)) * Heading(s.yaw));
    if (t >= kMotionDuration_s) break;
  }
  return keys;
}

Eigen::Vector3f RandomWind(Rng& rng) {
  const float a = rng.Uniform(0, kTwoPi);
  return Eigen::Vector3f(std::cos(a), 0, std::sin(a));
}

Sway RandomSway(float yaw, const Eigen::Vector3f& wind, Rng& rng) {
  Sway s;
  s.yaw = yaw;
  s.wind = wind;
  s.amplitude_rad = rng.Uniform(1.5f, 3.f) * kPi / 180;
  s.period_s = rng.Uniform(2.5f, 4.5f);
  s.phase = rng.Uniform();
  return s;
}

void AddMotion(SceneBuilder* builder, int node, const MotionKeys& keys) {
  if (!keys.translations.empty()) builder->AddTranslationAnimation(node, keys.times_s, keys.translations);
  if (!keys.rotations.empty()) builder->AddRotationAnimation(node, keys.times_s, keys.rotations);
}

float ClearLength(const Eigen::Vector2f& start, const Eigen::Vector2f& dir, float max_m, float clearance,
                  const std::vector<Obstacle>& obstacles, float half_x, float half_z) {
  float length = max_m;
  for (const Obstacle& o : obstacles) {
    const Eigen::Vector2f to = start - Eigen::Vector2f(o.x, o.z);
    const float r = o.radius + clearance, b = to.dot(dir), c = to.squaredNorm() - r * r;
    if (c <= 0) return 0;  // starts inside
    const float disc = b * b - c;
    if (disc < 0 || b >= 0) continue;  // misses, or lies behind
    length = std::min(length, -b - std::sqrt(disc));
  }
  const float limits[2] = {half_x - clearance, half_z - clearance};
  for (int i = 0; i < 2; ++i) {
    if (std::abs(start[i]) > limits[i]) return 0;
    if (dir[i] != 0) length = std::min(length, ((dir[i] > 0 ? limits[i] : -limits[i]) - start[i]) / dir[i]);
  }
  return std::max(length, 0.f);
}

}  // namespace rigsim::procedural
