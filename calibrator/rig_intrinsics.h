// Rig calibration that refines the cameras' intrinsics too (RigBundleAdjustmentOptions::
// refine_intrinsics), from given values a few percent off: what `rigsim calibrate
// --refine-intrinsics` runs.
//
// Intrinsics a few percent off bend every stage before the bundle adjustment: a camera's pairs
// keep fewer inliers and their two-view poses are off by degrees (VALIDATION.md, "Where the
// calibrator's thresholds come from"), so the checks of the pairs against the rig would throw out
// the very pairs that place it. Two passes:
//  1. The rig stages on the pairs as estimated with the given intrinsics, no pair rejected for
//     disagreeing with the rig, the intrinsics refined in the bundle adjustment.
//  2. Every pair and temporal pair estimated again from its matches with the refined intrinsics,
//     and the rig stages run again on them as usual, the intrinsics refined again from there
//     with the priors still centred on the given values.
#pragma once

#include <functional>

#include "calibrator/stages/rig_calibration.h"

namespace rigsim {

// One run of the rig stage on observations: EstimateRig itself, or the controller's run with the
// motion stage's links where they apply (motion_passes.h).
using RigPass = std::function<RigCalibrationResult(const RigObservations&, const RigCalibrationOptions&)>;

// The two passes above, each run by `pass`; the result's rig has the refined intrinsics,
// camera_stats their given and refined values and standard deviations. Throws like EstimateRig.
RigCalibrationResult EstimateRigAndIntrinsics(const RigObservations& observations, const RigCalibrationOptions& options,
                                              const RigPass& pass = EstimateRig);

// `observations` with other intrinsics: `cameras`, and every pair and temporal pair estimated
// again from its matches with them (a pair without matches, screened out, stays as it was).
RigObservations ReestimateWithIntrinsics(const RigObservations& observations, const std::vector<Camera>& cameras,
                                         const TwoViewOptions& options);

}  // namespace rigsim
