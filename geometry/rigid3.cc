#include "geometry/rigid3.h"

#include <algorithm>
#include <cmath>
#include <numbers>

#include <Eigen/SVD>

namespace rigsim {

Eigen::Matrix<double, 3, 4> Rigid3d::ToMatrix() const {
  Eigen::Matrix<double, 3, 4> m;
  m.leftCols<3>() = RotationMatrix();
  m.col(3) = translation;
  return m;
}

double RotationDifferenceDeg(const Eigen::Quaterniond& a, const Eigen::Quaterniond& b) {
  // Angle from the quaternion of the relative rotation: stable near 0, unlike acos of the trace.
  const Eigen::Quaterniond d = a.normalized() * b.normalized().conjugate();
  const double s = d.vec().norm();
  const double c = std::abs(d.w());
  return RadToDeg(2.0 * std::atan2(s, c));
}

double AngleBetweenDeg(const Eigen::Vector3d& a, const Eigen::Vector3d& b) {
  const double na = a.norm();
  const double nb = b.norm();
  if (na < 1e-300 || nb < 1e-300) return 0.0;
  return RadToDeg(std::atan2(a.cross(b).norm(), a.dot(b)));
}

Eigen::Matrix3d NearestRotation(const Eigen::Matrix3d& m) {
  const Eigen::JacobiSVD<Eigen::Matrix3d> svd(m, Eigen::ComputeFullU | Eigen::ComputeFullV);
  Eigen::Matrix3d d = Eigen::Matrix3d::Identity();
  d(2, 2) = (svd.matrixU() * svd.matrixV().transpose()).determinant() < 0 ? -1.0 : 1.0;
  return svd.matrixU() * d * svd.matrixV().transpose();
}

Eigen::Matrix3d CrossProductMatrix(const Eigen::Vector3d& v) {
  Eigen::Matrix3d m;
  m << 0, -v.z(), v.y(), v.z(), 0, -v.x(), -v.y(), v.x(), 0;
  return m;
}

Eigen::Vector3d RotationVector(const Eigen::Quaterniond& q) {
  // The quaternion with w >= 0 gives the angle in [0, pi]; atan2 is stable near 0 and near pi.
  const Eigen::Quaterniond p = q.w() < 0 ? Eigen::Quaterniond(-q.w(), -q.x(), -q.y(), -q.z()) : q;
  const double s = p.vec().norm();
  if (s < 1e-300) return Eigen::Vector3d::Zero();
  return (2.0 * std::atan2(s, p.w()) / s) * p.vec();
}

Eigen::Matrix3d CvFromGlRotation() { return Eigen::Vector3d(1.0, -1.0, -1.0).asDiagonal(); }

Rigid3d CamFromWorldFromGltfCameraNode(const Eigen::Matrix4d& world_from_glcam) {
  Eigen::Matrix3d r = world_from_glcam.topLeftCorner<3, 3>();
  // Remove any scale the node carries: cameras are rigid.
  for (int c = 0; c < 3; ++c) r.col(c).normalize();
  const Eigen::Vector3d centre = world_from_glcam.topRightCorner<3, 1>();
  const Eigen::Matrix3d glcam_from_world = r.transpose();
  const Eigen::Matrix3d cam_from_world = CvFromGlRotation() * glcam_from_world;
  return Rigid3d(cam_from_world, -(cam_from_world * centre));
}

double DegToRad(double deg) { return deg * std::numbers::pi / 180.0; }
double RadToDeg(double rad) { return rad * 180.0 / std::numbers::pi; }

Rigid3d MeanOfNearbyPoses(const std::vector<Rigid3d>& poses) {
  if (poses.empty()) return Rigid3d();
  Eigen::Vector4d q_sum = Eigen::Vector4d::Zero();
  Eigen::Vector3d t_sum = Eigen::Vector3d::Zero();
  for (const Rigid3d& p : poses) {
    const Eigen::Vector4d q = p.rotation.coeffs();
    q_sum += q.dot(poses.front().rotation.coeffs()) < 0 ? -q : q;
    t_sum += p.translation;
  }
  return Rigid3d(Eigen::Quaterniond(q_sum.normalized()), t_sum / double(poses.size()));
}

}  // namespace rigsim
