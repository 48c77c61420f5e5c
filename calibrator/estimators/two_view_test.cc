#include "calibrator/estimators/two_view.h"

#include <algorithm>
#include <cmath>
#include <cstdio>
#include <random>

#include <gtest/gtest.h>

#include "evaluation/match_precision.h"
#include "evaluation/pose_errors.h"

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
  ASSERT_TRUE(r.estimate.success) << r.estimate.failure_reason;
  EXPECT_FALSE(r.estimate.rotation_only);
  EXPECT_EQ(r.estimate.pair_type, PairType::kGeneral)
      << r.estimate.num_homography_inliers << " homography vs " << r.num_essential_inliers << " essential inliers";
  EXPECT_LT(RotationErrorDeg(r.estimate.cam_b_from_cam_a, gt), 0.05);
  EXPECT_LT(TranslationDirectionErrorDeg(r.estimate.cam_b_from_cam_a, gt).value(), 0.5);
  EXPECT_NEAR(r.estimate.cam_b_from_cam_a.translation.norm(), 1.0, 1e-9);
  // The inliers are (nearly) the true correspondences.
  int true_in = 0, false_in = 0, outliers = 0;
  for (size_t i = 0; i < s.px_a.size(); ++i) {
    outliers += s.is_outlier[i];
    if (r.inlier_mask[i]) (s.is_outlier[i] ? false_in : true_in)++;
  }
  EXPECT_GT(true_in, 0.85 * (400 - outliers));
  EXPECT_LT(false_in, 0.05 * outliers + 3);
  EXPECT_EQ(r.estimate.num_inliers, true_in + false_in);
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
  ASSERT_TRUE(r.estimate.success) << r.estimate.failure_reason;
  EXPECT_LT(RotationErrorDeg(r.estimate.cam_b_from_cam_a, gt), 0.05);
  EXPECT_LT(TranslationDirectionErrorDeg(r.estimate.cam_b_from_cam_a, gt).value(), 0.5);
  EXPECT_GT(r.estimate.num_inliers, 360);  // the wide-angle bearings are inliers too
  EXPECT_EQ(r.estimate.pair_type, PairType::kGeneral);
  // Cheirality counts every inlier with parallax, those beyond 90 deg included (depth along the
  // ray): the right pose puts nearly all of them in front of both cameras, the other three few.
  EXPECT_GT(r.estimate.cheirality_points, 300);
  EXPECT_GT(r.estimate.points_in_front, 0.95 * r.estimate.cheirality_points);
  EXPECT_LT(r.estimate.points_in_front_otherwise, 0.05 * r.estimate.cheirality_points);
}

// --- Pair type: planar ---------------------------------------------------------------------------

// Points on the plane n . x = d (in A), seen by both cameras, with pixel noise and outliers.
Scenario MakePlanarScenario(const Camera& cam_a, const Camera& cam_b, const Rigid3d& b_from_a,
                            const Eigen::Vector3d& n, double d, int n_points, double noise_px, double outlier_fraction,
                            unsigned seed) {
  std::mt19937 rng(seed);
  std::uniform_real_distribution<double> u01(0.0, 1.0);
  std::normal_distribution<double> noise(0.0, noise_px);
  Scenario s;
  while (static_cast<int>(s.px_a.size()) < n_points) {
    // A random pixel of A, lifted to the plane along its ray.
    const Eigen::Vector2d px(u01(rng) * (cam_a.width() - 1), u01(rng) * (cam_a.height() - 1));
    const auto ray = cam_a.CamFromImg(px);
    if (!ray || n.dot(*ray) <= 1e-3) continue;
    const Eigen::Vector3d x_a = *ray * (d / n.dot(*ray));
    if (x_a.norm() > 60.0) continue;  // grazing rays: the plane's far horizon
    const auto pb = cam_b.ImgFromCam(b_from_a * x_a);
    if (!pb || !cam_b.IsInImage(*pb)) continue;
    const bool outlier = u01(rng) < outlier_fraction;
    Eigen::Vector2d b = *pb + Eigen::Vector2d(noise(rng), noise(rng));
    if (outlier) b = Eigen::Vector2d(u01(rng) * (cam_b.width() - 1), u01(rng) * (cam_b.height() - 1));
    s.px_a.push_back(px + Eigen::Vector2d(noise(rng), noise(rng)));
    s.px_b.push_back(b);
    s.is_outlier.push_back(outlier);
  }
  return s;
}

double HomographyToEssential(const TwoViewResult& r) {
  return r.num_essential_inliers > 0 ? double(r.estimate.num_homography_inliers) / r.num_essential_inliers : 0.0;
}

TEST(TwoViewPairType, Names) {
  EXPECT_EQ(PairTypeName(PairType::kGeneral), "general");
  EXPECT_EQ(PairTypeName(PairType::kPlanar), "planar");
  EXPECT_EQ(PairTypeName(PairType::kRotationOnly), "rotation-only");
}

// A facade 8 m ahead, tilted, seen with a 1 m baseline: the homography explains the matches as
// well as the essential matrix; the pose is still the essential matrix's.
TEST(TwoViewPairType, PointsOnOnePlaneAreFlaggedPlanar) {
  const Rigid3d gt = TestPose();
  const Eigen::Vector3d n = Eigen::Vector3d(0.3, -0.2, 1.0).normalized();
  for (double noise : {0.3, 0.5}) {
    const Scenario s = MakePlanarScenario(Pinhole(), Pinhole(), gt, n, 8.0, 400, noise, 0.2, 11);
    const TwoViewResult r = EstimateRelativePose(Pinhole(), s.px_a, Pinhole(), s.px_b, TwoViewOptions());
    std::printf("  planar, noise %.1f px: H/E inliers %d/%d = %.3f, rot err %.4f deg, t dir err %.3f deg\n", noise,
                r.estimate.num_homography_inliers, r.num_essential_inliers, HomographyToEssential(r),
                RotationErrorDeg(r.estimate.cam_b_from_cam_a, gt), TranslationDirectionErrorDeg(r.estimate.cam_b_from_cam_a, gt).value_or(-1));
    ASSERT_TRUE(r.estimate.success) << r.estimate.failure_reason;
    EXPECT_EQ(r.estimate.pair_type, PairType::kPlanar) << HomographyToEssential(r);
    EXPECT_FALSE(r.estimate.rotation_only);
    EXPECT_GT(r.estimate.cam_b_from_cam_a.translation.norm(), 0.5);  // a pose, not "rotation only"
    EXPECT_GT(HomographyToEssential(r), 0.9);
  }
  // The option decides: asking the homography to explain more than the essential matrix does
  // leaves the same pair general.
  const Scenario s = MakePlanarScenario(Pinhole(), Pinhole(), gt, n, 8.0, 400, 0.3, 0.2, 11);
  TwoViewOptions strict;
  strict.planar_ratio = 1.05;
  EXPECT_EQ(EstimateRelativePose(Pinhole(), s.px_a, Pinhole(), s.px_b, strict).estimate.pair_type, PairType::kGeneral);
}

// A plane fits two poses (the homography's two decompositions) and one pair's matches cannot say
// which: the other is reported beside the pose, and one of the two is the truth.
TEST(TwoViewPairType, APlaneReportsItsOtherPose) {
  const Rigid3d gt = TestPose();
  const Eigen::Vector3d n = Eigen::Vector3d(0.3, -0.2, 1.0).normalized();
  const Scenario s = MakePlanarScenario(Pinhole(), Pinhole(), gt, n, 8.0, 400, 0.3, 0.2, 11);
  const TwoViewResult r = EstimateRelativePose(Pinhole(), s.px_a, Pinhole(), s.px_b, TwoViewOptions());
  ASSERT_TRUE(r.estimate.success) << r.estimate.failure_reason;
  ASSERT_EQ(r.estimate.pair_type, PairType::kPlanar);
  ASSERT_FALSE(r.estimate.planar_alternatives.empty());
  double nearest = RotationErrorDeg(r.estimate.cam_b_from_cam_a, gt);
  for (const Rigid3d& other : r.estimate.planar_alternatives) {
    EXPECT_GT(RotationDifferenceDeg(other.rotation, r.estimate.cam_b_from_cam_a.rotation), TwoViewOptions().min_planar_alternative_deg);
    EXPECT_NEAR(other.translation.norm(), 1.0, 1e-9);
    nearest = std::min(nearest, RotationErrorDeg(other, gt));
  }
  std::printf("  plane: pose %.3f deg off, %zu alternative(s), nearest %.3f deg off\n", RotationErrorDeg(r.estimate.cam_b_from_cam_a, gt),
              r.estimate.planar_alternatives.size(), nearest);
  EXPECT_LT(nearest, 0.2);
}

// The ground below a fisheye camera, out to beyond 90 degrees off-axis: the homography's angular
// error is defined on the whole sphere, so those bearings count for it as for the essential matrix.
TEST(TwoViewPairType, GroundPlaneThroughFisheyeIsPlanar) {
  const Camera fisheye(CameraModelId::kOpenCVFisheye, 800, 800, {170, 170, 399.5, 399.5, 0.02, -0.005, 0.001, 0.0});
  const Rigid3d gt(Eigen::Quaterniond(Eigen::AngleAxisd(DegToRad(10.0), Eigen::Vector3d::UnitY())),
                   Eigen::Vector3d(-0.8, 0.0, 0.3));
  // Ground 1.5 m below (camera y points down), camera pitched 30 degrees down towards it.
  const Eigen::Vector3d n = Eigen::AngleAxisd(DegToRad(-30.0), Eigen::Vector3d::UnitX()) * Eigen::Vector3d::UnitY();
  const Scenario s = MakePlanarScenario(fisheye, fisheye, gt, n, 1.5, 400, 0.3, 0.1, 12);
  int beyond_90 = 0;
  for (const Eigen::Vector2d& p : s.px_a) beyond_90 += fisheye.CamFromImg(p)->z() < 0;
  ASSERT_GT(beyond_90, 10);
  // Which way the baseline points is not this test's question: the plane's essential matrix here
  // is its other solution (32 deg off), which the cheirality test refuses (see below).
  TwoViewOptions any_side;
  any_side.cheirality_margin = 1.0;
  const TwoViewResult r = EstimateRelativePose(fisheye, s.px_a, fisheye, s.px_b, any_side);
  std::printf("  fisheye ground: H/E inliers %d/%d = %.3f (%d bearings beyond 90 deg)\n", r.estimate.num_homography_inliers,
              r.num_essential_inliers, HomographyToEssential(r), beyond_90);
  ASSERT_TRUE(r.estimate.success) << r.estimate.failure_reason;
  EXPECT_EQ(r.estimate.pair_type, PairType::kPlanar) << HomographyToEssential(r);
  EXPECT_GT(HomographyToEssential(r), 0.9);
}

// A pose that puts a third of the inliers with parallax behind a camera is not an answer: the
// fisheye ground above gives a pose 32 deg and 79 deg off with 225 points in front and 103 in
// front under another of the essential matrix's poses, which was reported solved. It is refused,
// saying why.
TEST(TwoView, PoseThatPutsManyPointsBehindTheCamerasIsRefused) {
  const Camera fisheye(CameraModelId::kOpenCVFisheye, 800, 800, {170, 170, 399.5, 399.5, 0.02, -0.005, 0.001, 0.0});
  const Rigid3d gt(Eigen::Quaterniond(Eigen::AngleAxisd(DegToRad(10.0), Eigen::Vector3d::UnitY())),
                   Eigen::Vector3d(-0.8, 0.0, 0.3));
  const Eigen::Vector3d n = Eigen::AngleAxisd(DegToRad(-30.0), Eigen::Vector3d::UnitX()) * Eigen::Vector3d::UnitY();
  const Scenario s = MakePlanarScenario(fisheye, fisheye, gt, n, 1.5, 400, 0.3, 0.1, 12);
  TwoViewOptions any_side;
  any_side.cheirality_margin = 1.0;
  const TwoViewResult loose = EstimateRelativePose(fisheye, s.px_a, fisheye, s.px_b, any_side);
  ASSERT_TRUE(loose.estimate.success);
  EXPECT_GT(RotationErrorDeg(loose.estimate.cam_b_from_cam_a, gt), 10.0);  // the wrong pose the test is about
  EXPECT_GT(loose.estimate.points_in_front_otherwise, loose.estimate.points_in_front / 3);

  const TwoViewResult r = EstimateRelativePose(fisheye, s.px_a, fisheye, s.px_b, TwoViewOptions());
  EXPECT_FALSE(r.estimate.success);
  EXPECT_EQ(r.estimate.failure, TwoViewFailure::kCheiralityUndecided) << r.estimate.failure_reason;
  EXPECT_EQ(r.estimate.points_in_front, loose.estimate.points_in_front);
}

// Points spread in depth (3-12 m) with the same baseline: far from any one plane.
TEST(TwoViewPairType, PointsInGeneral3DAreGeneral) {
  const Rigid3d gt = TestPose();
  for (unsigned seed : {13u, 14u}) {
    const Scenario s = MakeScenario(Pinhole(), Pinhole(), gt, 400, 0.3, 0.2, seed);
    const TwoViewResult r = EstimateRelativePose(Pinhole(), s.px_a, Pinhole(), s.px_b, TwoViewOptions());
    std::printf("  general 3D: H/E inliers %d/%d = %.3f\n", r.estimate.num_homography_inliers, r.num_essential_inliers,
                HomographyToEssential(r));
    ASSERT_TRUE(r.estimate.success) << r.estimate.failure_reason;
    EXPECT_EQ(r.estimate.pair_type, PairType::kGeneral) << HomographyToEssential(r);
    EXPECT_LT(HomographyToEssential(r), 0.5);
    EXPECT_GT(r.estimate.num_homography_inliers, 0);  // the homography was fitted, it just explains little
    EXPECT_TRUE(r.estimate.planar_alternatives.empty());
  }
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
  ASSERT_TRUE(r.estimate.success) << r.estimate.failure_reason;
  EXPECT_TRUE(r.estimate.rotation_only);
  EXPECT_EQ(r.estimate.pair_type, PairType::kRotationOnly);  // a rotation is a homography too: precedence
  EXPECT_LT(RotationErrorDeg(r.estimate.cam_b_from_cam_a, gt), 0.05);
  EXPECT_EQ(r.estimate.cam_b_from_cam_a.translation.norm(), 0.0);
  EXPECT_FALSE(TranslationDirectionErrorDeg(r.estimate.cam_b_from_cam_a, TestPose()).has_value());
}

// --- Rival poses ----------------------------------------------------------------------------------

// Two cameras 0.7 m apart side by side, B turned 50 deg towards A's right edge, as a car's front and
// front-right cameras: they share a strip at A's right edge. The points there lie at depths in
// [near, far] m.
Scenario MakeEdgeStripScenario(double near, double far, unsigned seed) {
  const Rigid3d b_from_a = Rigid3d(Eigen::Quaterniond(Eigen::AngleAxisd(DegToRad(-50.0), Eigen::Vector3d::UnitY())),
                                   Eigen::Vector3d::Zero()) *
                           Rigid3d(Eigen::Quaterniond::Identity(), Eigen::Vector3d(-0.7, 0.0, 0.0));
  std::mt19937 rng(seed);
  std::uniform_real_distribution<double> depth(near, far), u01(0.0, 1.0);
  std::normal_distribution<double> noise(0.0, 0.3);
  Scenario s;
  const Camera cam = Pinhole();
  while (s.px_a.size() < 400) {
    const Eigen::Vector2d px(560 + 79 * u01(rng), 60 + 200 * u01(rng));  // A's right edge, upper half
    const Eigen::Vector3d x_a = *cam.CamFromImg(px) * depth(rng);
    const auto pb = cam.ImgFromCam(b_from_a * x_a);
    if (!pb || !cam.IsInImage(*pb)) continue;
    s.px_a.push_back(px + Eigen::Vector2d(noise(rng), noise(rng)));
    s.px_b.push_back(*pb + Eigen::Vector2d(noise(rng), noise(rng)));
    s.is_outlier.push_back(0);
  }
  return s;
}

Rigid3d EdgeStripTruth() {
  return Rigid3d(Eigen::Quaterniond(Eigen::AngleAxisd(DegToRad(-50.0), Eigen::Vector3d::UnitY())),
                 Eigen::Vector3d::Zero()) *
         Rigid3d(Eigen::Quaterniond::Identity(), Eigen::Vector3d(-0.7, 0.0, 0.0));
}

// One tree 14-16 m away in the shared strip: a small turn moves its points as the baseline's
// parallax does, so poses far apart fit the matches alike. The pair keeps its pose and reports a
// rival whose baseline points elsewhere, unless its pose is near the truth and no restart finds
// another minimum. Without the restarts, seed 1's pose is over 100 deg off with nothing said.
TEST(TwoViewRival, PointsAtOneDepthInOnePartOfTheViewDoNotFixTheBaseline) {
  int with_rival = 0;
  for (unsigned seed : {1u, 2u, 3u, 4u, 5u, 6u}) {
    const Scenario s = MakeEdgeStripScenario(14.0, 16.0, seed);
    const TwoViewResult r = EstimateRelativePose(Pinhole(), s.px_a, Pinhole(), s.px_b, TwoViewOptions());
    const TwoViewEstimate& e = r.estimate;
    ASSERT_TRUE(e.success) << e.failure_reason;
    EXPECT_EQ(e.pair_type, PairType::kGeneral);
    const double rotation_error = RotationErrorDeg(e.cam_b_from_cam_a, EdgeStripTruth());
    const double direction_error = TranslationDirectionErrorDeg(e.cam_b_from_cam_a, EdgeStripTruth()).value();
    std::printf("  seed %u: pose %.2f deg / %.1f deg off", seed, rotation_error, direction_error);
    if (!e.rival) {
      std::printf(", no rival\n");
      EXPECT_LT(rotation_error, 2.0) << "seed " << seed;
      EXPECT_LT(direction_error, 10.0) << "seed " << seed;
      continue;
    }
    ++with_rival;
    std::printf("; rival %.1f deg away, turned %.2f deg, %d/%d closer\n", e.rival->direction_deg,
                e.rival->rotation_deg, e.rival->rival_closer, e.rival->pose_closer);
    EXPECT_GT(e.rival->direction_deg, TwoViewOptions().rival_min_direction_deg);
    // The sign test let it through: neither pose fits clearly more of the matches closer.
    EXPECT_LE(e.rival->pose_closer - e.rival->rival_closer,
              TwoViewOptions().rival_sign_test_sigma * std::sqrt(double(e.rival->pose_closer + e.rival->rival_closer)));
    EXPECT_GT(e.rival->inliers, 0.8 * e.num_inliers);
  }
  EXPECT_GE(with_rival, 4);
  TwoViewOptions no_rivals;
  no_rivals.rival_seeds = 0;
  const Scenario s = MakeEdgeStripScenario(14.0, 16.0, 1);
  const TwoViewResult r = EstimateRelativePose(Pinhole(), s.px_a, Pinhole(), s.px_b, no_rivals);
  ASSERT_TRUE(r.estimate.success) << r.estimate.failure_reason;
  EXPECT_FALSE(r.estimate.rival.has_value());
  EXPECT_GT(TranslationDirectionErrorDeg(r.estimate.cam_b_from_cam_a, EdgeStripTruth()).value(), 30.0);
}

// The same strip with depths from 2 to 40 m: the parallax differs from point to point, which no
// turn mimics; the pose is general, has no rival, and is right.
TEST(TwoViewRival, DepthsSpreadInTheSameStripFixTheBaseline) {
  for (unsigned seed : {1u, 2u, 3u}) {
    const Scenario s = MakeEdgeStripScenario(2.0, 40.0, seed);
    const TwoViewResult r = EstimateRelativePose(Pinhole(), s.px_a, Pinhole(), s.px_b, TwoViewOptions());
    ASSERT_TRUE(r.estimate.success) << r.estimate.failure_reason;
    EXPECT_FALSE(r.estimate.rival.has_value()) << "seed " << seed << ": rival " << r.estimate.rival->direction_deg
                                               << " deg, " << r.estimate.rival->rotation_deg << " deg";
    EXPECT_EQ(r.estimate.pair_type, PairType::kGeneral);
    EXPECT_LT(RotationErrorDeg(r.estimate.cam_b_from_cam_a, EdgeStripTruth()), 0.2);
    EXPECT_LT(TranslationDirectionErrorDeg(r.estimate.cam_b_from_cam_a, EdgeStripTruth()).value(), 5.0);
  }
}

TEST(TwoView, TooFewMatchesFailsWithReason) {
  const Camera cam = Pinhole();
  const Scenario s = MakeScenario(cam, cam, TestPose(), 10, 0.3, 0.0, 5);
  const TwoViewResult r = EstimateRelativePose(cam, s.px_a, cam, s.px_b, TwoViewOptions());
  EXPECT_FALSE(r.estimate.success);
  EXPECT_EQ(r.estimate.failure, TwoViewFailure::kTooFewMatches) << r.estimate.failure_reason;
  EXPECT_EQ(r.estimate.num_matches, 10);
  EXPECT_EQ(r.inlier_mask.size(), 10u);
}

TEST(TwoView, PureOutliersFail) {
  const Camera cam = Pinhole();
  const Scenario s = MakeScenario(cam, cam, TestPose(), 200, 0.3, 1.0, 6);
  const TwoViewResult r = EstimateRelativePose(cam, s.px_a, cam, s.px_b, TwoViewOptions());
  EXPECT_FALSE(r.estimate.success);
  EXPECT_NE(r.estimate.failure, TwoViewFailure::kNone);
  EXPECT_FALSE(r.estimate.failure_reason.empty());
}

TEST(TwoView, Deterministic) {
  const Camera cam = Pinhole();
  const Scenario s = MakeScenario(cam, cam, TestPose(), 300, 0.5, 0.3, 7);
  const TwoViewResult a = EstimateRelativePose(cam, s.px_a, cam, s.px_b, TwoViewOptions());
  const TwoViewResult b = EstimateRelativePose(cam, s.px_a, cam, s.px_b, TwoViewOptions());
  EXPECT_EQ(a.inlier_mask, b.inlier_mask);
  EXPECT_EQ(a.estimate.cam_b_from_cam_a.rotation.coeffs(), b.estimate.cam_b_from_cam_a.rotation.coeffs());
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
  EXPECT_FALSE(r.estimate.success);
  EXPECT_EQ(r.estimate.failure, TwoViewFailure::kTooFewInliers) << r.estimate.failure_reason;
}

}  // namespace
}  // namespace rigsim
