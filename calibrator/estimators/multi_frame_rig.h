// Multi-frame rig calibration: the rig's motion between frames links the scales of the camera
// pairs, so a ring where only neighbours overlap (a chain view graph, not parallel rigid) still
// has determined camera positions once the rig has moved.
//
// Views: (camera, frame). Unknowns: cam_from_rig per camera (camera 0 = the rig frame, identity)
// and rig_from_world per frame (the world is frame 0's rig frame: identity). A view's pose is
// cam_from_world = cam_from_rig * rig_from_world (geometry/rigid3.h).
//
// Stages:
//  1. Tracks over views (model/tracks.h BuildViewTracks) from the same-frame inliers of the camera
//     pairs and the temporal inliers of each camera between consecutive frames.
//  2. Rig rotations per frame (EstimateRigRotations) from the temporal rotations conjugated by the
//     cameras' rotations in the rig, averaged over cameras.
//  3. Positions (rig_positions.h): initial camera and rig centres.
//  4. Bundle adjustment (MultiFrameRigBundleAdjust, Ceres; its cost is calibrator/cost_functions.h
//     RigReprojectionCost, the templated camera model with the intrinsics held constant, or
//     refined under priors with RigBundleAdjustmentOptions::refine_intrinsics).
//
// Gauge: camera 0 in the rig, frame 0's rig in the world; the scale camera's translation is held
// on a sphere (|its centre| fixed), the caller picks the radius.
#pragma once

#include <optional>
#include <string>
#include <vector>

#include <Eigen/Core>
#include <Eigen/Geometry>

#include "calibrator/estimators/intrinsics_refinement.h"
#include "calibrator/estimators/jackknife.h"
#include "calibrator/model/correspondences.h"
#include "calibrator/model/rig_state.h"
#include "calibrator/model/tracks.h"
#include "calibrator/model/view_graph.h"
#include "geometry/camera.h"
#include "geometry/rigid3.h"

namespace rigsim {

// rig_from_world rotation per frame: frame 0 is the identity; R_{k+1} R_k^T is the chordal mean
// over cameras c with a rotation and a successful temporal pair (c, k) of Q_c^T T_ck Q_c
// (Q_c = cam_from_rig rotation, T_ck = the temporal rotation). A frame not chained to frame 0 by
// such pairs gets nullopt, and so do the frames after it.
PerFrame<Eigen::Quaterniond> EstimateRigRotations(
    int num_frames, const PerCamera<Eigen::Quaterniond>& cam_from_rig,
    const std::vector<TemporalPairEstimate>& temporal);

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
  // The covariance at the solution (the result's standard deviations); off for solves that are
  // only compared by their cost.
  bool covariance = true;
  // Refine each camera's intrinsics too, under Gaussian priors centred on the given ones
  // (intrinsics_refinement.h). The poses are first adjusted with the given intrinsics held;
  // then intrinsics_passes times: every track triangulated again from the current poses and
  // intrinsics, and solved and filtered with the intrinsics free (observations that wrong
  // intrinsics put beyond max_reprojection_error_px come back as the intrinsics improve).
  bool refine_intrinsics = false;
  IntrinsicsPriorOptions intrinsics_priors;
  int intrinsics_passes = 3;
  // Observations of points seen by two or more cameras weigh this much (a factor on their loss):
  // on a rig linked by its motion (motion_links.h) they are few beside each camera's own, and
  // they alone fix where the cameras sit relative to each other. 1: every observation alike.
  double inter_camera_weight = 1.0;
  // Empty, or per camera: a unit direction in the rig along which the camera's centre is held at
  // its start, for a camera the data leave open along it (a planar motion and no point shared with
  // another camera, hand_eye.h); its covariance is then across that direction only.
  PerCamera<Eigen::Vector3d> held_centre_axis;
  // The given intrinsics' own uncertainty, counted in the covariances (GivenIntrinsicsDeviation);
  // nullopt: the intrinsics count as exact. Not with refine_intrinsics nor a CaptureTiming.
  std::optional<GivenIntrinsicsDeviation> given_intrinsics_sd;

  // Throws std::invalid_argument naming the first bad field.
  void Check() const;
  // Every field alike: the rig stage reuses an adjustment only for equal options
  // (stages/rig_adjustment_cache.h), so a field added here counts there too.
  bool operator==(const RigBundleAdjustmentOptions&) const = default;
};

// When cameras capture at other times than their frame's timestamp (a trigger offset, a rolling
// shutter): the frames' timestamps and each camera's timing, given or to estimate. A view's pose is
// then cam_from_rig times the rig's pose at the capture time t_frame + offset + (row / height) *
// readout (rows in readout order), interpolated between the two posed frames around it
// (geometry/pose_interpolation.h, the renderer's model of the rig between frames). Intrinsics are
// held with a timing model (refine_intrinsics is not combined with it).
struct CaptureTiming {
  std::vector<double> frame_times_s;     // one per frame, distinct
  std::vector<double> time_offset_s;     // per camera: given, or the start of the estimate
  std::vector<double> readout_s;         // per camera: given, or the start of the estimate
  std::vector<char> readout_bottom_to_top;  // per camera; empty: every camera top to bottom
  // Estimate every camera's offset but camera 0's (the gauge: offsets are relative to it), and
  // every camera's readout time.
  bool estimate_offsets = false;
  bool estimate_readout = false;
  // Per camera, or empty: a camera marked here keeps its time_offset_s while the others' are
  // estimated (a profile of the cost over one camera's offset).
  std::vector<char> offset_held;

  // Throws std::invalid_argument naming the first bad field, for `cameras` cameras and `frames` frames.
  void Check(int cameras, int frames) const;
  bool operator==(const CaptureTiming&) const = default;
};

struct MultiFrameBundleAdjustmentResult {
  // The cameras as adjusted: the given ones, or with RigBundleAdjustmentOptions::refine_intrinsics
  // their refined intrinsics (a camera without observations keeps its given ones).
  std::vector<Camera> cameras;
  // With refine_intrinsics, per camera that was refined: the standard deviation of each intrinsic
  // parameter (camera_models.h order) from the covariance at the solution; empty otherwise.
  std::vector<std::vector<double>> intrinsics_stddev;
  RigPoses poses;  // refined; nullopt where not given
  std::vector<int> observations_per_camera;            // kept in the final solve
  int num_tracks = 0;
  int num_points = 0;
  int num_observations = 0;
  int num_filtered_observations = 0;
  double initial_rms_px = 0.0;
  double reprojection_rms_px = 0.0;
  // The median depth of the points in the views that see them (the result's unit); 0 without points.
  double median_depth = 0.0;
  int iterations = 0;
  // Per camera: covariance of its centre in the rig (in the result's units, squared) at the
  // solution, from the Jacobian and the reprojection RMS, plus with given_intrinsics_sd what the
  // given intrinsics' uncertainty adds; nullopt for camera 0 and cameras not adjusted, or when it
  // could not be computed.
  PerCamera<Eigen::Matrix3d> centre_covariance;
  // Per camera: the standard deviation of its rotation in the rig (deg, along the covariance's
  // worst axis), from the same covariance; nullopt where the centre's is.
  PerCamera<double> rotation_stddev_deg;
  // With given_intrinsics_sd only (empty otherwise): the given intrinsics' share of the two above
  // alone, which the jackknives' spreads (data alone) are widened by.
  PerCamera<Eigen::Matrix3d> centre_covariance_of_intrinsics;
  PerCamera<double> rotation_stddev_of_intrinsics_deg;
  // With a CaptureTiming: per camera its (offset, readout) in seconds as adjusted (or as given), and
  // the standard deviations of the estimated ones from the covariance (nullopt where held).
  std::vector<Eigen::Vector2d> timing;
  PerCamera<double> time_offset_stddev_s, readout_stddev_s;
  // The factor by which every variance above was scaled: for the residual coordinates the fit
  // itself takes up (bundle_covariance.h ResidualDegreesOfFreedomFactor: each point takes 3 of the
  // coordinates of its observations, so short tracks leave a residual RMS well below the keypoints'
  // error) times that for residuals that move together by image region (CorrelatedResidualFactor);
  // 1 without covariances.
  double residual_correlation = 1.0;
  // With covariances, the jackknives (jackknife.h) over frames (with 3 or more posed frames) and
  // over points: per camera the standard deviations of its rotation in the rig and of its
  // centre's direction from camera 0's.
  JackknifeSpread frame_jackknife, point_jackknife;
  // With RigBundleAdjustmentOptions::keep_points only: the final solve's points (world frame) and
  // how many views see each, and the reprojection error (px) of every observation triangulated
  // from the initial poses (before any solve) and of every observation kept at the end.
  std::vector<Eigen::Vector3d> points;
  std::vector<int> point_observations;
  std::vector<double> initial_residuals_px, final_residuals_px;
};

// Least-squares point closest to the rays (origins, unit directions); nullopt when the rays span
// less than min_angle_rad or the point lies behind one of them.
std::optional<Eigen::Vector3d> TriangulateRays(const std::vector<Eigen::Vector3d>& origins,
                                               const std::vector<Eigen::Vector3d>& dirs, double min_angle_rad);

// Triangulates the tracks (world frame) over the posed views, then solves and filters
// (RigBundleAdjustmentOptions). Camera 0's cam_from_rig and frame 0's rig_from_world must be
// given and are held constant (normally the identity); `scale_camera` (-1: none) keeps |its
// centre|; `hold_frames` holds every frame's rig_from_world constant (a static rig, see
// rig_positions.h); `timing`, when given, models each camera's capture time (CaptureTiming). Throws
// std::invalid_argument on sizes that do not match or a missing reference.
MultiFrameBundleAdjustmentResult MultiFrameRigBundleAdjust(
    const std::vector<Camera>& cameras, const FrameKeypoints& keypoints, const std::vector<ViewTrack>& tracks,
    const RigPoses& initial, int scale_camera,
    const RigBundleAdjustmentOptions& options, bool hold_frames = false, const CaptureTiming* timing = nullptr);

// How well poses explain the tracks, comparable between poses of the same views (the starts of
// the bundle adjustment, rig_calibration.h): every posed observation of every track contributes
// min(e^2, max_error_px^2), e its reprojection error (px) from the track's point triangulated from
// its posed views. A point whose rays meet at under min_angle_deg is put far along their mean
// direction (1e6 times the largest distance between the views' centres), as good as at infinity.
// Also returns the number of observations summed.
double TruncatedReprojectionCost(const std::vector<Camera>& cameras, const FrameKeypoints& keypoints,
                                 const std::vector<ViewTrack>& tracks,
                                 const RigPoses& poses, double max_error_px,
                                 double min_angle_deg, int* observations = nullptr);

}  // namespace rigsim
