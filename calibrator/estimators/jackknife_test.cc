#include "calibrator/estimators/jackknife.h"

#include <algorithm>
#include <cmath>
#include <cstdio>
#include <random>

#include <ceres/ceres.h>
#include <gtest/gtest.h>
#include <Eigen/Eigenvalues>
#include <Eigen/QR>

#include "calibrator/calibrator_test_support.h"
#include "calibrator/estimators/bundle_covariance.h"
#include "geometry/rigid3.h"
#include "testing/synthetic_rig.h"

namespace rigsim {
namespace {

// As Observe, but each point's keypoints are off by one offset of `feature_px` per coordinate in
// every view that sees it (a detector's bias on that feature's texture), beside `noise_px` of
// their own.
FrameKeypoints ObserveWithFeatureBias(const TwoCameraDrive& d, double feature_px, double noise_px, std::mt19937& rng) {
  std::normal_distribution<double> unit(0.0, 1.0);
  std::vector<Eigen::Vector2d> bias;
  for (size_t i = 0; i < d.points.size(); ++i) bias.emplace_back(feature_px * unit(rng), feature_px * unit(rng));
  FrameKeypoints kp = ObserveTwoCameraDrive(d, noise_px, rng);
  for (auto& frame : kp) {
    for (auto& view : frame) {
      for (size_t i = 0; i < view.size(); ++i) view[i] += bias[i];
    }
  }
  return kp;
}

// As Observe, but the keypoints of every point in one cell of a 5 x 4 grid over the field (x, z)
// are off by one offset of `region_px` per coordinate, the cell's own (one facade's texture, one
// viewing angle), beside `noise_px` of their own.
FrameKeypoints ObserveWithRegionBias(const TwoCameraDrive& d, double region_px, double noise_px, std::mt19937& rng) {
  std::normal_distribution<double> unit(0.0, 1.0);
  std::vector<Eigen::Vector2d> bias;
  for (int cell = 0; cell < 20; ++cell) bias.emplace_back(region_px * unit(rng), region_px * unit(rng));
  FrameKeypoints kp = ObserveTwoCameraDrive(d, noise_px, rng);
  for (size_t i = 0; i < d.points.size(); ++i) {
    const Eigen::Vector3d& p = d.points[i];
    const int cx = std::clamp(static_cast<int>((p.x() + 4.0) / 11.0 * 5.0), 0, 4);
    const int cz = std::clamp(static_cast<int>((p.z() - 4.0) / 8.0 * 4.0), 0, 3);
    for (auto& frame : kp) {
      for (auto& view : frame) view[i] += bias[cz * 5 + cx];
    }
  }
  return kp;
}

struct Solved {
  MultiFrameBundleAdjustmentResult ba;
  JackknifeSpread jackknife;
  JackknifeSpread points;
};

Solved SolveAndJackknife(const TwoCameraDrive& d, const FrameKeypoints& kp,
                         const RigBundleAdjustmentOptions& options = RigBundleAdjustmentOptions()) {
  Solved s;
  s.ba = MultiFrameRigBundleAdjust(d.cameras, kp, d.tracks, d.truth, 1, options);
  s.jackknife = s.ba.frame_jackknife;
  s.points = s.ba.point_jackknife;
  return s;
}

// cam1's rotation error against the truth, as a rotation vector (deg).
Eigen::Vector3d RotationErrorDeg(const Solved& s, const TwoCameraDrive& d) {
  const Eigen::AngleAxisd e(s.ba.poses.cam_from_rig[1]->rotation * d.truth.cam_from_rig[1]->rotation.inverse());
  return RadToDeg(e.angle()) * e.axis();
}

// The root mean square of `errors` (about zero, the truth) along their worst axis.
double WorstAxisRms(const std::vector<Eigen::Vector3d>& errors) {
  Eigen::Matrix3d scatter = Eigen::Matrix3d::Zero();
  for (const Eigen::Vector3d& v : errors) scatter += v * v.transpose() / static_cast<double>(errors.size());
  return std::sqrt(Eigen::SelfAdjointEigenSolver<Eigen::Matrix3d>(scatter).eigenvalues().maxCoeff());
}

// (m - 1) / m times the scatter of `samples` about their mean: its worst axis's standard deviation.
double JackknifeStd(const std::vector<Eigen::Vector3d>& samples) {
  const double m = static_cast<double>(samples.size());
  Eigen::Vector3d mean = Eigen::Vector3d::Zero();
  for (const Eigen::Vector3d& x : samples) mean += x / m;
  Eigen::Matrix3d scatter = Eigen::Matrix3d::Zero();
  for (const Eigen::Vector3d& x : samples) scatter += (m - 1.0) / m * (x - mean) * (x - mean).transpose();
  return std::sqrt(Eigen::SelfAdjointEigenSolver<Eigen::Matrix3d>(scatter).eigenvalues().maxCoeff());
}

TEST(FrameJackknife, IsZeroOnExactObservations) {
  std::mt19937 rng(TestSeed());
  const TwoCameraDrive d = MakeTwoCameraDrive(4, rng);
  const Solved s = SolveAndJackknife(d, ObserveTwoCameraDrive(d, 0.0, rng));
  EXPECT_EQ(s.jackknife.groups_left_out, 4);
  EXPECT_FALSE(s.jackknife.rotation_std_deg[0].has_value());
  ASSERT_TRUE(s.jackknife.rotation_std_deg[1] && s.jackknife.direction_std_deg[1]);
  EXPECT_LT(*s.jackknife.rotation_std_deg[1], 1e-6);
  EXPECT_LT(*s.jackknife.direction_std_deg[1], 1e-6);
}

// An adjustment that holds every pose (a check whose every camera but the reference lost its
// pose) has no column to step in: each group's step is empty, and nothing reads a diagonal that
// is not there.
TEST(FrameJackknife, TakesNoStepWhereNothingIsAdjusted) {
  const BundleLinearisation nothing_free;
  NormalEquations normal;
  normal.reduced = Eigen::MatrixXd(0, 0);
  normal.reduced_gradient = Eigen::VectorXd(0);
  const std::vector<Eigen::VectorXd> steps = StepsWithoutGroups(nothing_free, normal, {}, 3, {});
  ASSERT_EQ(steps.size(), 3u);
  for (const Eigen::VectorXd& step : steps) EXPECT_EQ(step.size(), 0);
}

TEST(FrameJackknife, NeedsThreePosedFrames) {
  std::mt19937 rng(TestSeed());
  const TwoCameraDrive d = MakeTwoCameraDrive(2, rng);
  const Solved s = SolveAndJackknife(d, ObserveTwoCameraDrive(d, 0.3, rng));
  EXPECT_EQ(s.jackknife.groups_left_out, 0);
  EXPECT_FALSE(s.jackknife.rotation_std_deg[1].has_value());
}

// In one frame camera 1 sits 3 cm to the side, turned to see the scene's middle depth where it
// did (a mount that gives for a moment). Left out, that frame moves the camera by its share of the
// error, so the jackknife states about the error. The jolted frame is frame 0, whose leaving out
// hands the gauge to frame 1.
TEST(FrameJackknife, StatesTheErrorAJoltedFrameBrings) {
  std::mt19937 rng(TestSeed());
  const TwoCameraDrive d = MakeTwoCameraDrive(4, rng);
  const Rigid3d jolt(Eigen::AngleAxisd(-0.03 / 8.0, Eigen::Vector3d::UnitY()).toRotationMatrix(),
                     Eigen::Vector3d(-0.03, 0.0, 0.0));
  const Solved s = SolveAndJackknife(d, ObserveTwoCameraDrive(d, 0.2, rng, 0, jolt));
  ASSERT_TRUE(s.ba.centre_covariance[1] && s.jackknife.direction_std_deg[1]);
  const Eigen::Vector3d centre = s.ba.poses.cam_from_rig[1]->SourceOriginInTarget();
  const double error = AngleBetweenDeg(centre, d.truth.cam_from_rig[1]->SourceOriginInTarget());
  const double covariance = DirectionStdDeg(centre, *s.ba.centre_covariance[1]);
  std::printf("direction error %.4f deg, covariance %.4f deg, jackknife %.4f deg, RMS %.3f px\n", error, covariance,
              *s.jackknife.direction_std_deg[1], s.ba.reprojection_rms_px);
  EXPECT_GT(*s.jackknife.direction_std_deg[1], 0.5 * error);
  EXPECT_LT(*s.jackknife.direction_std_deg[1], 2.0 * error);
}

// Beyond ten posed frames, runs of consecutive frames leave together: ten adjustments, and a jolt
// in frame 0 (left out with frame 1, the gauge going to frame 2) is still stated.
TEST(FrameJackknife, LeavesOutRunsOfFramesBeyondTen) {
  std::mt19937 rng(TestSeed());
  const TwoCameraDrive d = MakeTwoCameraDrive(13, rng);
  const Rigid3d jolt(Eigen::AngleAxisd(-0.03 / 8.0, Eigen::Vector3d::UnitY()).toRotationMatrix(),
                     Eigen::Vector3d(-0.03, 0.0, 0.0));
  const Solved s = SolveAndJackknife(d, ObserveTwoCameraDrive(d, 0.2, rng, 0, jolt));
  EXPECT_EQ(s.jackknife.groups_left_out, 10);
  ASSERT_TRUE(s.jackknife.direction_std_deg[1]);
  const double error = AngleBetweenDeg(s.ba.poses.cam_from_rig[1]->SourceOriginInTarget(),
                                       d.truth.cam_from_rig[1]->SourceOriginInTarget());
  std::printf("direction error %.4f deg, jackknife %.4f deg\n", error, *s.jackknife.direction_std_deg[1]);
  EXPECT_GT(*s.jackknife.direction_std_deg[1], 0.5 * error);
  EXPECT_LT(*s.jackknife.direction_std_deg[1], 2.0 * error);
}

// The jackknife is the adjustments without each frame to first order: here they are run in full,
// each from the solution (frame 0 left out by swapping it with frame 1, which then holds the
// gauge), and their spread is the one stated. With a quadratic loss and no filtering, so that the
// same observations count with the same weights in both; the Huber loss's weights, which move
// with the fit, part them by up to 10 % on this drive.
TEST(FrameJackknife, AgreesWithTheAdjustmentsRunWithoutEachFrame) {
  std::mt19937 rng(TestSeed());
  constexpr int kFrames = 5;
  const TwoCameraDrive d = MakeTwoCameraDrive(kFrames, rng);
  const FrameKeypoints kp = ObserveTwoCameraDrive(d, 0.5, rng);
  RigBundleAdjustmentOptions options;
  options.loss_scale_px = 100.0;
  options.filter_rounds = 0;
  const Solved s = SolveAndJackknife(d, kp, options);
  ASSERT_TRUE(s.jackknife.rotation_std_deg[1] && s.jackknife.direction_std_deg[1]);
  std::vector<Eigen::Vector3d> turns, centres;
  for (int left_out = 0; left_out < kFrames; ++left_out) {
    const auto frame_of = [&](int k) { return left_out != 0 ? k : k == 0 ? 1 : k == 1 ? 0 : k; };
    FrameKeypoints swapped = kp;
    RigPoses start = s.ba.poses;
    if (left_out == 0) {
      std::swap(swapped[0], swapped[1]);
      std::swap(start.rig_from_world[0], start.rig_from_world[1]);
    }
    start.rig_from_world[frame_of(left_out)].reset();
    std::vector<ViewTrack> tracks;
    for (const ViewTrack& t : d.tracks) {
      ViewTrack kept;
      for (ViewObservation o : t.observations) {
        o.frame = frame_of(o.frame);
        if (o.frame != frame_of(left_out)) kept.observations.push_back(o);
      }
      if (kept.observations.size() >= 2) tracks.push_back(kept);
    }
    RigBundleAdjustmentOptions left_out_options = options;
    left_out_options.covariance = false;
    left_out_options.coarse_points = 0;
    const MultiFrameBundleAdjustmentResult a =
        MultiFrameRigBundleAdjust(d.cameras, swapped, tracks, start, 1, left_out_options);
    const Eigen::AngleAxisd turn(a.poses.cam_from_rig[1]->rotation * s.ba.poses.cam_from_rig[1]->rotation.inverse());
    turns.push_back(turn.angle() * turn.axis());
    centres.push_back(a.poses.cam_from_rig[1]->SourceOriginInTarget());
  }
  const double rotation = RadToDeg(JackknifeStd(turns));
  const Eigen::Vector3d centre = s.ba.poses.cam_from_rig[1]->SourceOriginInTarget();
  const double direction = RadToDeg(std::atan2(JackknifeStd(centres), centre.norm()));
  std::printf("rotation %.5f deg (run) against %.5f (stated); direction %.5f against %.5f\n", rotation,
              *s.jackknife.rotation_std_deg[1], direction, *s.jackknife.direction_std_deg[1]);
  EXPECT_NEAR(*s.jackknife.rotation_std_deg[1], rotation, 0.04 * rotation);
  EXPECT_NEAR(*s.jackknife.direction_std_deg[1], direction, 0.04 * direction);
}

// On independent keypoint errors the jackknife states the estimate's spread over noise draws, as
// the covariance does.
TEST(FrameJackknife, StatesTheSpreadOfIndependentErrors) {
  std::mt19937 rng(TestSeed());
  const TwoCameraDrive d = MakeTwoCameraDrive(6, rng);
  constexpr int kDraws = 24;
  std::vector<Eigen::Vector3d> errors;
  double stated = 0.0;
  for (int i = 0; i < kDraws; ++i) {
    const Solved s = SolveAndJackknife(d, ObserveTwoCameraDrive(d, 0.5, rng));
    ASSERT_TRUE(s.jackknife.rotation_std_deg[1]);
    errors.push_back(RotationErrorDeg(s, d));
    stated += *s.jackknife.rotation_std_deg[1] / kDraws;
  }
  const double spread = WorstAxisRms(errors);
  std::printf("rotation spread %.4f deg, jackknife %.4f deg\n", spread, stated);
  EXPECT_GT(stated, 0.6 * spread);
  EXPECT_LT(stated, 1.7 * spread);
}

// Where each feature's error is the same in all its views, the covariance, which counts every
// residual as independent, states the rotation too tightly; the jackknife over points, whose
// units are the features, states the estimate's spread over draws.
TEST(PointJackknife, StatesTheSpreadOfErrorsEachFeatureRepeatsInItsViews) {
  std::mt19937 rng(TestSeed());
  const TwoCameraDrive d = MakeTwoCameraDrive(4, rng);
  constexpr int kDraws = 24;
  std::vector<Eigen::Vector3d> errors;
  double stated = 0.0, covariance = 0.0;
  for (int i = 0; i < kDraws; ++i) {
    const Solved s = SolveAndJackknife(d, ObserveWithFeatureBias(d, 0.5, 0.05, rng));
    ASSERT_TRUE(s.points.rotation_std_deg[1] && s.ba.rotation_stddev_deg[1]);
    errors.push_back(RotationErrorDeg(s, d));
    stated += *s.points.rotation_std_deg[1] / kDraws;
    covariance += *s.ba.rotation_stddev_deg[1] / kDraws;
  }
  const double spread = WorstAxisRms(errors);
  std::printf("rotation spread %.4f deg, point jackknife %.4f deg, covariance %.4f deg\n", spread, stated, covariance);
  EXPECT_LT(covariance, 0.6 * spread) << "the case the covariance misses";
  EXPECT_GT(stated, 0.6 * spread);
  EXPECT_LT(stated, 1.7 * spread);
}

// One residual per block, linear in two unknowns of units far apart: a turn's tangent (2000 px
// per unit) and a principal point (1 px per px) that nearly mimics it. Each group's step must be
// where the least-squares fit without its rows goes; cut at 1e-12 of the raw system's largest
// eigenvalue, the weak mode of the two took no step at all.
struct LinearRow {
  double a0, a1, y;
  template <typename T>
  bool operator()(const T* x0, const T* x1, T* residual) const {
    residual[0] = T(a0) * x0[0] + T(a1) * x1[0] - T(y);
    return true;
  }
};

TEST(StepsWithoutGroups, FollowAWeakModeOfColumnsInOtherUnits) {
  constexpr int kRows = 1000, kGroups = 10;
  std::mt19937 rng(11);
  std::uniform_real_distribution<double> side(-1, 1);
  std::normal_distribution<double> noise(0, 0.5);
  Eigen::MatrixXd a(kRows, 2);
  Eigen::VectorXd y(kRows);
  for (int i = 0; i < kRows; ++i) {
    const double x = side(rng);
    a(i, 0) = 2000.0 * (1.0 + 0.3 * x * x);
    a(i, 1) = a(i, 0) / 2000.0 + 1e-4 * side(rng);
    y[i] = noise(rng);
  }
  const auto fit = [&](int without) {
    std::vector<int> rows;
    for (int i = 0; i < kRows; ++i) {
      if (i % kGroups != without) rows.push_back(i);
    }
    Eigen::MatrixXd as(rows.size(), 2);
    Eigen::VectorXd ys(rows.size());
    for (size_t k = 0; k < rows.size(); ++k) {
      as.row(k) = a.row(rows[k]);
      ys[k] = y[rows[k]];
    }
    return Eigen::Vector2d(as.householderQr().solve(ys));
  };
  const Eigen::Vector2d solved = fit(-1);
  double x0 = solved[0], x1 = solved[1];
  ceres::Problem problem;
  for (int i = 0; i < kRows; ++i) {
    problem.AddResidualBlock(new ceres::AutoDiffCostFunction<LinearRow, 1, 1, 1>(new LinearRow{a(i, 0), a(i, 1), y[i]}),
                             nullptr, &x0, &x1);
  }
  const BundleLinearisation linearised = Linearise(problem, {&x0, &x1});
  std::vector<int> block_group(kRows);
  for (int i = 0; i < kRows; ++i) block_group[i] = i % kGroups;
  const std::vector<Eigen::VectorXd> steps =
      StepsWithoutGroups(linearised, NormalEquationsOf(linearised), block_group, kGroups, {});
  ASSERT_EQ(steps.size(), static_cast<size_t>(kGroups));
  for (int g = 0; g < kGroups; ++g) {
    const Eigen::Vector2d expected = fit(g) - solved;
    EXPECT_NEAR(steps[g][1], expected[1], 1e-4 * std::abs(expected[1])) << g;
    EXPECT_NEAR(steps[g][0], expected[0], 1e-4 * std::abs(expected[0]) + 1e-15) << g;
  }
}

TEST(PointJackknife, RegionGroupsAreContiguousAndEven) {
  std::vector<Eigen::Vector3d> points;
  for (int i = 0; i < 1000; ++i) points.emplace_back(0.01 * (i * 37 % 1000), 0.001 * (i % 7), 5.0);
  const std::vector<int> group = JackknifeRegionGroups(points);
  std::vector<double> low(kJackknifePointGroups, 1e9), high(kJackknifePointGroups, -1e9);
  std::vector<int> count(kJackknifePointGroups, 0);
  for (size_t i = 0; i < points.size(); ++i) {
    ASSERT_GE(group[i], 0);
    ASSERT_LT(group[i], kJackknifePointGroups);
    ++count[group[i]];
    low[group[i]] = std::min(low[group[i]], points[i].x());
    high[group[i]] = std::max(high[group[i]], points[i].x());
  }
  // Points along x (their widest axis): ten runs of a hundred, one after the other.
  for (int g = 0; g < kJackknifePointGroups; ++g) {
    EXPECT_EQ(count[g], 100) << g;
    if (g > 0) {
      EXPECT_LT(high[g - 1], low[g]) << g;
    }
  }
}

// Where the features of one part of the scene share their error (each cell of the field its own
// offset), every tenth point leaves each cell's share in every group and states next to nothing;
// the groups by region leave whole cells out, and the point jackknife (the larger of the two)
// states the estimate's spread over draws.
TEST(PointJackknife, StatesTheSpreadOfErrorsThePointsOfARegionShare) {
  std::mt19937 rng(TestSeed());
  const TwoCameraDrive d = MakeTwoCameraDrive(4, rng);
  constexpr int kDraws = 24;
  std::vector<Eigen::Vector3d> errors;
  double stated = 0.0;
  for (int i = 0; i < kDraws; ++i) {
    const Solved s = SolveAndJackknife(d, ObserveWithRegionBias(d, 0.3, 0.05, rng));
    ASSERT_TRUE(s.points.rotation_std_deg[1]);
    errors.push_back(RotationErrorDeg(s, d));
    stated += *s.points.rotation_std_deg[1] / kDraws;
  }
  const double spread = WorstAxisRms(errors);
  std::printf("rotation spread %.4f deg, point jackknife %.4f deg\n", spread, stated);
  EXPECT_GT(stated, 0.6 * spread);
  EXPECT_LT(stated, 1.7 * spread);
}

}  // namespace
}  // namespace rigsim
