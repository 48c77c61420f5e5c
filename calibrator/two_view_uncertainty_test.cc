#include "calibrator/two_view_uncertainty.h"

#include <cmath>
#include <random>

#include <gtest/gtest.h>

#include "calibrator/evaluation.h"
#include "calibrator/two_view.h"

namespace rigsim {
namespace {

const Rigid3d kTruth(Eigen::Quaterniond(Eigen::AngleAxisd(DegToRad(20.0), Eigen::Vector3d(0.1, 1.0, 0.0).normalized())),
                     Eigen::Vector3d(-1.0, 0.05, 0.2).normalized());

// Bearings of points in A's view within `half_angle_deg` of `centre` (A's frame), 3-12 m away, seen
// by B under kTruth, both with angular noise `noise_rad`.
void Observe(const Eigen::Vector3d& centre, double half_angle_deg, double noise_rad, int n, unsigned seed,
             std::vector<Eigen::Vector3d>* fa, std::vector<Eigen::Vector3d>* fb) {
  std::mt19937 rng(seed);
  std::normal_distribution<double> gauss(0.0, 1.0);
  std::uniform_real_distribution<double> depth(3.0, 12.0);
  const auto noisy = [&](const Eigen::Vector3d& v) {
    return (v.normalized() + noise_rad * Eigen::Vector3d(gauss(rng), gauss(rng), gauss(rng))).normalized();
  };
  while (static_cast<int>(fa->size()) < n) {
    const Eigen::Vector3d dir = (centre.normalized() + std::tan(DegToRad(half_angle_deg)) *
                                                           Eigen::Vector3d(gauss(rng), gauss(rng), gauss(rng)) / 2.0)
                                    .normalized();
    if (std::acos(dir.dot(centre.normalized())) > DegToRad(half_angle_deg)) continue;
    const Eigen::Vector3d x = depth(rng) * dir;
    const Eigen::Vector3d xb = kTruth * x;
    if (xb.z() <= 0.2 * xb.norm()) continue;
    fa->push_back(noisy(x));
    fb->push_back(noisy(xb));
  }
}

std::vector<int> All(size_t n) {
  std::vector<int> v(n);
  for (size_t i = 0; i < n; ++i) v[i] = static_cast<int>(i);
  return v;
}

// The deviations the Jacobian predicts are the spread of the refined poses over noise draws.
TEST(TwoViewUncertainty, PredictsTheSpreadOfTheRefinedPose) {
  constexpr double kNoise = 1e-3;  // rad, about a pixel at f = 1000
  double sum_rot_sq = 0.0, sum_dir_sq = 0.0, predicted_rot = 0.0, predicted_dir = 0.0;
  constexpr int kDraws = 40;
  for (int d = 0; d < kDraws; ++d) {
    std::vector<Eigen::Vector3d> fa, fb;
    Observe(Eigen::Vector3d(0, 0, 1), 35.0, kNoise, 200, 100u + d, &fa, &fb);
    const Rigid3d refined = RefineRelativePose(fa, fb, kTruth, 10 * kNoise, 50);
    const TwoViewUncertainty u = EstimateTwoViewUncertainty(refined, fa, fb, All(fa.size()));
    sum_rot_sq += std::pow(RotationErrorDeg(refined, kTruth), 2);
    sum_dir_sq += std::pow(TranslationDirectionErrorDeg(refined, kTruth).value(), 2);
    predicted_rot += u.rotation_std_deg / kDraws;
    predicted_dir += u.direction_std_deg / kDraws;
  }
  // The errors are norms over 3 (rotation) and 2 (direction) axes, the deviations the largest
  // axis's: the RMS error lies between one and sqrt(axes) times the largest deviation.
  const double rms_rot = std::sqrt(sum_rot_sq / kDraws), rms_dir = std::sqrt(sum_dir_sq / kDraws);
  std::printf("rotation: rms error %.4f deg, predicted std %.4f; direction: rms error %.3f deg, predicted std %.3f\n",
              rms_rot, predicted_rot, rms_dir, predicted_dir);
  EXPECT_GT(rms_rot, 0.5 * predicted_rot);
  EXPECT_LT(rms_rot, 2.0 * std::sqrt(3.0) * predicted_rot);
  EXPECT_GT(rms_dir, 0.5 * predicted_dir);
  EXPECT_LT(rms_dir, 2.0 * std::sqrt(2.0) * predicted_dir);
}

// A small shared view (the corner two cameras of a ring both see) fixes the pose far less well than
// a wide one with the same number of matches.
TEST(TwoViewUncertainty, ASmallSharedViewFixesThePoseLessWell) {
  std::vector<Eigen::Vector3d> wide_a, wide_b, small_a, small_b;
  Observe(Eigen::Vector3d(0, 0, 1), 35.0, 1e-3, 150, 7u, &wide_a, &wide_b);
  Observe(Eigen::Vector3d(-0.3, 0, 1), 3.0, 1e-3, 150, 7u, &small_a, &small_b);
  const TwoViewUncertainty wide = EstimateTwoViewUncertainty(kTruth, wide_a, wide_b, All(wide_a.size()));
  const TwoViewUncertainty small = EstimateTwoViewUncertainty(kTruth, small_a, small_b, All(small_a.size()));
  EXPECT_GT(small.rotation_std_deg, 10 * wide.rotation_std_deg);
  EXPECT_GT(small.direction_std_deg, 10 * wide.direction_std_deg);
}

TEST(TwoViewUncertainty, TooFewInliersAreUndetermined) {
  std::vector<Eigen::Vector3d> fa, fb;
  Observe(Eigen::Vector3d(0, 0, 1), 35.0, 1e-3, 10, 3u, &fa, &fb);
  const TwoViewUncertainty u = EstimateTwoViewUncertainty(kTruth, fa, fb, {0, 1});
  EXPECT_TRUE(std::isinf(u.rotation_std_deg));
  EXPECT_TRUE(std::isinf(u.direction_std_deg));
}

}  // namespace
}  // namespace rigsim
