// How well a pair's matches fix its relative pose: first-order standard deviations of the rotation
// and of the baseline direction, from the Jacobian of the angular epipolar residuals
// (two_view.h EpipolarAngularResidual) at the pose over its inliers, with the residual variance
// estimated from the same inliers. The rotation and the direction are marginals: a rotation that
// trades off against the direction (a small shared view seen through narrow parallax) shows as
// large deviations of both.
#pragma once

#include <vector>

#include <Eigen/Core>

#include "geometry/rigid3.h"

namespace rigsim {

struct TwoViewUncertainty {
  double rotation_std_deg = 0.0;   // the largest, over axes
  double direction_std_deg = 0.0;  // the largest, over the two directions across the baseline
};

// Infinite deviations when the inliers do not determine the pose (fewer than three, or a singular
// system).
TwoViewUncertainty EstimateTwoViewUncertainty(const Rigid3d& cam_b_from_cam_a, const std::vector<Eigen::Vector3d>& bearings_a,
                                              const std::vector<Eigen::Vector3d>& bearings_b,
                                              const std::vector<int>& inliers);

}  // namespace rigsim
