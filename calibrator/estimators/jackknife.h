// The rig's bundle adjustment with a part of its observations left out at a time, to first order
// (a delete-a-group jackknife, linearised at the solution): how far each camera's pose in the rig
// moves, as a deviation beside the covariance's.
//
// The covariance (bundle_covariance.h) counts the residuals as independent errors around a model
// that fits. On real photos and renders alike the keypoints' error is structured (it grows with
// octave, near depth edges and under foreshortening, and repeats on one texture and in every view
// of one feature), and then the poses move several times further than the covariance says. The
// jackknife needs no model of the error, only units it does not span: frames (each brings its own
// views of the scene; three or more posed) and points (each feature's error is its own, however
// alike in all its views).
#pragma once

#include <vector>

#include <Eigen/Core>
#include <ceres/problem.h>

#include "calibrator/estimators/bundle_covariance.h"
#include "calibrator/model/rig_state.h"

namespace rigsim {

// The posed frames left out together: each alone, or beyond 10 posed frames 10 runs of
// consecutive frames (neighbours share most of their scene, so they leave together), as even as
// they divide; none with fewer than 3 posed frames.
std::vector<std::vector<int>> JackknifeFrameGroups(const std::vector<int>& posed_frames);

// The group point `point` leaves with: every 10th point together (points are listed as their
// tracks were found, so each group spans the images).
int JackknifePointGroup(int point);
constexpr int kJackknifePointGroups = 10;

// The group each point leaves with when the points go by region: kJackknifePointGroups groups of
// neighbouring points (as even in count as they divide), cut by halving the points along the axis
// they spread widest over, again and again (a k-d tree). Features of one facade or one object
// share their error (one texture, one viewing angle, one way the renderer or the lens smears
// them), so every tenth point leaves a tenth of that shared error behind in every group and
// states none of it; a region leaves with all of its own. Deterministic: ties go by index.
std::vector<int> JackknifeRegionGroups(const std::vector<Eigen::Vector3d>& points);

// Per group, the Gauss-Newton step from the solution of the linearised adjustment (`normal` its
// normal equations) without the rows of that group's residual blocks (`block_group`: per residual
// block in the linearisation's order, its group, -1 for blocks that always stay), over the pose
// columns: where the adjustment without them goes, to first order. `held[g]`: pose columns held as well when group g is out (the gauge a
// left-out frame 0 hands on). Columns nothing constrains without the group are NaN in its step.
std::vector<Eigen::VectorXd> StepsWithoutGroups(const BundleLinearisation& linearised, const NormalEquations& normal,
                                                const std::vector<int>& block_group, int groups,
                                                const std::vector<std::vector<int>>& held);

struct JackknifeSpread {
  int groups_left_out = 0;
  // Per camera, from the spread of its pose over the groups' steps ((m - 1) / m times the sum of
  // squared deviations from their mean, m the steps in which its columns stay constrained, at
  // least 2): its rotation in the rig along the worst axis (deg) and the direction of its centre
  // from camera 0's (deg). nullopt for cameras not adjusted.
  PerCamera<double> rotation_std_deg;
  PerCamera<double> direction_std_deg;
};

// Per camera, the larger of the two spreads' deviations (nullopt where neither states one).
JackknifeSpread LargerSpread(const JackknifeSpread& a, const JackknifeSpread& b);

// The cameras' spread over `steps`, cam_from_rig's quaternion and translation being `cq[c]` and
// `ct[c]` (with their manifolds in `problem`).
JackknifeSpread CameraSpread(ceres::Problem& problem, const BundleLinearisation& linearised,
                            const std::vector<Eigen::VectorXd>& steps, const std::vector<Eigen::Vector4d>& cq,
                            const std::vector<Eigen::Vector3d>& ct);

}  // namespace rigsim
