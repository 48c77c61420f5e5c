#include "calibrator/motion_links.h"

#include <stdexcept>

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

TemporalPairEstimate& PairOf(RigObservations& obs, int camera, int frame) {
  for (TemporalPairEstimate& t : obs.temporal) {
    if (t.camera == camera && t.frame == frame) return t;
  }
  throw std::out_of_range("no such temporal pair");
}

// Two steps whose pose is wrong: camera 2's, a facade's essential matrix 8 deg off with the true pose
// as its planar alternative, and camera 1's, 7 deg off with no alternative. The rig takes the
// alternative of the one and leaves out the pose of the other, and calibrates every camera.
TEST(MotionLinks, StepsTheRigContradictsTakeTheirOtherPoseOrAreLeftOut) {
  SyntheticRig s = SynthesizeRig(LowOverlapRing(TurningPath(16, 1.0, 8.0, 0.3, 15.0, 5.0), false));
  SyntheticObservationOptions observe;
  observe.temporal_pairs = true;
  RigObservations obs = ObserveSyntheticRig(s, observe);
  const Eigen::Quaterniond off8(Eigen::AngleAxisd(DegToRad(8.0), Eigen::Vector3d(1.0, 0.3, 0.0).normalized()));
  const Eigen::Quaterniond off7(Eigen::AngleAxisd(DegToRad(7.0), Eigen::Vector3d(0.0, 0.2, 1.0).normalized()));
  TwoViewEstimate& planar = PairOf(obs, 2, 3).two_view;
  const Eigen::Quaterniond truth = planar.cam_b_from_cam_a.rotation;
  planar.pair_type = PairType::kPlanar;
  planar.planar_alternatives = {planar.cam_b_from_cam_a};
  planar.cam_b_from_cam_a.rotation = off8 * truth;
  PairOf(obs, 1, 5).two_view.cam_b_from_cam_a.rotation = off7 * PairOf(obs, 1, 5).two_view.cam_b_from_cam_a.rotation;

  RigCalibrationOptions options;
  options.pairwise.num_threads = 2;
  std::vector<std::optional<Eigen::Quaterniond>> known(4);
  known[0] = Eigen::Quaterniond::Identity();
  const MotionLinks links = FindMotionLinks(obs, known, SyntheticMatcher(s), options);
  EXPECT_EQ(links.temporal_alternatives_taken, 1);
  EXPECT_EQ(links.temporal_pairs_disagreeing, 1);
  for (const TemporalPairEstimate& t : links.temporal) {
    if (t.camera == 2 && t.frame == 3) EXPECT_LT(RotationDifferenceDeg(t.two_view.cam_b_from_cam_a.rotation, truth), 0.01);
    EXPECT_EQ(t.PoseUsable(), !(t.camera == 1 && t.frame == 5)) << t.camera << " " << t.frame;
  }

  const RigCalibrationResult r = EstimateRigWithMotionLinks(obs, SyntheticMatcher(s), options);
  ASSERT_TRUE(r.motion_links.has_value());
  EXPECT_TRUE(r.motion_links->kept);
  EXPECT_EQ(r.motion_links->temporal_alternatives_taken, 1);
  EXPECT_EQ(r.motion_links->temporal_pairs_disagreeing, 1);
  EXPECT_GT(r.motion_links->predicted_views_agreeing, 0);
  EXPECT_EQ(r.motion_links->predicted_views_contradicting, 0);
  const std::vector<CameraErrors> errors = ErrorsAgainst(s.rig, r);
  for (int cam = 1; cam < 4; ++cam) {
    ASSERT_EQ(r.camera_status[cam].outcome, CameraOutcome::kCalibrated) << r.camera_status[cam];
    EXPECT_LT(errors[cam].rotation_error_deg.value_or(180), 1.0) << cam;
  }
}

// The views a rig predicts to meet show whether it is right: the calibrated ring's predictions agree
// with views matched afresh; the same rig with one camera turned 15 deg about the vertical (what
// consistent wrong matches of repeated structure can make where the motion leaves a turn open)
// predicts views that contradict it.
TEST(MotionLinks, ViewsAWrongRigPredictsContradictIt) {
  SyntheticRig s = SynthesizeRig(LowOverlapRing(TurningPath(16, 1.0, 8.0, 0.3, 15.0, 5.0), false));
  SyntheticObservationOptions observe;
  observe.temporal_pairs = true;
  const RigObservations obs = ObserveSyntheticRig(s, observe);
  RigCalibrationOptions options;
  options.pairwise.num_threads = 2;
  std::vector<std::optional<Eigen::Quaterniond>> known(4);
  known[0] = Eigen::Quaterniond::Identity();
  MotionLinks links = FindMotionLinks(obs, known, SyntheticMatcher(s), options);
  links.matched.clear();  // every predicted view pair counts as fresh
  RigCalibrationResult r = EstimateRigWithMotionLinks(obs, SyntheticMatcher(s), options);
  ASSERT_TRUE(r.cam_from_rig_rotation[1]);
  const PredictionCheck right = CheckPredictedViews(obs, links, r, SyntheticMatcher(s), options);
  EXPECT_GT(right.agreeing, 3);
  EXPECT_EQ(right.contradicting, 0);
  r.cam_from_rig_rotation[1] = Eigen::Quaterniond(Eigen::AngleAxisd(DegToRad(15.0), Eigen::Vector3d::UnitY())) *
                               *r.cam_from_rig_rotation[1];
  const PredictionCheck wrong = CheckPredictedViews(obs, links, r, SyntheticMatcher(s), options);
  EXPECT_GT(wrong.camera_contradicting[1], wrong.camera_agreeing[1]);
  EXPECT_TRUE(wrong.AnyCameraContradicted(options.motion.min_prediction_contradictions));
  EXPECT_FALSE(right.AnyCameraContradicted(options.motion.min_prediction_contradictions));
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
