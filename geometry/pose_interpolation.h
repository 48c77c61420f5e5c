// The rig's pose between two frames, as the renderer takes it (dataset/capture_poses.h RigTrajectory)
// and the calibrator models it (a camera that captures between frames): the rig's centre moves on
// the straight line and its orientation turns by slerp, at constant speed over the time between
// them; a fraction s < 0 or > 1 extrapolates with the same velocities. A template on the scalar
// type, so that Ceres differentiates the very same arithmetic (as the camera models).
//
// Conventions: geometry/rigid3.h; quaternions as Eigen stores them (x, y, z, w).
#pragma once

#include <cmath>

#include <Eigen/Core>
#include <Eigen/Geometry>

#include <vector>

#include "geometry/rigid3.h"

namespace rigsim {

// The rotation vector (axis times angle) of a unit quaternion, the short way round; near the
// identity its first-order form, so that its derivative is defined there.
template <typename T>
Eigen::Matrix<T, 3, 1> QuaternionLog(const Eigen::Quaternion<T>& q) {
  using std::atan2;
  using std::sqrt;
  const T sign = q.w() < T(0) ? T(-1) : T(1);
  const Eigen::Matrix<T, 3, 1> v = sign * q.vec();
  const T w = sign * q.w();
  const T s2 = v.squaredNorm();
  if (s2 > T(1e-24)) {
    const T s = sqrt(s2);
    return (T(2) * atan2(s, w) / s) * v;
  }
  return (T(2) / w) * v;
}

// The unit quaternion of a rotation vector; near zero its first-order form.
template <typename T>
Eigen::Quaternion<T> QuaternionExp(const Eigen::Matrix<T, 3, 1>& r) {
  using std::cos;
  using std::sin;
  using std::sqrt;
  const T a2 = r.squaredNorm();
  if (a2 > T(1e-24)) {
    const T a = sqrt(a2);
    const Eigen::Matrix<T, 3, 1> v = (sin(a / T(2)) / a) * r;
    return Eigen::Quaternion<T>(cos(a / T(2)), v.x(), v.y(), v.z());
  }
  return Eigen::Quaternion<T>(T(1), r.x() / T(2), r.y() / T(2), r.z() / T(2));
}

// rig_from_world at fraction s of the way from pose a to pose b (rig_from_world each, as rotation
// and translation).
template <typename T>
void InterpolateRigFromWorld(const Eigen::Quaternion<T>& q_a, const Eigen::Matrix<T, 3, 1>& t_a,
                             const Eigen::Quaternion<T>& q_b, const Eigen::Matrix<T, 3, 1>& t_b, const T& s,
                             Eigen::Quaternion<T>* q, Eigen::Matrix<T, 3, 1>* t) {
  // world_from_rig turns by s of the relative rotation; the centre moves on the line.
  const Eigen::Quaternion<T> world_from_a = q_a.conjugate();
  const Eigen::Quaternion<T> delta = q_a * q_b.conjugate();  // a_from_b = world_from_a^-1 world_from_b
  const Eigen::Quaternion<T> world_from_rig = world_from_a * QuaternionExp<T>(s * QuaternionLog<T>(delta));
  const Eigen::Matrix<T, 3, 1> centre_a = -(world_from_a * t_a);
  const Eigen::Matrix<T, 3, 1> centre_b = -(q_b.conjugate() * t_b);
  const Eigen::Matrix<T, 3, 1> centre = centre_a + s * (centre_b - centre_a);
  *q = world_from_rig.conjugate();
  *t = -(*q * centre);
}

// The rig's pose at any time on a path through poses at distinct times, as the renderer moves it:
// between the two poses around the time InterpolateRigFromWorld; before the first and after the
// last the velocities of the nearest two; one pose stands still. At a pose's time it is that pose
// exactly.
struct TimedPose {
  double time_s = 0.0;
  Rigid3d rig_from_world;
};
// `path`: at least one pose, any order of time, no two at the same time (the caller checks).
Rigid3d RigFromWorldOnPath(const std::vector<TimedPose>& path_by_time, double time_s);
// Sorts by time (stable), for RigFromWorldOnPath.
std::vector<TimedPose> SortedByTime(std::vector<TimedPose> path);

}  // namespace rigsim
