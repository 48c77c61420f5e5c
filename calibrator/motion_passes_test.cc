#include "calibrator/motion_passes.h"

#include <algorithm>
#include <optional>
#include <stdexcept>
#include <vector>

#include <gtest/gtest.h>

#include "calibrator/calibrator_test_support.h"
#include "calibrator/estimators/cross_time_candidates.h"
#include "calibrator/rig_intrinsics.h"
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

struct Calibrated {
  RigCalibrationResult result;
  std::vector<CameraErrors> errors;
};

RigObservations ObserveMoving(SyntheticRig& s) {
  SyntheticObservationOptions observe;
  observe.temporal_pairs = true;
  return ObserveSyntheticRig(s, observe);
}

RigCalibrationOptions TwoThreads() {
  RigCalibrationOptions options;
  options.pairwise.num_threads = 2;
  return options;
}

Calibrated CalibrateFromMotion(SyntheticRig& s) {
  Calibrated out;
  out.result = EstimateRigWithMotionLinks(ObserveMoving(s), SyntheticMatcher(s), TwoThreads());
  out.errors = ErrorsAgainst(s.rig, out.result);
  return out;
}

TEST(MotionLinks, WithoutTheMotionOnlyTheReferenceIsPlaced) {
  SyntheticRig s = SynthesizeRig(LowOverlapRing(TurningPath(16, 1.0, 8.0, 0.3, 15.0, 5.0), false));
  const RigCalibrationResult r = EstimateRig(ObserveMoving(s), RigCalibrationOptions{});
  EXPECT_EQ(r.camera_status[0].outcome, CameraOutcome::kCalibrated);
  for (int c = 1; c < 4; ++c) EXPECT_EQ(r.camera_status[c].outcome, CameraOutcome::kNotConnected) << c;
}

TEST(MotionLinks, OverlappingRingRunsOnePassWithoutTheMotionStage) {
  SyntheticRigOptions o = LowOverlapRing(TurningPath(8, 1.0, 8.0, 0.3, 15.0, 5.0), false);
  o.yaw_step_deg = 30;  // neighbours share half their views
  SyntheticRig s = SynthesizeRig(o);
  const RigCalibrationResult r = EstimateRigWithMotionLinks(ObserveMoving(s), SyntheticMatcher(s), TwoThreads());
  EXPECT_FALSE(r.motion_links.has_value());  // no round stopped, and the result places every camera
  EXPECT_EQ(r.work.rig_passes, 1);
  for (int cam = 0; cam < 4; ++cam) {
    EXPECT_EQ(r.camera_status[cam].outcome, CameraOutcome::kCalibrated) << r.camera_status[cam];
  }
}

TEST(MotionLinks, LinksThatPlaceEveryCameraMakeTheOnlyFullPass) {
  // The early stages already show cameras 1-3 without a rotation: the pass with the motion links
  // runs first and, as it places every camera, the pass without them never runs.
  SyntheticRig s = SynthesizeRig(LowOverlapRing(TurningPath(16, 1.0, 8.0, 0.3, 15.0, 5.0), false));
  const RigObservations obs = ObserveMoving(s);
  RigPreCheck stop;
  EXPECT_FALSE(EstimateRigUnlessUnplaced(obs, TwoThreads(), &stop).has_value());
  EXPECT_EQ(stop.round, 0);
  EXPECT_EQ(stop.work.bundle_adjustment_time_s, 0.0);  // stopped before any bundle adjustment
  EXPECT_TRUE(stop.may_be_placed[0]);
  for (int cam = 1; cam < 4; ++cam) {
    EXPECT_FALSE(stop.may_be_placed[cam]) << cam;
    EXPECT_FALSE(stop.cam_from_rig_rotation[cam].has_value()) << cam;
  }
  const RigCalibrationResult r = EstimateRigWithMotionLinks(obs, SyntheticMatcher(s), TwoThreads());
  ASSERT_TRUE(r.motion_links.has_value());
  EXPECT_TRUE(r.motion_links->kept);
  EXPECT_EQ(r.work.rig_passes, 1);
  for (int cam = 0; cam < 4; ++cam) EXPECT_EQ(r.camera_status[cam].outcome, CameraOutcome::kCalibrated) << cam;
}

TEST(MotionLinks, ACameraThatOnlyAPairTheRigRejectsReachesIsPlacedByTheLinksInOnePass) {
  // cam0-cam2 overlap at the same instant; cam3 sees points of its own, and a wrong pair (its
  // rotation 10 deg off) joins it with cam2. The first round places cam3 by that pair; the rig
  // rejects the pair, and the next round stops before its bundle adjustment: cam3 has no rotation.
  // The links (hand-eye on a path that turns and pitches) place it, in one full pass.
  const std::vector<Rigid3d> path = TurningPath(16, 1.0, 8.0, 0.3, 15.0, 5.0);
  SyntheticRigOptions o = LowOverlapRing(path, false);
  o.yaw_step_deg = 30;
  o.isolated_cameras = {3};
  o.num_points = 1500;
  SyntheticRig s = SynthesizeRig(o);
  RigObservations obs = ObserveMoving(s);
  const auto wrong = std::find_if(obs.pairs.begin(), obs.pairs.end(),
                                  [](const PairEstimate& p) { return p.cam_a == 2 && p.cam_b == 3; });
  ASSERT_NE(wrong, obs.pairs.end());
  const Rigid3d truth = *s.rig.cameras[3].cam_from_rig * s.rig.cameras[2].cam_from_rig->Inverse();
  wrong->two_view.success = true;
  wrong->two_view.num_matches = 400;
  wrong->two_view.num_inliers = 300;
  wrong->two_view.cam_b_from_cam_a.rotation =
      Eigen::Quaterniond(Eigen::AngleAxisd(DegToRad(10.0), Eigen::Vector3d::UnitY())) * truth.rotation;
  wrong->two_view.cam_b_from_cam_a.translation = truth.translation.normalized();

  RigPreCheck stop;
  EXPECT_FALSE(EstimateRigUnlessUnplaced(obs, TwoThreads(), &stop).has_value());
  EXPECT_EQ(stop.round, 1);
  EXPECT_GT(stop.work.bundle_adjustment_time_s, 0.0);  // the first round's
  EXPECT_FALSE(stop.may_be_placed[3]);
  EXPECT_FALSE(stop.cam_from_rig_rotation[3].has_value());
  // The full pass resumed where the check stopped is the full pass run from the start, to the bit.
  const RigCalibrationResult resumed = EstimateRigFrom(obs, TwoThreads(), stop);
  const RigCalibrationResult whole = EstimateRig(obs, TwoThreads());
  EXPECT_EQ(resumed.work.rig_passes, 1);
  ASSERT_EQ(resumed.edges.size(), whole.edges.size());
  for (size_t e = 0; e < whole.edges.size(); ++e) EXPECT_EQ(resumed.edges[e].status, whole.edges[e].status) << e;
  for (int cam = 0; cam < 4; ++cam) {
    EXPECT_EQ(resumed.camera_status[cam].Text(), whole.camera_status[cam].Text()) << cam;
    const auto& a = resumed.rig.cameras[cam].cam_from_rig;
    const auto& b = whole.rig.cameras[cam].cam_from_rig;
    ASSERT_EQ(a.has_value(), b.has_value()) << cam;
    if (!a) continue;
    EXPECT_EQ(a->rotation.coeffs(), b->rotation.coeffs()) << cam;
    EXPECT_EQ(a->translation, b->translation) << cam;
  }
  const RigCalibrationResult r = EstimateRigWithMotionLinks(obs, SyntheticMatcher(s), TwoThreads());
  ASSERT_TRUE(r.motion_links.has_value());
  EXPECT_TRUE(r.motion_links->kept);
  EXPECT_EQ(r.work.rig_passes, 1);
  const std::vector<CameraErrors> errors = ErrorsAgainst(s.rig, r);
  for (int cam = 1; cam < 4; ++cam) {
    SCOPED_TRACE(cam);
    ASSERT_EQ(r.camera_status[cam].outcome, CameraOutcome::kCalibrated) << r.camera_status[cam];
    EXPECT_LT(errors[cam].rotation_error_deg.value_or(180), 1.0);
    EXPECT_LT(errors[cam].direction_error_deg.value_or(180), 5.0);
  }
}

TEST(MotionLinks, PassWithoutTheLinksIsKeptWhenTheLinksPlaceNoMoreCameras) {
  // Hand-eye solves every camera of a ring without overlap, but a camera keeps the rotation the
  // links give it only where two things agree on it: with hand-eye held to no disagreement at all,
  // the pass with the links places camera 0 alone, as the pass without them does, which then runs
  // and is the result.
  SyntheticRig s = SynthesizeRig(LowOverlapRing(TurningPath(16, 1.0, 8.0, 0.3, 15.0, 5.0), true));
  const RigObservations obs = ObserveMoving(s);
  RigCalibrationOptions options = TwoThreads();
  options.motion.max_hand_eye_disagreement_deg = 1e-12;
  const RigCalibrationResult without = EstimateRig(obs, options);
  const RigCalibrationResult r = EstimateRigWithMotionLinks(obs, SyntheticMatcher(s), options);
  ASSERT_TRUE(r.motion_links.has_value());
  EXPECT_FALSE(r.motion_links->kept);
  EXPECT_EQ(r.work.rig_passes, 2);  // with the links, then without
  for (int cam = 0; cam < 4; ++cam) {
    SCOPED_TRACE(cam);
    EXPECT_EQ(r.camera_status[cam].outcome, without.camera_status[cam].outcome);
    EXPECT_EQ(r.cam_from_rig_rotation[cam].has_value(), without.cam_from_rig_rotation[cam].has_value());
  }
  for (int cam = 1; cam < 4; ++cam) EXPECT_EQ(r.camera_status[cam].outcome, CameraOutcome::kNotConnected) << cam;
  EXPECT_EQ(r.reprojection_rms_px, without.reprojection_rms_px);
  EXPECT_EQ(r.num_observations, without.num_observations);
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

// With refined intrinsics the rig stage runs twice (rig_intrinsics.h); the controller runs both
// passes with the motion stage's links, so a ring that only its motion links is placed then too.
TEST(MotionLinks, IntrinsicsRefinementRunsBothOfItsPassesWithTheLinks) {
  SyntheticRig s = SynthesizeRig(LowOverlapRing(TurningPath(16, 1.0, 8.0, 0.3, 15.0, 5.0), false));
  const RigObservations obs = ObserveMoving(s);
  RigCalibrationOptions options = TwoThreads();
  options.bundle_adjustment.refine_intrinsics = true;
  const ViewPairMatcher match = SyntheticMatcher(s);
  const RigCalibrationResult alone = EstimateRigAndIntrinsics(obs, options);
  const RigCalibrationResult linked = EstimateRigAndIntrinsics(
      obs, options, [&match](const RigObservations& o, const RigCalibrationOptions& opt) {
        return EstimateRigWithMotionLinks(o, match, opt);
      });
  EXPECT_FALSE(HasFullPose(alone.camera_status[1].outcome)) << alone.camera_status[1];
  ASSERT_TRUE(linked.motion_links.has_value());
  EXPECT_TRUE(linked.motion_links->kept);
  const std::vector<CameraErrors> errors = ErrorsAgainst(s.rig, linked);
  for (int cam = 0; cam < 4; ++cam) {
    SCOPED_TRACE(cam);
    ASSERT_EQ(linked.camera_status[cam].outcome, CameraOutcome::kCalibrated) << linked.camera_status[cam];
    EXPECT_TRUE(linked.camera_stats[cam].intrinsics.has_value());
    ASSERT_TRUE(errors[cam].rotation_error_deg);
    EXPECT_LT(*errors[cam].rotation_error_deg, 1.0);
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
    if (t.camera == 2 && t.frame == 3) {
      EXPECT_LT(RotationDifferenceDeg(t.two_view.cam_b_from_cam_a.rotation, truth), 0.01);
    }
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

// A ring without same-instant overlap on a path that turns and pitches, its motion links with every
// predicted view pair counted as fresh, and the rig the links make: what CheckPredictedViews checks.
struct LinkedRing {
  SyntheticRig s = SynthesizeRig(LowOverlapRing(TurningPath(16, 1.0, 8.0, 0.3, 15.0, 5.0), false));
  RigObservations obs = ObserveMoving(s);
  RigCalibrationOptions options = TwoThreads();
  MotionLinks links;
  RigCalibrationResult rig;

  LinkedRing() {
    std::vector<std::optional<Eigen::Quaterniond>> known(4);
    known[0] = Eigen::Quaterniond::Identity();
    links = FindMotionLinks(obs, known, SyntheticMatcher(s), options);
    links.matched.clear();
    rig = EstimateRigWithMotionLinks(obs, SyntheticMatcher(s), options);
  }
  LinkedRing(const LinkedRing&) = delete;  // the matcher refers to `s`
  PredictionCheck Check(const RigCalibrationResult& r) const {
    return CheckPredictedViews(obs, links, r, SyntheticMatcher(s), options);
  }
};

// The views a rig predicts to meet show whether it is right: the calibrated ring's predictions agree
// with views matched afresh; the same rig with one camera turned 15 deg about the vertical (what
// consistent wrong matches of repeated structure can make where the motion leaves a turn open)
// predicts views that contradict it.
TEST(MotionLinks, ViewsAWrongRigPredictsContradictIt) {
  const LinkedRing ring;
  RigCalibrationResult r = ring.rig;
  ASSERT_TRUE(r.cam_from_rig_rotation[1]);
  const PredictionCheck right = ring.Check(r);
  EXPECT_GT(right.agreeing, 3);
  EXPECT_EQ(right.contradicting, 0);
  r.cam_from_rig_rotation[1] = Eigen::Quaterniond(Eigen::AngleAxisd(DegToRad(15.0), Eigen::Vector3d::UnitY())) *
                               *r.cam_from_rig_rotation[1];
  const PredictionCheck wrong = ring.Check(r);
  EXPECT_GT(wrong.camera_contradicting[1], wrong.camera_agreeing[1]);
  EXPECT_TRUE(wrong.AnyCameraContradicted());
  EXPECT_FALSE(right.AnyCameraContradicted());
}

// A camera's pairs with itself predict the same rotation whatever its turn about a planar motion's
// axis: they measure its own matching, not the rig, and the check leaves them out.
TEST(MotionLinks, TheCheckCountsOnlyPairsOfTwoCameras) {
  const LinkedRing ring;
  const RigCalibrationResult& r = ring.rig;
  ASSERT_TRUE(r.cam_from_rig_rotation[1]);

  CrossTimeCandidateInputs inputs;
  inputs.cameras = ring.obs.cameras;
  inputs.cam_from_rig = r.cam_from_rig_rotation;
  for (const auto& pose : r.rig_from_world) inputs.rig_from_world.push_back(pose ? std::optional(pose->rotation) : std::nullopt);
  int own = 0, between = 0;
  for (const CrossTimeCandidate& c : SelectCrossTimeCandidates(inputs, ring.options.motion.candidates)) {
    if (!ring.links.placed_by_motion[c.cam_a] && !ring.links.placed_by_motion[c.cam_b]) continue;
    (c.cam_a == c.cam_b ? own : between) += 1;
  }
  ASSERT_GT(own, 0) << "the rig predicts pairs of a camera with itself";
  const PredictionCheck check = ring.Check(r);
  EXPECT_GT(check.agreeing, 0);
  EXPECT_LE(check.agreeing + check.contradicting, between);
}

TEST(MotionLinks, TurningAtAConstantRateWithoutSharedPointsPlacesNoCameraByGuess) {
  // A circle: each camera's own motion trades its turn about the axis against its centre, and no
  // point joins it with another camera, so nothing decides its rotation.
  SyntheticRig s = SynthesizeRig(LowOverlapRing(TurningPath(16, 1.0, 12.0, 0.0, 0.0, 0.0), true));
  const Calibrated c = CalibrateFromMotion(s);
  ASSERT_TRUE(c.result.motion_links.has_value());  // it ran, and its result was not kept
  EXPECT_FALSE(c.result.motion_links->kept);
  EXPECT_EQ(c.result.work.rig_passes, 1);  // it found nothing to link: no pass with the links
  for (int cam = 1; cam < 4; ++cam) {
    EXPECT_EQ(c.result.camera_status[cam].outcome, CameraOutcome::kNotConnected) << cam;
    EXPECT_FALSE(c.result.cam_from_rig_rotation[cam].has_value()) << cam;
  }
}

}  // namespace
}  // namespace rigsim
