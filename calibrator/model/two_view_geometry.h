// What a camera pair's correspondences determine (its configuration) and the two-view estimate the
// pairwise report, the view graph and the rig stages keep of it. Conventions: cam_b_from_cam_a
// (x_in_b = R x_in_a + t) with |t| = 1; the scale of a relative pose is unobservable from images.
#pragma once

#include <optional>
#include <string>
#include <string_view>
#include <vector>

#include "geometry/rigid3.h"

namespace rigsim {

// What the correspondences of a pair determine:
//  - kGeneral: a relative pose from the essential matrix.
//  - kPlanar: a homography explains the matches about as well as the essential matrix (a planar
//    scene, or one whose depth variation gives less parallax than the noise). The pose is still
//    the essential matrix's, but it rests on a degenerate configuration for the 5-point solver
//    (two poses fit a plane: the pose is less certain than its inlier count suggests).
//  - kRotationOnly: a pure rotation explains them; the translation is unobservable. A pure
//    rotation is also a homography: rotation-only takes precedence over planar.
enum class PairType { kGeneral, kPlanar, kRotationOnly };
// "general", "planar", "rotation-only".
std::string_view PairTypeName(PairType type);

// Why a pair has no two-view estimate (two_view.h says how each is decided).
enum class TwoViewFailure {
  kNone,                  // the estimate succeeded
  kNotEstimated,          // no estimate was made (a pair screened out before matching)
  kTooFewMatches,         // fewer valid correspondences than TwoViewOptions::min_matches
  kTooFewInFront,         // too few bearings in front of both cameras for the essential matrix
  kNoEssentialMatrix,     // the essential-matrix fit found no model
  kEssentialMatrixError,  // the essential-matrix fit failed (OpenCV's words in failure_reason)
  kPoseRecoveryFailed,    // pose recovery left fewer than 5 points in front of both cameras
  kTooFewInliers,         // "no consistent geometry": below min_inliers or min_inlier_ratio of the matches
  kCheiralityUndecided,   // the matches do not say which way the baseline points
};

// Another local minimum of the relative pose that explains a pair's matches about as well as the
// reported pose (TwoViewOptions::rival_*): its distance from the reported pose and its support.
struct RivalPose {
  double direction_deg = 0.0;  // between the two translations' directions
  double rotation_deg = 0.0;   // between the two rotations
  int inliers = 0;             // matches it explains
  // Of the matches either explains: those it fits closer than the reported pose, and the other way.
  int rival_closer = 0, pose_closer = 0;
};

// One camera pair's two-view outcome: what the pairwise report, the view graph and the rig stages
// keep of an estimate (the estimator's TwoViewResult holds it, with its inlier mask).
struct TwoViewEstimate {
  bool success = false;
  TwoViewFailure failure = TwoViewFailure::kNotEstimated;  // kNone when the estimator succeeded
  // The translation is unobservable (pure rotation or parallax below the noise). The rotation
  // is still reported; the translation is then zero, meaning "unknown".
  bool rotation_only = false;
  // kRotationOnly exactly when rotation_only; kPlanar when the homography explains the matches
  // about as well as the essential matrix (TwoViewOptions::planar_ratio). Set on success.
  PairType pair_type = PairType::kGeneral;
  Rigid3d cam_b_from_cam_a;                // unit translation (zero when rotation_only)
  int num_matches = 0;                     // the correspondences the fit saw
  int num_inliers = 0;                     // of the reported model (rotation model when rotation_only)
  int num_homography_inliers = 0;          // of the homography (0 when not fitted: rotation-only or no pose)
  double median_residual_deg = 0.0;        // median angular residual of the inliers
  // kPlanar only: the homography's other poses that explain the matches as well as the reported one
  // (TwoViewOptions::min_planar_alternative_deg), cam_b_from_cam_a with a unit translation; the
  // matches do not decide between them.
  std::vector<Rigid3d> planar_alternatives;
  // Cheirality of the essential-matrix pose: the inliers with parallax enough to tell
  // (TwoViewOptions::cheirality_min_angle_factor), how many of them the reported pose puts in
  // front of both cameras, and how many the best of the other three poses would.
  int cheirality_points = 0;
  int points_in_front = 0;
  int points_in_front_otherwise = 0;
  // The strongest rival pose whose translation points elsewhere, when one explains the matches
  // about as well: these matches alone do not fix the translation (nor the rotation closer than
  // the rival's). General pairs only: a planar pair reports planar_alternatives instead.
  std::optional<RivalPose> rival;
  // The failure in words, with its figures (what the pairwise report prints); empty on success.
  std::string failure_reason;
};

}  // namespace rigsim
