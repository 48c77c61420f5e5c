#include "procedural/motion.h"

#include <algorithm>
#include <cmath>

#include <gtest/gtest.h>

namespace rigsim::procedural {
namespace {

// The translation the keys give at `t`, interpolated linearly as glTF LINEAR does (held outside).
Eigen::Vector3f TranslationAt(const MotionKeys& keys, float t) {
  const auto& times = keys.times_s;
  if (t <= times.front()) return keys.translations.front();
  if (t >= times.back()) return keys.translations.back();
  const size_t k = size_t(std::upper_bound(times.begin(), times.end(), t) - times.begin()) - 1;
  const float a = (t - times[k]) / (times[k + 1] - times[k]);
  return (1 - a) * keys.translations[k] + a * keys.translations[k + 1];
}

void ExpectIncreasingTimes(const MotionKeys& keys) {
  ASSERT_FALSE(keys.times_s.empty());
  EXPECT_EQ(keys.times_s.front(), 0.f);
  EXPECT_GE(keys.times_s.back(), kMotionDuration_s);
  for (size_t k = 1; k < keys.times_s.size(); ++k) ASSERT_GT(keys.times_s[k], keys.times_s[k - 1]) << k;
}

TEST(Motion, VehiclesOnLanesRoundsTheDensity) {
  EXPECT_EQ(VehiclesOnLanes(2.0, 240), 5);  // the street's default
  EXPECT_EQ(VehiclesOnLanes(2.0, 120), 2);  // the parking's
  EXPECT_EQ(VehiclesOnLanes(0.0, 240), 0);
  EXPECT_EQ(VehiclesOnLanes(6.0, 240), 14);
}

TEST(Motion, AWalkerPacesItsPathAtWalkingSpeedFacingWhereItGoes) {
  Walk w;
  w.start = Eigen::Vector3f(3, 0.15f, -2);
  w.yaw = 0.5f * kPi;  // towards +x
  w.leg_m = 8;
  w.speed_mps = 1.4f;
  w.phase = 0.3f;
  const MotionKeys keys = WalkKeys(w);
  ExpectIncreasingTimes(keys);
  ASSERT_EQ(keys.rotations.size(), keys.times_s.size());
  ASSERT_EQ(keys.translations.size(), keys.times_s.size());
  // Out along +x: 0.14 m in 0.1 s, on the path, rising by at most the bob.
  const Eigen::Vector3f a = TranslationAt(keys, 2.0f), b = TranslationAt(keys, 2.1f);
  EXPECT_NEAR(Eigen::Vector2f(b.x() - a.x(), b.z() - a.z()).norm(), 0.14f, 1e-4f);
  EXPECT_GT(b.x(), a.x());
  EXPECT_TRUE(WalkPosition(w, 2.0f).isApprox(Eigen::Vector3f(3 + 2.8f, 0.15f, -2), 1e-5f));
  for (size_t k = 0; k < keys.times_s.size(); ++k) {
    const Eigen::Vector3f& p = keys.translations[k];
    ASSERT_GE(p.x(), 3 - 1e-4f);
    ASSERT_LE(p.x(), 11 + 1e-4f);
    ASSERT_NEAR(p.z(), -2, 1e-5f);
    ASSERT_GE(p.y(), 0.15f - 1e-6f);
    ASSERT_LE(p.y(), 0.15f + Walk::kBob_m + 1e-6f);
    // Upright but for the gait's roll.
    const float tilt = std::asin(std::min(1.f, std::abs((keys.rotations[k] * Eigen::Vector3f::UnitX()).y())));
    ASSERT_LE(tilt, Walk::kRoll_rad + 1e-4f);
  }
  // Facing along the path: +x on the way out (t = 2 s is key 32).
  const float dt = Walk::kStep_m / w.speed_mps / 8;
  ASSERT_NEAR(keys.times_s[32], 2.f, 1e-5f);
  EXPECT_TRUE((keys.rotations[32] * Eigen::Vector3f::UnitZ()).isApprox(Eigen::Vector3f::UnitX(), 1e-5f));
  // Back at the start after a whole cycle (two legs and two turns).
  const float cycle = 2 * (8 / 1.4f + Walk::kTurn_s);
  EXPECT_TRUE(WalkPosition(w, cycle + 0.5f).isApprox(WalkPosition(w, 0.5f), 1e-4f));
  // On the way back at the middle of the second leg: heading -x.
  const float back = 8 / 1.4f + Walk::kTurn_s + 4 / 1.4f;
  EXPECT_NEAR(WalkPosition(w, back).x(), 7, 1e-4f);
  EXPECT_LT(TranslationAt(keys, back + 0.1f).x(), TranslationAt(keys, back).x());
  const size_t k_back = size_t(std::lround(back / dt));
  EXPECT_TRUE((keys.rotations[k_back] * Eigen::Vector3f::UnitZ()).isApprox(-Eigen::Vector3f::UnitX(), 1e-4f));
}

TEST(Motion, ALaneDriveLoopsUnderTheGroundAndKeepsItsSpeed) {
  LaneDrive d;
  d.from = Eigen::Vector3f(-2, 0, -64);
  d.to = Eigen::Vector3f(-2, 0, 64);
  d.offset_m = 100;
  d.speed_mps = 8;
  const MotionKeys keys = LaneDriveKeys(d);
  ExpectIncreasingTimes(keys);
  // 28 m to the lane's end: 3.5 s; then under the ground and back at the start.
  EXPECT_TRUE(TranslationAt(keys, 1.0f).isApprox(Eigen::Vector3f(-2, 0, 44), 1e-5f));
  EXPECT_TRUE(TranslationAt(keys, 3.5f).isApprox(d.to, 1e-4f));
  EXPECT_LT(TranslationAt(keys, 3.5015f).y(), -9.f);
  EXPECT_TRUE(TranslationAt(keys, 4.003f).isApprox(Eigen::Vector3f(-2, 0, -60), 1e-3f));
  // Everywhere over the minute: on the lane at the drive's place, or under the ground.
  for (float t = 0; t <= kMotionDuration_s; t += 0.0371f) {
    const Eigen::Vector3f p = TranslationAt(keys, t);
    if (p.y() < -1e-3f) continue;  // jumping back
    ASSERT_NEAR(p.y(), 0, 1e-6f) << t;
    ASSERT_TRUE(p.isApprox(LaneDrivePosition(d, t), 1e-3f)) << t << ": " << p.transpose() << " vs " << LaneDrivePosition(d, t).transpose();
  }
  for (const Eigen::Quaternionf& q : keys.rotations) EXPECT_TRUE((q * Eigen::Vector3f::UnitZ()).isApprox(Eigen::Vector3f::UnitZ(), 1e-6f));
}

TEST(Motion, SpreadOnLanesSpacesVehiclesEvenly) {
  LaneDrive a, b;
  a.to = Eigen::Vector3f(0, 0, 100);
  b.from = Eigen::Vector3f(5, 0, 100);
  b.to = Eigen::Vector3f(5, 0, 0);
  a.offset_m = 10;
  const std::vector<LaneDrive> five = SpreadOnLanes(5, {a, b});
  ASSERT_EQ(five.size(), 5u);
  EXPECT_EQ(five[0].from, a.from);
  EXPECT_EQ(five[1].from, b.from);
  EXPECT_FLOAT_EQ(five[0].offset_m, 10);
  EXPECT_FLOAT_EQ(five[2].offset_m, 10 + 100.f / 3);  // lane a takes three
  EXPECT_FLOAT_EQ(five[4].offset_m, 10 + 200.f / 3);
  EXPECT_FLOAT_EQ(five[3].offset_m, 50);  // lane b two
  EXPECT_TRUE(SpreadOnLanes(0, {a, b}).empty());
}

TEST(Motion, SwayIsBoundedPeriodicAndAboutTheBase) {
  Sway s;
  s.yaw = 1.0f;
  s.wind = Eigen::Vector3f(0.6f, 0, 0.8f);
  s.amplitude_rad = 0.05f;
  s.period_s = 3.f;
  s.phase = 0.2f;
  const MotionKeys keys = SwayKeys(s);
  ExpectIncreasingTimes(keys);
  EXPECT_TRUE(keys.translations.empty());  // the base stays where it stands
  float most = 0;
  for (const Eigen::Quaternionf& q : keys.rotations) {
    const Eigen::Vector3f up = q * Eigen::Vector3f::UnitY();
    const float lean = std::acos(std::min(1.f, up.y()));
    most = std::max(most, lean);
    ASSERT_LE(lean, s.amplitude_rad + 1e-4f);
    // Leaning along the wind, never across it.
    ASSERT_NEAR(up.cross(s.wind).y(), 0, 1e-4f);
  }
  EXPECT_GT(most, 0.95f * s.amplitude_rad);
  // Keys a period apart (16 a period) are the same rotation.
  EXPECT_TRUE(keys.rotations[5].isApprox(keys.rotations[21], 1e-4f) || keys.rotations[5].coeffs().isApprox(-keys.rotations[21].coeffs(), 1e-4f));
}

TEST(Motion, ClearLengthStopsBeforeObstaclesAndTheBox) {
  const std::vector<Obstacle> obstacles = {{5, 0, 1}};
  EXPECT_NEAR(ClearLength({0, 0}, {1, 0}, 10, 0.5f, obstacles, 20, 20), 3.5f, 1e-5f);
  EXPECT_NEAR(ClearLength({0, 0}, {-1, 0}, 10, 0.5f, obstacles, 20, 20), 10.f, 1e-5f);
  EXPECT_NEAR(ClearLength({0, 0}, {-1, 0}, 30, 0.5f, obstacles, 20, 20), 19.5f, 1e-5f);
  EXPECT_NEAR(ClearLength({0, 3}, {1, 0}, 10, 0.5f, obstacles, 20, 20), 10.f, 1e-5f);  // passes by
  EXPECT_EQ(ClearLength({4.5f, 0}, {-1, 0}, 10, 0.5f, obstacles, 20, 20), 0.f);       // starts inside
}

}  // namespace
}  // namespace rigsim::procedural
