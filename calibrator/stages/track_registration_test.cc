#include "calibrator/stages/track_registration.h"

#include <algorithm>
#include <string>
#include <vector>

#include <gtest/gtest.h>

#include "calibrator/calibrator_test_support.h"
#include "calibrator/motion_passes.h"
#include "calibrator/stages/registered_rig_adjustment.h"
#include "testing/synthetic_rig.h"

namespace rigsim {
namespace {

constexpr int kWeakCamera = 3;

// Five cameras of 90 deg round a ring, neighbours sharing a little, on a rig driving a gently
// turning path: each camera's pairs place it, and camera kWeakCamera's are made to fail as pairs
// that find too few inliers do.
SyntheticRig FiveCameraRing(const std::vector<double>& time_offset_s = {}, bool stands_still = false) {
  const Camera pinhole(CameraModelId::kPinhole, 640, 360, {320, 320, 319.5, 179.5});
  SyntheticRigOptions o;
  o.cameras.assign(5, pinhole);
  o.max_tilt_deg = 3;
  o.max_offset_m = 0.05;
  o.path = stands_still ? std::vector<Rigid3d>(3, Rigid3d()) : TurningPath(4, 1.0, 4.0, 0.3, 2.0, 1.0);
  o.num_frames = static_cast<int>(o.path.size());
  o.num_points = 3000;
  o.min_distance_m = 4;
  o.max_distance_m = 25;
  o.noise_px = 0.5;
  o.time_offset_s = time_offset_s;
  o.seed = TestSeed();
  return SynthesizeRig(o);
}

// The observations with every pair of the `weak` cameras failed.
RigObservations ObserveWithWeakCameras(SyntheticRig& s, const std::vector<int>& weak) {
  SyntheticObservationOptions observe;
  observe.temporal_pairs = true;
  RigObservations obs = ObserveSyntheticRig(s, observe);
  auto is_weak = [&](int c) { return std::find(weak.begin(), weak.end(), c) != weak.end(); };
  for (size_t p = 0; p < obs.pairs.size(); ++p) {
    PairEstimate& e = obs.pairs[p];
    if (!is_weak(e.cam_a) && !is_weak(e.cam_b)) continue;
    e.two_view = TwoViewEstimate{};
    e.two_view.failure = TwoViewFailure::kTooFewInliers;
    e.two_view.failure_reason = "no consistent geometry: 12 inliers of 110 matches";
    for (auto& frame : obs.inliers[p].per_frame) frame.clear();
  }
  return obs;
}

RigCalibrationOptions WithoutMotionLinks() {
  RigCalibrationOptions options;
  options.pairwise.num_threads = 2;
  options.motion.enabled = false;  // what places the camera here is the registration alone
  return options;
}

TEST(TrackRegistration, PlacesACameraWhosePairsFailThroughItsMatchesWithPlacedPoints) {
  SyntheticRig s = FiveCameraRing();
  const RigObservations obs = ObserveWithWeakCameras(s, {kWeakCamera});
  RigCalibrationOptions off = WithoutMotionLinks();
  off.registration.enabled = false;
  const RigCalibrationResult before = EstimateRigWithMotionLinks(obs, SyntheticMatcher(s), off);
  ASSERT_EQ(before.camera_status[kWeakCamera].outcome, CameraOutcome::kNotConnected);
  for (int c : {0, 1, 2, 4}) ASSERT_TRUE(HasFullPose(before.camera_status[c].outcome)) << c;

  const RigCalibrationResult r = EstimateRigWithMotionLinks(obs, SyntheticMatcher(s), WithoutMotionLinks());
  ASSERT_TRUE(HasFullPose(r.camera_status[kWeakCamera].outcome)) << r.camera_status[kWeakCamera].reason;
  const std::vector<CameraErrors> errors = ErrorsAgainst(s.rig, r);
  for (int c = 1; c < 5; ++c) {
    EXPECT_LT(*errors[c].rotation_error_deg, 0.1) << c;
    EXPECT_LT(*errors[c].direction_error_deg, 1.0) << c;
  }
  bool said = false;
  for (const std::string& w : r.warnings) said = said || w.find("cam3 is placed through tracks") != std::string::npos;
  EXPECT_TRUE(said);
  // Its deviations are the adjustment's, and they bound its errors: independent noise of 0.5 px,
  // so three deviations (and a hair for the truth's own rounding) cover it.
  const RigCameraStats& stats = r.camera_stats[kWeakCamera];
  ASSERT_TRUE(stats.rotation_std_deg && stats.direction_std_deg);
  EXPECT_GT(*stats.rotation_std_deg, 1e-4);
  EXPECT_GT(*stats.direction_std_deg, 1e-3);
  EXPECT_LT(*errors[kWeakCamera].rotation_error_deg, 3 * *stats.rotation_std_deg + 1e-3);
  EXPECT_LT(*errors[kWeakCamera].direction_error_deg, 3 * *stats.direction_std_deg + 1e-2);
  EXPECT_GT(stats.observations, 0);
  EXPECT_EQ(r.scale_kind, before.scale_kind);
}

TEST(TrackRegistration, LeavesACameraWhoseMatchesFitNoPoseUnplacedAndSaysWhy) {
  SyntheticRig s = FiveCameraRing();
  const RigObservations obs = ObserveWithWeakCameras(s, {kWeakCamera});
  const ViewPairMatcher truthful = SyntheticMatcher(s);
  // The weak camera's view pairs match keypoints that are not of one point.
  const ViewPairMatcher wrong_for_weak = [&](int cam_a, int frame_a, int cam_b, int frame_b) {
    std::vector<std::pair<int, int>> m = truthful(cam_a, frame_a, cam_b, frame_b);
    if (cam_a != kWeakCamera && cam_b != kWeakCamera) return m;
    const int nb = static_cast<int>(s.keypoints[frame_b][cam_b].size());
    for (size_t i = 0; i < m.size(); ++i) m[i].second = static_cast<int>((m[i].second + 977 * (i + 1)) % nb);
    return m;
  };
  const RigCalibrationResult r = EstimateRigWithMotionLinks(obs, wrong_for_weak, WithoutMotionLinks());
  const CameraStatus& weak = r.camera_status[kWeakCamera];
  EXPECT_EQ(weak.outcome, CameraOutcome::kNotConnected);
  EXPECT_NE(weak.reason.find("nor was it registered through tracks"), std::string::npos) << weak.reason;
  for (int c : {0, 1, 2, 4}) EXPECT_TRUE(HasFullPose(r.camera_status[c].outcome)) << c;
}

TEST(TrackRegistration, PlacesTheRigAgainstTheReferenceCamerasOwnMotionWhenNoPairHolds) {
  SyntheticRig s = FiveCameraRing();
  const RigObservations obs = ObserveWithWeakCameras(s, {1, 2, 3, 4});
  RigCalibrationOptions off = WithoutMotionLinks();
  off.registration.enabled = false;
  const RigCalibrationResult before = EstimateRigWithMotionLinks(obs, SyntheticMatcher(s), off);
  for (int c = 1; c < 5; ++c) ASSERT_FALSE(HasFullPose(before.camera_status[c].outcome)) << c;

  const RigCalibrationResult r = EstimateRigWithMotionLinks(obs, SyntheticMatcher(s), WithoutMotionLinks());
  const std::vector<CameraErrors> errors = ErrorsAgainst(s.rig, r);
  // Camera 0's neighbours see what it saw; the far ones what its neighbours saw, a round later.
  for (int c = 1; c < 5; ++c) {
    ASSERT_TRUE(HasFullPose(r.camera_status[c].outcome)) << c << ": " << r.camera_status[c].reason;
    EXPECT_LT(*errors[c].rotation_error_deg, 0.1) << c;
    EXPECT_LT(*errors[c].direction_error_deg, 1.0) << c;
  }
  // Camera 0 alone had no unit of length; a registered camera's distance from it is now the unit.
  EXPECT_EQ(before.scale_kind, ScaleKind::kNone);
  ASSERT_EQ(r.scale_kind, ScaleKind::kUnit) << r.scale;
  int unit_camera = -1;
  for (int c = 1; c < 5; ++c) {
    if (r.scale.find("|centre of " + r.rig.cameras[c].name + "| = 1") != std::string::npos) unit_camera = c;
  }
  ASSERT_GE(unit_camera, 1) << r.scale;
  EXPECT_NEAR(r.rig.cameras[unit_camera].cam_from_rig->translation.norm(), 1.0, 1e-9);
  // The frames are in the same unit: the rig's first step against the truth's, in units of that
  // camera's distance from camera 0.
  const double truth_unit = s.rig.cameras[unit_camera].cam_from_rig->SourceOriginInTarget().norm();
  const double truth_step = (s.rig_from_world[1].Inverse().translation - s.rig_from_world[0].Inverse().translation).norm();
  ASSERT_TRUE(r.rig_from_world[1]);
  const double step = r.rig_from_world[1]->Inverse().translation.norm();
  EXPECT_NEAR(step, truth_step / truth_unit, 0.02 * truth_step / truth_unit);
}

// A known distance between cameras only registration places: the rig stage alone ignores it (one
// of them has no position) and says so; the registered rig is metric and no longer says it.
TEST(TrackRegistration, AKnownDistanceBetweenRegisteredCamerasMakesTheRigMetric) {
  SyntheticRig s = FiveCameraRing();
  const RigObservations obs = ObserveWithWeakCameras(s, {kWeakCamera});
  const Eigen::Vector3d a = s.rig.cameras[1].cam_from_rig->SourceOriginInTarget();
  const Eigen::Vector3d b = s.rig.cameras[kWeakCamera].cam_from_rig->SourceOriginInTarget();
  RigCalibrationOptions options = WithoutMotionLinks();
  options.known_distance = KnownDistance{"cam1", "cam3", (a - b).norm()};
  const auto ignored = [](const RigCalibrationResult& r) {
    return std::any_of(r.warnings.begin(), r.warnings.end(),
                       [](const std::string& w) { return w.rfind("known distance ignored", 0) == 0; });
  };
  RigCalibrationOptions off = options;
  off.registration.enabled = false;
  const RigCalibrationResult before = EstimateRigWithMotionLinks(obs, SyntheticMatcher(s), off);
  EXPECT_TRUE(ignored(before));
  EXPECT_NE(before.scale_kind, ScaleKind::kMetric);

  const RigCalibrationResult r = EstimateRigWithMotionLinks(obs, SyntheticMatcher(s), options);
  ASSERT_TRUE(HasFullPose(r.camera_status[kWeakCamera].outcome)) << r.camera_status[kWeakCamera].reason;
  EXPECT_EQ(r.scale_kind, ScaleKind::kMetric) << r.scale;
  EXPECT_FALSE(ignored(r));
  const std::vector<CameraErrors> errors = ErrorsAgainst(s.rig, r);
  for (int c = 1; c < 5; ++c) EXPECT_LT(*errors[c].position_error_m, 0.02) << c;
}

// A rig that stands still poses no frame from its reference camera's motion and triangulates no
// point from one placed camera: no camera can be registered, and each unplaced one says so.
TEST(TrackRegistration, SaysWhyNoCameraCanBeRegisteredOnARigThatStandsStill) {
  SyntheticRig s = FiveCameraRing({}, true);
  const RigObservations obs = ObserveWithWeakCameras(s, {1, 2, 3, 4});
  const RigCalibrationResult r = EstimateRigWithMotionLinks(obs, SyntheticMatcher(s), WithoutMotionLinks());
  for (int c = 1; c < 5; ++c) {
    EXPECT_FALSE(HasFullPose(r.camera_status[c].outcome)) << c;
    EXPECT_NE(r.camera_status[c].reason.find("nor was it registered through tracks (") , std::string::npos)
        << c << ": " << r.camera_status[c].reason;
    EXPECT_NE(r.camera_status[c].reason.find("the rig stood still or only turned"), std::string::npos) << c;
  }
}

// The adjustment confirms a registration or does not place the camera: a registered pose turned
// 5 deg from where its matches put it is pulled back by the adjustment, and the camera is left
// unplaced with why, the placed ones where they were.
TEST(RegisteredRigAdjustment, DoesNotPlaceACameraItsAdjustmentTurnsAwayFromTheRegisteredPose) {
  SyntheticRig s = FiveCameraRing();
  const RigObservations obs = ObserveWithWeakCameras(s, {kWeakCamera});
  RigCalibrationOptions options = WithoutMotionLinks();
  options.registration.enabled = false;
  const RigCalibrationResult placed = EstimateRigWithMotionLinks(obs, SyntheticMatcher(s), options);
  TrackRegistration reg = RegisterCamerasThroughTracks(obs, placed, SyntheticMatcher(s), options.registration);
  ASSERT_EQ(reg.cameras.size(), 1u);
  ASSERT_TRUE(reg.cameras[0].registered) << reg.cameras[0].reason;
  const RigObservations with_pairs = WithRegisteredViewPairs(obs, reg);

  const RegisteredRig good = AdjustRegisteredRig(with_pairs, placed, reg, options);
  EXPECT_TRUE(HasFullPose(good.result.camera_status[kWeakCamera].outcome));
  EXPECT_TRUE(good.not_placed.empty());

  reg.cameras[0].cam_from_rig.rotation =
      Eigen::Quaterniond(Eigen::AngleAxisd(DegToRad(5.0), Eigen::Vector3d::UnitY())) * reg.cameras[0].cam_from_rig.rotation;
  const RegisteredRig turned = AdjustRegisteredRig(with_pairs, placed, reg, options);
  EXPECT_EQ(turned.result.camera_status[kWeakCamera].outcome, CameraOutcome::kNotConnected);
  ASSERT_EQ(turned.not_placed.size(), 1u);
  EXPECT_EQ(turned.not_placed[0].rfind("cam3: the adjustment", 0), 0u) << turned.not_placed[0];
  for (int c : {0, 1, 2, 4}) {
    EXPECT_TRUE(HasFullPose(turned.result.camera_status[c].outcome)) << c;
    EXPECT_LT(RotationDifferenceDeg(*turned.result.cam_from_rig_rotation[c], *placed.cam_from_rig_rotation[c]), 0.05) << c;
  }
}

// A registered camera that captured 30 ms after the others while the rig drove on (0.3 m): taken
// as synchronised, the check the rig stage runs finds it, and it is not placed as if it had
// captured with them (its status says when it captured); with the offsets estimated, it is placed
// and its offset found.
TEST(RegisteredRigAdjustment, ChecksARegisteredCamerasCaptureTimeAsTheRigStageDoes) {
  SyntheticRig s = FiveCameraRing({0.0, 0.0, 0.0, 0.03, 0.0});
  RigObservations obs = ObserveWithWeakCameras(s, {kWeakCamera});
  for (int k = 0; k < static_cast<int>(obs.keypoints.size()); ++k) obs.frame_times_s.push_back(0.1 * k);

  const RigCalibrationResult synchronised = EstimateRigWithMotionLinks(obs, SyntheticMatcher(s), WithoutMotionLinks());
  const CameraStatus& taken = synchronised.camera_status[kWeakCamera];
  EXPECT_FALSE(HasFullPose(taken.outcome)) << taken.Text();
  EXPECT_FALSE(synchronised.rig.cameras[kWeakCamera].cam_from_rig);
  const size_t says = taken.reason.find("cam3: it captures ");
  ASSERT_NE(says, std::string::npos) << taken.reason;
  EXPECT_NEAR(std::stod(taken.reason.substr(says + 18)), 30.0, 1.5) << taken.reason;  // ms after cam0

  RigCalibrationOptions options = WithoutMotionLinks();
  options.capture_time.estimate_offsets = true;
  const RigCalibrationResult estimated = EstimateRigWithMotionLinks(obs, SyntheticMatcher(s), options);
  ASSERT_EQ(estimated.camera_status[kWeakCamera].outcome, CameraOutcome::kCalibrated)
      << estimated.camera_status[kWeakCamera].Text();
  const RigCameraStats& stats = estimated.camera_stats[kWeakCamera];
  ASSERT_TRUE(stats.time_offset_s && stats.time_offset_stddev_s);
  EXPECT_NEAR(*stats.time_offset_s, 0.03, 3 * *stats.time_offset_stddev_s + 1e-3);
  const std::vector<CameraErrors> errors = ErrorsAgainst(s.rig, estimated);
  EXPECT_LT(*errors[kWeakCamera].rotation_error_deg, 0.1);
  EXPECT_LT(*errors[kWeakCamera].direction_error_deg, 1.0);
}

}  // namespace
}  // namespace rigsim
