// What the rig stages share: keypoint and match containers, camera centres from the pairwise
// translation directions (the check whether one frame alone fixes the positions), and the
// options of the bundle adjustment (multi_frame_rig.h solves it).
#pragma once

#include <optional>
#include <string>
#include <utility>
#include <vector>

#include <Eigen/Core>
#include <Eigen/Geometry>

#include "calibrator/view_graph.h"
#include "geometry/camera.h"
#include "geometry/rigid3.h"

namespace rigsim {

// Keypoint positions: [frame][camera][keypoint].
using FrameKeypoints = std::vector<std::vector<std::vector<Eigen::Vector2d>>>;

// Inlier correspondences of one camera pair: per frame, (keypoint index in cam_a, in cam_b).
struct PairMatches {
  int cam_a = -1;
  int cam_b = -1;
  std::vector<std::vector<std::pair<int, int>>> per_frame;
};

struct CameraCentres {
  // Centre of each camera in the rig frame; nullopt outside the reference camera's component
  // of translation edges or without a rotation. The reference camera is at the origin. The
  // scale is arbitrary: the mean length of the used edges is 1.
  std::vector<std::optional<Eigen::Vector3d>> centre_in_rig;
  // False when the translation directions leave the shape of the rig ambiguous beyond the scale
  // (the graph is not parallel rigid, e.g. a ring of cameras where only neighbours overlap). The
  // centres are then one of the solutions; tracks seen by three or more cameras can still fix it.
  bool unique = true;
  int edges_used = 0;
};

// Centres from the unit translation directions of the active, non-rotation-only edges given the
// rotations: for an edge (a, b), R_b^T t_ab is parallel to c_a - c_b. Solved as the homogeneous
// linear system [R_b^T t_ab]_x (c_a - c_b) = 0 with c_reference = 0 (smallest singular vector),
// re-weighted a few times by the inverse of each edge's angular residual (an L1-like fit, robust
// to a wrong direction), sign chosen so that the directions point the right way.
CameraCentres EstimateCameraCentres(const ViewGraph& graph,
                                    const std::vector<std::optional<Eigen::Quaterniond>>& cam_from_rig,
                                    int reference_camera, int reweighting_iterations = 5);

struct RigBundleAdjustmentOptions {
  // Tracks whose rays meet at less than this angle (deg) are not triangulated: their depth is
  // undetermined, and they only slow the solver.
  double min_triangulation_angle_deg = 0.25;
  // Scale (px) of the Huber loss: quadratic for inliers, linear beyond, so the few wrong matches
  // that survived two-view pull little.
  double loss_scale_px = 1.0;
  // After each solve, observations reprojecting farther than this (px), or behind their camera,
  // are removed and the problem is solved again; points left with one observation go.
  double max_reprojection_error_px = 3.0;
  // Solve-and-filter rounds after the first solve.
  int filter_rounds = 2;
  // Points in the coarse first solve of the multi-frame adjustment (an even subsample of the
  // tracks), skipped when there are fewer than twice as many; 0 = no coarse solve.
  int coarse_points = 2000;
  // Ceres iterations per solve.
  int max_iterations = 100;
  // Ceres threads.
  int num_threads = 1;

  // Throws std::invalid_argument naming the first bad field.
  void Check() const;
};

}  // namespace rigsim
