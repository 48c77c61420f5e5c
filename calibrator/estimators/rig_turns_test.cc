#include "calibrator/estimators/rig_turns.h"

#include <cmath>
#include <random>
#include <stdexcept>

#include <gtest/gtest.h>

#include "geometry/rigid3.h"

namespace rigsim {
namespace {

using Quat = Eigen::Quaterniond;

Quat Turn(double deg, const Eigen::Vector3d& axis) { return Quat(Eigen::AngleAxisd(DegToRad(deg), axis.normalized())); }

// Four cameras around a rig that turns 15-25 deg a step about an axis that pitches and rolls (a
// handheld path): camera c turns X_c R_k X_c^T over step k.
struct TurningRig {
  std::vector<Quat> mounting;  // cam_from_rig; camera 0 the identity
  std::vector<Quat> turn;      // rig(k+1)_from_rig(k)
  std::vector<TemporalPairEstimate> temporal;

  TurningRig(int cameras, int steps, double noise_deg, unsigned seed) {
    std::mt19937 rng(seed);
    std::uniform_real_distribution<double> u(-1.0, 1.0);
    for (int c = 0; c < cameras; ++c) {
      mounting.push_back(c == 0 ? Quat::Identity()
                                : Turn(90.0 * c, Eigen::Vector3d::UnitY()) * Turn(5.0, Eigen::Vector3d(u(rng), 0.0, u(rng))));
    }
    for (int k = 0; k < steps; ++k) turn.push_back(Turn(20.0 + 5.0 * u(rng), Eigen::Vector3d(0.4 * u(rng), 1.0, 0.4 * u(rng))));
    for (int c = 0; c < cameras; ++c) {
      for (int k = 0; k < steps; ++k) {
        const Quat noise = Turn(noise_deg, Eigen::Vector3d(u(rng), u(rng), u(rng)));
        temporal.push_back(Pair(c, k, noise * Seen(c, k)));
      }
    }
  }
  // Camera c's true turn over step k.
  Quat Seen(int c, int k) const { return mounting[c] * turn[k] * mounting[c].conjugate(); }
  TemporalPairEstimate& At(int c, int k) {
    for (TemporalPairEstimate& t : temporal) {
      if (t.camera == c && t.frame == k) return t;
    }
    throw std::out_of_range("no such pair");
  }
  static TemporalPairEstimate Pair(int c, int k, const Quat& rotation) {
    TemporalPairEstimate t;
    t.camera = c;
    t.frame = k;
    t.two_view.success = true;
    t.two_view.cam_b_from_cam_a = Rigid3d(rotation, Eigen::Vector3d(1.0, 0.0, 0.0));
    t.inliers = {{0, 0}, {1, 1}};
    return t;
  }
};

std::vector<std::optional<Quat>> Unknown(int cameras) { return std::vector<std::optional<Quat>>(cameras); }

TEST(RigTurns, ChoosesThePlanarAlternativeTheOtherCamerasAgreeWith) {
  TurningRig rig(4, 8, 0.2, 1);
  // Camera 2 at step 3 and the reference at step 5: a facade whose essential matrix took the wrong
  // one of its two poses, 8 and 6 deg off; the right one is the alternative.
  for (const auto& [c, k, off] : {std::tuple{2, 3, 8.0}, std::tuple{0, 5, 6.0}}) {
    TwoViewEstimate& tv = rig.At(c, k).two_view;
    tv.pair_type = PairType::kPlanar;
    tv.planar_alternatives = {tv.cam_b_from_cam_a};
    tv.cam_b_from_cam_a.rotation = Turn(off, Eigen::Vector3d(1.0, 0.3, 0.0)) * tv.cam_b_from_cam_a.rotation;
  }
  const RigTurns r = ResolveStepsByTheRig(rig.temporal, Unknown(4), 9, {});
  EXPECT_EQ(r.alternatives_taken, 2);
  EXPECT_EQ(r.pairs_disagreeing, 0);
  for (int c = 0; c < 4; ++c) {
    SCOPED_TRACE(c);
    ASSERT_TRUE(r.cam_from_rig[c]);
    EXPECT_LT(RotationDifferenceDeg(*r.cam_from_rig[c], rig.mounting[c]), 0.5);  // the path pitches: fixed
    for (int k = 0; k < 8; ++k) {
      const bool swapped = (c == 2 && k == 3) || (c == 0 && k == 5);
      EXPECT_EQ(r.choice[c][k], swapped ? StepChoice::kAlternative : StepChoice::kAgrees) << k;
      ASSERT_TRUE(r.step_rotation[c][k]);
      EXPECT_LT(RotationDifferenceDeg(*r.step_rotation[c][k], rig.Seen(c, k)), 0.6) << k;
    }
  }
  // The rig stages get the chosen pose, and the one it replaced as the alternative.
  for (const auto& [c, k] : {std::pair{2, 3}, std::pair{0, 5}}) {
    const TemporalPairEstimate* t = nullptr;
    for (const TemporalPairEstimate& p : r.temporal) {
      if (p.camera == c && p.frame == k) t = &p;
    }
    ASSERT_TRUE(t);
    EXPECT_LT(RotationDifferenceDeg(t->two_view.cam_b_from_cam_a.rotation, rig.Seen(c, k)), 0.6);
    ASSERT_EQ(t->two_view.planar_alternatives.size(), 1u);
    EXPECT_GT(RotationDifferenceDeg(t->two_view.planar_alternatives[0].rotation, rig.Seen(c, k)), 5.0);
    EXPECT_TRUE(t->PoseUsable());
  }
  // The rig's rotation per frame chains its turns.
  Quat truth = Quat::Identity();
  for (int k = 0; k < 8; ++k) {
    truth = rig.turn[k] * truth;
    ASSERT_TRUE(r.rig_from_world[k + 1]);
    EXPECT_LT(RotationDifferenceDeg(*r.rig_from_world[k + 1], truth), 1.0) << k;
  }
}

TEST(RigTurns, LeavesOutAPoseNoOtherCameraAgreesWithAndBridgesAMissingStep) {
  TurningRig rig(4, 8, 0.2, 2);
  // Camera 1 at step 2: consistent wrong matches, 7 deg off, with no other pose. Camera 3 has no
  // pair at step 4.
  TemporalPairEstimate& wrong = rig.At(1, 2);
  wrong.two_view.cam_b_from_cam_a.rotation = Turn(7.0, Eigen::Vector3d(0.0, 0.2, 1.0)) * wrong.two_view.cam_b_from_cam_a.rotation;
  rig.At(3, 4).two_view.success = false;
  const RigTurns r = ResolveStepsByTheRig(rig.temporal, Unknown(4), 9, {});
  EXPECT_EQ(r.pairs_disagreeing, 1);
  EXPECT_EQ(r.choice[1][2], StepChoice::kDisagrees);
  EXPECT_EQ(r.choice[3][4], StepChoice::kNone);
  // The camera's trajectory crosses both steps with the rig's turn seen through its mounting.
  for (const auto& [c, k] : {std::pair{1, 2}, std::pair{3, 4}}) {
    ASSERT_TRUE(r.step_rotation[c][k]);
    EXPECT_LT(RotationDifferenceDeg(*r.step_rotation[c][k], rig.Seen(c, k)), 0.6);
  }
  // The rig stages keep the wrong pair's matches but not its pose.
  for (const TemporalPairEstimate& t : r.temporal) {
    const bool left_out = t.camera == 1 && t.frame == 2;
    EXPECT_EQ(t.PoseUsable(), left_out ? false : t.two_view.success) << t.camera << " " << t.frame;
    if (left_out) {
      EXPECT_TRUE(t.two_view.success);
      EXPECT_EQ(t.inliers.size(), 2u);
      EXPECT_FALSE(t.pose_left_out.empty());
    }
  }
}

TEST(RigTurns, KnownMountingsAreUsedAndACameraThatTurnsOtherwiseIsUndecided) {
  TurningRig rig(4, 8, 0.2, 3);
  // Camera 3 is not on this rig: its turns follow a path of its own.
  std::mt19937 rng(7);
  std::uniform_real_distribution<double> u(-1.0, 1.0);
  for (int k = 0; k < 8; ++k) {
    rig.At(3, k).two_view.cam_b_from_cam_a.rotation = Turn(10.0 + 20.0 * std::abs(u(rng)), Eigen::Vector3d(u(rng), u(rng), u(rng)));
  }
  std::vector<std::optional<Quat>> known = Unknown(4);
  known[1] = rig.mounting[1];
  const RigTurns r = ResolveStepsByTheRig(rig.temporal, known, 9, {});
  ASSERT_TRUE(r.cam_from_rig[1]);
  EXPECT_EQ(RotationDifferenceDeg(*r.cam_from_rig[1], rig.mounting[1]), 0.0);
  EXPECT_FALSE(r.cam_from_rig[3]);
  for (int k = 0; k < 8; ++k) {
    EXPECT_EQ(r.choice[3][k], StepChoice::kUndecided) << k;
    EXPECT_EQ(RotationDifferenceDeg(*r.step_rotation[3][k], rig.At(3, k).two_view.cam_b_from_cam_a.rotation), 0.0);
  }
  EXPECT_EQ(r.pairs_disagreeing, 0);
}

TEST(RigTurns, AStraightPathDecidesNothing) {
  TurningRig rig(3, 6, 0.0, 4);
  for (TemporalPairEstimate& t : rig.temporal) t.two_view.cam_b_from_cam_a.rotation = Quat::Identity();
  const RigTurns r = ResolveStepsByTheRig(rig.temporal, Unknown(3), 7, {});
  for (int c = 1; c < 3; ++c) EXPECT_FALSE(r.cam_from_rig[c]);
  for (int c = 1; c < 3; ++c) {
    for (int k = 0; k < 6; ++k) EXPECT_EQ(r.choice[c][k], StepChoice::kUndecided);
  }
}

TEST(RigTurns, RefusesPairsOutOfRangeAndBadOptions) {
  TurningRig rig(2, 3, 0.0, 5);
  EXPECT_THROW(ResolveStepsByTheRig(rig.temporal, Unknown(2), 3, {}), std::invalid_argument);  // step 2 needs frame 3
  RigTurnOptions bad;
  bad.max_disagreement_deg = 0.0;
  EXPECT_THROW(ResolveStepsByTheRig(rig.temporal, Unknown(2), 4, bad), std::invalid_argument);
}

}  // namespace
}  // namespace rigsim
