#include "calibrator/estimators/translation_averaging.h"

#include <algorithm>
#include <cmath>
#include <stdexcept>
#include <string>

#include <Eigen/Cholesky>
#include <Eigen/Geometry>

namespace rigsim {
namespace {

Eigen::Vector3d Difference(const DirectionConstraint& c, const Eigen::VectorXd& x) {
  Eigen::Vector3d d = Eigen::Vector3d::Zero();
  for (const auto& [block, m] : c.terms) d += m * x.segment<3>(3 * block);
  return d;
}

}  // namespace

TranslationAveragingResult AverageTranslations(int num_blocks, const std::vector<DirectionConstraint>& constraints,
                                               const TranslationAveragingOptions& options) {
  if (num_blocks < 0) throw std::invalid_argument("AverageTranslations: negative number of blocks");
  for (const DirectionConstraint& c : constraints) {
    if (std::abs(c.direction.norm() - 1.0) > 1e-6 || !(c.weight > 0)) {
      throw std::invalid_argument("AverageTranslations: a direction must be unit and its weight > 0");
    }
    for (const auto& term : c.terms) {
      if (term.first < 0 || term.first >= num_blocks) {
        throw std::invalid_argument("AverageTranslations: block " + std::to_string(term.first) + " out of range");
      }
    }
  }
  const int dim = 3 * num_blocks;
  TranslationAveragingResult out;
  out.x = Eigen::VectorXd::Zero(dim);
  if (dim == 0 || constraints.empty()) {
    out.residual_deg.assign(constraints.size(), 180.0);
    return out;
  }
  // Each round minimises sum w_e |r_e|^2 for the current weights, where r_e = A_e x - s_e v_e with
  // s_e eliminated: a constraint whose difference reaches past length 1 along its direction is
  // "free" (s_e = v_e . A_e x, r_e = (I - v_e v_e^T) A_e x), the others sit at the bound (s_e = 1,
  // r_e = A_e x - v_e). Solving for x with s_e eliminated converges in a few rounds; alternating
  // between x and s_e crawls (each s_e moves only as far as its own constraint pulls it).
  std::vector<double> irls(constraints.size(), 1.0);
  std::vector<char> free(constraints.size(), 0);
  for (int iter = 0; iter < options.iterations; ++iter) {
    Eigen::MatrixXd normal = Eigen::MatrixXd::Zero(dim, dim);
    Eigen::VectorXd rhs = Eigen::VectorXd::Zero(dim);
    for (size_t e = 0; e < constraints.size(); ++e) {
      const DirectionConstraint& c = constraints[e];
      const double w = c.weight * irls[e];
      const Eigen::Matrix3d p =
          free[e] ? Eigen::Matrix3d(Eigen::Matrix3d::Identity() - c.direction * c.direction.transpose())
                  : Eigen::Matrix3d::Identity();
      for (const auto& [b1, m1] : c.terms) {
        if (!free[e]) rhs.segment<3>(3 * b1) += w * m1.transpose() * c.direction;
        for (const auto& [b2, m2] : c.terms) normal.block<3, 3>(3 * b1, 3 * b2) += w * m1.transpose() * p * m2;
      }
    }
    // Directions the constraints leave free (a block tied on one side only) get a tiny ridge
    // instead of an infinite solution: they stay where the others put them.
    normal.diagonal().array() += 1e-9 * std::max(normal.diagonal().maxCoeff(), 1e-300);
    out.x = normal.ldlt().solve(rhs);
    for (size_t e = 0; e < constraints.size(); ++e) {
      const DirectionConstraint& c = constraints[e];
      const Eigen::Vector3d d = Difference(c, out.x);
      const double along = c.direction.dot(d);
      free[e] = along > 1.0;
      irls[e] = 1.0 / std::max((d - std::max(1.0, along) * c.direction).norm(), options.min_residual);
    }
  }
  for (const DirectionConstraint& c : constraints) {
    const Eigen::Vector3d d = Difference(c, out.x);
    out.residual_deg.push_back(d.norm() > 0 ? std::atan2(d.cross(c.direction).norm(), d.dot(c.direction)) * 180.0 / M_PI
                                            : 180.0);
  }
  return out;
}

}  // namespace rigsim
