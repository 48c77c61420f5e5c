// Robust translation averaging: positions from unit directions between them, up to one global
// scale, in the Least Unsquared Deviations form (Ozyesil & Singer, "Robust camera location
// estimation by convex programming", CVPR 2015):
//
//   minimise  sum_e w_e || A_e x - s_e v_e ||   over x and the scales s_e >= 1,
//
// where A_e x is the difference of two positions that the direction v_e (unit) says they differ
// by. The unsquared norm makes a wrong direction pull with a bounded force (an L1 fit over the
// constraints), and s_e >= 1 fixes the scale and the sign without the collapse to zero that a
// homogeneous least-squares fit falls into when a camera is weakly tied. Solved by iteratively
// re-weighted least squares: each round is one small linear solve.
//
// Generic over what the positions are: each constraint's difference is a sum of 3x3 blocks times
// 3-vector unknowns (a camera centre in the rig, a rig centre in the world, ...).
#pragma once

#include <utility>
#include <vector>

#include <Eigen/Core>

namespace rigsim {

struct DirectionConstraint {
  // A_e x = sum of matrix * x[3 block .. 3 block + 2] over the terms.
  std::vector<std::pair<int, Eigen::Matrix3d>> terms;
  Eigen::Vector3d direction = Eigen::Vector3d::UnitX();  // unit
  double weight = 1.0;
};

struct TranslationAveragingOptions {
  // Re-weighting rounds.
  int iterations = 100;
  // Residuals (in units of the smallest difference) below this weigh as this: the IRLS weight
  // 1 / |residual| is bounded.
  double min_residual = 1e-4;
};

struct TranslationAveragingResult {
  Eigen::VectorXd x;  // 3 * num_blocks
  // Per constraint: the angle (deg) between A_e x and its direction at the solution; 180 for a
  // difference of zero length.
  std::vector<double> residual_deg;
};

// Throws std::invalid_argument on a block index out of range or a direction that is not unit.
TranslationAveragingResult AverageTranslations(int num_blocks, const std::vector<DirectionConstraint>& constraints,
                                               const TranslationAveragingOptions& options = {});

}  // namespace rigsim
