#include "calibrator/estimators/intrinsics_refinement.h"

#include <cmath>
#include <cstdio>

#include <gmock/gmock.h>
#include <gtest/gtest.h>

#include "calibrator/calibrator_test_support.h"
#include "calibrator/estimators/cost_functions.h"
#include "calibrator/rig_intrinsics.h"
#include "calibrator/stages/rig_calibration.h"
#include "evaluation/intrinsics_errors.h"
#include "testing/expect_error.h"
#include "testing/synthetic_rig.h"

namespace rigsim {
namespace {

// Datasheet intrinsics: focal lengths off by `focal_fraction` (alternating in sign per camera),
// the principal point by `pp_px` (alternating), the distortion zeroed.
Camera Perturbed(const Camera& truth, int index, double focal_fraction, double pp_px) {
  std::vector<double> p = truth.params();
  const double sign = index % 2 == 0 ? 1.0 : -1.0;
  p[0] *= 1.0 + sign * focal_fraction;
  p[1] *= 1.0 + sign * focal_fraction;
  p[2] += sign * pp_px;
  p[3] -= sign * pp_px;
  for (size_t i = 4; i < p.size(); ++i) p[i] = 0.0;
  return Camera(truth.model(), truth.width(), truth.height(), p);
}

// A turning ring of four cameras, one with barrel distortion, over four frames: the rig's
// rotation between frames fixes each camera's focal length in its own images.
struct PerturbedRing {
  Rig truth;
  RigObservations observations;  // with the perturbed intrinsics, as the pairwise stage would give them
};

PerturbedRing MakePerturbedRing(double focal_fraction, double pp_px) {
  SyntheticRigOptions o;
  o.cameras.assign(4, Camera(CameraModelId::kPinhole, 640, 480, {300, 300, 319.5, 239.5}));
  o.cameras[1] = Camera(CameraModelId::kOpenCV, 640, 480, {310, 310, 322.0, 236.0, -0.2, 0.04, 0.0, 0.0});
  o.ring_radius_m = 0.3;
  o.yaw_step_deg = 45;
  o.max_tilt_deg = 1.5;
  o.max_offset_m = 0.01;
  o.num_frames = 4;
  o.step_m = Eigen::Vector3d(0.1, 0.0, 1.0);
  o.turn_deg = 6.0;
  o.num_points = 2000;
  o.seed = 20241126u;  // fixed: the ring is shared between tests
  SyntheticRig s = SynthesizeRig(o);
  PerturbedRing out;
  out.truth = s.rig;
  for (size_t c = 0; c < s.rig.cameras.size(); ++c) {
    s.rig.cameras[c].camera = Perturbed(s.rig.cameras[c].camera, static_cast<int>(c), focal_fraction, pp_px);
  }
  SyntheticObservationOptions observe;
  observe.temporal_pairs = true;
  observe.two_view.max_error_px = 4.0;  // the perturbed intrinsics leave pixels off
  out.observations = ObserveSyntheticRig(s, observe);
  return out;
}

// The ring with datasheet intrinsics (+-3 % focal, +-10 px principal point, no distortion), made
// once for the tests that share it.
const PerturbedRing& DatasheetRing() {
  static const PerturbedRing ring = MakePerturbedRing(0.03, 10.0);
  return ring;
}

TEST(IntrinsicsRefinement, PerturbedIntrinsicsAreRecoveredWithTheirStandardDeviations) {
  const PerturbedRing& ring = DatasheetRing();
  RigCalibrationOptions options;
  options.bundle_adjustment.refine_intrinsics = true;
  RigCalibrationResult r = EstimateRigAndIntrinsics(ring.observations, options);
  const std::vector<CameraErrors> r_errors = ErrorsAgainst(ring.truth, r);
  for (size_t c = 0; c < ring.truth.cameras.size(); ++c) {
    const RigCameraStats& s = r.camera_stats[c];
    ASSERT_TRUE(s.intrinsics.has_value()) << c << ": " << r.camera_status[c];
    const RefinedIntrinsics& in = *s.intrinsics;
    const std::optional<IntrinsicsErrors> errors = ScoreIntrinsics(in.given, in.refined, ring.truth.cameras[c].camera);
    EXPECT_EQ(in.given, ring.observations.cameras[c].params()) << c;
    EXPECT_EQ(in.refined, r.rig.cameras[c].camera.params()) << c << ": the result's rig carries the refined values";
    ASSERT_EQ(in.stddev.size(), in.refined.size()) << c;
    for (double sd : in.stddev) EXPECT_TRUE(sd > 0 && std::isfinite(sd)) << c;
    // The noise is 0.3 px over a few thousand observations: a focal length to about 0.05 %.
    EXPECT_LT(in.stddev[0] / in.refined[0], 0.001) << c;
    EXPECT_LT(in.stddev[2], 1.0) << c;
    ASSERT_TRUE(errors.has_value()) << c;
    std::printf("cam%zu focal %.3f%% -> %.4f%% (std %.4f%%), pp %.2f -> %.3f px (std %.3f px), k1 %.4f (true %.4f)\n", c,
                errors->given_focal_error_percent, errors->focal_error_percent, 100 * in.stddev[0] / in.refined[0],
                errors->given_principal_point_error_px, errors->principal_point_error_px, in.stddev[2],
                in.refined.size() > 4 ? in.refined[4] : 0.0,
                ring.truth.cameras[c].camera.params().size() > 4 ? ring.truth.cameras[c].camera.params()[4] : 0.0);
    EXPECT_GT(errors->given_focal_error_percent, 2.9) << c;
    // Within about three standard deviations (measured 0.007-0.056 %, 0.08-0.32 px, 0.05-0.08 deg).
    EXPECT_LT(errors->focal_error_percent, 0.15) << c;
    EXPECT_LT(errors->principal_point_error_px, 1.0) << c;
    EXPECT_LT(r_errors[c].rotation_error_deg.value(), 0.1) << c;
    if (c > 0) {
      EXPECT_LT(r_errors[c].direction_error_deg.value(), 0.5) << c;
    }
  }
  // The distorted camera's k1 is found from zero.
  EXPECT_NEAR(r.rig.cameras[1].camera.params()[4], -0.2, 0.02);
  EXPECT_EQ(r.rig.cameras[1].camera.model(), CameraModelId::kOpenCV);
  EXPECT_EQ(r.camera_stats[1].intrinsics->stddev.size(), 8u);
}

TEST(IntrinsicsRefinement, WithoutTheOptionTheIntrinsicsStayAsGiven) {
  const PerturbedRing& ring = DatasheetRing();
  const RigCalibrationResult r = EstimateRig(ring.observations, {});
  for (size_t c = 0; c < ring.truth.cameras.size(); ++c) {
    EXPECT_FALSE(r.camera_stats[c].intrinsics.has_value()) << c;
    EXPECT_EQ(r.rig.cameras[c].camera.params(), ring.observations.cameras[c].params()) << c;
  }
}

TEST(IntrinsicsRefinement, ExactIntrinsicsStayWhereTheyAre) {
  const PerturbedRing ring = MakePerturbedRing(0.0, 0.0);
  RigCalibrationOptions options;
  options.bundle_adjustment.refine_intrinsics = true;
  RigCalibrationResult r = EstimateRigAndIntrinsics(ring.observations, options);
  // Cameras 0, 2, 3 are given exactly (camera 1's distortion is zeroed): they must not drift.
  for (size_t c : {0u, 2u, 3u}) {
    ASSERT_TRUE(r.camera_stats[c].intrinsics.has_value()) << c;
    const RefinedIntrinsics& in = *r.camera_stats[c].intrinsics;
    const std::optional<IntrinsicsErrors> errors = ScoreIntrinsics(in.given, in.refined, ring.truth.cameras[c].camera);
    ASSERT_TRUE(errors.has_value()) << c;
    EXPECT_LT(errors->focal_error_percent, 0.15) << c;  // std 0.04 %
    EXPECT_LT(errors->principal_point_error_px, 0.75) << c;
  }
}

TEST(IntrinsicsRefinement, PriorsScaleWithTheGivenValues) {
  const Camera camera(CameraModelId::kOpenCV, 1920, 1080, {1000, 1000, 960, 540, -0.3, 0.1, 0.0, 0.0});
  IntrinsicsPriorOptions o;
  const std::vector<double> sigma = IntrinsicsPriorSigmas(camera, o);
  ASSERT_EQ(sigma.size(), 8u);
  EXPECT_DOUBLE_EQ(sigma[0], 50.0);               // 5 % of 1000 px
  EXPECT_DOUBLE_EQ(sigma[2], 0.025 * 1920);       // of the larger side
  EXPECT_DOUBLE_EQ(sigma[4], o.first_radial);
  EXPECT_DOUBLE_EQ(sigma[6], o.tangential);
  o.focal_fraction = 0;
  EXPECT_THAT([&] { o.Check(); }, ThrowsWith<std::invalid_argument>("focal_fraction"));
}

TEST(IntrinsicsRefinement, PriorCostIsZeroAtTheGivenValuesAndLinear) {
  const std::vector<double> given = {500, 502, 320, 240};
  const IntrinsicsPriorCost cost(given, {2, 2, 0.5, 0.5}, 10);
  std::vector<double> p = given;
  const double* params[] = {p.data()};
  double residuals[5], jacobian[20];
  double* jacobians[] = {jacobian};
  ASSERT_TRUE(cost.Evaluate(params, residuals, jacobians));
  for (double r : residuals) EXPECT_EQ(r, 0.0);
  p[0] += 1.0;  // fx up by one: its own residual and the aspect's
  ASSERT_TRUE(cost.Evaluate(params, residuals, nullptr));
  EXPECT_DOUBLE_EQ(residuals[0], 2.0);
  EXPECT_DOUBLE_EQ(residuals[4], 10.0);
  EXPECT_DOUBLE_EQ(jacobian[4 * 4 + 0], 10.0);
  EXPECT_DOUBLE_EQ(jacobian[4 * 4 + 1], -10.0);
}

}  // namespace
}  // namespace rigsim
