// The covariances the multi-frame rig bundle adjustment reports (multi_frame_rig.cc): the reduced
// system over the pose blocks after the points are eliminated, and each camera's centre from it.
#pragma once

#include <map>
#include <optional>
#include <vector>

#include <Eigen/Core>
#include <ceres/problem.h>
#include "calibrator/model/rig_state.h"

namespace rigsim {

// The inverse of J^T J (robustified Jacobian, in the tangent spaces of the manifolds) over the
// pose blocks (and the intrinsics blocks when refined: every block that is not a point) after the
// points are eliminated (Schur complement), in units of the variance of one residual coordinate.
// The gauge is fixed by the problem itself (camera 0 and frame 0 constant, the scale camera's
// |t|). Directions the data barely fix have tiny eigenvalues in the reduced system and come out
// with a huge variance (a pseudo-inverse, not a failure: a camera next to camera 0 must read as
// uncertain, not as missing).
struct ReducedCovariance {
  Eigen::MatrixXd covariance;
  std::map<const double*, int> offset;  // tangent column of each adjusted pose block
};

ReducedCovariance PoseCovariance(ceres::Problem& problem, const std::vector<double*>& pose_blocks);

// Covariance of each camera's centre in the rig (C = -R^T t of cam_from_rig, whose translation
// block is `ct[c]`) at the solution, `variance` being that of one image coordinate. nullopt for
// cameras not adjusted.
PerCamera<Eigen::Matrix3d> CentreCovariances(ceres::Problem& problem, const ReducedCovariance& reduced,
                                                              const std::vector<Eigen::Vector4d>& cq,
                                                              const std::vector<Eigen::Vector3d>& ct, double variance);

// Standard deviation (deg) of each camera's rotation in the rig (cam_from_rig's quaternion block
// `cq[c]`) along its worst axis, `variance` being that of one image coordinate. nullopt for
// cameras not adjusted.
PerCamera<double> RotationStdDevsDeg(ceres::Problem& problem, const ReducedCovariance& reduced,
                                     const std::vector<Eigen::Vector4d>& cq, double variance);

// One reprojection residual of the adjustment and where in which image it lies.
struct LocatedResidual {
  int view = 0;                                      // any id unique to its image (camera and frame)
  Eigen::Vector2d position = Eigen::Vector2d::Zero();  // in its image, as fractions of width and height
  Eigen::Vector2d residual_px = Eigen::Vector2d::Zero();
};

// How many residuals count as one independent residual: the covariance above treats every
// residual as independent, but a lens model that does not quite fit, a keypoint detector's bias on
// one texture, or an image's own small motion move the residuals of one image region together, and
// the poses are then known only as well as the regions agree. The factor is the design effect of
// cluster sampling, sum over regions of |sum of residuals|^2 over the sum of |residual|^2: about 1
// for independent residuals, up to a region's size when they move as one. Regions are the cells of
// a 2x2, 4x4 and 8x8 grid over each image, each grid counted when it has 20 regions with residuals
// or more; the largest factor is returned (at least 1), so that whichever scale the errors share,
// the variance covers it.
double CorrelatedResidualFactor(const std::vector<LocatedResidual>& residuals);

// How much larger the variance of one residual coordinate is than the mean square residual at the
// solution: `residuals` coordinates fitted with `parameters` free parameters (tangent dimensions:
// points, poses) leave residuals - parameters degrees of freedom, and the unbiased variance is the
// sum of squares over those, not over every coordinate. A point seen twice takes 3 of its 4
// coordinates, so on short tracks the factor is large. 1 when the fit leaves no freedom.
double ResidualDegreesOfFreedomFactor(int residuals, int parameters);

// The free tangent dimensions of `problem`'s parameter blocks (those not held constant).
int FreeParameterCount(ceres::Problem& problem);

// Standard deviation (deg) of the direction of `centre` (from camera 0 at the origin) under the
// covariance `cov` of the centre: the largest spread across the direction, over the distance.
double DirectionStdDeg(const Eigen::Vector3d& centre, const Eigen::Matrix3d& cov);

}  // namespace rigsim
