#include "calibrator/motion_links.h"

#include <gtest/gtest.h>

#include "calibrator/calibrator_test_support.h"
#include "testing/synthetic_rig.h"

namespace rigsim {
namespace {

// Four pinhole cameras of 60 deg horizontal field of view every 90 deg round a ring: no two see the
// same thing at the same instant; as the rig turns, one sees what another saw frames before.
SyntheticRigOptions LowOverlapRing(const std::vector<Rigid3d>& path, bool isolated) {
  const Camera pinhole(CameraModelId::kPinhole, 640, 360, {554, 554, 319.5, 179.5});
  SyntheticRigOptions o;
  o.cameras = {pinhole, pinhole, pinhole, pinhole};
  o.yaw_step_deg = 90;
  o.max_tilt_deg = 3;
  o.max_offset_m = 0.05;
  if (isolated) o.isolated_cameras = {0, 1, 2, 3};
  o.num_frames = static_cast<int>(path.size());
  o.path = path;
  o.num_points = 3000;
  o.min_distance_m = 4;
  o.max_distance_m = 20;
  o.seed = TestSeed();
  return o;
}

// What a matcher finds between two views: the true correspondences and a twentieth as many wrong
// ones, drawn from the view pair alone (the matcher runs on several threads at once).
ViewPairMatcher SyntheticMatcher(const SyntheticRig& s) {
  return [&s](int cam_a, int frame_a, int cam_b, int frame_b) {
    std::vector<std::pair<int, int>> m = s.TrueMatches({frame_a, cam_a}, {frame_b, cam_b});
    const int na = static_cast<int>(s.keypoints[frame_a][cam_a].size());
    const int nb = static_cast<int>(s.keypoints[frame_b][cam_b].size());
    const int wrong = static_cast<int>(m.size()) / 20 + 6;
    for (int i = 0; i < wrong && na > 0 && nb > 0; ++i) {
      m.push_back({(i * 7919 + 31 * frame_a + cam_a) % na, (i * 104729 + 17 * frame_b + cam_b) % nb});
    }
    return m;
  };
}

struct Calibrated {
  RigCalibrationResult result;
  std::vector<CameraErrors> errors;
};

Calibrated CalibrateFromMotion(SyntheticRig& s) {
  SyntheticObservationOptions observe;
  observe.temporal_pairs = true;
  const RigObservations obs = ObserveSyntheticRig(s, observe);
  RigCalibrationOptions options;
  options.pairwise.num_threads = 2;
  Calibrated out;
  out.result = EstimateRigWithMotionLinks(obs, SyntheticMatcher(s), options);
  out.errors = ErrorsAgainst(s.rig, out.result);
  return out;
}

TEST(MotionLinks, WithoutTheMotionOnlyTheReferenceIsPlaced) {
  SyntheticRig s = SynthesizeRig(LowOverlapRing(TurningPath(16, 1.0, 8.0, 0.3, 15.0, 5.0), false));
  SyntheticObservationOptions observe;
  observe.temporal_pairs = true;
  const RigCalibrationResult r = EstimateRig(ObserveSyntheticRig(s, observe), RigCalibrationOptions{});
  EXPECT_EQ(r.camera_status[0].outcome, CameraOutcome::kCalibrated);
  for (int c = 1; c < 4; ++c) EXPECT_EQ(r.camera_status[c].outcome, CameraOutcome::kNotConnected) << c;
}

TEST(MotionLinks, RingWithoutSameInstantOverlapIsCalibratedOnAPathThatTurnsAndPitches) {
  SyntheticRig s = SynthesizeRig(LowOverlapRing(TurningPath(16, 1.0, 8.0, 0.3, 15.0, 5.0), false));
  const Calibrated c = CalibrateFromMotion(s);
  ASSERT_TRUE(c.result.motion_links.has_value());
  EXPECT_TRUE(c.result.motion_links->kept);
  EXPECT_EQ(c.result.motion_links->motion, MotionKind::kGeneral);
  EXPECT_GT(c.result.num_cross_time_pairs_used, 0);
  for (int cam = 0; cam < 4; ++cam) {
    SCOPED_TRACE(cam);
    ASSERT_EQ(c.result.camera_status[cam].outcome, CameraOutcome::kCalibrated) << c.result.camera_status[cam];
    ASSERT_TRUE(c.errors[cam].rotation_error_deg);
    EXPECT_LT(*c.errors[cam].rotation_error_deg, 1.0);
    if (cam > 0) {
      ASSERT_TRUE(c.errors[cam].direction_error_deg);
      EXPECT_LT(*c.errors[cam].direction_error_deg, 5.0);
    }
  }
}

TEST(MotionLinks, StrictlyNonOverlappingRingIsCalibratedByHandEyeOnAPathThatTurnsAndPitches) {
  SyntheticRig s = SynthesizeRig(LowOverlapRing(TurningPath(16, 1.0, 8.0, 0.3, 15.0, 5.0), true));
  const Calibrated c = CalibrateFromMotion(s);
  ASSERT_TRUE(c.result.motion_links.has_value());
  EXPECT_TRUE(c.result.motion_links->kept);
  for (int cam = 1; cam < 4; ++cam) {
    SCOPED_TRACE(cam);
    ASSERT_EQ(c.result.camera_status[cam].outcome, CameraOutcome::kCalibrated) << c.result.camera_status[cam];
    EXPECT_LT(c.errors[cam].rotation_error_deg.value_or(180), 1.0);
    EXPECT_LT(c.errors[cam].direction_error_deg.value_or(180), 5.0);
  }
}

TEST(MotionLinks, RingWithoutSameInstantOverlapIsCalibratedOnAPlanarLoop) {
  // Points seen across time join the cameras: they fix the heights a planar motion alone leaves open.
  SyntheticRig s = SynthesizeRig(LowOverlapRing(TurningPath(16, 1.0, 12.0, 0.3, 0.0, 0.0), false));
  const Calibrated c = CalibrateFromMotion(s);
  ASSERT_TRUE(c.result.motion_links.has_value());
  EXPECT_TRUE(c.result.motion_links->kept);
  EXPECT_EQ(c.result.motion_links->motion, MotionKind::kPlanar);
  for (int cam = 1; cam < 4; ++cam) {
    SCOPED_TRACE(cam);
    ASSERT_EQ(c.result.camera_status[cam].outcome, CameraOutcome::kCalibrated) << c.result.camera_status[cam];
    EXPECT_LT(c.errors[cam].rotation_error_deg.value_or(180), 1.0);
    EXPECT_LT(c.errors[cam].direction_error_deg.value_or(180), 5.0);
  }
}

TEST(MotionLinks, PlanarMotionWithoutSharedPointsLeavesTheHeightOpen) {
  // Turns about one axis with a wobble too small to fix a height: hand-eye gives the rotations and
  // the centres across the axis; nothing gives the heights.
  SyntheticRig s = SynthesizeRig(LowOverlapRing(TurningPath(16, 1.0, 12.0, 0.3, 8.0, 5.0), true));
  const Calibrated c = CalibrateFromMotion(s);
  ASSERT_TRUE(c.result.motion_links.has_value());
  EXPECT_TRUE(c.result.motion_links->kept);
  EXPECT_EQ(c.result.motion_links->motion, MotionKind::kPlanar);
  const Eigen::Vector3d up = Eigen::Vector3d::UnitY();  // TurningPath turns about the rig's y axis
  for (int cam = 1; cam < 4; ++cam) {
    SCOPED_TRACE(cam);
    const CameraStatus& status = c.result.camera_status[cam];
    ASSERT_EQ(status.outcome, CameraOutcome::kOpenAlongAxis) << status;
    EXPECT_EQ(status.position, PositionOutcome::kOpenAlongTurnAxis);
    EXPECT_FALSE(c.result.rig.cameras[cam].cam_from_rig.has_value());  // no made-up height
    EXPECT_LT(c.errors[cam].rotation_error_deg.value_or(180), 1.0);
    ASSERT_TRUE(c.result.open_axis[cam] && c.result.partial_centre[cam]);
    EXPECT_GT(std::abs(c.result.open_axis[cam]->dot(up)), 0.99);
    EXPECT_NEAR(c.result.partial_centre[cam]->dot(*c.result.open_axis[cam]), 0.0, 1e-9);
    // The part the motion fixes: the centre's direction across the axis, against the truth's.
    const Eigen::Vector3d truth = s.rig.cameras[cam].cam_from_rig->SourceOriginInTarget();
    const Eigen::Vector3d axis = *c.result.open_axis[cam];
    EXPECT_LT(AngleBetweenDeg(*c.result.partial_centre[cam], truth - axis * axis.dot(truth)), 5.0);
    // As evaluation.json scores it (in camera 0's frame, evaluation/rig_scores.h).
    ASSERT_TRUE(c.errors[cam].across_axis_direction_error_deg.has_value());
    EXPECT_LT(*c.errors[cam].across_axis_direction_error_deg, 5.0);
    EXPECT_FALSE(c.errors[cam].direction_error_deg.has_value());
  }
}

TEST(MotionLinks, TurningAtAConstantRateWithoutSharedPointsPlacesNoCameraByGuess) {
  // A circle: each camera's own motion trades its turn about the axis against its centre, and no
  // point joins it with another camera, so nothing decides its rotation.
  SyntheticRig s = SynthesizeRig(LowOverlapRing(TurningPath(16, 1.0, 12.0, 0.0, 0.0, 0.0), true));
  const Calibrated c = CalibrateFromMotion(s);
  ASSERT_TRUE(c.result.motion_links.has_value());  // it ran, and its result was not kept
  EXPECT_FALSE(c.result.motion_links->kept);
  for (int cam = 1; cam < 4; ++cam) {
    EXPECT_EQ(c.result.camera_status[cam].outcome, CameraOutcome::kNotConnected) << cam;
    EXPECT_FALSE(c.result.cam_from_rig_rotation[cam].has_value()) << cam;
  }
}

}  // namespace
}  // namespace rigsim
