#include "calibrator/two_view_uncertainty.h"

#include <cmath>
#include <limits>

#include <Eigen/Eigenvalues>
#include <Eigen/Geometry>

#include "calibrator/two_view.h"
#include "geometry/rigid3.h"

namespace rigsim {

namespace {

// The pose moved in its 5 degrees of freedom: a rotation vector (rad) applied in B's frame and a
// step (rad) of the unit translation across itself, along `across`'s columns.
Rigid3d Perturbed(const Rigid3d& pose, const Eigen::Matrix<double, 3, 2>& across, const Eigen::Matrix<double, 5, 1>& d) {
  const Eigen::Vector3d w = d.head<3>();
  const Eigen::Quaterniond dq = w.norm() > 0 ? Eigen::Quaterniond(Eigen::AngleAxisd(w.norm(), w.normalized()))
                                             : Eigen::Quaterniond::Identity();
  const Eigen::Vector3d t = (pose.translation.normalized() + across * d.tail<2>()).normalized();
  return Rigid3d((dq * pose.rotation).normalized(), t);
}

}  // namespace

TwoViewUncertainty EstimateTwoViewUncertainty(const Rigid3d& cam_b_from_cam_a, const std::vector<Eigen::Vector3d>& bearings_a,
                                              const std::vector<Eigen::Vector3d>& bearings_b,
                                              const std::vector<int>& inliers) {
  constexpr double kInf = std::numeric_limits<double>::infinity();
  TwoViewUncertainty out{kInf, kInf};
  const int n = static_cast<int>(inliers.size());
  if (n < 3 || cam_b_from_cam_a.translation.norm() == 0.0) return out;
  const Eigen::Vector3d t = cam_b_from_cam_a.translation.normalized();
  Eigen::Matrix<double, 3, 2> across;
  across.col(0) = t.unitOrthogonal();
  across.col(1) = t.cross(across.col(0));

  // Central differences: the residual is smooth and 5 parameters are cheap next to the fit.
  constexpr double kStep = 1e-6;
  Eigen::Matrix<double, 5, 5> jtj = Eigen::Matrix<double, 5, 5>::Zero();
  double sum_sq = 0.0;
  for (int i : inliers) {
    const Eigen::Vector3d& a = bearings_a[i];
    const Eigen::Vector3d& b = bearings_b[i];
    Eigen::Matrix<double, 2, 5> j;
    for (int k = 0; k < 5; ++k) {
      Eigen::Matrix<double, 5, 1> d = Eigen::Matrix<double, 5, 1>::Zero();
      d(k) = kStep;
      j.col(k) = (EpipolarAngularResidual(Perturbed(cam_b_from_cam_a, across, d), a, b) -
                  EpipolarAngularResidual(Perturbed(cam_b_from_cam_a, across, -d), a, b)) /
                 (2.0 * kStep);
    }
    jtj += j.transpose() * j;
    sum_sq += EpipolarAngularResidual(cam_b_from_cam_a, a, b).squaredNorm();
  }
  const double variance = sum_sq / std::max(1, 2 * n - 5);
  const Eigen::SelfAdjointEigenSolver<Eigen::Matrix<double, 5, 5>> eig(jtj);
  if (eig.info() != Eigen::Success || !(eig.eigenvalues()(0) > 1e-12 * eig.eigenvalues()(4))) return out;
  const Eigen::Matrix<double, 5, 5> cov =
      variance * eig.eigenvectors() * eig.eigenvalues().cwiseInverse().asDiagonal() * eig.eigenvectors().transpose();
  const auto largest = [](const Eigen::MatrixXd& block) {
    return std::sqrt(Eigen::SelfAdjointEigenSolver<Eigen::MatrixXd>(block).eigenvalues().maxCoeff());
  };
  out.rotation_std_deg = RadToDeg(largest(cov.topLeftCorner<3, 3>()));
  out.direction_std_deg = RadToDeg(largest(cov.bottomRightCorner<2, 2>()));
  return out;
}

}  // namespace rigsim
