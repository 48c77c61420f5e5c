// Rotations of a moving rig, jointly from every relative rotation its images give: each camera's in
// the rig (Q_c, of cam_from_rig) and the rig's at each frame (R_k, of rig_from_world).
//
// A measurement between camera a at frame t and camera b at frame t' is the rotation of
// cam_b(t')_from_cam_a(t) = Q_b R_t' R_t^T Q_a^T:
//   - a camera pair pooled over the frames (the same instant in every frame): Q_b Q_a^T;
//   - a camera's own motion (a = b): Q_a R_t' R_t^T Q_a^T, which links frames, and over turns
//     about two axes fixes Q_a too (hand-eye calibration inside the averaging);
//   - a cross-time pair (a != b, t != t'): the general form, which links cameras that never see
//     the same thing at the same instant.
// Gauge: Q_0 = R_0 = identity.
//
// Method: initial rotations propagated from the gauge by consensus (each step fixes the unknown the
// most measurements can fix, to the value most of them agree on); a camera no measurement reaches
// that way may bring its own start (hand_eye.h). Then
// non-linear least squares (Ceres) over unit quaternions of every measurement's angle-axis
// residual, weighted by sqrt(inliers / median inliers) under a Cauchy loss. Measurements whose
// residual exceeds outlier_threshold_deg are dropped and both steps repeat.
#pragma once

#include <optional>
#include <vector>

#include <Eigen/Geometry>
#include "calibrator/model/rig_state.h"

namespace rigsim {

struct ViewPairRotation {
  int cam_a = -1;
  int cam_b = -1;
  // The frames of the two views; both -1 for a camera pair pooled over the frames.
  int frame_a = -1;
  int frame_b = -1;
  Eigen::Quaterniond b_from_a = Eigen::Quaterniond::Identity();
  int inliers = 1;  // weight
};

struct RigRotationAveragingOptions {
  // Scale of the Cauchy loss (deg): residuals well above it barely pull.
  double loss_scale_deg = 2.0;
  // Measurements whose final residual exceeds this (deg) are outliers and dropped.
  double outlier_threshold_deg = 5.0;
  int max_iterations = 100;  // Ceres iterations per round
  int max_rounds = 4;        // drop-and-refit rounds at most

  // Throws std::invalid_argument naming the first bad field.
  void Check() const;
};

struct RigRotationAveragingResult {
  // Per camera and per frame; nullopt where no measurement (or start) reaches from the gauge.
  PerCamera<Eigen::Quaterniond> cam_from_rig;
  PerFrame<Eigen::Quaterniond> rig_from_world;
  // Per measurement: rejected as an outlier, and its residual at the solution (deg; NaN where one
  // of its rotations is unknown).
  std::vector<char> outlier;
  std::vector<double> residual_deg;
  int num_outliers = 0;
  int rounds = 0;
};

// `camera_starts` (empty, or one per camera) seeds cameras that propagation does not reach.
// Throws std::invalid_argument on a measurement naming a camera or frame out of range, or a camera
// pair measured against itself at one frame.
RigRotationAveragingResult AverageRigRotations(int num_cameras, int num_frames,
                                               const std::vector<ViewPairRotation>& measurements,
                                               const PerCamera<Eigen::Quaterniond>& camera_starts,
                                               const RigRotationAveragingOptions& options);

}  // namespace rigsim
