// Robust rotation averaging over a view graph: the rotation cam_from_rig of every camera in the
// reference camera's component, with the reference camera as the rig frame (identity).
//
// Method:
//  1. Initial rotations from a maximum spanning tree. The edge weight is first the number of
//     triangles (a, b, c) in which the edge closes a consistent loop R_ca R_bc R_ab ~ I, then the
//     inlier count: an outlier edge closes almost no consistent loop whatever its inlier count,
//     so the tree avoids it. Graphs without triangles (a chain of cameras) fall back to inliers.
//  2. Non-linear least squares (Ceres) over unit quaternions of the angle-axis residual
//     log(R_ab^T R_b R_a^T), weighted by sqrt(inliers / median inliers) (a pairwise rotation's
//     variance falls as 1/inliers), under a Cauchy loss.
//  3. Edges whose residual exceeds outlier_threshold_deg are outliers: they are dropped and 1-3
//     repeat on the remaining graph (a camera may lose its connection and is then left out).
#pragma once

#include <optional>
#include <vector>

#include <Eigen/Geometry>

#include "calibrator/model/rig_state.h"
#include "calibrator/model/view_graph.h"

namespace rigsim {

struct RotationAveragingOptions {
  // A triangle of edges is consistent when its loop rotation is below this angle (deg).
  double loop_threshold_deg = 3.0;
  // Scale of the Cauchy loss (deg): residuals well above it barely pull.
  double loss_scale_deg = 2.0;
  // Edges whose final residual exceeds this (deg) are outliers and dropped.
  double outlier_threshold_deg = 5.0;
  // Ceres iterations per round.
  int max_iterations = 100;
  // Drop-and-refit rounds at most.
  int max_rounds = 4;

  // Throws std::invalid_argument naming the first bad field.
  void Check() const;
};

struct RotationAveragingResult {
  // cam_from_rig rotation per camera; nullopt outside the reference camera's final component.
  PerCamera<Eigen::Quaterniond> cam_from_rig;
  // Per graph edge: identified as an outlier (it was active and is rejected).
  std::vector<char> outlier;
  // Per graph edge: angle (deg) of R_b R_a^T against the edge's rotation at the solution; NaN for
  // edges between cameras without a rotation or inactive on input.
  std::vector<double> residual_deg;
  int num_outliers = 0;
  int rounds = 0;
};

// Uses the active edges of `graph` (rotation-only edges too: their rotation is valid).
// Throws std::invalid_argument when the reference camera is out of range.
RotationAveragingResult AverageRotations(const ViewGraph& graph, int reference_camera,
                                         const RotationAveragingOptions& options);

}  // namespace rigsim
