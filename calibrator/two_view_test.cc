#include "calibrator/two_view.h"

#include <random>

#include <gtest/gtest.h>

#include "calibrator/evaluation.h"

namespace rigsim {
namespace {

struct Scenario {
  std::vector<Eigen::Vector2d> px_a, px_b;
  std::vector<char> is_outlier;
};

// Random points 3..12 m in front of A, seen by both cameras, with Gaussian pixel noise; a
// fraction of B's pixels replaced by random ones (outliers).
Scenario MakeScenario(const Camera& cam_a, const Camera& cam_b, const Rigid3d& b_from_a, int n, double noise_px,
                      double outlier_fraction, unsigned seed) {
  std::mt19937 rng(seed);
  std::uniform_real_distribution<double> uni(-1.0, 1.0), depth(3.0, 12.0), u01(0.0, 1.0);
  std::normal_distribution<double> noise(0.0, noise_px);
  Scenario s;
  while (static_cast<int>(s.px_a.size()) < n) {
    const double z = depth(rng);
    const Eigen::Vector3d x_a(uni(rng) * z * 0.7, uni(rng) * z * 0.5, z);
    const auto pa = cam_a.ImgFromCam(x_a);
    const auto pb = cam_b.ImgFromCam(b_from_a * x_a);
    if (!pa || !pb || !cam_a.IsInImage(*pa) || !cam_b.IsInImage(*pb)) continue;
    const bool outlier = u01(rng) < outlier_fraction;
    Eigen::Vector2d b = *pb + Eigen::Vector2d(noise(rng), noise(rng));
    if (outlier) b = Eigen::Vector2d(u01(rng) * (cam_b.width() - 1), u01(rng) * (cam_b.height() - 1));
    s.px_a.push_back(*pa + Eigen::Vector2d(noise(rng), noise(rng)));
    s.px_b.push_back(b);
    s.is_outlier.push_back(outlier);
  }
  return s;
}

Rigid3d TestPose() {
  const Eigen::Quaterniond r = Eigen::AngleAxisd(DegToRad(12.0), Eigen::Vector3d(0.2, 1.0, 0.1).normalized()) *
                               Eigen::Quaterniond::Identity();
  return Rigid3d(r, Eigen::Vector3d(-1.0, 0.1, 0.2));
}

Camera Pinhole() { return Camera(CameraModelId::kPinhole, 640, 480, {500, 505, 319.5, 239.5}); }
Camera Distorted() {
  return Camera(CameraModelId::kOpenCV, 640, 480, {480, 482, 322, 241, -0.25, 0.06, 0.001, -0.0008});
}

void ExpectAccurate(const Camera& cam_a, const Camera& cam_b, unsigned seed) {
  const Rigid3d gt = TestPose();
  const Scenario s = MakeScenario(cam_a, cam_b, gt, 400, 0.3, 0.2, seed);
  const TwoViewResult r = EstimateRelativePose(cam_a, s.px_a, cam_b, s.px_b, TwoViewOptions());
  ASSERT_TRUE(r.success) << r.failure_reason;
  EXPECT_FALSE(r.rotation_only);
  EXPECT_LT(RotationErrorDeg(r.cam_b_from_cam_a, gt), 0.05);
  EXPECT_LT(TranslationDirectionErrorDeg(r.cam_b_from_cam_a, gt).value(), 0.5);
  EXPECT_NEAR(r.cam_b_from_cam_a.translation.norm(), 1.0, 1e-9);
  // The inliers are (nearly) the true correspondences.
  int true_in = 0, false_in = 0, outliers = 0;
  for (size_t i = 0; i < s.px_a.size(); ++i) {
    outliers += s.is_outlier[i];
    if (r.inlier_mask[i]) (s.is_outlier[i] ? false_in : true_in)++;
  }
  EXPECT_GT(true_in, 0.85 * (400 - outliers));
  EXPECT_LT(false_in, 0.05 * outliers + 3);
  EXPECT_EQ(r.num_inliers, true_in + false_in);
}

TEST(TwoView, PinholeNoiseAndOutliers) { ExpectAccurate(Pinhole(), Pinhole(), 1); }

TEST(TwoView, OpenCvDistortionNoiseAndOutliers) { ExpectAccurate(Distorted(), Pinhole(), 2); }

// Fisheye lenses see beyond 90 deg: those bearings cannot enter the essential-matrix fit as
// normalised coordinates but must still count as inliers and enter the refinement.
TEST(TwoView, FisheyeBeyondNinetyDegrees) {
  const Camera fisheye(CameraModelId::kOpenCVFisheye, 800, 800, {170, 170, 399.5, 399.5, 0.02, -0.005, 0.001, 0.0});
  ASSERT_GT(fisheye.max_valid_angle(), DegToRad(100.0));
  const Rigid3d gt = TestPose();
  std::mt19937 rng(8);
  std::normal_distribution<double> gauss(0.0, 1.0), noise(0.0, 0.3);
  std::uniform_real_distribution<double> depth(3.0, 12.0);
  std::vector<Eigen::Vector2d> pa, pb;
  int beyond_90 = 0;
  while (pa.size() < 400) {
    const Eigen::Vector3d dir = Eigen::Vector3d(gauss(rng), gauss(rng), gauss(rng)).normalized();
    const Eigen::Vector3d x_a = depth(rng) * dir;
    const auto a = fisheye.ImgFromCam(x_a);
    const auto b = fisheye.ImgFromCam(gt * x_a);
    if (!a || !b || !fisheye.IsInImage(*a) || !fisheye.IsInImage(*b)) continue;
    beyond_90 += dir.z() < 0;
    pa.push_back(*a + Eigen::Vector2d(noise(rng), noise(rng)));
    pb.push_back(*b + Eigen::Vector2d(noise(rng), noise(rng)));
  }
  ASSERT_GT(beyond_90, 20);
  const TwoViewResult r = EstimateRelativePose(fisheye, pa, fisheye, pb, TwoViewOptions());
  ASSERT_TRUE(r.success) << r.failure_reason;
  EXPECT_LT(RotationErrorDeg(r.cam_b_from_cam_a, gt), 0.05);
  EXPECT_LT(TranslationDirectionErrorDeg(r.cam_b_from_cam_a, gt).value(), 0.5);
  EXPECT_GT(r.num_inliers, 360);  // the wide-angle bearings are inliers too
}

TEST(TwoView, RefinementAtTheTruthHasZeroResidual) {
  const Rigid3d gt = TestPose();
  const Camera cam = Distorted();
  const Scenario s = MakeScenario(cam, cam, gt, 100, 0.0, 0.0, 3);
  std::vector<Eigen::Vector3d> fa, fb;
  for (size_t i = 0; i < s.px_a.size(); ++i) {
    fa.push_back(*cam.CamFromImg(s.px_a[i]));
    fb.push_back(*cam.CamFromImg(s.px_b[i]));
    EXPECT_LT(EpipolarAngularResidual(gt, fa.back(), fb.back()).norm(), 1e-9);
  }
  const Rigid3d unit_gt(gt.rotation, gt.translation.normalized());
  RefinementSummary summary;
  const Rigid3d at_truth = RefineRelativePose(fa, fb, unit_gt, 1e-3, 50, &summary);
  EXPECT_LT(summary.initial_cost, 1e-18);
  EXPECT_LT(RotationErrorDeg(at_truth, gt), 1e-6);
  // From a start 1 deg and 5 deg off it converges back to the truth.
  const Rigid3d start(Eigen::AngleAxisd(DegToRad(1.0), Eigen::Vector3d::UnitX()) * gt.rotation,
                      (gt.translation.normalized() + Eigen::Vector3d(0, 0.09, 0)).normalized());
  const Rigid3d refined = RefineRelativePose(fa, fb, start, 1e-3, 100, &summary);
  EXPECT_LT(RotationErrorDeg(refined, gt), 1e-5);
  EXPECT_LT(TranslationDirectionErrorDeg(refined, gt).value(), 1e-4);
  EXPECT_LT(summary.final_cost, 1e-16);
}

TEST(TwoView, PureRotationIsFlaggedRotationOnly) {
  const Rigid3d gt(Eigen::Quaterniond(Eigen::AngleAxisd(DegToRad(8.0), Eigen::Vector3d::UnitY())),
                   Eigen::Vector3d::Zero());
  const Camera cam = Pinhole();
  const Scenario s = MakeScenario(cam, cam, gt, 300, 0.3, 0.2, 4);
  const TwoViewResult r = EstimateRelativePose(cam, s.px_a, cam, s.px_b, TwoViewOptions());
  ASSERT_TRUE(r.success) << r.failure_reason;
  EXPECT_TRUE(r.rotation_only);
  EXPECT_LT(RotationErrorDeg(r.cam_b_from_cam_a, gt), 0.05);
  EXPECT_EQ(r.cam_b_from_cam_a.translation.norm(), 0.0);
  EXPECT_FALSE(TranslationDirectionErrorDeg(r.cam_b_from_cam_a, TestPose()).has_value());
}

TEST(TwoView, TooFewMatchesFailsWithReason) {
  const Camera cam = Pinhole();
  const Scenario s = MakeScenario(cam, cam, TestPose(), 10, 0.3, 0.0, 5);
  const TwoViewResult r = EstimateRelativePose(cam, s.px_a, cam, s.px_b, TwoViewOptions());
  EXPECT_FALSE(r.success);
  EXPECT_NE(r.failure_reason.find("too few matches"), std::string::npos) << r.failure_reason;
  EXPECT_EQ(r.inlier_mask.size(), 10u);
}

TEST(TwoView, PureOutliersFail) {
  const Camera cam = Pinhole();
  const Scenario s = MakeScenario(cam, cam, TestPose(), 200, 0.3, 1.0, 6);
  const TwoViewResult r = EstimateRelativePose(cam, s.px_a, cam, s.px_b, TwoViewOptions());
  EXPECT_FALSE(r.success);
  EXPECT_FALSE(r.failure_reason.empty());
}

TEST(TwoView, Deterministic) {
  const Camera cam = Pinhole();
  const Scenario s = MakeScenario(cam, cam, TestPose(), 300, 0.5, 0.3, 7);
  const TwoViewResult a = EstimateRelativePose(cam, s.px_a, cam, s.px_b, TwoViewOptions());
  const TwoViewResult b = EstimateRelativePose(cam, s.px_a, cam, s.px_b, TwoViewOptions());
  EXPECT_EQ(a.inlier_mask, b.inlier_mask);
  EXPECT_EQ(a.cam_b_from_cam_a.rotation.coeffs(), b.cam_b_from_cam_a.rotation.coeffs());
}

}  // namespace
}  // namespace rigsim

namespace rigsim {
namespace {

// Views that share nothing: every match is an outlier. RANSAC still finds a few random matches
// that agree with some pose; that must be a failure, not a confident wrong answer.
TEST(TwoView, UnrelatedViewsAreNoGeometry) {
  const Scenario s = MakeScenario(Pinhole(), Pinhole(), TestPose(), 800, 0.3, 1.0, 7);
  const TwoViewResult r = EstimateRelativePose(Pinhole(), s.px_a, Pinhole(), s.px_b, TwoViewOptions());
  EXPECT_FALSE(r.success);
  EXPECT_NE(r.failure_reason.find("no consistent geometry"), std::string::npos) << r.failure_reason;
}

}  // namespace
}  // namespace rigsim
