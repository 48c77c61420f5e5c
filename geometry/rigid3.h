// Rigid transforms between frames.
//
// Naming convention (used everywhere in rigsim): a transform is named
// `target_from_source`, so `x_in_cam = cam_from_world * x_in_world` and
// `cam_from_world = cam_from_rig * rig_from_world`.
//
// Frames:
//   camera: x right, y down, z forward (OpenCV / COLMAP).
//   rig:    same axes as a camera; a camera with identity cam_from_rig looks along the rig's +z.
//   world:  glTF's frame (right-handed, +Y up, metres).
#pragma once

#include <vector>

#include <Eigen/Core>
#include <Eigen/Geometry>

namespace rigsim {

struct Rigid3d {
  Eigen::Quaterniond rotation = Eigen::Quaterniond::Identity();
  Eigen::Vector3d translation = Eigen::Vector3d::Zero();

  Rigid3d() = default;
  Rigid3d(const Eigen::Quaterniond& r, const Eigen::Vector3d& t) : rotation(r.normalized()), translation(t) {}
  Rigid3d(const Eigen::Matrix3d& r, const Eigen::Vector3d& t) : rotation(Eigen::Quaterniond(r).normalized()), translation(t) {}

  Eigen::Vector3d operator*(const Eigen::Vector3d& x) const { return rotation * x + translation; }
  // (a_from_b * b_from_c) = a_from_c
  Rigid3d operator*(const Rigid3d& b_from_c) const {
    return Rigid3d(rotation * b_from_c.rotation, rotation * b_from_c.translation + translation);
  }
  Rigid3d Inverse() const {
    const Eigen::Quaterniond inv = rotation.conjugate();
    return Rigid3d(inv, -(inv * translation));
  }
  Eigen::Matrix3d RotationMatrix() const { return rotation.toRotationMatrix(); }
  Eigen::Matrix<double, 3, 4> ToMatrix() const;
  // Centre of the source frame's origin expressed in the target frame of the inverse,
  // e.g. for cam_from_world this is the camera centre in world coordinates.
  Eigen::Vector3d SourceOriginInTarget() const { return Inverse().translation; }
};

// Angle of R_a * R_b^T in degrees (0..180).
double RotationDifferenceDeg(const Eigen::Quaterniond& a, const Eigen::Quaterniond& b);

// Angle between two directions in degrees (0..180); 0 if either is (near) zero.
double AngleBetweenDeg(const Eigen::Vector3d& a, const Eigen::Vector3d& b);

// The rotation nearest to `m` in the Frobenius norm (its projection onto SO(3)): the chordal mean
// of rotations summed into m, or, for m = sum b_i a_i^T, the least-squares rotation taking each a_i
// to b_i (Kabsch / Wahba).
Eigen::Matrix3d NearestRotation(const Eigen::Matrix3d& m);

// The matrix [v]x with [v]x w = v x w.
Eigen::Matrix3d CrossProductMatrix(const Eigen::Vector3d& v);

// The rotation vector (axis times angle, radians, angle in [0, pi]) of `q`.
Eigen::Vector3d RotationVector(const Eigen::Quaterniond& q);

// glTF cameras (and OpenGL) look down -Z with +Y up; rigsim cameras look down +Z with +Y down.
// This is the one place the two are related: cv_from_gl flips y and z.
Eigen::Matrix3d CvFromGlRotation();

// Given a glTF camera node's world transform (world_from_glcam, the node's global matrix with
// scale removed), returns the OpenCV-convention cam_from_world.
Rigid3d CamFromWorldFromGltfCameraNode(const Eigen::Matrix4d& world_from_glcam);

double DegToRad(double deg);
double RadToDeg(double rad);

// The mean of poses close to each other: the normalised sum of their quaternions (each taken on
// the first one's side of the sphere) and the mean of their translations. The identity when empty.
Rigid3d MeanOfNearbyPoses(const std::vector<Rigid3d>& poses);

}  // namespace rigsim
