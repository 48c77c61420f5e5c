// What the rig stages make of the bundle adjustment's covariances per camera beyond the stated
// deviations themselves: the deviation the placement bound is held against, and the given
// intrinsics' share (RigBundleAdjustmentOptions::given_intrinsics_sd) of the stated ones.
#pragma once

#include <optional>

#include <Eigen/Core>

#include "calibrator/estimators/multi_frame_rig.h"
#include "calibrator/stages/rig_result.h"

namespace rigsim {

// The deviation (deg) of camera `c`'s direction from camera 0, its centre in the rig at `centre`,
// that RigCalibrationOptions::max_direction_std_deg is held against (bundle_covariance.h
// PlacementDirectionStdDeg); nullopt without its covariance.
std::optional<double> PlacementDirectionStdDeg(const MultiFrameBundleAdjustmentResult& ba, int c,
                                               const Eigen::Vector3d& centre);

// Whether camera `c`'s centre covariance has the given intrinsics' share in it.
bool HasIntrinsicsShare(const MultiFrameBundleAdjustmentResult& ba, int c);

// Into `stats`, where it states camera `c`'s direction and rotation deviations: the given
// intrinsics' share of them (RigCameraStats::direction_intrinsics_std_deg and
// rotation_intrinsics_std_deg); reset without given_intrinsics_sd.
void SetIntrinsicsShare(const MultiFrameBundleAdjustmentResult& ba, int c, RigCameraStats* stats);

}  // namespace rigsim
