// The skeleton the two rotation averagers (rotation_averaging.h, rig_rotation_averaging.h) share:
// rounds of fit, residuals and outliers dropped, and inside a round the weighted Ceres refinement of
// the known rotations. Internal to the estimators.
#pragma once

#include <functional>
#include <optional>
#include <utility>
#include <vector>

#include <Eigen/Geometry>

#include "calibrator/model/rig_state.h"

namespace ceres {
class LossFunction;
class Problem;
}  // namespace ceres

namespace rigsim {

// The outcome of the drop-and-refit rounds, per measurement and in all.
struct DropRounds {
  std::vector<char> outlier;        // dropped
  std::vector<double> residual_deg;  // at the last fit; NaN where it cannot be measured
  int num_outliers = 0;
  int rounds = 0;
};

// Each round, `fit(outlier)` fits to the measurements not dropped yet, `residual_deg(i)` gives each
// measurement's residual at that fit (NaN where it cannot be measured), and those not dropped yet
// whose residual exceeds `outlier_threshold_deg` are dropped. Stops after a round that drops none,
// or after `max_rounds`.
DropRounds FitDroppingOutliers(int num_measurements, int max_rounds, double outlier_threshold_deg,
                               const std::function<void(const std::vector<char>& outlier)>& fit,
                               const std::function<double(int)>& residual_deg);

// Where rotation `index` of group `group` lives in the problem: its 4 coefficients (Eigen's order).
using RotationBlock = std::function<double*(int group, int index)>;
// Adds term `term`'s residual block under `loss` with the weight `weight` (RefineRotations).
using AddRotationTerm = std::function<void(ceres::Problem& problem, ceres::LossFunction* loss, int term, double weight,
                                           const RotationBlock& block)>;

// Refines the known rotations of every group (cameras, frames: PerFrame is the same type) in place,
// unknown ones staying unknown, under one Cauchy loss of scale `loss_scale_deg`. Term k weighs
// sqrt(inliers[k] / median inliers), counting at least one inlier each: a relative rotation's
// variance falls as 1 / inliers. The rotations named in `gauge` ((group, index)) are held fixed, the
// others move on the unit-quaternion manifold. Does nothing without terms.
void RefineRotations(const std::vector<int>& inliers, const AddRotationTerm& add,
                     const std::vector<std::pair<int, int>>& gauge, double loss_scale_deg, int max_iterations,
                     const std::vector<PerCamera<Eigen::Quaterniond>*>& groups);

}  // namespace rigsim
