// What a camera pair's correspondences determine (its configuration) and the two-view estimate the
// pairwise report, the view graph and the rig stages keep of it. Conventions: cam_b_from_cam_a
// (x_in_b = R x_in_a + t) with |t| = 1; the scale of a relative pose is unobservable from images.
#pragma once

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

// One camera pair's two-view outcome: what the pairwise report, the view graph and the rig stages
// keep of an estimate (TwoViewResult below is the estimator's raw output, with its inlier mask).
struct TwoViewEstimate {
  bool success = false;
  // The translation is unobservable; the rotation is still reported, the translation is zero.
  bool rotation_only = false;
  PairType pair_type = PairType::kGeneral;  // meaningful on success
  Rigid3d cam_b_from_cam_a;                 // unit translation (zero when rotation_only)
  int num_matches = 0;                      // the correspondences the fit saw
  int num_inliers = 0;                      // of the reported model
  int num_homography_inliers = 0;           // of the homography the planar test fits
  double median_residual_deg = 0.0;         // median angular residual of the inliers
  std::vector<Rigid3d> planar_alternatives;  // TwoViewResult below
  // Cheirality (TwoViewResult below).
  int cheirality_points = 0;
  int points_in_front = 0;
  int points_in_front_otherwise = 0;
  std::string failure_reason;               // empty on success
};

}  // namespace rigsim
