// Relative pose of two cameras from matched keypoints, through bearing vectors so that every
// camera model (fisheye beyond 90 degrees included) is handled by its own unprojection.
//
// Steps: pixels -> unit bearings (Camera::CamFromImg); robust essential matrix (OpenCV USAC
// MAGSAC++) on the bearings in front of both cameras, as normalised coordinates with K = I;
// pose recovery (cheirality); non-linear refinement of R and the unit t over all bearings with
// a robust angular epipolar error (Ceres); a pure-rotation model fitted alongside detects pairs
// whose translation is unobservable, a homography fitted alongside detects planar pairs, and the
// refinement restarted from other translations finds a rival pose that fits the matches as well.
//
// Conventions: the result is cam_b_from_cam_a (x_in_b = R x_in_a + t) with |t| = 1; the scale of
// a relative pose is unobservable from images. Angles in options and results are in degrees or
// pixels as named; radians inside.
#pragma once

#include <string>
#include <string_view>
#include <vector>

#include <Eigen/Core>

#include "calibrator/model/two_view_geometry.h"
#include "geometry/camera.h"
#include "geometry/rigid3.h"

namespace rigsim {

struct TwoViewOptions {
  // Fewer correspondences than this fail at once ("too few matches").
  int min_matches = 15;
  // Fewer inliers than this after the fit fail ("too few inliers"). A count, not an a contrario
  // test: matches of repeated structure between views that share nothing pass such a test at
  // 10^-3 (VALIDATION.md, "Where the calibrator's thresholds come from").
  int min_inliers = 30;
  // ... and so does a fit that explains less than this fraction of the correspondences: between
  // views that share nothing, RANSAC still finds a few dozen random matches that agree with
  // some pose, a confident wrong answer (VALIDATION.md, "Where the calibrator's thresholds come
  // from").
  double min_inlier_ratio = 0.1;
  // Inlier threshold in pixels; converted to an angle with the mean focal length of the two
  // cameras (the scale at which a pixel of noise is an angle).
  double max_error_px = 1.0;
  // RANSAC confidence and iteration cap of the essential-matrix fit.
  double ransac_confidence = 0.9999;
  int ransac_max_iterations = 10000;
  // Bearings with z below this (about 75 deg off-axis) are left out of the essential-matrix fit,
  // whose normalised coordinates x/z, y/z blow up there; the refinement uses them all.
  double min_bearing_z = 0.25;
  // Non-linear refinement of the pose after RANSAC.
  bool refine = true;
  int refine_max_iterations = 50;
  // A pair is rotation-only when a pure rotation explains at least this fraction as many
  // correspondences as the essential matrix: the parallax is below the noise and the
  // translation direction is then not observable.
  double rotation_only_ratio = 0.9;
  // A pair is planar when a homography explains at least this fraction as many correspondences
  // as the essential matrix (an inlier-ratio rule, as COLMAP's max_H_inlier_ratio). The
  // homography's inlier threshold is the essential matrix's times sqrt(5.99 / 3.84): its transfer
  // error has two degrees of freedom, the epipolar error one, so both keep 95% of noisy true
  // matches. 0.95 lies between the ratios of points on one plane and those of the street's pairs,
  // whose facades fill most of the matches but leave enough off-plane support (VALIDATION.md,
  // "Where the calibrator's thresholds come from"); COLMAP's 0.8 would flag street pairs.
  double planar_ratio = 0.95;
  // A planar pair also reports the homography's other pose (TwoViewEstimate::planar_alternatives) when
  // its rotation differs from the reported one by more than this (deg): a plane fits two poses, and
  // the matches of one pair cannot say which; the poses of other pairs can (camera_trajectory.h).
  double min_planar_alternative_deg = 0.5;
  // RANSAC iterations of the 2-point pure-rotation fit, and its seed (fixed: reproducible).
  int rotation_ransac_iterations = 300;
  unsigned rotation_ransac_seed = 1;
  // Cheirality (which of the essential matrix's four poses) is decided by the inliers whose rays
  // meet at this many times the inlier threshold or more; nearer to parallel, noise alone could
  // put their point on either side.
  double cheirality_min_angle_factor = 4.0;
  // The chosen pose must put at least min_cheirality_points of those inliers in front of both
  // cameras, and cheirality_margin times as many as any of the other three poses; otherwise the
  // matches do not say which way the baseline points (the sign, or the twisted pair, would be
  // a guess) and the pair fails rather than report a direction that may be reversed.
  int min_cheirality_points = 10;
  double cheirality_margin = 3.0;
  // Rival poses. Points at one depth in one part of the view cannot tell a baseline's parallax
  // from a small turn: poses far apart then fit the matches equally, and the refinement keeps
  // whichever RANSAC began near. The refinement restarts from rival_seeds translation directions
  // spread over the sphere (at the reported rotation, on at most rival_max_matches of the
  // matches); a minimum whose translation (cheirality resolved) is more than
  // rival_min_direction_deg from the reported one is a rival unless the reported pose fits the
  // matches clearly better: of the matches either explains, those the reported pose fits closer
  // outnumber those the rival fits closer by more than rival_sign_test_sigma standard deviations
  // of a fair split (a sign test). The pair keeps its pose and reports the rival
  // (TwoViewEstimate::rival): other pairs may decide what its matches cannot; the rig stage judges.
  int rival_seeds = 16;
  int rival_max_matches = 400;
  double rival_min_direction_deg = 30.0;
  double rival_sign_test_sigma = 2.5;

  // Throws std::invalid_argument naming the first bad field.
  void Check() const;
};

// The estimator's output: the estimate the pairwise report and the rig stages keep, and what only
// the estimator's callers use.
struct TwoViewResult {
  TwoViewEstimate estimate;
  std::vector<char> inlier_mask;  // one per input correspondence; 0 also for invalid pixels
  int num_essential_inliers = 0;  // of the essential-matrix model after refinement
  int num_rotation_inliers = 0;   // of the pure-rotation model
  int num_valid = 0;              // correspondences with a valid bearing in both cameras
};

// `options` without the rival search (rival_seeds 0), for the view pairs whose rivals nothing
// judges (a camera with itself across frames, a cross-time pair): the restarts are most of the fit.
TwoViewOptions WithoutRivalSearch(TwoViewOptions options);

// From pixel correspondences (px_a[i] <-> px_b[i]).
TwoViewResult EstimateRelativePose(const Camera& cam_a, const std::vector<Eigen::Vector2d>& px_a,
                                   const Camera& cam_b, const std::vector<Eigen::Vector2d>& px_b,
                                   const TwoViewOptions& options);

// From unit bearings, with the inlier threshold as an angle (radians).
TwoViewResult EstimateRelativePoseFromBearings(const std::vector<Eigen::Vector3d>& bearings_a,
                                               const std::vector<Eigen::Vector3d>& bearings_b,
                                               double max_error_rad, const TwoViewOptions& options);

// Angular epipolar residual: sines of the angles between bearing_b and the epipolar plane of
// bearing_a (in B), and between bearing_a and the epipolar plane of bearing_b (in A). Zero for a
// noise-free correspondence under the true pose; defined on the whole sphere.
Eigen::Vector2d EpipolarAngularResidual(const Rigid3d& cam_b_from_cam_a, const Eigen::Vector3d& bearing_a,
                                        const Eigen::Vector3d& bearing_b);

struct RefinementSummary {
  double initial_cost = 0.0;
  double final_cost = 0.0;
  int iterations = 0;
};

// Minimises the robust (Cauchy, scale `loss_scale_rad`) angular epipolar error over R (unit
// quaternion manifold) and the unit translation (sphere manifold). Returns the refined pose
// with |t| = 1.
Rigid3d RefineRelativePose(const std::vector<Eigen::Vector3d>& bearings_a,
                           const std::vector<Eigen::Vector3d>& bearings_b, const Rigid3d& initial,
                           double loss_scale_rad, int max_iterations, RefinementSummary* summary = nullptr);

}  // namespace rigsim
