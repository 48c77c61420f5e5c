// Intrinsics against the truth (a rendered dataset's rig.json): how far a focal length and a
// principal point are from the true ones, for the intrinsics a calibration was given and those
// it refined (calibrator/estimators/intrinsics_refinement.h).
#pragma once

#include <optional>
#include <vector>

#include "geometry/camera.h"

namespace rigsim {

// The larger of the fx and fy errors of `estimate` against `truth`, percent of the true value
// (parameters in camera_models.h order).
double FocalErrorPercent(const std::vector<double>& estimate, const std::vector<double>& truth);
// The distance (px) between the principal points of `estimate` and `truth`.
double PrincipalPointErrorPx(const std::vector<double>& estimate, const std::vector<double>& truth);

struct IntrinsicsErrors {
  double focal_error_percent = 0.0;  // refined
  double principal_point_error_px = 0.0;
  double given_focal_error_percent = 0.0;  // as given, for comparison
  double given_principal_point_error_px = 0.0;
};

// The errors of the `given` and `refined` parameters against `truth`'s; nullopt when either has
// another number of parameters than the truth (another model).
std::optional<IntrinsicsErrors> ScoreIntrinsics(const std::vector<double>& given, const std::vector<double>& refined,
                                                const Camera& truth);

}  // namespace rigsim
