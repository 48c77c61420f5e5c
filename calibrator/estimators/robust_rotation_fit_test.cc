#include "calibrator/estimators/robust_rotation_fit.h"

#include <cmath>
#include <limits>

#include <ceres/ceres.h>
#include <gtest/gtest.h>

#include "calibrator/estimators/cost_functions.h"
#include "geometry/rigid3.h"

namespace rigsim {
namespace {

// Three measurements of one value, the fit their mean over those not dropped: the far one goes in
// the first round, the second round drops nothing and ends the rounds.
TEST(FitDroppingOutliers, DropsWhatExceedsTheThresholdAndFitsAgainWithoutIt) {
  const std::vector<double> m = {1.0, 1.2, 9.0};
  double mean = 0.0;
  int fits = 0;
  auto fit = [&](const std::vector<char>& outlier) {
    ++fits;
    double sum = 0.0;
    int n = 0;
    for (size_t i = 0; i < m.size(); ++i) {
      if (!outlier[i]) sum += m[i], ++n;
    }
    mean = sum / n;
  };
  const DropRounds r = FitDroppingOutliers(3, 4, 4.0, fit, [&](int i) { return std::abs(m[i] - mean); });
  EXPECT_EQ(r.outlier, (std::vector<char>{0, 0, 1}));
  EXPECT_EQ(r.num_outliers, 1);
  EXPECT_EQ(r.rounds, 2);
  EXPECT_EQ(fits, 2);
  EXPECT_NEAR(r.residual_deg[2], 7.9, 1e-12);  // measured at the last fit, dropped or not
}

TEST(FitDroppingOutliers, NeverDropsWhatCannotBeMeasuredAndStopsAtMaxRounds) {
  int fits = 0;
  const DropRounds r = FitDroppingOutliers(
      2, 3, 1.0, [&](const std::vector<char>&) { ++fits; },
      [&](int i) { return i == 0 ? std::numeric_limits<double>::quiet_NaN() : 2.0 * fits; });
  EXPECT_EQ(r.outlier, (std::vector<char>{0, 1}));
  EXPECT_TRUE(std::isnan(r.residual_deg[0]));
  EXPECT_EQ(r.rounds, 2);  // the second round drops nothing

  const DropRounds capped = FitDroppingOutliers(
      1, 1, 1.0, [](const std::vector<char>&) {}, [](int) { return 5.0; });
  EXPECT_EQ(capped.rounds, 1);
  EXPECT_EQ(capped.num_outliers, 1);
}

// Two cameras and one relative rotation: the gauge stays, the other camera takes the measured
// rotation, and an unknown rotation stays unknown.
TEST(RefineRotations, MovesTheFreeRotationsToTheMeasurementAndKeepsTheGauge) {
  const Eigen::Quaterniond measured(Eigen::AngleAxisd(0.3, Eigen::Vector3d(1, 2, 3).normalized()));
  PerCamera<Eigen::Quaterniond> rot = {Eigen::Quaterniond::Identity(), Eigen::Quaterniond::Identity(), std::nullopt};
  auto add = [&](ceres::Problem& problem, ceres::LossFunction* loss, int, double weight, const RotationBlock& block) {
    problem.AddResidualBlock(RelativeRotationCost::Create(measured, weight), loss, block(0, 0), block(0, 1));
  };
  RefineRotations({50}, add, {{0, 0}}, 2.0, 100, {&rot});
  ASSERT_TRUE(rot[0] && rot[1]);
  EXPECT_FALSE(rot[2].has_value());
  EXPECT_EQ(rot[0]->coeffs(), Eigen::Quaterniond::Identity().coeffs());
  EXPECT_LT(RotationDifferenceDeg(*rot[1], measured), 1e-6);
}

}  // namespace
}  // namespace rigsim
