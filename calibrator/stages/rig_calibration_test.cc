#include "calibrator/stages/rig_calibration.h"

#include <cstdio>
#include <cstring>
#include <optional>
#include <utility>

#include <gmock/gmock.h>
#include <gtest/gtest.h>

#include "calibrator/calibrate_rig.h"
#include "calibrator/calibrator_test_support.h"
#include "calibrator/estimators/multi_frame_rig.h"
#include "calibrator/stages/rig_capture_times.h"
#include "testing/expect_error.h"
#include "testing/synthetic_rig.h"

namespace rigsim {
namespace {

// A ring of six cameras looking outwards every 60 deg (radius 0.3 m, a few degrees of tilt),
// PINHOLE / OPENCV at about 105 deg of field of view and OPENCV_FISHEYE at 200 deg, alternating
// so that every camera overlaps its neighbours and the fisheyes overlap each other (the pairwise
// directions then fix the ring's shape). Plus a seventh camera that sees a scene of its own: no
// overlap with anyone. The rig stands still; each frame sees new points around it, 2-12 m away.
SyntheticRigOptions RingOptions(uint32_t seed) {
  const Camera pinhole(CameraModelId::kPinhole, 640, 480, {230, 230, 319.5, 239.5});
  const Camera opencv(CameraModelId::kOpenCV, 640, 480, {240, 238, 322, 236, -0.05, 0.01, 0.001, -0.0005});
  const Camera fisheye(CameraModelId::kOpenCVFisheye, 640, 480, {180, 180, 318, 241, 0.02, -0.005, 0.001, 0.0});
  SyntheticRigOptions o;
  o.cameras = {pinhole, fisheye, opencv, fisheye, pinhole, fisheye, pinhole};
  o.yaw_step_deg = 60;
  o.max_tilt_deg = 5;
  o.max_offset_m = 0.03;
  o.isolated_cameras = {6};
  o.num_frames = 4;
  o.new_points_every_frame = true;
  o.num_points = 400;
  o.min_distance_m = 2;
  o.max_distance_m = 12;
  o.max_elevation_deg = 35;
  o.seed = seed;
  return o;
}

// The synthetic rig and its pairwise estimates are made once: the pairwise stage is the slow part.
// The index of the pair (cam_a, cam_b) in `obs.pairs`; -1 when there is none.
int PairIndex(const RigObservations& obs, int cam_a, int cam_b) {
  for (size_t p = 0; p < obs.pairs.size(); ++p) {
    if (obs.pairs[p].cam_a == cam_a && obs.pairs[p].cam_b == cam_b) return static_cast<int>(p);
  }
  return -1;
}

// Turns pair e's baseline direction by `deg` about an axis across it, its rotation kept (a share of
// wrong inliers does that).
void TurnDirection(RigObservations* obs, int e, double deg) {
  Eigen::Vector3d& t = obs->pairs[e].two_view.cam_b_from_cam_a.translation;
  t = Eigen::AngleAxisd(DegToRad(deg), t.unitOrthogonal()) * t;
}

class RigCalibrationTest : public ::testing::Test {
 protected:
  static void SetUpTestSuite() {
    synthetic_ = new SyntheticRig(SynthesizeRig(RingOptions(TestSeed())));
    observations_ = new RigObservations(ObserveSyntheticRig(*synthetic_));
  }
  static void TearDownTestSuite() {
    delete synthetic_;
    delete observations_;
  }
  static SyntheticRig* synthetic_;
  static RigObservations* observations_;
};
SyntheticRig* RigCalibrationTest::synthetic_ = nullptr;
RigObservations* RigCalibrationTest::observations_ = nullptr;

TEST_F(RigCalibrationTest, RingRigIsRecoveredAndTheBlindCameraIsNotConnected) {
  RigCalibrationResult r = EstimateRig(*observations_, {});
  const std::vector<CameraErrors> r_errors = ErrorsAgainst(synthetic_->rig, r);
  for (int c = 0; c < 6; ++c) {
    SCOPED_TRACE(r.rig.cameras[c].name + " (" + std::string(CameraModelName(r.rig.cameras[c].camera.model())) + ")");
    ASSERT_TRUE(r.rig.cameras[c].cam_from_rig.has_value()) << r.camera_status[c];
    EXPECT_EQ(r.camera_status[c].outcome, CameraOutcome::kCalibrated) << r.camera_status[c];
    EXPECT_LT(r_errors[c].rotation_error_deg.value(), 0.05);
    if (c > 0) {
      EXPECT_LT(r_errors[c].direction_error_deg.value(), 0.5);
    }
    EXPECT_GT(r.camera_stats[c].observations, 200);
    std::printf("%s %-14s rot %.4f deg  dir %.4f deg  obs %d\n", r.rig.cameras[c].name.c_str(),
                std::string(CameraModelName(r.rig.cameras[c].camera.model())).c_str(),
                *r_errors[c].rotation_error_deg, r_errors[c].direction_error_deg.value_or(0.0),
                r.camera_stats[c].observations);
  }
  // Camera 0 is the rig frame.
  EXPECT_LT(r.rig.cameras[0].cam_from_rig->translation.norm(), 1e-12);
  EXPECT_LT(RotationDifferenceDeg(r.rig.cameras[0].cam_from_rig->rotation, Eigen::Quaterniond::Identity()), 1e-12);
  // Unit scale on the first other camera.
  EXPECT_EQ(r.scale_kind, ScaleKind::kUnit) << r.scale;
  EXPECT_NEAR(r.rig.cameras[1].cam_from_rig->SourceOriginInTarget().norm(), 1.0, 1e-9);
  EXPECT_FALSE(r_errors[1].position_error_m.has_value());
  // The blind camera: no pose, and why.
  EXPECT_FALSE(r.rig.cameras[6].cam_from_rig.has_value());
  EXPECT_EQ(r.camera_status[6].outcome, CameraOutcome::kNotConnected) << r.camera_status[6];
  EXPECT_NE(r.camera_status[6].reason.find("cam0-cam6"), std::string::npos) << r.camera_status[6];
  // Noise of 0.3 px per coordinate: RMS of the 2D residual about 0.3 * sqrt(2).
  EXPECT_LT(r.reprojection_rms_px, 0.5);
  EXPECT_GT(r.num_points, 1000);
  EXPECT_TRUE(r.warnings.empty()) << r.warnings.front();
  std::printf("reprojection RMS %.3f px (initial %.3f), %d points, %d observations, %d tracks (%d conflicting), "
              "%d filtered\n",
              r.reprojection_rms_px, r.initial_reprojection_rms_px, r.num_points, r.num_observations, r.num_tracks,
              r.num_conflicting_tracks, r.num_filtered_observations);
}

TEST_F(RigCalibrationTest, KnownDistanceGivesMetricPositions) {
  RigCalibrationOptions options;
  const Rigid3d& gt0 = *synthetic_->rig.cameras[0].cam_from_rig;
  const Rigid3d& gt3 = *synthetic_->rig.cameras[3].cam_from_rig;
  const double metres = (gt0.SourceOriginInTarget() - gt3.SourceOriginInTarget()).norm();
  options.known_distance = KnownDistance{"cam0", "cam3", metres};
  RigCalibrationResult r = EstimateRig(*observations_, options);
  const std::vector<CameraErrors> r_errors = ErrorsAgainst(synthetic_->rig, r);
  EXPECT_EQ(r.scale_kind, ScaleKind::kMetric) << r.scale;
  const Eigen::Vector3d c3 = r.rig.cameras[3].cam_from_rig->SourceOriginInTarget();
  EXPECT_NEAR(c3.norm(), metres, 1e-9);
  for (int c = 1; c < 6; ++c) {
    ASSERT_TRUE(r_errors[c].position_error_m.has_value());
    EXPECT_LT(*r_errors[c].position_error_m, 0.005) << c;  // 5 mm on a 0.6 m rig
  }
}

// The result names every camera and every camera pair's edge, and the blind camera's lack of a
// pose (evaluation.json's records of them are pipeline/calibration_json_test.cc's).
TEST_F(RigCalibrationTest, TheResultNamesEveryCameraAndEdge) {
  const RigCalibrationResult r = EstimateRig(*observations_, {});
  ASSERT_EQ(r.rig.cameras.size(), 7u);
  ASSERT_EQ(r.camera_status.size(), 7u);
  ASSERT_EQ(r.cam_from_rig_rotation.size(), 7u);
  EXPECT_FALSE(r.cam_from_rig_rotation[6].has_value());
  EXPECT_EQ(r.edges.size(), 21u);
  EXPECT_TRUE(r.pairwise.pairs.empty());  // EstimateRig alone: no pairwise report
}

TEST_F(RigCalibrationTest, RotationOutlierEdgeIsDroppedWithItsReason) {
  RigObservations obs = *observations_;
  // Corrupt the rotation of one good pair by 20 deg, as a wrong two-view fit would. The pair is
  // cam1-cam3 (two fisheyes with four neighbours each): an edge of a camera with only two edges
  // (cam0) could not be told from its partner, every loop through that camera uses both.
  const int e = PairIndex(obs, 1, 3);
  ASSERT_GE(e, 0);
  ASSERT_TRUE(obs.pairs[e].two_view.success);
  obs.pairs[e].two_view.cam_b_from_cam_a.rotation =
      Eigen::Quaterniond(Eigen::AngleAxisd(DegToRad(20), Eigen::Vector3d::UnitX())) * obs.pairs[e].two_view.cam_b_from_cam_a.rotation;
  RigCalibrationResult r = EstimateRig(obs, {});
  const std::vector<CameraErrors> r_errors = ErrorsAgainst(synthetic_->rig, r);
  EXPECT_EQ(r.edges[e].outcome, EdgeOutcome::kRotationOutlier) << r.edges[e].status;
  EXPECT_FALSE(r.edges[e].Used());
  EXPECT_EQ(r.num_rotation_outliers, 1);
  for (int c = 0; c < 6; ++c) EXPECT_LT(r_errors[c].rotation_error_deg.value(), 0.05) << c;
}

// A pair whose rotation is right but whose baseline points the other way (the mirror pose that
// repeated structure or a wrong cheirality gives: the surround rig's back-left pair came out 160
// deg off and "ok"). Rotation averaging cannot see it; the rig the other pairs make can: the pair
// is left out, says why, and the rig stays right.
TEST_F(RigCalibrationTest, PairWhoseDirectionDisagreesWithTheRigIsRejected) {
  RigObservations obs = *observations_;
  const int e = PairIndex(obs, 1, 3);
  ASSERT_GE(e, 0);
  ASSERT_TRUE(obs.pairs[e].two_view.success);
  obs.pairs[e].two_view.cam_b_from_cam_a.translation *= -1.0;
  RigCalibrationResult r = EstimateRig(obs, {});
  const std::vector<CameraErrors> r_errors = ErrorsAgainst(synthetic_->rig, r);
  EXPECT_EQ(r.edges[e].outcome, EdgeOutcome::kRejected) << r.edges[e].status;
  EXPECT_FALSE(r.edges[e].Used());
  for (int c = 0; c < 6; ++c) {
    ASSERT_TRUE(r.rig.cameras[c].cam_from_rig.has_value()) << r.camera_status[c];
    EXPECT_LT(r_errors[c].rotation_error_deg.value(), 0.05) << c;
    if (c > 0) {
      EXPECT_LT(r_errors[c].direction_error_deg.value(), 0.5) << c;
    }
  }
  for (size_t p = 0; p < r.edges.size(); ++p) {  // every other used pair agrees with the rig
    if (static_cast<int>(p) == e || !r.edges[p].Used()) continue;
    EXPECT_NE(r.edges[p].outcome, EdgeOutcome::kRejected) << r.edges[p].cam_a << "-" << r.edges[p].cam_b << ": " << r.edges[p].status;
    EXPECT_LT(r.edges[p].rotation_disagreement_deg.value(), 1.0);
  }
  // The pair's own result says the calibrator no longer stands by it: not "ok", not a success in
  // evaluation.json (the surround rig's 160 deg pair stayed "ok" there).
  for (const RigEdgeStats& edge : r.edges) {
    PairResult pr;
    pr.cam_a = edge.cam_a;
    pr.cam_b = edge.cam_b;
    pr.two_view.success = true;
    r.pairwise.pairs.push_back(pr);
  }
  MarkPairsTheRigLeftOut(&r);
  for (size_t p = 0; p < r.edges.size(); ++p) {
    const PairResult& pr = r.pairwise.pairs[p];
    if (static_cast<int>(p) != e) {
      EXPECT_EQ(pr.Outcome(), PairOutcome::kSolved) << PairStatus(pr);
      continue;
    }
    EXPECT_EQ(pr.Outcome(), PairOutcome::kLeftOutByRig) << PairStatus(pr);
    EXPECT_EQ(pr.left_out_by_rig, r.edges[e].status);  // why: what the rig stage says of the edge
    EXPECT_FALSE(pr.Solved());
  }
}

// A pair whose rotation agrees but whose direction is biased 15 deg (a share of wrong inliers does
// that: the parking surround rig without masks) keeps its rotation and its matches in the rig;
// only its direction is left out. Leaving the whole pair out there cut the reference camera off.
TEST_F(RigCalibrationTest, PairWhoseDirectionAloneDisagreesKeepsItsRotation) {
  RigObservations obs = *observations_;
  const int e = PairIndex(obs, 1, 3);
  ASSERT_GE(e, 0);
  TurnDirection(&obs, e, 15.0);
  RigCalibrationResult r = EstimateRig(obs, {});
  const std::vector<CameraErrors> r_errors = ErrorsAgainst(synthetic_->rig, r);
  EXPECT_EQ(r.edges[e].outcome, EdgeOutcome::kDirectionLeftOut) << r.edges[e].status;
  EXPECT_TRUE(r.edges[e].direction_left_out);
  EXPECT_TRUE(r.edges[e].Used());
  EXPECT_TRUE(r.edges[e].rotation_only);
  for (int c = 0; c < 6; ++c) {
    ASSERT_TRUE(r.rig.cameras[c].cam_from_rig.has_value()) << r.camera_status[c];
    EXPECT_LT(r_errors[c].rotation_error_deg.value(), 0.05) << c;
    if (c > 0) {
      EXPECT_LT(r_errors[c].direction_error_deg.value(), 0.5) << c;
    }
  }
}

// Bit for bit: a reused adjustment must be the solve it stands for.
bool SameBits(const std::optional<Rigid3d>& a, const std::optional<Rigid3d>& b) {
  if (!a || !b) return a.has_value() == b.has_value();
  return std::memcmp(a->rotation.coeffs().data(), b->rotation.coeffs().data(), 4 * sizeof(double)) == 0 &&
         std::memcmp(a->translation.data(), b->translation.data(), 3 * sizeof(double)) == 0;
}

// The round that leaves the pair's direction out keeps its matches, so the tracks and the start
// from the tracks are the first round's: that adjustment is not solved again, and the rig is the
// very one of a pass that has the pair without its direction from the start (where it is solved).
TEST_F(RigCalibrationTest, ARoundThatKeepsTheTracksDoesNotSolveTheirAdjustmentAgain) {
  RigObservations obs = *observations_;
  const int e = PairIndex(obs, 1, 3);
  ASSERT_GE(e, 0);
  TurnDirection(&obs, e, 15.0);
  const RigCalibrationResult rounds = EstimateRig(obs, {});
  ASSERT_TRUE(rounds.edges[e].direction_left_out) << rounds.edges[e].status;
  obs.pairs[e].two_view.rotation_only = true;
  obs.pairs[e].two_view.cam_b_from_cam_a.translation.setZero();
  const RigCalibrationResult fresh = EstimateRig(obs, {});
  ASSERT_FALSE(fresh.edges[e].direction_left_out) << fresh.edges[e].status;  // one round
  std::printf("two rounds: %d adjustments solved, %d reused; one round: %d solved\n",
              rounds.work.start_adjustments_solved, rounds.work.start_adjustments_reused,
              fresh.work.start_adjustments_solved);
  EXPECT_EQ(rounds.work.start_adjustments_reused, 1);  // the start from the tracks
  EXPECT_EQ(fresh.work.start_adjustments_reused, 0);
  EXPECT_EQ(rounds.work.start_adjustments_solved + rounds.work.start_adjustments_reused,
            2 * fresh.work.start_adjustments_solved);
  ASSERT_EQ(rounds.position_starts.size(), fresh.position_starts.size());
  for (size_t i = 0; i < fresh.position_starts.size(); ++i) {
    const RigStartSummary &a = rounds.position_starts[i], &b = fresh.position_starts[i];
    EXPECT_EQ(a.source, b.source);
    EXPECT_EQ(std::memcmp(&a.cost, &b.cost, sizeof a.cost), 0) << a.source << ": " << a.cost << " vs " << b.cost;
    EXPECT_EQ(a.observations, b.observations) << a.source;
    EXPECT_EQ(a.chosen, b.chosen) << a.source;
  }
  for (size_t c = 0; c < fresh.rig.cameras.size(); ++c) {
    EXPECT_TRUE(SameBits(rounds.rig.cameras[c].cam_from_rig, fresh.rig.cameras[c].cam_from_rig)) << c;
  }
  for (size_t k = 0; k < fresh.rig_from_world.size(); ++k) {
    EXPECT_TRUE(SameBits(rounds.rig_from_world[k], fresh.rig_from_world[k])) << k;
  }
  EXPECT_EQ(std::memcmp(&rounds.reprojection_rms_px, &fresh.reprojection_rms_px, sizeof(double)), 0);
}

TEST_F(RigCalibrationTest, CameraZeroAloneCalibratesNothingElse) {
  RigObservations obs = *observations_;
  for (PairEstimate& p : obs.pairs) {
    if (p.cam_a == 0) {
      p.two_view.success = false;
      p.two_view.failure = TwoViewFailure::kTooFewMatches;
      p.two_view.failure_reason = "too few matches";
    }
  }
  const RigCalibrationResult r = EstimateRig(obs, {});
  EXPECT_EQ(r.camera_status[0].outcome, CameraOutcome::kCalibrated) << r.camera_status[0];
  for (int c = 1; c < 7; ++c) {
    EXPECT_FALSE(r.rig.cameras[c].cam_from_rig.has_value());
    EXPECT_EQ(r.camera_status[c].outcome, CameraOutcome::kNotConnected) << r.camera_status[c];
    EXPECT_EQ(r.camera_status[c].reason, "cam0-cam" + std::to_string(c) + ": two-view failed: too few matches");
  }
  for (const RigEdgeStats& edge : r.edges) {
    if (edge.cam_a == "cam0") {
      EXPECT_EQ(edge.outcome, EdgeOutcome::kTwoViewFailed) << edge.status;
    }
  }
}

// The words evaluation.json and the tables give for each outcome.
TEST(CameraStatus, TextNamesTheOutcomeAndSaysWhy) {
  EXPECT_EQ((CameraStatus{CameraOutcome::kCalibrated, PositionOutcome::kPlaced, ""}).Text(), "calibrated");
  EXPECT_EQ((CameraStatus{CameraOutcome::kCalibrated, PositionOutcome::kPlaced, "reference: rig frame"}).Text(),
            "calibrated (reference: rig frame)");
  EXPECT_EQ((CameraStatus{CameraOutcome::kRotationOnly, PositionOutcome::kNotObservable, "not observable: why"}).Text(),
            "rotation only: position not observable: why");
  EXPECT_EQ((CameraStatus{CameraOutcome::kNotConnected, PositionOutcome::kNotObservable, "cam0-cam1: why"}).Text(),
            "not connected: cam0-cam1: why");
}

// Fails every pair of cam2 but cam1-cam2, which then alone places cam2; returns its index (-1: none).
int LeaveCam1Cam2AloneToPlaceCam2(RigObservations* obs) {
  int held = -1;
  for (size_t p = 0; p < obs->pairs.size(); ++p) {
    PairEstimate& e = obs->pairs[p];
    if (e.cam_a == 1 && e.cam_b == 2) {
      held = static_cast<int>(p);
    } else if (e.cam_a == 2 || e.cam_b == 2) {
      e.two_view.success = false;
      e.two_view.failure = TwoViewFailure::kTooFewMatches;
      e.two_view.failure_reason = "too few matches";
    }
  }
  return held;
}

TEST_F(RigCalibrationTest, CameraHeldByOneWeakPairIsWarnedAbout) {
  RigObservations obs = *observations_;
  const int held = LeaveCam1Cam2AloneToPlaceCam2(&obs);
  ASSERT_GE(held, 0);
  ASSERT_TRUE(obs.pairs[held].two_view.success);
  auto warned = [](const RigCalibrationResult& r) {
    for (const std::string& w : r.warnings) {
      if (w.rfind("cam2 is placed by one pair only, cam1-cam2, whose fit explains ", 0) == 0) return true;
    }
    return false;
  };
  obs.pairs[held].two_view.num_matches = obs.pairs[held].two_view.num_inliers * 5 / 4;  // 80%: as genuine pairs do
  const RigCalibrationResult strong = EstimateRig(obs, {});
  ASSERT_TRUE(strong.rig.cameras[2].cam_from_rig.has_value()) << strong.camera_status[2];
  EXPECT_FALSE(warned(strong));
  obs.pairs[held].two_view.num_matches = obs.pairs[held].two_view.num_inliers * 6;  // 17%: a chance agreement looks so
  const RigCalibrationResult weak = EstimateRig(obs, {});
  EXPECT_TRUE(weak.rig.cameras[2].cam_from_rig.has_value());  // kept: the warning says what to check
  EXPECT_TRUE(warned(weak));
  const int other_warnings = static_cast<int>(weak.warnings.size()) - 1;
  EXPECT_EQ(other_warnings, static_cast<int>(strong.warnings.size()));
}

// A camera placed by one pair whose matches fit a rival pose as well is not placed: its position
// is ambiguous, and its rotation too when the rival's is more than max_rival_rotation_deg away. A
// rival on a pair of a camera that other pairs place changes nothing.
TEST_F(RigCalibrationTest, CameraHeldByOnePairWithARivalPoseIsNotPlaced) {
  RigObservations obs = *observations_;
  const int held = LeaveCam1Cam2AloneToPlaceCam2(&obs);
  ASSERT_GE(held, 0);
  const RigCalibrationResult alone = EstimateRig(obs, {});
  ASSERT_EQ(alone.camera_status[2].outcome, CameraOutcome::kCalibrated) << alone.camera_status[2];
  ASSERT_TRUE(alone.camera_stats[2].rotation_std_deg.has_value());

  obs.pairs[held].two_view.rival = RivalPose{120.0, 0.4, 300, 150, 160};
  const RigCalibrationResult near_turn = EstimateRig(obs, {});
  EXPECT_EQ(near_turn.camera_status[2].outcome, CameraOutcome::kRotationOnly) << near_turn.camera_status[2];
  EXPECT_EQ(near_turn.camera_status[2].position, PositionOutcome::kAmbiguous);
  EXPECT_THAT(near_turn.camera_status[2].reason, ::testing::HasSubstr("cam1-cam2, fits another pose about as well"));
  EXPECT_FALSE(near_turn.rig.cameras[2].cam_from_rig.has_value());
  EXPECT_TRUE(near_turn.cam_from_rig_rotation[2].has_value());
  for (int c : {1, 3, 4, 5}) EXPECT_EQ(near_turn.camera_status[c].outcome, CameraOutcome::kCalibrated) << c;

  obs.pairs[held].two_view.rival->rotation_deg = 2.5;
  const RigCalibrationResult far_turn = EstimateRig(obs, {});
  EXPECT_EQ(far_turn.camera_status[2].outcome, CameraOutcome::kNotConnected) << far_turn.camera_status[2];
  EXPECT_EQ(far_turn.camera_status[2].position, PositionOutcome::kAmbiguous);
  EXPECT_FALSE(far_turn.cam_from_rig_rotation[2].has_value());
  EXPECT_FALSE(far_turn.camera_stats[2].rotation_std_deg.has_value());

  // cam1 is placed by cam0-cam1 too: a rival on cam1-cam2 leaves it placed.
  RigObservations both = *observations_;
  for (PairEstimate& e : both.pairs) {
    if (e.cam_a == 1 && e.cam_b == 2) e.two_view.rival = RivalPose{120.0, 2.5, 300, 150, 160};
  }
  const RigCalibrationResult ring = EstimateRig(both, {});
  for (int c = 1; c < 6; ++c) EXPECT_EQ(ring.camera_status[c].outcome, CameraOutcome::kCalibrated) << c;
}

TEST_F(RigCalibrationTest, BadOptionsThrow) {
  RigCalibrationOptions options;
  options.known_distance = KnownDistance{"cam0", "nope", 1.0};
  EXPECT_THAT([&] { EstimateRig(*observations_, options); },
              ThrowsWith<std::invalid_argument>("camera 'nope', which is not in the rig (cam0, cam1, cam2, cam3, cam4, cam5, cam6)"));
  options.known_distance = KnownDistance{"cam0", "cam1", -1.0};
  EXPECT_THROW(options.Check(), std::invalid_argument);
}

// The bundle adjustment's cost is zero at the truth, and the truth is a fixed point of the solver.
TEST(RigBundleAdjustmentAtTruth, ResidualIsZeroAndPosesStay) {
  SyntheticRigOptions opt = RingOptions(TestSeed());
  opt.noise_px = 0.0;
  opt.num_frames = 2;
  opt.num_points = 200;
  const SyntheticRig s = SynthesizeRig(opt);
  const int n = 6;  // the ring without the blind camera
  std::vector<Camera> cameras;
  std::vector<std::optional<Rigid3d>> truth;  // camera 0 is the synthetic rig's frame
  for (int c = 0; c < n; ++c) {
    cameras.push_back(s.rig.cameras[c].camera);
    truth.push_back(*s.rig.cameras[c].cam_from_rig);
  }
  std::vector<PairMatches> pairs;  // the true matches only
  for (int a = 0; a < n; ++a) {
    for (int b = a + 1; b < n; ++b) {
      PairMatches p{a, b, {}};
      for (int f = 0; f < opt.num_frames; ++f) p.per_frame.push_back(s.TrueMatches({f, a}, {f, b}));
      pairs.push_back(std::move(p));
    }
  }
  FrameKeypoints keypoints = s.keypoints;
  for (auto& frame : keypoints) frame.resize(n);
  int conflicting = -1;
  const std::vector<ViewTrack> tracks = BuildViewTracks(n, opt.num_frames, pairs, {}, &conflicting);
  EXPECT_EQ(conflicting, 0);
  // Each frame's points live in that frame's rig frame: every rig_from_world is the identity, held.
  const std::vector<std::optional<Rigid3d>> rig_from_world(opt.num_frames, Rigid3d());
  const MultiFrameBundleAdjustmentResult ba =
      MultiFrameRigBundleAdjust(cameras, keypoints, tracks, {truth, rig_from_world}, 1, {}, /*hold_frames=*/true);
  EXPECT_GT(ba.num_points, 200);
  EXPECT_LT(ba.initial_rms_px, 1e-6);
  EXPECT_LT(ba.reprojection_rms_px, 1e-6);
  EXPECT_EQ(ba.num_filtered_observations, 0);
  for (int c = 0; c < n; ++c) {
    EXPECT_LT(RotationDifferenceDeg(ba.poses.cam_from_rig[c]->rotation, truth[c]->rotation), 1e-7) << c;
    EXPECT_LT((ba.poses.cam_from_rig[c]->translation - truth[c]->translation).norm(), 1e-8) << c;
  }
}

// A camera the synchronisation check did not find capturing apart, but whose offset the images do
// not bound (CameraSynchronisation::offset_not_excluded_s), is calibrated only if synchronised,
// and says which offset it could not exclude.
TEST(SetCaptureTimes, ACameraWhoseOffsetTheImagesDoNotBoundIsCalibratedOnlyIfSynchronised) {
  RigObservations obs;
  obs.camera_names = {"front", "left"};
  obs.cameras.resize(2);
  obs.frame_times_s = {0.0, 0.1, 0.2, 0.3};
  RigCalibrationResult result;
  result.camera_status.assign(2, CameraStatus{CameraOutcome::kCalibrated, PositionOutcome::kPlaced, ""});
  result.camera_stats.assign(2, {});
  std::vector<CameraSynchronisation> checked(2);
  checked[1].checked = true;
  checked[1].interval_visibility_px = 40.0;
  checked[1].offset_s = 0.0064;
  checked[1].offset_stddev_s = 0.0035;
  checked[1].offset_undetermined = true;
  checked[1].offset_not_excluded_s = 0.0239;
  SetCaptureTimes(obs, CaptureTimeOptions{}, MultiFrameBundleAdjustmentResult{}, checked, &result);
  EXPECT_EQ(result.camera_status[0].outcome, CameraOutcome::kCalibrated);
  EXPECT_EQ(result.camera_status[1].outcome, CameraOutcome::kCalibratedIfSynchronised);
  EXPECT_THAT(result.camera_status[1].reason, testing::HasSubstr("do not exclude 24 ms"));
  EXPECT_TRUE(result.camera_stats[1].time_offset_undetermined);
  // Bounded, the camera stays calibrated.
  checked[1].offset_undetermined = false;
  checked[1].offset_not_excluded_s.reset();
  result.camera_status[1] = CameraStatus{CameraOutcome::kCalibrated, PositionOutcome::kPlaced, ""};
  SetCaptureTimes(obs, CaptureTimeOptions{}, MultiFrameBundleAdjustmentResult{}, checked, &result);
  EXPECT_EQ(result.camera_status[1].outcome, CameraOutcome::kCalibrated);
}

// The capture times are asked of the rig the pairs agree with. A round with a pair to leave out is
// made again without it, so its rig, bent by the wrong pair, is not checked: on the six-camera
// twin such a rig put a camera 20 ms apart, which hid the wrong pair for a round.
TEST(RigCaptureTimes, AreCheckedOnTheRoundWhosePairsAgreeWithTheRig) {
  const Camera pinhole(CameraModelId::kPinhole, 640, 360, {320, 320, 319.5, 179.5});
  SyntheticRigOptions o;
  o.cameras.assign(5, pinhole);
  o.max_tilt_deg = 3;
  o.max_offset_m = 0.05;
  o.path = TurningPath(4, 1.0, 4.0, 0.3, 2.0, 1.0);  // it changes its turn: the path shows time
  o.num_frames = static_cast<int>(o.path.size());
  o.num_points = 3000;
  o.min_distance_m = 4;
  o.max_distance_m = 25;
  o.noise_px = 0.5;
  o.seed = TestSeed();
  SyntheticRig s = SynthesizeRig(o);
  SyntheticObservationOptions observe;
  observe.temporal_pairs = true;
  RigObservations obs = ObserveSyntheticRig(s, observe);
  for (int k = 0; k < static_cast<int>(obs.keypoints.size()); ++k) obs.frame_times_s.push_back(0.1 * k);
  const int e = PairIndex(obs, 1, 2);
  ASSERT_GE(e, 0);
  obs.pairs[e].two_view.cam_b_from_cam_a.translation *= -1.0;

  const RigCalibrationResult r = EstimateRig(obs, {});
  EXPECT_EQ(r.edges[e].outcome, EdgeOutcome::kRejected) << r.edges[e].status;
  EXPECT_EQ(r.work.rounds_checked_for_capture_times, 1);  // of two rounds
  const std::vector<CameraErrors> errors = ErrorsAgainst(s.rig, r);
  for (int c = 1; c < 5; ++c) {
    ASSERT_EQ(r.camera_status[c].outcome, CameraOutcome::kCalibrated) << r.camera_status[c].Text();
    EXPECT_GT(r.camera_stats[c].interval_visibility_px, 5.0) << c;  // the check ran on the rig kept
    EXPECT_LT(*errors[c].rotation_error_deg, 0.1) << c;
    EXPECT_LT(*errors[c].direction_error_deg, 1.0) << c;
  }
}

// The warning that names the cameras whose capture time the path hides speaks of every camera
// placed: after a registration round that placed more, it still comes last, the round's own
// warnings in their order before it.
TEST(SetCaptureTimes, TheWarningOfTheCamerasWhoseTimeThePathHidesComesLast) {
  RigObservations obs;
  obs.camera_names = {"front", "left", "rear"};
  obs.cameras.resize(3);
  obs.frame_times_s = {0.0, 0.1, 0.2};
  RigCalibrationResult result;
  result.camera_status.assign(3, CameraStatus{CameraOutcome::kCalibrated, PositionOutcome::kPlaced, ""});
  result.camera_stats.assign(3, {});
  result.warnings = {"left is placed through tracks: 900 of its 1200 matches"};
  std::vector<CameraSynchronisation> checked(3);
  for (int c : {1, 2}) {
    checked[c].checked = true;
    checked[c].interval_visibility_px = 0.02;  // a path that moves alike at every frame
  }
  SetCaptureTimes(obs, CaptureTimeOptions{}, MultiFrameBundleAdjustmentResult{}, checked, &result);
  ASSERT_EQ(result.warnings.size(), 2u);
  EXPECT_THAT(result.warnings[1], testing::StartsWith("the rig's path cannot show whether left, rear"));
  result.warnings.push_back("rear is placed through tracks: 600 of its 1000 matches");
  result.warnings.push_back("rear is held by one weak pair");
  PutHiddenTimeWarningLast(&result);
  ASSERT_EQ(result.warnings.size(), 4u);
  EXPECT_THAT(result.warnings[0], testing::StartsWith("left is placed"));
  EXPECT_THAT(result.warnings[1], testing::StartsWith("rear is placed"));
  EXPECT_THAT(result.warnings[2], testing::StartsWith("rear is held"));
  EXPECT_THAT(result.warnings[3], testing::StartsWith("the rig's path cannot show whether left, rear"));
}

}  // namespace
}  // namespace rigsim
