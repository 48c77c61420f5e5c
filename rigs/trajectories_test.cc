#include "rigs/trajectories.h"

#include <cmath>
#include <numbers>

#include <Eigen/Core>
#include <Eigen/SVD>
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

namespace rigsim {
namespace {

Eigen::Vector3d Centre(const Frame& f) { return f.rig_from_world->SourceOriginInTarget(); }
Eigen::Vector3d Forward(const Rigid3d& rig_from_world) {
  return rig_from_world.Inverse().rotation * Eigen::Vector3d::UnitZ();
}
// The signed turn from heading a to heading b about world up (deg; > 0 left).
double TurnDeg(const Eigen::Vector3d& a, const Eigen::Vector3d& b) {
  return RadToDeg(std::atan2(a.cross(b).y(), a.dot(b)));
}

// Singular values of the frame-to-frame rotation vectors (each rig_k+1 from rig_k, in the rig's
// frame), largest first: how many independent axes the rig turns about.
Eigen::Vector3d RotationAxisSpread(const FramesFile& frames) {
  Eigen::Matrix3Xd vectors(3, frames.frames.size() - 1);
  for (size_t k = 0; k + 1 < frames.frames.size(); ++k) {
    const Eigen::Quaterniond next_from_this =
        frames.frames[k + 1].rig_from_world->rotation * frames.frames[k].rig_from_world->rotation.conjugate();
    const Eigen::AngleAxisd aa(next_from_this);
    vectors.col(k) = aa.angle() * aa.axis();
  }
  return Eigen::JacobiSVD<Eigen::Matrix3Xd>(vectors).singularValues();
}

// At a steady speed and turn rate a time offset between cameras looks like a mounting: the demo's
// path changes speed so that its first calibration can check that the cameras capture together.
TEST(Trajectory, TheDemoPathSlowsIntoItsTurn) {
  const FramesFile frames = MakeDemoTrajectory(4);
  ASSERT_EQ(frames.frames.size(), 4u);
  EXPECT_EQ(frames.frames[0].timestamp_s, 0.0);
  std::vector<double> speeds;
  for (size_t k = 1; k < frames.frames.size(); ++k) {
    const double metres = (frames.frames[k].rig_from_world->SourceOriginInTarget() -
                           frames.frames[k - 1].rig_from_world->SourceOriginInTarget())
                              .norm();
    speeds.push_back(metres / (frames.frames[k].timestamp_s - frames.frames[k - 1].timestamp_s));
  }
  EXPECT_NEAR(speeds[0], 10.0, 0.05);  // 2 m chords of a 12 m circle in 0.2 s
  for (size_t k = 1; k < speeds.size(); ++k) EXPECT_LT(speeds[k], 0.9 * speeds[k - 1]) << k;
}

TEST(Trajectory, NewPathsHaveOneNameEach) {
  for (TrajectoryKind k : kNamedTrajectoryKinds) EXPECT_EQ(TrajectoryKindFromName(TrajectoryKindName(k)), k);
  EXPECT_EQ(TrajectoryKindFromName("figure-eight"), TrajectoryKind::kFigureEight);
  EXPECT_THROW(TrajectoryKindFromName("figure8"), std::invalid_argument);
}

TEST(Trajectory, TheLoopEndsWhereItStarted) {
  TrajectoryOptions o;
  o.kind = TrajectoryKind::kLoop;
  o.circle_radius_m = 6.0;
  o.num_frames = 12;
  o.start_world = Eigen::Vector3d(3, 1.6, -2);
  o.heading_deg = 40.0;
  const FramesFile f = MakeTrajectory(o);
  ASSERT_EQ(f.frames.size(), 12u);
  // The frames spread evenly over one lap: the move after the last frame, back to the start,
  // is as long as every other, and the path's end is its start, facing the same way.
  const double length = ClosedPathLength(o);
  EXPECT_NEAR(length, 2 * std::numbers::pi * 6.0, 1e-12);
  EXPECT_NEAR(PathStep(o), length / 12, 1e-12);
  const Rigid3d end = RigFromWorldAlongPath(o, length);
  EXPECT_LT((end.SourceOriginInTarget() - o.start_world).norm(), 1e-9);
  EXPECT_LT(RotationDifferenceDeg(end.rotation, f.frames[0].rig_from_world->rotation), 1e-9);
  const double chord = (Centre(f.frames[1]) - Centre(f.frames[0])).norm();
  EXPECT_NEAR((end.SourceOriginInTarget() - Centre(f.frames[11])).norm(), chord, 1e-9);
  // It turns left (radius > 0) by a twelfth of a lap per frame, and stays on its circle.
  EXPECT_NEAR(TurnDeg(Forward(*f.frames[0].rig_from_world), Forward(*f.frames[1].rig_from_world)), 30.0, 1e-9);
  const Eigen::Vector3d centre = o.start_world + 6.0 * HeadingDirection(o.heading_deg - 90.0);
  for (const Frame& fr : f.frames) EXPECT_NEAR((Centre(fr) - centre).norm(), 6.0, 1e-9);
  // Continuous: a small distance moves the rig a little, anywhere on the lap.
  for (double s = 0; s < length; s += 0.37) {
    EXPECT_LT((RigFromWorldAlongPath(o, s + 1e-6).SourceOriginInTarget() - RigFromWorldAlongPath(o, s).SourceOriginInTarget()).norm(),
              2e-6);
  }
}

TEST(Trajectory, TheFigureEightTurnsLeftThenRight) {
  TrajectoryOptions o;
  o.kind = TrajectoryKind::kFigureEight;
  o.circle_radius_m = 5.0;
  o.num_frames = 16;
  o.start_world = Eigen::Vector3d(0, 1.6, 0);
  const FramesFile f = MakeTrajectory(o);
  const double lap = 2 * std::numbers::pi * 5.0;
  EXPECT_NEAR(ClosedPathLength(o), 2 * lap, 1e-12);
  // Frames 0-7 go round the circle on the left (heading 0 = -Z: left is -X), turning left; frames
  // 8-15 round the one on the right, turning right; both laps pass through the start.
  const Eigen::Vector3d left_centre(-5, 1.6, 0), right_centre(5, 1.6, 0);
  for (int k = 0; k < 16; ++k) {
    const Eigen::Vector3d c = Centre(f.frames[k]);
    const Eigen::Vector3d turn_centre = k < 8 ? left_centre : right_centre;
    EXPECT_NEAR((c - turn_centre).norm(), 5.0, 1e-9) << k;
    const double turn = TurnDeg(Forward(*f.frames[k].rig_from_world), Forward(*f.frames[(k + 1) % 16].rig_from_world));
    EXPECT_NEAR(turn, k < 8 ? 45.0 : -45.0, 1e-9) << k;
  }
  EXPECT_LT((Centre(f.frames[8]) - o.start_world).norm(), 1e-9);
  EXPECT_LT((RigFromWorldAlongPath(o, 2 * lap).SourceOriginInTarget() - o.start_world).norm(), 1e-9);
  // Continuous where the laps meet.
  EXPECT_LT(RotationDifferenceDeg(RigFromWorldAlongPath(o, lap - 1e-7).rotation, RigFromWorldAlongPath(o, lap).rotation),
            1e-5);
  // Still planar: every turn is about world up.
  const Eigen::Vector3d spread = RotationAxisSpread(f);
  EXPECT_LT(spread(1), 1e-9 * spread(0));
}

TEST(Trajectory, TheHandheldPathTurnsAboutThreeAxesAndStartsUpright) {
  TrajectoryOptions o;
  o.kind = TrajectoryKind::kHandheld;
  o.circle_radius_m = 12.0;
  o.step_m = 2.0;
  o.tilt_deg = 10.0;
  o.start_world = Eigen::Vector3d(1, 1.6, 2);
  // Frame 0 stands upright where the placement put it; then the rig pitches and rolls as the
  // header says: pitch > 0 raises the view, roll > 0 dips the right side.
  const Rigid3d upright = RigFromWorldAt(o.start_world, 0.0);
  EXPECT_LT(RotationDifferenceDeg(RigFromWorldAlongPath(o, 0).rotation, upright.rotation), 1e-12);
  const double quarter_pitch = kHandheldPitchWavelengthM / 4;  // pitch at its peak
  const Rigid3d pitched = RigFromWorldAlongPath(o, quarter_pitch);
  EXPECT_GT(Forward(pitched).y(), 0.0);  // looks up
  const Rigid3d rolled = RigFromWorldAlongPath(o, kHandheldRollWavelengthM / 4);
  EXPECT_LT((rolled.Inverse().rotation * Eigen::Vector3d::UnitX()).y(), 0.0);  // the right side below
  // The centre follows the circle: the tilt turns the rig about itself.
  o.kind = TrajectoryKind::kCircle;
  EXPECT_LT((pitched.SourceOriginInTarget() - RigFromWorldAlongPath(o, quarter_pitch).SourceOriginInTarget()).norm(), 1e-12);
  const Eigen::Vector3d planar = RotationAxisSpread([&] {
    o.num_frames = 12;
    return MakeTrajectory(o);
  }());
  EXPECT_LT(planar(1), 1e-9 * planar(0));
  // The frame-to-frame rotations spread over all three axes, even over three frames (two motions,
  // not parallel), so hand-eye fixes every camera's offset.
  o.kind = TrajectoryKind::kHandheld;
  for (int frames : {3, 12, 30}) {
    o.num_frames = frames;
    const Eigen::Vector3d spread = RotationAxisSpread(MakeTrajectory(o));
    EXPECT_GT(spread(1), 0.3 * spread(0)) << frames << " frames";
    if (frames > 3) {
      EXPECT_GT(spread(2), 0.2 * spread(0)) << frames << " frames";
    }
  }
}

}  // namespace
}  // namespace rigsim
