// Initial positions of the cameras in the rig and of the rig in the world, every rotation known
// (rotation averaging for the cameras, the temporal pairs for the rig per frame). Two estimates
// from different data, which the bundle adjustment starts from (rig_calibration.h runs it from
// each and keeps the one the images agree with best):
//  - from the tracks (EstimateRigPositions): every view centre is linear in the unknowns
//    x = (rig centre in the world C_k for k > 0, camera centre in the rig o_c for c > 0):
//    centre(c, k) = C_k + R_k^T o_c. Each track's point is eliminated in closed form from the ray
//    constraints (I - f f^T)(X - centre) = 0, leaving a quadratic form in x whose smallest
//    eigenvector is the solution (up to scale), re-weighted by depth and robustly.
//  - from the two-view directions (EstimateRigPositionsFromDirections): robust translation
//    averaging (translation_averaging.h) of every camera pair's baseline, o_b - o_a (the same in
//    every frame), and of every temporal pair's motion, centre(c, k+1) - centre(c, k) =
//    C_{k+1} - C_k + (R_{k+1}^T - R_k^T) o_c. It needs no point depths, so it holds where the
//    tracks' depths are poorly fixed (short baselines, few frames).
// Neither decides whether the images determine the positions: the bundle adjustment's covariance
// and the agreement of its starts do (rig_calibration.h).
//
// Gauge: camera 0 at the rig origin, frame 0's rig at the world origin; scale: the mean distance
// of the solved cameras' centres from camera 0 is 1 (the caller rescales).
#pragma once

#include <optional>
#include <string>
#include <vector>

#include <Eigen/Core>
#include <Eigen/Geometry>

#include "calibrator/estimators/multi_frame_rig.h"
#include "calibrator/model/correspondences.h"
#include "calibrator/model/rig_state.h"
#include "calibrator/model/view_graph.h"
#include "geometry/camera.h"

namespace rigsim {

struct RigPositionOptions {
  // Tracks whose rays (with the known rotations) span less than this angle (deg) are left out:
  // their point's depth, hence their constraint on the positions, is undetermined.
  double min_ray_angle_deg = 0.5;
  // Scale (rad) of the Cauchy weight on a track's RMS angular residual in the re-weighting.
  double loss_scale_rad = 0.003;
  // Solve-and-reweight rounds after the first (unweighted) solve.
  int reweighting_iterations = 4;

  // Throws std::invalid_argument naming the first bad field.
  void Check() const;
};

struct RigPositions {
  // Camera centre in the rig (camera 0 at the origin), per camera; nullopt where not solved for.
  PerCamera<Eigen::Vector3d> centre_in_rig;
  // Rig centre in the world (frame 0 at the origin), per frame; nullopt where not solved for.
  PerFrame<Eigen::Vector3d> rig_centre_in_world;
  // A solution was found (some camera besides camera 0 placed, not all at camera 0's centre).
  bool solved = false;
  std::string reason;  // why not solved; empty otherwise
  int constraints_used = 0;  // tracks, or directions
  // The track solve only: the second smallest eigenvalue of its quadratic form over the smallest,
  // how clearly the tracks single out one solution (large when they do; noise alone gives ~1).
  double eigenvalue_ratio = 0.0;
};

// From the tracks. Cameras without a rotation or without tracks linking their views to view
// (camera 0, frame 0), and frames without a rig rotation, are not solved for.
// `static_rig`: the frames are independent captures of a rig that is not tracked between them
// (no temporal matches): every frame's rig_from_world is taken as given (identity) and fixed, only
// the camera centres are unknowns; a track never spans frames then.
// `held_axis` (empty, or one entry per camera): a unit direction in the rig along which the
// camera's centre is held at camera 0's, for a camera the data leave open along it (a planar
// motion without matches to other cameras, hand_eye.h): not estimated.
RigPositions EstimateRigPositions(const std::vector<Camera>& cameras, const FrameKeypoints& keypoints,
                                  const std::vector<ViewTrack>& tracks,
                                  const PerCamera<Eigen::Quaterniond>& cam_from_rig,
                                  const PerFrame<Eigen::Quaterniond>& rig_from_world,
                                  const RigPositionOptions& options, bool static_rig = false,
                                  const PerCamera<Eigen::Vector3d>& held_axis = {});

// One camera's own centres over the frames (its trajectory, calibrator/camera_trajectory.h), from
// its tracks across frames with every rotation known: `rotations[k]` is cam(k)_from_cam(0)'s,
// `keypoints[k]` the camera's keypoints at frame k, the tracks' camera index 0. Frame 0's centre
// is the origin and the mean distance of the others from it is 1; nullopt for frames the tracks
// do not link to frame 0.
PerFrame<Eigen::Vector3d> EstimateTrajectoryCentres(
    const Camera& camera, const std::vector<std::vector<Eigen::Vector2d>>& keypoints,
    const std::vector<ViewTrack>& tracks, const PerCamera<Eigen::Quaterniond>& rotations,
    const RigPositionOptions& options);

// From the directions of the active, non-rotation-only edges of `graph` and of the successful,
// non-rotation-only temporal pairs (ignored when `static_rig`). The same unknowns and gauge as
// EstimateRigPositions.
RigPositions EstimateRigPositionsFromDirections(const ViewGraph& graph, const std::vector<TemporalPairEstimate>& temporal,
                                                const PerCamera<Eigen::Quaterniond>& cam_from_rig,
                                                const PerFrame<Eigen::Quaterniond>& rig_from_world,
                                                bool static_rig = false);

}  // namespace rigsim
