#include "calibrator/estimators/camera_trajectory.h"

#include <gtest/gtest.h>

#include "calibrator/calibrator_test_support.h"
#include "calibrator/estimators/rig_turns.h"
#include "testing/synthetic_rig.h"

namespace rigsim {
namespace {

SyntheticObservationOptions WithTemporalPairs() {
  SyntheticObservationOptions o;
  o.temporal_pairs = true;
  return o;
}

// A ring whose cameras see points of their own only, on a turning path: each camera's trajectory
// from its own matches, against the truth up to its unit of length; then the hand-eye mountings
// from those trajectories.
SyntheticRig IsolatedRing(int frames, double turn_deg, double turn_variation) {
  SyntheticRigOptions o;
  o.cameras.assign(4, Camera::PinholeFromHorizontalFov(640, 360, 90.0));
  o.ring_radius_m = 0.4;
  o.max_tilt_deg = 5.0;
  o.max_offset_m = 0.1;
  o.isolated_cameras = {0, 1, 2, 3};
  o.num_frames = frames;
  o.path = TurningPath(frames, 1.0, turn_deg, turn_variation, 0.0, 0.0);
  o.num_points = 600;
  o.seed = TestSeed();
  return SynthesizeRig(o);
}

TEST(CameraTrajectory, FollowsTheTrueMotionUpToScale) {
  SyntheticRig s = IsolatedRing(6, 8.0, 0.0);
  const RigObservations obs = ObserveSyntheticRig(s, WithTemporalPairs());
  const RigTurns turns = ResolveStepsByTheRig(obs.temporal, std::vector<std::optional<Eigen::Quaterniond>>(4), 6, {});
  for (int c = 0; c < 4; ++c) {
    SCOPED_TRACE(c);
    const CameraTrajectory t =
        EstimateCameraTrajectory(obs.cameras[c], c, obs.keypoints, obs.temporal, turns.step_rotation[c], {});
    ASSERT_EQ(t.size(), 6u);
    const Rigid3d first = s.CamFromWorld({0, c});
    double scale = 0.0;
    for (int k = 1; k < 6; ++k) {
      ASSERT_TRUE(t[k]);
      const Rigid3d truth = s.CamFromWorld({k, c}) * first.Inverse();
      EXPECT_LT(RotationDifferenceDeg(t[k]->rotation, truth.rotation), 0.2);
      if (k == 1) scale = t[k]->SourceOriginInTarget().norm() / truth.SourceOriginInTarget().norm();
      EXPECT_LT(AngleBetweenDeg(t[k]->SourceOriginInTarget(), truth.SourceOriginInTarget()), 1.0);
      EXPECT_NEAR(t[k]->SourceOriginInTarget().norm(), scale * truth.SourceOriginInTarget().norm(),
                  0.03 * scale * truth.SourceOriginInTarget().norm());
    }
  }
}

TEST(CameraTrajectory, HandEyeFromOwnMotionsPlacesCamerasThatShareNothing) {
  SyntheticRig s = IsolatedRing(10, 10.0, 2.0);
  const RigObservations obs = ObserveSyntheticRig(s, WithTemporalPairs());
  const RigTurns turns = ResolveStepsByTheRig(obs.temporal, std::vector<std::optional<Eigen::Quaterniond>>(4), 10, {});
  std::vector<CameraTrajectory> trajectories;
  for (int c = 0; c < 4; ++c) {
    trajectories.push_back(
        EstimateCameraTrajectory(obs.cameras[c], c, obs.keypoints, obs.temporal, turns.step_rotation[c], {}));
  }
  const HandEyeResult r = SolveHandEye(trajectories, {});
  ASSERT_EQ(r.motion.kind, MotionKind::kPlanar);
  for (int c = 1; c < 4; ++c) {
    SCOPED_TRACE(c);
    const HandEyeCamera& h = r.cameras[c];
    ASSERT_EQ(h.status, HandEyeStatus::kSolved) << h.reason;
    EXPECT_LT(RotationDifferenceDeg(h.cam_from_rig->rotation, s.rig.cameras[c].cam_from_rig->rotation), 0.5);
    ASSERT_TRUE(h.undetermined_axis);
  }
  // The motion leaves no ring camera undecided except along the turn axis: with that axis left
  // out, the centres point the right way from camera 0.
  const Eigen::Vector3d axis = r.motion.axis;
  for (int c = 1; c < 4; ++c) {
    const Eigen::Vector3d est = r.cameras[c].cam_from_rig->SourceOriginInTarget();
    Eigen::Vector3d truth = s.rig.cameras[c].cam_from_rig->SourceOriginInTarget();
    truth -= axis * axis.dot(truth);
    EXPECT_LT(AngleBetweenDeg(est, truth), 5.0) << c;
  }
}

}  // namespace
}  // namespace rigsim
