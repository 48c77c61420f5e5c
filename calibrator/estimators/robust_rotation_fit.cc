#include "calibrator/estimators/robust_rotation_fit.h"

#include <algorithm>
#include <cmath>
#include <limits>

#include <ceres/ceres.h>
#include <ceres/manifold.h>

#include "calibrator/estimators/cost_functions.h"

namespace rigsim {

DropRounds FitDroppingOutliers(int num_measurements, int max_rounds, double outlier_threshold_deg,
                               const std::function<void(const std::vector<char>& outlier)>& fit,
                               const std::function<double(int)>& residual_deg) {
  DropRounds out;
  out.outlier.assign(num_measurements, 0);
  out.residual_deg.assign(num_measurements, std::numeric_limits<double>::quiet_NaN());
  for (int round = 0; round < max_rounds; ++round) {
    out.rounds = round + 1;
    fit(out.outlier);
    int fresh = 0;
    for (int i = 0; i < num_measurements; ++i) {
      out.residual_deg[i] = residual_deg(i);
      if (!out.outlier[i] && out.residual_deg[i] > outlier_threshold_deg) {  // false for NaN
        out.outlier[i] = 1;
        ++fresh;
      }
    }
    out.num_outliers += fresh;
    if (fresh == 0) break;
  }
  return out;
}

void RefineRotations(const std::vector<int>& inliers, const AddRotationTerm& add,
                     const std::vector<std::pair<int, int>>& gauge, double loss_scale_deg, int max_iterations,
                     const std::vector<PerCamera<Eigen::Quaterniond>*>& groups) {
  if (inliers.empty()) return;
  std::vector<int> sorted(inliers.size());
  std::transform(inliers.begin(), inliers.end(), sorted.begin(), [](int w) { return std::max(1, w); });
  std::nth_element(sorted.begin(), sorted.begin() + sorted.size() / 2, sorted.end());
  const double median_weight = sorted[sorted.size() / 2];
  // Unknown rotations get a placeholder that no term uses.
  std::vector<std::vector<Eigen::Quaterniond>> values(groups.size());
  for (size_t g = 0; g < groups.size(); ++g) {
    values[g].assign(groups[g]->size(), Eigen::Quaterniond::Identity());
    for (size_t i = 0; i < groups[g]->size(); ++i) {
      if ((*groups[g])[i]) values[g][i] = *(*groups[g])[i];
    }
  }
  const RotationBlock block = [&](int g, int i) { return values[g][i].coeffs().data(); };
  ceres::Problem::Options problem_options;
  problem_options.manifold_ownership = ceres::TAKE_OWNERSHIP;
  problem_options.loss_function_ownership = ceres::TAKE_OWNERSHIP;
  ceres::Problem problem(problem_options);
  ceres::LossFunction* loss = new ceres::CauchyLoss(DegToRad(loss_scale_deg));
  for (size_t k = 0; k < inliers.size(); ++k) {
    add(problem, loss, static_cast<int>(k), std::sqrt(std::max(1, inliers[k]) / median_weight), block);
  }
  for (size_t g = 0; g < groups.size(); ++g) {
    for (size_t i = 0; i < values[g].size(); ++i) {
      double* x = values[g][i].coeffs().data();
      if (!problem.HasParameterBlock(x)) continue;
      const bool fixed = std::find(gauge.begin(), gauge.end(), std::pair<int, int>(static_cast<int>(g), static_cast<int>(i))) != gauge.end();
      if (fixed) {
        problem.SetParameterBlockConstant(x);
      } else {
        problem.SetManifold(x, new ceres::EigenQuaternionManifold);
      }
    }
  }
  SolveRotationProblem(problem, max_iterations);
  for (size_t g = 0; g < groups.size(); ++g) {
    for (size_t i = 0; i < values[g].size(); ++i) {
      if ((*groups[g])[i]) (*groups[g])[i] = values[g][i].normalized();
    }
  }
}

}  // namespace rigsim
