#include "calibrator/estimators/bundle_covariance.h"

#include <algorithm>
#include <cmath>
#include <functional>
#include <stdexcept>
#include <utility>
#include <vector>

#include <Eigen/Eigenvalues>
#include <ceres/ceres.h>

#include "calibrator/estimators/cost_functions.h"
#include "calibrator/model/rig_state.h"

namespace rigsim {

BundleLinearisation Linearise(ceres::Problem& problem, const std::vector<double*>& pose_blocks,
                              std::vector<ceres::ResidualBlockId> residual_blocks) {
  BundleLinearisation out;
  // The adjusted pose blocks first, in `pose_blocks` order, then the points. Ceres lists its
  // blocks in the order of their addresses, which differ from run to run: summed in that order
  // the reduced system, and so the covariance, would change in its last bits between runs. The
  // points live in one array, so their address order is their order there.
  std::vector<double*> all, poses, points;
  problem.GetParameterBlocks(&all);
  for (double* block : pose_blocks) {
    if (problem.HasParameterBlock(block) && !problem.IsParameterBlockConstant(block)) poses.push_back(block);
  }
  for (double* block : all) {
    if (problem.IsParameterBlockConstant(block)) continue;
    if (std::find(pose_blocks.begin(), pose_blocks.end(), block) == pose_blocks.end()) points.push_back(block);
  }
  std::sort(points.begin(), points.end(), std::less<double*>());
  for (double* block : poses) {
    out.offset[block] = out.pose_dim;
    out.pose_dim += problem.ParameterBlockTangentSize(block);
  }
  out.num_points = static_cast<int>(points.size());
  if (out.pose_dim == 0) return out;
  if (residual_blocks.empty()) problem.GetResidualBlocks(&residual_blocks);
  std::vector<double*> ordered = poses;
  ordered.insert(ordered.end(), points.begin(), points.end());
  QuietCeresLogs();
  ceres::Problem::EvaluateOptions evaluate;
  evaluate.parameter_blocks = ordered;
  evaluate.residual_blocks = residual_blocks;
  if (!problem.Evaluate(evaluate, nullptr, &out.residuals, nullptr, &out.jacobian)) {
    out.offset.clear();
    out.pose_dim = 0;
    return out;
  }
  for (size_t b = 0; b < residual_blocks.size(); ++b) {
    const int rows = problem.GetCostFunctionForResidualBlock(residual_blocks[b])->num_residuals();
    out.row_block.insert(out.row_block.end(), rows, static_cast<int>(b));
  }
  return out;
}

void ReadRow(const BundleLinearisation& linearised, int row, JacobianRow* out) {
  const ceres::CRSMatrix& jacobian = linearised.jacobian;
  const int pose_dim = linearised.pose_dim;
  out->pose.clear();
  out->point_entries.setZero();
  out->point = -1;
  for (int k = jacobian.rows[row]; k < jacobian.rows[row + 1]; ++k) {
    const int col = jacobian.cols[k];
    if (col < pose_dim) {
      out->pose.emplace_back(col, jacobian.values[k]);
    } else {
      out->point = (col - pose_dim) / 3;
      out->point_entries[(col - pose_dim) % 3] = jacobian.values[k];
    }
  }
}

namespace {

Eigen::MatrixXd EliminatePoints(const NormalEquations& normal) {
  Eigen::MatrixXd reduced = normal.h_poses;
  for (size_t p = 0; p < normal.h_point.size(); ++p) {
    if (normal.h_cross[p].empty()) continue;
    const Eigen::Matrix3d h_point_inv = PointPseudoInverse(normal.h_point[p]);
    for (const auto& [col_a, cross_a] : normal.h_cross[p]) {
      const Eigen::RowVector3d weighted = cross_a * h_point_inv;
      for (const auto& [col_b, cross_b] : normal.h_cross[p]) reduced(col_a, col_b) -= weighted.dot(cross_b);
    }
  }
  return reduced;
}

Eigen::VectorXd EliminatePointsFromGradient(const NormalEquations& normal) {
  Eigen::VectorXd reduced = normal.g_poses;
  for (size_t p = 0; p < normal.h_point.size(); ++p) {
    if (normal.h_cross[p].empty()) continue;
    const Eigen::Vector3d weighted = PointPseudoInverse(normal.h_point[p]) * normal.g_point[p];
    for (const auto& [col, cross] : normal.h_cross[p]) reduced[col] -= cross.dot(weighted.transpose());
  }
  return reduced;
}

}  // namespace

NormalEquations NormalEquationsOf(const BundleLinearisation& linearised) {
  NormalEquations out;
  const int pose_dim = linearised.pose_dim;
  out.h_poses = Eigen::MatrixXd::Zero(pose_dim, pose_dim);
  out.h_point.assign(linearised.num_points, Eigen::Matrix3d::Zero());
  out.h_cross.assign(linearised.num_points, {});
  out.g_poses = Eigen::VectorXd::Zero(pose_dim);
  out.g_point.assign(linearised.num_points, Eigen::Vector3d::Zero());
  JacobianRow row;
  for (int r = 0; r < linearised.jacobian.num_rows; ++r) {
    ReadRow(linearised, r, &row);
    const double residual = linearised.residuals[r];
    for (const auto& [col_a, a] : row.pose) {
      for (const auto& [col_b, b] : row.pose) out.h_poses(col_a, col_b) += a * b;
      out.g_poses[col_a] += a * residual;
    }
    if (row.point < 0) continue;
    out.h_point[row.point] += row.point_entries.transpose() * row.point_entries;
    out.g_point[row.point] += row.point_entries.transpose() * residual;
    for (const auto& [col, a] : row.pose) {
      out.h_cross[row.point].try_emplace(col, Eigen::RowVector3d::Zero()).first->second += a * row.point_entries;
    }
  }
  out.reduced = EliminatePoints(out);
  out.reduced_gradient = EliminatePointsFromGradient(out);
  return out;
}

Eigen::Matrix3d PointPseudoInverse(const Eigen::Matrix3d& h_point, double min_ratio) {
  const Eigen::SelfAdjointEigenSolver<Eigen::Matrix3d> eig(h_point);
  const double top = eig.eigenvalues().maxCoeff();
  Eigen::Vector3d inv = Eigen::Vector3d::Zero();
  for (int i = 0; i < 3; ++i) {
    if (eig.eigenvalues()[i] > min_ratio * top) inv[i] = 1.0 / eig.eigenvalues()[i];
  }
  return eig.eigenvectors() * inv.asDiagonal() * eig.eigenvectors().transpose();
}

Eigen::VectorXd EquilibratingScale(const Eigen::MatrixXd& system) {
  Eigen::VectorXd scale(system.rows());
  for (int i = 0; i < system.rows(); ++i) scale[i] = system(i, i) > 0 ? 1.0 / std::sqrt(system(i, i)) : 1.0;
  return scale;
}

ReducedCovariance PoseCovariance(const BundleLinearisation& linearised, const NormalEquations& normal) {
  ReducedCovariance out;
  const int pose_dim = linearised.pose_dim;
  if (pose_dim == 0) return out;
  out.offset = linearised.offset;
  // Pseudo-inverse of the reduced system: directions with (next to) no information get a variance
  // 1e12 times the best determined one's, instead of an infinity or a failure. The columns' units
  // differ by orders of magnitude (a turn moves the keypoints by twice the focal length per unit of
  // its tangent, a principal point by one pixel per pixel), so the system is equilibrated first:
  // against the raw system's largest eigenvalue, a real but weak mode of pixel-sized columns (the
  // principal points against the turns of a one-frame rig with refined intrinsics) fell below the
  // cut and was stated tens of times too tightly.
  const Eigen::VectorXd scale = EquilibratingScale(normal.reduced);
  const Eigen::MatrixXd reduced =
      scale.asDiagonal() * (0.5 * (normal.reduced + normal.reduced.transpose())) * scale.asDiagonal();
  const Eigen::SelfAdjointEigenSolver<Eigen::MatrixXd> eig(reduced);
  const double top = std::max(eig.eigenvalues().maxCoeff(), 1e-300);
  Eigen::VectorXd inv(pose_dim);
  for (int i = 0; i < pose_dim; ++i) inv[i] = 1.0 / std::max(eig.eigenvalues()[i], 1e-12 * top);
  out.covariance = scale.asDiagonal() * (eig.eigenvectors() * inv.asDiagonal() * eig.eigenvectors().transpose()) *
                   scale.asDiagonal();
  return out;
}

PerCamera<Eigen::Matrix3d> RotationCovariances(ceres::Problem& problem, const ReducedCovariance& reduced,
                                               const std::vector<Eigen::Vector4d>& cq, double variance) {
  PerCamera<Eigen::Matrix3d> out(cq.size());
  for (size_t c = 0; c < cq.size(); ++c) {
    const auto it = reduced.offset.find(cq[c].data());
    if (it == reduced.offset.end() || problem.ParameterBlockTangentSize(cq[c].data()) != 3) continue;
    out[c] = variance * reduced.covariance.block<3, 3>(it->second, it->second);
  }
  return out;
}

double RotationStdDevDeg(const Eigen::Matrix3d& tangent_covariance) {
  // Ceres' EigenQuaternionManifold turns by exp(delta) = [cos|d|, sin|d| d/|d|]: an angle of 2|d|.
  const double worst = Eigen::SelfAdjointEigenSolver<Eigen::Matrix3d>(tangent_covariance).eigenvalues().maxCoeff();
  return 2.0 * std::sqrt(std::max(worst, 0.0)) * 180.0 / M_PI;
}

PerCamera<double> RotationStdDevsDeg(ceres::Problem& problem, const ReducedCovariance& reduced,
                                     const std::vector<Eigen::Vector4d>& cq, double variance) {
  const PerCamera<Eigen::Matrix3d> tangent = RotationCovariances(problem, reduced, cq, variance);
  PerCamera<double> out(cq.size());
  for (size_t c = 0; c < cq.size(); ++c) {
    if (tangent[c]) out[c] = RotationStdDevDeg(*tangent[c]);
  }
  return out;
}

Eigen::MatrixXd HeldParameterSensitivity(const ReducedCovariance& reduced, const NormalEquations& with_held) {
  const int pose_dim = static_cast<int>(reduced.covariance.rows());
  const int held = static_cast<int>(with_held.reduced.rows()) - pose_dim;
  if (pose_dim == 0 || held <= 0) return Eigen::MatrixXd::Zero(pose_dim, std::max(held, 0));
  return -reduced.covariance * with_held.reduced.block(0, pose_dim, pose_dim, held);
}

ReducedCovariance HeldParameterCovariance(const ReducedCovariance& reduced, const NormalEquations& with_held,
                                          const Eigen::VectorXd& held_variance) {
  ReducedCovariance out;
  out.offset = reduced.offset;
  const Eigen::MatrixXd sensitivity = HeldParameterSensitivity(reduced, with_held);
  if (sensitivity.cols() != held_variance.size()) {
    throw std::invalid_argument("HeldParameterCovariance: one variance per held column");
  }
  out.covariance = sensitivity * held_variance.asDiagonal() * sensitivity.transpose();
  return out;
}

HeldShare HeldBlocksShare(ceres::Problem& problem, const ReducedCovariance& reduced, const std::vector<HeldBlock>& held,
                          const std::vector<Eigen::Vector4d>& cq, const std::vector<Eigen::Vector3d>& ct) {
  // The adjusted blocks in `reduced`'s column order, then the held ones: the linearisation's
  // first columns are then `reduced`'s.
  std::vector<std::pair<int, double*>> by_column;
  for (const auto& [block, column] : reduced.offset) by_column.emplace_back(column, const_cast<double*>(block));
  std::sort(by_column.begin(), by_column.end());
  std::vector<double*> blocks;
  for (const auto& [column, block] : by_column) blocks.push_back(block);
  std::vector<const HeldBlock*> freed;
  for (const HeldBlock& h : held) {
    if (!problem.HasParameterBlock(h.block) || !problem.IsParameterBlockConstant(h.block)) continue;
    problem.SetParameterBlockVariable(h.block);
    blocks.push_back(h.block);
    freed.push_back(&h);
  }
  const BundleLinearisation with_held = Linearise(problem, blocks);
  for (const HeldBlock* h : freed) problem.SetParameterBlockConstant(h->block);
  for (const auto& [block, column] : reduced.offset) {
    const auto it = with_held.offset.find(block);
    if (it == with_held.offset.end() || it->second != column) {
      throw std::logic_error("HeldBlocksShare: the adjusted blocks' columns moved");
    }
  }
  const int pose_dim = static_cast<int>(reduced.covariance.rows());
  Eigen::VectorXd variance = Eigen::VectorXd::Zero(std::max(with_held.pose_dim - pose_dim, 0));
  for (const HeldBlock* h : freed) {
    const int first = with_held.offset.at(h->block) - pose_dim;
    const int size = std::min<int>(h->sd.size(), problem.ParameterBlockTangentSize(h->block));
    for (int i = 0; i < size; ++i) variance[first + i] = h->sd[i] * h->sd[i];
  }
  const ReducedCovariance share = HeldParameterCovariance(reduced, NormalEquationsOf(with_held), variance);
  return {CentreCovariances(problem, share, cq, ct, 1.0, true), RotationCovariances(problem, share, cq, 1.0)};
}

void AddHeldShare(ceres::Problem& problem, const ReducedCovariance& reduced, const std::vector<Eigen::Vector4d>& cq,
                  double variance, const HeldShare& share, PerCamera<Eigen::Matrix3d>* centre_covariance,
                  PerCamera<double>* rotation_std_deg, PerCamera<double>* share_rotation_std_deg) {
  const PerCamera<Eigen::Matrix3d> data = RotationCovariances(problem, reduced, cq, variance);
  share_rotation_std_deg->assign(cq.size(), std::nullopt);
  for (size_t c = 0; c < cq.size(); ++c) {
    if (c < centre_covariance->size() && (*centre_covariance)[c] && c < share.centre_covariance.size() &&
        share.centre_covariance[c]) {
      *(*centre_covariance)[c] += *share.centre_covariance[c];
    }
    if (!data[c] || c >= share.rotation_covariance.size() || !share.rotation_covariance[c]) continue;
    if (c < rotation_std_deg->size()) (*rotation_std_deg)[c] = RotationStdDevDeg(*data[c] + *share.rotation_covariance[c]);
    (*share_rotation_std_deg)[c] = RotationStdDevDeg(*share.rotation_covariance[c]);
  }
}

PerCamera<Eigen::Matrix3d> CentreCovariances(ceres::Problem& problem, const ReducedCovariance& reduced,
                                                              const std::vector<Eigen::Vector4d>& cq,
                                                              const std::vector<Eigen::Vector3d>& ct, double variance,
                                                              bool with_rotation) {
  PerCamera<Eigen::Matrix3d> out(ct.size());
  const std::map<const double*, int>& offset = reduced.offset;
  const Eigen::MatrixXd& covariance = reduced.covariance;
  for (size_t c = 0; c < ct.size(); ++c) {
    const auto it = offset.find(ct[c].data());
    if (it == offset.end()) continue;
    const int size = problem.ParameterBlockTangentSize(ct[c].data());
    const Eigen::MatrixXd tangent = covariance.block(it->second, it->second, size, size);
    Eigen::Matrix3d t_cov = Eigen::Matrix3d::Zero();
    Eigen::Matrix<double, 3, Eigen::Dynamic, Eigen::RowMajor> plus = Eigen::MatrixXd::Identity(3, size);
    if (const ceres::Manifold* manifold = problem.GetManifold(ct[c].data())) {  // the scale camera: |t| held
      manifold->PlusJacobian(ct[c].data(), plus.data());
      t_cov = plus * tangent * plus.transpose();
    } else {
      t_cov = tangent;
    }
    const Eigen::Matrix3d r = Eigen::Quaterniond(cq[c].data()).toRotationMatrix();
    const auto q = offset.find(cq[c].data());
    if (!with_rotation || q == offset.end() || problem.ParameterBlockTangentSize(cq[c].data()) != 3) {
      out[c] = variance * r.transpose() * t_cov * r;  // C = -R^T t; R's own uncertainty is far smaller
      continue;
    }
    // Ceres' quaternion manifold turns R to exp([2 d]x) R, so C = -R^T t moves by -2 R^T [t]x d
    // through the rotation's tangent d, and by -R^T dt through t's.
    Eigen::Matrix3d t_cross;
    t_cross << 0, -ct[c].z(), ct[c].y(), ct[c].z(), 0, -ct[c].x(), -ct[c].y(), ct[c].x(), 0;
    Eigen::MatrixXd jacobian(3, 3 + size);
    jacobian << -2.0 * r.transpose() * t_cross, -r.transpose() * plus;
    Eigen::MatrixXd joint(3 + size, 3 + size);
    joint << covariance.block(q->second, q->second, 3, 3), covariance.block(q->second, it->second, 3, size),
        covariance.block(it->second, q->second, size, 3), tangent;
    out[c] = variance * jacobian * joint * jacobian.transpose();
  }
  return out;
}

double CorrelatedResidualFactor(const std::vector<LocatedResidual>& residuals) {
  // A grid needs enough regions for its sum to mean anything: over K regions the factor of
  // independent residuals scatters by sqrt(1 / K) about 1 (both coordinates pooled).
  constexpr int kMinRegions = 20;
  double factor = 1.0;
  for (const int cells : {2, 4, 8}) {
    // Region -> summed residual; std::map keeps the sums in one order on every machine.
    std::map<std::pair<int, int>, Eigen::Vector2d> sums;
    double squares = 0.0;
    for (const LocatedResidual& r : residuals) {
      const int cx = std::clamp(static_cast<int>(std::floor(r.position.x() * cells)), 0, cells - 1);
      const int cy = std::clamp(static_cast<int>(std::floor(r.position.y() * cells)), 0, cells - 1);
      sums.try_emplace({r.view, cy * cells + cx}, Eigen::Vector2d::Zero()).first->second += r.residual_px;
      squares += r.residual_px.squaredNorm();
    }
    if (static_cast<int>(sums.size()) < kMinRegions || !(squares > 0)) continue;
    double clustered = 0.0;
    for (const auto& [region, sum] : sums) clustered += sum.squaredNorm();
    factor = std::max(factor, clustered / squares);
  }
  return factor;
}

double ResidualDegreesOfFreedomFactor(int residuals, int parameters) {
  if (residuals <= parameters || parameters <= 0) return 1.0;
  return static_cast<double>(residuals) / static_cast<double>(residuals - parameters);
}

int FreeParameterCount(ceres::Problem& problem) {
  std::vector<double*> blocks;
  problem.GetParameterBlocks(&blocks);
  int free = 0;
  for (double* b : blocks) {
    if (!problem.IsParameterBlockConstant(b)) free += problem.ParameterBlockTangentSize(b);
  }
  return free;
}

double DirectionStdDeg(const Eigen::Vector3d& centre, const Eigen::Matrix3d& cov) {
  const double d = centre.norm();
  if (!(d > 0)) return 180.0;
  const Eigen::Vector3d u = centre / d;
  const Eigen::Matrix3d across = Eigen::Matrix3d::Identity() - u * u.transpose();
  const double spread = Eigen::SelfAdjointEigenSolver<Eigen::Matrix3d>(across * cov * across).eigenvalues().maxCoeff();
  return RadToDeg(std::atan2(std::sqrt(std::max(spread, 0.0)), d));
}

double PlacementDirectionStdDeg(const Eigen::Vector3d& centre, const Eigen::Matrix3d& cov,
                                const Eigen::Matrix3d* held_share, double residual_correlation) {
  if (!held_share) return DirectionStdDeg(centre, cov) / std::sqrt(residual_correlation);
  return DirectionStdDeg(centre, (cov - *held_share) / residual_correlation + *held_share);
}

}  // namespace rigsim
