// Camera centres in the rig from the pairwise translation directions alone: how the rig stage
// checks whether one frame (a static rig) fixes the positions (rig_calibration.h).
#pragma once

#include <optional>
#include <vector>

#include <Eigen/Core>
#include <Eigen/Geometry>

#include "calibrator/model/rig_state.h"
#include "calibrator/model/view_graph.h"

namespace rigsim {

struct CameraCentres {
  // Centre of each camera in the rig frame; nullopt outside the reference camera's component
  // of translation edges or without a rotation. The reference camera is at the origin. The
  // scale is arbitrary: the mean length of the used edges is 1.
  PerCamera<Eigen::Vector3d> centre_in_rig;
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
                                    const PerCamera<Eigen::Quaterniond>& cam_from_rig,
                                    int reference_camera, int reweighting_iterations = 5);

}  // namespace rigsim
