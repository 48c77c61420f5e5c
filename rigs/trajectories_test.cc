#include "rigs/trajectories.h"

#include <Eigen/Core>
#include <gtest/gtest.h>

namespace rigsim {
namespace {

TEST(RigPlacement, HeadingZeroLooksDownMinusZUpright) {
  const Rigid3d rig_from_world = RigFromWorldAt(Eigen::Vector3d(1, 1.6, 2), 0.0);
  EXPECT_LT((rig_from_world * Eigen::Vector3d(1, 1.6, -3) - Eigen::Vector3d(0, 0, 5)).norm(), 1e-12);
  EXPECT_LT((rig_from_world * Eigen::Vector3d(1, 2.6, 2)).y(), 0.0);  // world up = rig -y
  const Rigid3d right = RigFromWorldAt(Eigen::Vector3d::Zero(), 90.0);
  EXPECT_GT((right * Eigen::Vector3d(5, 0, 0)).z(), 4.99);
}

TEST(Trajectory, MovesForwardByTheStep) {
  const FramesFile f = MakeStraightTrajectory(Eigen::Vector3d(0, 1.6, 0), 0.0, 3, 2.0, 0.5);
  ASSERT_EQ(f.frames.size(), 3u);
  EXPECT_EQ(f.frames[2].name, "000002");
  EXPECT_DOUBLE_EQ(f.frames[2].timestamp_s, 1.0);
  const Eigen::Vector3d c2 = f.frames[2].rig_from_world->SourceOriginInTarget();
  EXPECT_LT((c2 - Eigen::Vector3d(0, 1.6, -4)).norm(), 1e-12);
}

TEST(Trajectory, CircleKeepsRadiusAndTangentHeading) {
  TrajectoryOptions o;
  o.kind = TrajectoryKind::kCircle;
  o.circle_radius_m = 5.0;  // turning left
  o.num_frames = 9;
  o.step_m = 2 * 3.14159265358979 * 5.0 / 8;  // 8 steps = one lap
  o.start_world = Eigen::Vector3d(1, 1.6, 2);
  const FramesFile f = MakeTrajectory(o);
  const Eigen::Vector3d centre = o.start_world + Eigen::Vector3d(-5, 0, 0);  // left of heading 0 (-Z) is -X
  for (const Frame& fr : f.frames) {
    const Rigid3d world_from_rig = fr.rig_from_world->Inverse();
    const Eigen::Vector3d p = world_from_rig.translation;
    EXPECT_NEAR((p - centre).norm(), 5.0, 1e-9);
    const Eigen::Vector3d forward = world_from_rig.rotation * Eigen::Vector3d::UnitZ();
    EXPECT_NEAR(forward.dot(p - centre), 0.0, 1e-9);  // tangent
  }
  EXPECT_LT((f.frames[8].rig_from_world->Inverse().translation - o.start_world).norm(), 1e-9);
  EXPECT_LT((f.frames[2].rig_from_world->Inverse().translation - (centre + Eigen::Vector3d(0, 0, -5))).norm(), 1e-9);
}

TEST(Trajectory, PolylineFollowsWaypoints) {
  TrajectoryOptions o;
  o.kind = TrajectoryKind::kPolyline;
  o.start_world = Eigen::Vector3d(0, 1.6, 0);
  o.waypoints = {Eigen::Vector3d(0, 1.6, -4), Eigen::Vector3d(4, 1.6, -4)};
  o.num_frames = 6;
  o.step_m = 2.0;
  const FramesFile f = MakeTrajectory(o);
  auto pos = [&](int k) { return f.frames[k].rig_from_world->Inverse().translation; };
  EXPECT_LT((pos(2) - Eigen::Vector3d(0, 1.6, -4)).norm(), 1e-12);
  EXPECT_LT((pos(3) - Eigen::Vector3d(2, 1.6, -4)).norm(), 1e-12);
  EXPECT_LT((pos(5) - Eigen::Vector3d(4, 1.6, -4)).norm(), 1e-12);  // stops at the end
  const Eigen::Vector3d fwd = f.frames[3].rig_from_world->Inverse().rotation * Eigen::Vector3d::UnitZ();
  EXPECT_LT((fwd - Eigen::Vector3d::UnitX()).norm(), 1e-12);  // heading 90 along the second segment
}

}  // namespace
}  // namespace rigsim
