// PoseCovariance (the points eliminated by hand) against Ceres's own covariance of the same blocks.
#include "calibrator/estimators/bundle_covariance.h"

#include <array>
#include <cmath>
#include <random>
#include <vector>

#include <Eigen/Geometry>
#include <Eigen/QR>
#include <ceres/ceres.h>
#include <ceres/rotation.h>
#include <gtest/gtest.h>

namespace rigsim {
namespace {

// A pinhole camera (focal 500 px) with an angle-axis rotation and a translation.
struct PinholeCost {
  Eigen::Vector2d observed;
  template <typename T>
  bool operator()(const T* rotation, const T* translation, const T* point, T* residual) const {
    T p[3];
    ceres::AngleAxisRotatePoint(rotation, point, p);
    for (int i = 0; i < 3; ++i) p[i] += translation[i];
    residual[0] = T(500) * p[0] / p[2] - T(observed.x());
    residual[1] = T(500) * p[1] / p[2] - T(observed.y());
    return true;
  }
};

TEST(PoseCovariance, MatchesCeresCovarianceOfTheSameBlocks) {
  constexpr int kCameras = 3;
  constexpr int kPoints = 40;
  std::array<std::array<double, 3>, kCameras> rotation = {{{0, 0, 0}, {0.02, 0.3, -0.01}, {-0.03, -0.25, 0.02}}};
  std::array<std::array<double, 3>, kCameras> translation = {{{0, 0, 0}, {-1, 0.05, 0.1}, {1, -0.1, 0.05}}};
  std::vector<std::array<double, 3>> points(kPoints);
  std::mt19937 rng(3);
  std::uniform_real_distribution<double> across(-3, 3), depth(6, 12);
  std::normal_distribution<double> noise(0, 0.5);
  for (auto& x : points) x = {across(rng), across(rng), depth(rng)};

  ceres::Problem problem;
  for (int c = 0; c < kCameras; ++c) {
    for (auto& x : points) {
      double p[3];
      ceres::AngleAxisRotatePoint(rotation[c].data(), x.data(), p);
      for (int i = 0; i < 3; ++i) p[i] += translation[c][i];
      // Noisy observations: the Jacobian at this (non-optimal) point is what both compute from.
      const Eigen::Vector2d observed(500 * p[0] / p[2] + noise(rng), 500 * p[1] / p[2] + noise(rng));
      problem.AddResidualBlock(new ceres::AutoDiffCostFunction<PinholeCost, 2, 3, 3, 3>(new PinholeCost{observed}),
                               nullptr, rotation[c].data(), translation[c].data(), x.data());
    }
  }
  // Gauge: camera 0 fixed, camera 1's translation fixed (the scale).
  problem.SetParameterBlockConstant(rotation[0].data());
  problem.SetParameterBlockConstant(translation[0].data());
  problem.SetParameterBlockConstant(translation[1].data());

  const std::vector<double*> poses = {rotation[0].data(), translation[0].data(), rotation[1].data(),
                                      translation[1].data(), rotation[2].data(), translation[2].data()};
  const BundleLinearisation linearised = Linearise(problem, poses);
  const ReducedCovariance reduced = PoseCovariance(linearised, NormalEquationsOf(linearised));
  ASSERT_EQ(reduced.covariance.rows(), 9) << "rotation 1, rotation 2 and translation 2 are adjusted";
  ASSERT_EQ(reduced.offset.size(), 3u);
  EXPECT_EQ(reduced.offset.count(translation[1].data()), 0u) << "a constant block has no column";

  ceres::Covariance::Options options;
  options.algorithm_type = ceres::DENSE_SVD;
  ceres::Covariance covariance(options);
  const std::vector<const double*> adjusted = {rotation[1].data(), rotation[2].data(), translation[2].data()};
  std::vector<std::pair<const double*, const double*>> blocks;
  for (const double* a : adjusted) {
    for (const double* b : adjusted) blocks.emplace_back(a, b);
  }
  ASSERT_TRUE(covariance.Compute(blocks, &problem));
  for (const double* a : adjusted) {
    for (const double* b : adjusted) {
      Eigen::Matrix<double, 3, 3, Eigen::RowMajor> expected;
      ASSERT_TRUE(covariance.GetCovarianceBlock(a, b, expected.data()));
      const Eigen::Matrix3d got = reduced.covariance.block<3, 3>(reduced.offset.at(a), reduced.offset.at(b));
      EXPECT_LT((got - expected).norm(), 1e-9 * (1 + expected.norm())) << "got\n" << got << "\nexpected\n" << expected;
    }
  }
}

// Two unknowns of a linear fit in units far apart, as a turn's tangent (2000 px per unit) and a
// principal point (1 px per px): each residual is the turn's shift (larger towards the image's
// sides) plus the principal point's shift, which nearly mimics a turn, as on a rig of one frame.
// The weak mode of the two is real, and its variance must be stated as it is: cut off at 1e-12
// of the raw system's largest eigenvalue (the turn's), it came out orders of magnitude too small.
TEST(PoseCovariance, StatesAWeakModeOfColumnsInOtherUnits) {
  constexpr int kRows = 1000;
  std::mt19937 rng(5);
  std::uniform_real_distribution<double> side(-1, 1);
  Eigen::MatrixXd a(kRows, 2);
  for (int i = 0; i < kRows; ++i) {
    const double x = side(rng);
    a(i, 0) = 2000.0 * (1.0 + 0.3 * x * x);
    a(i, 1) = a(i, 0) / 2000.0 + 1e-4 * side(rng);
  }
  BundleLinearisation linearised;
  linearised.pose_dim = 2;
  NormalEquations normal;
  normal.reduced = a.transpose() * a;
  const ReducedCovariance reduced = PoseCovariance(linearised, normal);
  // The exact inverse from the QR factors of the columns themselves: (R^T R)^-1.
  const Eigen::MatrixXd r = Eigen::HouseholderQR<Eigen::MatrixXd>(a).matrixQR().topRows(2).triangularView<Eigen::Upper>();
  const Eigen::MatrixXd r_inv = r.inverse();
  const Eigen::MatrixXd expected = r_inv * r_inv.transpose();
  EXPECT_NEAR(reduced.covariance(1, 1), expected(1, 1), 1e-6 * expected(1, 1));
  EXPECT_NEAR(reduced.covariance(0, 0), expected(0, 0), 1e-6 * expected(0, 0));
  EXPECT_NEAR(reduced.covariance(0, 1), expected(0, 1), 1e-6 * std::abs(expected(0, 1)));
}

// One rotation observed N times, each residual its angle-axis difference (rad) divided by s: the
// rotation's variance is s^2 / N about every axis. RotationStdDevsDeg reads Ceres' quaternion
// tangent (a turn of exp(delta), an angle of 2|delta|) as that angle, not half of it.
struct RotationDifferenceCost {
  Eigen::Quaterniond observed;
  double scale = 1.0;
  template <typename T>
  bool operator()(const T* q_xyzw, T* residual) const {
    const Eigen::Map<const Eigen::Quaternion<T>> q(q_xyzw);
    const Eigen::Quaternion<T> difference = q * observed.cast<T>().conjugate();
    const T wxyz[4] = {difference.w(), difference.x(), difference.y(), difference.z()};
    ceres::QuaternionToAngleAxis(wxyz, residual);
    for (int i = 0; i < 3; ++i) residual[i] /= T(scale);
    return true;
  }
};

TEST(RotationStdDevsDeg, IsTheAngleOfTheRotationNotOfTheQuaternion) {
  const Eigen::Quaterniond truth = Eigen::Quaterniond(Eigen::AngleAxisd(0.4, Eigen::Vector3d(1, 2, 3).normalized()));
  std::vector<Eigen::Vector4d> cq = {truth.coeffs()};
  constexpr int kObservations = 25;
  constexpr double kScale = 0.01;  // rad
  ceres::Problem problem;
  for (int i = 0; i < kObservations; ++i) {
    problem.AddResidualBlock(new ceres::AutoDiffCostFunction<RotationDifferenceCost, 3, 4>(
                                 new RotationDifferenceCost{truth, kScale}),
                             nullptr, cq[0].data());
  }
  problem.SetManifold(cq[0].data(), new ceres::EigenQuaternionManifold);
  const BundleLinearisation linearised = Linearise(problem, {cq[0].data()});
  const ReducedCovariance reduced = PoseCovariance(linearised, NormalEquationsOf(linearised));
  const PerCamera<double> std_deg = RotationStdDevsDeg(problem, reduced, cq, 1.0);
  ASSERT_TRUE(std_deg[0]);
  EXPECT_NEAR(*std_deg[0], kScale / std::sqrt(kObservations) * 180.0 / M_PI, 1e-9);
}

// 64 residuals in each of the 64 cells of an 8x8 grid over each of 3 images, with noise of 0.3 px
// and, per cell, a shared offset of `shared_px` (scaled by a fixed draw per cell).
std::vector<LocatedResidual> CellResiduals(double shared_px, uint32_t seed) {
  std::mt19937 rng(seed);
  std::normal_distribution<double> unit(0, 1);
  std::uniform_real_distribution<double> within(0, 1);
  std::vector<LocatedResidual> out;
  for (int view = 0; view < 3; ++view) {
    for (int cell = 0; cell < 64; ++cell) {
      const Eigen::Vector2d shared(shared_px * unit(rng), shared_px * unit(rng));
      for (int i = 0; i < 64; ++i) {
        const Eigen::Vector2d at((cell % 8 + within(rng)) / 8, (cell / 8 + within(rng)) / 8);
        out.push_back({view, at, shared + Eigen::Vector2d(0.3 * unit(rng), 0.3 * unit(rng))});
      }
    }
  }
  return out;
}

TEST(CorrelatedResidualFactor, IsAboutOneForIndependentResiduals) {
  const double factor = CorrelatedResidualFactor(CellResiduals(0.0, 5));
  EXPECT_GE(factor, 1.0);
  EXPECT_LT(factor, 1.3);
  EXPECT_EQ(CorrelatedResidualFactor({}), 1.0);
}

// Residuals that share an offset per cell count as far fewer independent ones: with a shared
// offset as large as the noise, the factor is (64 * 0.09 + 0.09) / (0.09 + 0.09), about 32.
TEST(CorrelatedResidualFactor, GrowsWithTheErrorTheResidualsOfARegionShare) {
  const double half = CorrelatedResidualFactor(CellResiduals(0.3, 5));
  EXPECT_GT(half, 20.0);
  EXPECT_GT(CorrelatedResidualFactor(CellResiduals(0.6, 5)), half);
}

TEST(ResidualDegreesOfFreedomFactor, CountsTheCoordinatesTheFitLeavesFree) {
  // 100 points seen twice (400 coordinates) and 5 pose dimensions: 95 coordinates left.
  EXPECT_DOUBLE_EQ(ResidualDegreesOfFreedomFactor(400, 305), 400.0 / 95.0);
  // Long tracks: almost every coordinate is free.
  EXPECT_NEAR(ResidualDegreesOfFreedomFactor(2000, 30), 1.015, 1e-3);
  // Nothing left to estimate the variance from, or nothing fitted: no scaling.
  EXPECT_EQ(ResidualDegreesOfFreedomFactor(10, 10), 1.0);
  EXPECT_EQ(ResidualDegreesOfFreedomFactor(10, 0), 1.0);
}

}  // namespace
}  // namespace rigsim
