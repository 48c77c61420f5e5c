#include "calibrator/estimators/match_significance.h"

#include <cmath>
#include <random>
#include <vector>

#include <gmock/gmock.h>
#include <gtest/gtest.h>

#include "testing/expect_error.h"

namespace rigsim {
namespace {

// n = 6 matches, samples of 5: C(6, 5) = 6 models, and the one match beyond the sample is an
// inlier with probability 1/2: 3 false alarms for k = 6; k = 5 (the sample alone) gives 6.
TEST(Log10FalseAlarms, CountsTheModelsTimesTheChanceOfTheirInliers) {
  EXPECT_NEAR(Log10FalseAlarms(6, 6, 0.5, 5), std::log10(3.0), 1e-12);
  EXPECT_NEAR(Log10FalseAlarms(6, 5, 0.5, 5), std::log10(6.0), 1e-12);
  EXPECT_NEAR(Log10FalseAlarms(6, 2, 0.5, 5), std::log10(6.0), 1e-12);
  EXPECT_THAT([] { Log10FalseAlarms(4, 4, 0.5, 5); }, ThrowsWith<std::invalid_argument>("n >= sample_size"));
  EXPECT_THAT([] { Log10FalseAlarms(10, 6, 0.0, 5); }, ThrowsWith<std::invalid_argument>("p must be in (0, 1)"));
}

// What the rule is for: with a match in 500 falling within the threshold by chance, 15 inliers of
// 100 matches are meaningful, and so are 60 of 3000; 30 of 3000 are what chance gives.
TEST(Log10FalseAlarms, WeighsTheInliersByTheMatchesTheyAreFoundAmong) {
  const double p = 0.002;
  EXPECT_LT(Log10FalseAlarms(100, 15, p, 5), -5);
  EXPECT_GT(Log10FalseAlarms(100, 9, p, 5), 0);
  EXPECT_GT(Log10FalseAlarms(3000, 30, p, 5), 0);
  EXPECT_LT(Log10FalseAlarms(3000, 60, p, 5), 0);
  // More inliers among as many matches, or as many among fewer, are less likely by chance.
  EXPECT_LT(Log10FalseAlarms(200, 25, p, 5), Log10FalseAlarms(200, 20, p, 5));
  EXPECT_LT(Log10FalseAlarms(200, 20, p, 5), Log10FalseAlarms(400, 20, p, 5));
}

// A residual of |x_i - y_j| for points spread evenly over [0, 1]: within 0.01 with probability
// about 0.02.
TEST(ChanceWithinThreshold, IsTheShareOfMismatchedPairsWithinTheThreshold) {
  std::mt19937 rng(3);
  std::uniform_real_distribution<double> u(0, 1);
  std::vector<double> x(500), y(500);
  for (int i = 0; i < 500; ++i) x[i] = u(rng), y[i] = u(rng);
  const double p = ChanceWithinThreshold(500, [&](int i, int j) { return std::abs(x[i] - y[j]); }, 0.01);
  EXPECT_GT(p, 0.016);
  EXPECT_LT(p, 0.024);
  // Points crowded into a tenth of the range are ten times as likely to fall within it.
  for (int i = 0; i < 500; ++i) x[i] = 0.1 * x[i], y[i] = 0.1 * y[i];
  EXPECT_GT(ChanceWithinThreshold(500, [&](int i, int j) { return std::abs(x[i] - y[j]); }, 0.01), 0.15);
  // A true correspondence (i with i) is never drawn.
  EXPECT_LT(ChanceWithinThreshold(500, [&](int i, int j) { return i == j ? 0.0 : 1.0; }, 0.5), 1e-3);
}

}  // namespace
}  // namespace rigsim
