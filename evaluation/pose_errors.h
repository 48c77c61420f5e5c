// Errors of an estimated pose against the truth, and their area under the recall curve: the
// measures every comparison in rigsim uses (pairs, rigs, other tools' estimates).
#pragma once

#include <optional>
#include <vector>

#include "geometry/rigid3.h"

namespace rigsim {

// Angle of R_est * R_gt^T, degrees.
double RotationErrorDeg(const Rigid3d& est, const Rigid3d& gt);

// Angle between the translation directions, degrees; nullopt when either translation is (near)
// zero (true rig with co-located cameras, or an estimate flagged rotation-only).
std::optional<double> TranslationDirectionErrorDeg(const Rigid3d& est, const Rigid3d& gt, double min_norm = 1e-9);

// `v` without its component along `axis` (normalised here).
Eigen::Vector3d AcrossAxis(const Eigen::Vector3d& axis, const Eigen::Vector3d& v);

// Of a camera placed but for one axis: the angle (deg) between its estimated centre across the
// axis and the true centre with its component along the same axis removed, both in one frame (the
// estimate up to scale, so directions only); nullopt when either is (near) zero: a true centre on
// the axis has no direction across it.
std::optional<double> AcrossAxisDirectionErrorDeg(const Eigen::Vector3d& axis, const Eigen::Vector3d& est_centre_across,
                                                  const Eigen::Vector3d& true_centre, double min_norm = 1e-9);

// Area under the recall curve of errors up to `threshold_deg` (0..1), as in SuperGlue/LoFTR;
// failures enter as +inf (or NaN) and only lower the curve.
double PoseAuc(const std::vector<double>& errors_deg, double threshold_deg);

}  // namespace rigsim
