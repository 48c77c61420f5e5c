// Rig positions and refinement: tracks from the pairwise inlier matches, camera centres from the
// pairwise translation directions, triangulation, and bundle adjustment of cam_from_rig (Ceres).
//
// Frames: every track lives in one frame, and its point in the rig frame of that frame, so no
// per-frame rig pose is needed: camera c observes point X of a track as
// ImgFromCam(cam_from_rig_c * X) (geometry/camera_models.h, the very template the renderer
// uses). The price: only correspondences seen at the same instant constrain the rig, so the
// camera graph must fix the relative baselines (see EstimateCameraCentres).
//
// Gauge: the reference camera is the rig frame (cam_from_rig = identity, held constant). Scale:
// the translation of one other camera (the scale camera) is held on a sphere of its initial
// radius, so |its centre| does not change; the caller picks that radius (1, or metric).
// Intrinsics are fixed.
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

struct TrackObservation {
  int camera = -1;
  int keypoint = -1;
};

// One 3D point seen in one frame, at most once per camera; observations ordered by camera.
struct Track {
  int frame = -1;
  std::vector<TrackObservation> observations;
};

// Tracks per frame by union-find over (camera, keypoint) nodes joined by the pairs' matches.
// A connected set holding two different keypoints of one camera is contradictory (one of its
// matches is wrong, and which one is unknown): it is dropped whole and counted in
// `num_conflicting`. Throws std::invalid_argument on a camera index out of range or a pair with
// another number of frames.
std::vector<Track> BuildTracks(int num_cameras, int num_frames, const std::vector<PairMatches>& pairs,
                               int* num_conflicting = nullptr);

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

// Least-squares intersection of the rays of a track's observations (rig frame); nullopt when
// fewer than two observations have a valid bearing or the rays meet at less than
// `min_angle_rad` (the depth is then undetermined).
std::optional<Eigen::Vector3d> TriangulateTrack(const std::vector<Camera>& cameras, const FrameKeypoints& keypoints,
                                                const Track& track,
                                                const std::vector<std::optional<Rigid3d>>& cam_from_rig,
                                                double min_angle_rad);

// Reprojection residual of one observation (pixels, projected minus observed), Ceres-free so that
// tests can difference it; the bundle adjustment wraps it in ceres::AutoDiffCostFunction.
// Parameters: cam_from_rig rotation as an Eigen quaternion (x, y, z, w), its translation, the
// point in the rig frame.
struct RigReprojectionResidual {
  RigReprojectionResidual(const Camera& camera, const Eigen::Vector2d& observed);

  template <typename T>
  bool operator()(const T* rotation_xyzw, const T* translation, const T* point_in_rig, T* residual) const {
    const Eigen::Map<const Eigen::Quaternion<T>> q(rotation_xyzw);
    const Eigen::Map<const Eigen::Matrix<T, 3, 1>> t(translation);
    const Eigen::Map<const Eigen::Matrix<T, 3, 1>> x(point_in_rig);
    const Eigen::Matrix<T, 3, 1> x_in_cam = q * x + t;
    T params[12];
    for (int i = 0; i < num_params; ++i) params[i] = T(params_[i]);
    T px[2];
    if (!ImgFromCam(model, params, x_in_cam.data(), px)) return false;
    residual[0] = px[0] - T(observed.x());
    residual[1] = px[1] - T(observed.y());
    return true;
  }

  CameraModelId model;
  int num_params;
  double params_[12];
  Eigen::Vector2d observed;
};

// The residual and its Jacobians through the bundle adjustment's own Ceres cost (autodiff), with
// respect to the quaternion (4 ambient coordinates x, y, z, w), the translation and the point.
// Returns false where the point does not project.
bool EvaluateRigReprojection(const Camera& camera, const Eigen::Vector2d& observed, const Eigen::Vector4d& rotation_xyzw,
                             const Eigen::Vector3d& translation, const Eigen::Vector3d& point_in_rig,
                             Eigen::Vector2d* residual, Eigen::Matrix<double, 2, 4>* d_rotation,
                             Eigen::Matrix<double, 2, 3>* d_translation, Eigen::Matrix<double, 2, 3>* d_point);

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
  // Ceres iterations per solve.
  int max_iterations = 100;
  // Ceres threads.
  int num_threads = 1;

  // Throws std::invalid_argument naming the first bad field.
  void Check() const;
};

struct RigBundleAdjustmentResult {
  std::vector<std::optional<Rigid3d>> cam_from_rig;  // refined; nullopt where there was no initial pose
  std::vector<int> observations_per_camera;          // observations kept in the final solve
  int num_tracks = 0;                                // tracks given
  int num_points = 0;                                // points in the final solve
  int num_observations = 0;                          // observations in the final solve
  int num_filtered_observations = 0;                 // removed by the filter rounds
  double initial_rms_px = 0.0;  // reprojection RMS of the first solve's start
  double reprojection_rms_px = 0.0;  // of the final solve (plain, without the loss)
  int iterations = 0;                // summed over solves
};

// Triangulates the tracks seen by at least two posed cameras, then solves and filters.
// `initial_cam_from_rig`: the reference camera must be the identity; `scale_camera` (-1 for
// none, which leaves the scale free) is held at its initial distance from the reference.
RigBundleAdjustmentResult RigBundleAdjust(const std::vector<Camera>& cameras, const FrameKeypoints& keypoints,
                                          const std::vector<Track>& tracks,
                                          const std::vector<std::optional<Rigid3d>>& initial_cam_from_rig,
                                          int reference_camera, int scale_camera,
                                          const RigBundleAdjustmentOptions& options);

}  // namespace rigsim
