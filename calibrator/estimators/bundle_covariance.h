// The covariances the multi-frame rig bundle adjustment reports (multi_frame_rig.cc): the reduced
// system over the pose blocks after the points are eliminated, and each camera's centre from it.
#pragma once

#include <map>
#include <optional>
#include <utility>
#include <vector>

#include <Eigen/Core>
#include <ceres/crs_matrix.h>
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

// The adjustment linearised at its solution: the robustified Jacobian and residuals (Ceres'
// Evaluate, tangent spaces), columns the adjusted pose blocks first (in `pose_blocks` order), then
// the points' (3 each, in the order of their addresses: one array, so one order on every run).
struct BundleLinearisation {
  ceres::CRSMatrix jacobian;
  std::vector<double> residuals;
  std::vector<int> row_block;  // per row: its residual block's index in the order evaluated
  int pose_dim = 0;
  int num_points = 0;
  std::map<const double*, int> offset;  // tangent column of each adjusted pose block
};

// `residual_blocks` empty: every residual block of the problem, in the problem's order.
BundleLinearisation Linearise(ceres::Problem& problem, const std::vector<double*>& pose_blocks,
                              std::vector<ceres::ResidualBlockId> residual_blocks = {});

// One row of the linearisation: its entries in pose columns, in its point's 3 columns, and its
// point (-1: a row of no point, such as a prior).
struct JacobianRow {
  std::vector<std::pair<int, double>> pose;
  Eigen::RowVector3d point_entries = Eigen::RowVector3d::Zero();
  int point = -1;
};
void ReadRow(const BundleLinearisation& linearised, int row, JacobianRow* out);

// J^T J as the points' elimination needs it: the pose columns' block, each point's 3x3 block and
// its cross terms with the pose columns its rows touch (summed over those entries only, in row
// order, as a dense sum would: the zeros it skips change no bit).
// With them the gradient J^T r, split the same way, and both reduced to the pose columns with
// the points eliminated: S = H_cc - sum_p H_cp H_pp^+ H_pc and g_c - sum_p H_cp H_pp^+ g_p.
struct NormalEquations {
  Eigen::MatrixXd h_poses;
  std::vector<Eigen::Matrix3d> h_point;
  std::vector<std::map<int, Eigen::RowVector3d>> h_cross;  // pose column -> H_cp row
  Eigen::VectorXd g_poses;
  std::vector<Eigen::Vector3d> g_point;
  Eigen::MatrixXd reduced;
  Eigen::VectorXd reduced_gradient;
};
NormalEquations NormalEquationsOf(const BundleLinearisation& linearised);

// A point's H_pp^+: eigenvalues below `min_ratio` of the largest count as none (a point seen once
// is free along its ray).
Eigen::Matrix3d PointPseudoInverse(const Eigen::Matrix3d& h_point, double min_ratio = 1e-12);

// Per column of a symmetric system, 1 / sqrt of its diagonal (1 where the diagonal is not
// positive): D S D then has a unit diagonal, whatever the columns' units.
Eigen::VectorXd EquilibratingScale(const Eigen::MatrixXd& system);

ReducedCovariance PoseCovariance(const BundleLinearisation& linearised, const NormalEquations& normal);

// Covariance of each camera's centre in the rig (C = -R^T t of cam_from_rig, whose translation
// block is `ct[c]`) at the solution, `variance` being that of one image coordinate. nullopt for
// cameras not adjusted. The centre moves through t only, R's own uncertainty being far smaller;
// with `with_rotation` through R (block `cq[c]`) as well, for a covariance where R and t move
// together by as much (HeldBlocksShare: a principal point turns the camera and moves t with it).
PerCamera<Eigen::Matrix3d> CentreCovariances(ceres::Problem& problem, const ReducedCovariance& reduced,
                                                              const std::vector<Eigen::Vector4d>& cq,
                                                              const std::vector<Eigen::Vector3d>& ct, double variance,
                                                              bool with_rotation = false);

// Standard deviation (deg) of each camera's rotation in the rig (cam_from_rig's quaternion block
// `cq[c]`) along its worst axis, `variance` being that of one image coordinate. nullopt for
// cameras not adjusted.
PerCamera<double> RotationStdDevsDeg(ceres::Problem& problem, const ReducedCovariance& reduced,
                                     const std::vector<Eigen::Vector4d>& cq, double variance);

// The same per camera as the covariance of its rotation's tangent (Ceres' quaternion manifold),
// so that covariances from independent sources add before the worst axis is taken.
PerCamera<Eigen::Matrix3d> RotationCovariances(ceres::Problem& problem, const ReducedCovariance& reduced,
                                               const std::vector<Eigen::Vector4d>& cq, double variance);
double RotationStdDevDeg(const Eigen::Matrix3d& tangent_covariance);

// The covariance that held parameters' own uncertainty puts on the adjusted pose blocks (a
// "consider" covariance): held at given values that are off by dk, the solution moves by S dk,
// S = -H^+ B, with H^+ `reduced`'s pseudo-inverse (its gauge and equilibration, PoseCovariance)
// and B the cross block of the adjusted columns with the held ones, points eliminated.
// `with_held`: the normal equations of the same problem linearised with the held parameters free,
// their columns after the adjusted ones (from reduced.covariance.rows() on). `held_variance`: per
// held column its variance, 0 for one taken as exact. Returns S diag(held_variance) S^T over
// `reduced`'s columns, in the parameters' own units: S is a derivative, not scaled by the
// residuals' variance as the data's covariance is.
Eigen::MatrixXd HeldParameterSensitivity(const ReducedCovariance& reduced, const NormalEquations& with_held);
ReducedCovariance HeldParameterCovariance(const ReducedCovariance& reduced, const NormalEquations& with_held,
                                          const Eigen::VectorXd& held_variance);

// A held parameter block of the problem and the standard deviation of each of its leading
// coordinates (the coordinates after those count as exact).
struct HeldBlock {
  double* block = nullptr;
  Eigen::VectorXd sd;
};

// What the uncertainty of `held` adds to each camera's centre covariance and rotation tangent
// covariance (as CentreCovariances and RotationCovariances state them): HeldParameterCovariance,
// from `problem` linearised with the held blocks free for a moment (they are held again before it
// returns). Blocks not in the problem are skipped.
struct HeldShare {
  PerCamera<Eigen::Matrix3d> centre_covariance, rotation_covariance;
};
HeldShare HeldBlocksShare(ceres::Problem& problem, const ReducedCovariance& reduced, const std::vector<HeldBlock>& held,
                          const std::vector<Eigen::Vector4d>& cq, const std::vector<Eigen::Vector3d>& ct);

// Adds `share` to the data's centre covariances and rotation deviations, these stated from
// `reduced` at `variance` (CentreCovariances, RotationStdDevsDeg): the rotations' tangent
// covariances add before the worst axis is taken. The share's own rotation deviations go to
// `share_rotation_std_deg`.
void AddHeldShare(ceres::Problem& problem, const ReducedCovariance& reduced, const std::vector<Eigen::Vector4d>& cq,
                  double variance, const HeldShare& share, PerCamera<Eigen::Matrix3d>* centre_covariance,
                  PerCamera<double>* rotation_std_deg, PerCamera<double>* share_rotation_std_deg);

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

// The direction deviation the placement bound (RigCalibrationOptions::max_direction_std_deg) is
// held against: the bound was measured on deviations that count every residual as independent, so
// the data's share of `cov` is taken without `residual_correlation` (bundle adjustment result's),
// and the share of held parameters' uncertainty within it (`held_share`, nullptr: none) whole.
double PlacementDirectionStdDeg(const Eigen::Vector3d& centre, const Eigen::Matrix3d& cov,
                                const Eigen::Matrix3d* held_share, double residual_correlation);

}  // namespace rigsim
