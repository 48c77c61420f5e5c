#include "rigs/trajectories.h"

#include <Eigen/Core>
#include <gtest/gtest.h>

#include "dataset/capture_poses.h"

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

namespace rigsim {
namespace {

TEST(RigTrajectory, IsEachFrameAtItsTimestampAndInterpolatesBetween) {
  TrajectoryOptions o;
  o.kind = TrajectoryKind::kCircle;
  o.circle_radius_m = 6.0;
  o.num_frames = 3;
  o.step_m = 1.0;
  o.frame_interval_s = 0.1;
  const FramesFile frames = MakeTrajectory(o);
  const RigTrajectory trajectory(frames);
  for (const Frame& f : frames.frames) {
    const Rigid3d at = trajectory.RigFromWorldAt(f.timestamp_s);
    EXPECT_EQ(at.rotation.coeffs(), f.rig_from_world->rotation.coeffs());
    EXPECT_EQ(at.translation, f.rig_from_world->translation);
  }
  // Half way between frames 0 and 1: the centre half way along the chord, the heading half way.
  const Eigen::Vector3d c0 = frames.frames[0].rig_from_world->SourceOriginInTarget();
  const Eigen::Vector3d c1 = frames.frames[1].rig_from_world->SourceOriginInTarget();
  const Rigid3d mid = trajectory.RigFromWorldAt(0.05);
  EXPECT_LT((mid.SourceOriginInTarget() - 0.5 * (c0 + c1)).norm(), 1e-12);
  const double turn_deg = RadToDeg(1.0 / 6.0);  // 1 m of arc on a 6 m circle
  EXPECT_NEAR(RotationDifferenceDeg(mid.rotation, frames.frames[0].rig_from_world->rotation), turn_deg / 2, 1e-9);
  EXPECT_NEAR(RotationDifferenceDeg(mid.rotation, frames.frames[1].rig_from_world->rotation), turn_deg / 2, 1e-9);
}

TEST(RigTrajectory, ExtrapolatesWithTheNearestSegmentsVelocity) {
  const FramesFile frames = MakeStraightTrajectory(Eigen::Vector3d(0, 1.6, 0), 0.0, 2, 2.0, 0.5);  // 4 m/s along -z
  const RigTrajectory trajectory(frames);
  EXPECT_LT((trajectory.RigFromWorldAt(-0.25).SourceOriginInTarget() - Eigen::Vector3d(0, 1.6, 1)).norm(), 1e-12);
  EXPECT_LT((trajectory.RigFromWorldAt(1.0).SourceOriginInTarget() - Eigen::Vector3d(0, 1.6, -4)).norm(), 1e-12);
  // Turning: the heading keeps turning at the same rate.
  TrajectoryOptions o;
  o.kind = TrajectoryKind::kCircle;
  o.num_frames = 2;
  o.frame_interval_s = 1.0;
  const FramesFile turn = MakeTrajectory(o);
  const Rigid3d after = RigTrajectory(turn).RigFromWorldAt(2.0);
  const Rigid3d twice_on_circle = [&] {
    o.num_frames = 3;
    return *MakeTrajectory(o).frames[2].rig_from_world;
  }();
  EXPECT_LT(RotationDifferenceDeg(after.rotation, twice_on_circle.rotation), 1e-9);
}

TEST(RigTrajectory, OneFrameStandsStillAndRepeatedTimestampsAreRefused) {
  const FramesFile one = MakeStraightTrajectory(Eigen::Vector3d(1, 2, 3), 30.0, 1, 2.0);
  EXPECT_LT((RigTrajectory(one).RigFromWorldAt(5.0).SourceOriginInTarget() - Eigen::Vector3d(1, 2, 3)).norm(), 1e-12);
  FramesFile repeated = MakeStraightTrajectory(Eigen::Vector3d(0, 1.6, 0), 0.0, 2, 2.0);
  repeated.frames[1].timestamp_s = repeated.frames[0].timestamp_s;
  EXPECT_THROW(RigTrajectory{repeated}, std::invalid_argument);
}

}  // namespace
}  // namespace rigsim
