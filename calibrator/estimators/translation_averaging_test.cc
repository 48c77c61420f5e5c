#include "calibrator/estimators/translation_averaging.h"

#include <cmath>
#include <random>
#include <stdexcept>

#include <gtest/gtest.h>

#include <Eigen/Geometry>

namespace rigsim {
namespace {

// Positions 1..n-1 free, position 0 at the origin (not an unknown): block i-1 is position i.
DirectionConstraint Between(int a, int b, const Eigen::Vector3d& direction) {
  DirectionConstraint c;
  if (b > 0) c.terms.emplace_back(b - 1, Eigen::Matrix3d::Identity());
  if (a > 0) c.terms.emplace_back(a - 1, -Eigen::Matrix3d::Identity());
  c.direction = direction.normalized();
  return c;
}

// Ten positions, every pair's direction, a fifth of them pointing anywhere: the unsquared fit
// barely feels the wrong ones and returns the shape up to one scale within a few percent (a start
// for the bundle adjustment), the wrong ones standing out by their residuals.
TEST(AverageTranslations, RecoversTheShapeDespiteAFifthOfWrongDirections) {
  std::mt19937 rng(7);
  std::normal_distribution<double> g(0, 1);
  const int n = 10;
  std::vector<Eigen::Vector3d> truth(n, Eigen::Vector3d::Zero());
  for (int i = 1; i < n; ++i) truth[i] = Eigen::Vector3d(g(rng), g(rng), g(rng));
  std::vector<DirectionConstraint> constraints;
  std::vector<bool> wrong;
  int k = 0;
  for (int a = 0; a < n; ++a) {
    for (int b = a + 1; b < n; ++b, ++k) {
      const bool bad = k % 5 == 2;
      const Eigen::Vector3d d = bad ? Eigen::Vector3d(g(rng), g(rng), g(rng)) : Eigen::Vector3d(truth[b] - truth[a]);
      constraints.push_back(Between(a, b, d));
      wrong.push_back(bad);
    }
  }
  const TranslationAveragingResult r = AverageTranslations(n - 1, constraints);
  double num = 0.0, den = 0.0;  // the least-squares scale
  for (int i = 1; i < n; ++i) {
    num += r.x.segment<3>(3 * (i - 1)).dot(truth[i]);
    den += truth[i].squaredNorm();
  }
  const double scale = num / den;
  ASSERT_GT(scale, 0.0);
  for (int i = 1; i < n; ++i) {
    EXPECT_LT((r.x.segment<3>(3 * (i - 1)) / scale - truth[i]).norm(), 0.03 * truth[i].norm()) << i;
  }
  for (size_t e = 0; e < constraints.size(); ++e) {
    EXPECT_EQ(r.residual_deg[e] > 5.0, wrong[e]) << e << ": " << r.residual_deg[e] << " deg";
  }
}

// A chain of directions only: each constraint alone, and the sign comes from the directions (no
// collapse to zero, no mirror image).
TEST(AverageTranslations, ChainKeepsSignAndScale) {
  const std::vector<Eigen::Vector3d> truth = {{0, 0, 0}, {1, 0, 0}, {1, 2, 0}, {1, 2, 3}};
  std::vector<DirectionConstraint> constraints;
  for (int i = 0; i + 1 < 4; ++i) constraints.push_back(Between(i, i + 1, truth[i + 1] - truth[i]));
  const TranslationAveragingResult r = AverageTranslations(3, constraints);
  for (int i = 0; i + 1 < 4; ++i) {
    const Eigen::Vector3d a = i == 0 ? Eigen::Vector3d::Zero() : Eigen::Vector3d(r.x.segment<3>(3 * (i - 1)));
    const Eigen::Vector3d d = r.x.segment<3>(3 * i) - a;
    EXPECT_GT(d.normalized().dot((truth[i + 1] - truth[i]).normalized()), 1 - 1e-9) << i;
    EXPECT_GT(d.norm(), 1.0 - 1e-6);
  }
}

TEST(AverageTranslations, BadInputThrows) {
  DirectionConstraint c;
  c.terms.emplace_back(3, Eigen::Matrix3d::Identity());
  EXPECT_THROW(AverageTranslations(2, {c}), std::invalid_argument);
  c.terms[0].first = 0;
  c.direction = Eigen::Vector3d(2, 0, 0);
  EXPECT_THROW(AverageTranslations(2, {c}), std::invalid_argument);
}

}  // namespace
}  // namespace rigsim
