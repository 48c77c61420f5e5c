// Multi-frame rig calibration: the rig's motion between frames links the scales of the camera
// pairs, so a ring where only neighbours overlap (a chain view graph, not parallel rigid) still
// has determined camera positions once the rig has moved.
//
// Views: (camera, frame). Unknowns: cam_from_rig per camera (camera 0 = the rig frame, identity)
// and rig_from_world per frame (the world is frame 0's rig frame: identity). A view's pose is
// cam_from_world = cam_from_rig * rig_from_world (geometry/rigid3.h).
//
// Stages:
//  1. Tracks over views (BuildViewTracks) from the same-frame inliers of the camera pairs and the
//     temporal inliers of each camera between consecutive frames.
//  2. Rig rotations per frame (EstimateRigRotations) from the temporal rotations conjugated by the
//     cameras' rotations in the rig, averaged over cameras.
//  3. Positions (EstimateRigPositions): with all rotations known, every view centre is linear in
//     the unknowns x = (rig centre in world C_k for k > 0, camera centre in the rig o_c for c > 0):
//     centre(c, k) = C_k + R_k^T o_c. Each track's point is eliminated in closed form from the
//     ray constraints (I - f f^T)(X - centre) = 0, leaving a quadratic form in x; the smallest
//     eigenvector is the solution (up to scale), re-weighted by depth and robustly.
//  4. Bundle adjustment (MultiFrameRigBundleAdjust, Ceres; its cost is calibrator/cost_functions.h
//     RigReprojectionCost, the templated camera model with the intrinsics held constant).
//
// Gauge: camera 0 in the rig, frame 0's rig in the world; the scale camera's translation is held
// on a sphere (|its centre| fixed), the caller picks the radius.
#pragma once

#include <optional>
#include <string>
#include <vector>

#include <Eigen/Core>
#include <Eigen/Geometry>

#include "calibrator/correspondences.h"
#include "calibrator/view_graph.h"
#include "geometry/camera.h"
#include "geometry/rigid3.h"

namespace rigsim {

struct ViewObservation {
  int camera = -1;
  int frame = -1;
  int keypoint = -1;
};

// One 3D point (world frame) seen in any views, at most once per view; observations sorted by
// (frame, camera).
struct ViewTrack {
  std::vector<ViewObservation> observations;
};

// Union-find over (camera, frame, keypoint) nodes joined by the same-frame pair matches and the
// temporal matches (only successful temporal pairs count). A set holding two keypoints of one
// view is contradictory: dropped whole and counted in `num_conflicting`. Sets of one view are no
// tracks. Throws std::invalid_argument on indices out of range.
std::vector<ViewTrack> BuildViewTracks(int num_cameras, int num_frames, const std::vector<PairMatches>& pairs,
                                       const std::vector<TemporalPairEstimate>& temporal,
                                       int* num_conflicting = nullptr);

// rig_from_world rotation per frame: frame 0 is the identity; R_{k+1} R_k^T is the chordal mean
// over cameras c with a rotation and a successful temporal pair (c, k) of Q_c^T T_ck Q_c
// (Q_c = cam_from_rig rotation, T_ck = the temporal rotation). A frame not chained to frame 0 by
// such pairs gets nullopt, and so do the frames after it.
std::vector<std::optional<Eigen::Quaterniond>> EstimateRigRotations(
    int num_frames, const std::vector<std::optional<Eigen::Quaterniond>>& cam_from_rig,
    const std::vector<TemporalPairEstimate>& temporal);

struct RigPositionOptions {
  // Tracks whose rays (with the known rotations) span less than this angle (deg) are left out:
  // their point's depth, hence their constraint on the positions, is undetermined.
  double min_ray_angle_deg = 0.5;
  // Scale (rad) of the Cauchy weight on a track's RMS angular residual in the re-weighting.
  double loss_scale_rad = 0.003;
  // Solve-and-reweight rounds after the first (unweighted) solve.
  int reweighting_iterations = 4;
  // The positions are ambiguous when the second smallest eigenvalue is below this many times the
  // smallest (noise alone gives a ratio near 1; a determined solution a large one). Measured:
  // determined rigs 160-8218 (the test suite's synthetic and rendered rigs, the demo); the
  // undetermined one-frame chain 5.5; forward-moving rings 4-16, and 40 for the demo ring at
  // 640x360 over 3 straight frames, whose positions then came out 48-108 deg wrong at a 0.22 px
  // reprojection RMS. So 80: weakly determined positions are reported as not observable rather
  // than guessed.
  double min_eigenvalue_ratio = 80.0;

  // Throws std::invalid_argument naming the first bad field.
  void Check() const;
};

struct RigPositions {
  // Camera centre in the rig (camera 0 at the origin), per camera; nullopt where not solved for.
  std::vector<std::optional<Eigen::Vector3d>> centre_in_rig;
  // Rig centre in the world (frame 0 at the origin), per frame; nullopt where not solved for.
  std::vector<std::optional<Eigen::Vector3d>> rig_centre_in_world;
  // False when the tracks leave the positions ambiguous beyond one global scale; the positions
  // are then not reported (all nullopt except the references).
  bool unique = false;
  std::string reason;  // why not unique / not solved; empty otherwise
  int tracks_used = 0;
  double eigenvalue_ratio = 0.0;  // second smallest over smallest
};

// Positions up to one global scale: the mean distance of the solved cameras' centres from camera
// 0 is 1 (the caller rescales). Cameras without a rotation or without tracks linking their views
// to view (camera 0, frame 0), and frames without a rig rotation, are not solved for.
// `static_rig`: the frames are independent captures of a rig that is not tracked between them
// (no temporal matches): every frame's rig_from_world is taken as given (identity) and fixed, only
// the camera centres are unknowns; a track never spans frames then.
RigPositions EstimateRigPositions(const std::vector<Camera>& cameras, const FrameKeypoints& keypoints,
                                  const std::vector<ViewTrack>& tracks,
                                  const std::vector<std::optional<Eigen::Quaterniond>>& cam_from_rig,
                                  const std::vector<std::optional<Eigen::Quaterniond>>& rig_from_world,
                                  const RigPositionOptions& options, bool static_rig = false);

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
  // Keep the points and every observation's reprojection error in the result (for a report).
  bool keep_points = false;

  // Throws std::invalid_argument naming the first bad field.
  void Check() const;
};

struct MultiFrameBundleAdjustmentResult {
  std::vector<std::optional<Rigid3d>> cam_from_rig;    // refined; nullopt where not given
  std::vector<std::optional<Rigid3d>> rig_from_world;  // refined; nullopt where not given
  std::vector<int> observations_per_camera;            // kept in the final solve
  int num_tracks = 0;
  int num_points = 0;
  int num_observations = 0;
  int num_filtered_observations = 0;
  double initial_rms_px = 0.0;
  double reprojection_rms_px = 0.0;
  int iterations = 0;
  // Per camera: covariance of its centre in the rig (in the result's units, squared) at the
  // solution, from the Jacobian and the reprojection RMS; nullopt for camera 0 and cameras not
  // adjusted, or when it could not be computed.
  std::vector<std::optional<Eigen::Matrix3d>> centre_covariance;
  // With RigBundleAdjustmentOptions::keep_points only: the final solve's points (world frame) and
  // how many views see each, and the reprojection error (px) of every observation triangulated
  // from the initial poses (before any solve) and of every observation kept at the end.
  std::vector<Eigen::Vector3d> points;
  std::vector<int> point_observations;
  std::vector<double> initial_residuals_px, final_residuals_px;
};

// Triangulates the tracks (world frame) over the posed views, then solves and filters
// (RigBundleAdjustmentOptions). Camera 0's cam_from_rig and frame 0's rig_from_world must be
// given and are held constant (normally the identity); `scale_camera` (-1: none) keeps |its
// centre|; `hold_frames` holds every frame's rig_from_world constant (a static rig, see
// EstimateRigPositions). Throws std::invalid_argument on sizes that do not match or a missing
// reference.
MultiFrameBundleAdjustmentResult MultiFrameRigBundleAdjust(
    const std::vector<Camera>& cameras, const FrameKeypoints& keypoints, const std::vector<ViewTrack>& tracks,
    const std::vector<std::optional<Rigid3d>>& initial_cam_from_rig,
    const std::vector<std::optional<Rigid3d>>& initial_rig_from_world, int scale_camera,
    const RigBundleAdjustmentOptions& options, bool hold_frames = false);

}  // namespace rigsim
