// The rig with the cameras a registration through tracks placed (track_registration.h), adjusted
// as it stands: the placed rig and the registered poses are the start, and the observations are
// the placed cameras' tracks, the registered cameras' own motion and their inlier view pairs with
// placed views. Capture times are estimated where the rig stage estimated them and held
// otherwise, then checked as the rig stage checks them (rig_capture_times.h); refined intrinsics
// are refined again under the same priors. Rotation averaging and the position estimates do not
// run again: on a straight drive they let a shift along the path pose as a time offset and turn a
// group of cameras together, where the registered poses already fit.
#pragma once

#include <string>
#include <vector>

#include "calibrator/model/rig_observations.h"
#include "calibrator/stages/rig_options.h"
#include "calibrator/stages/rig_result.h"
#include "calibrator/stages/track_registration.h"

namespace rigsim {

struct RegisteredRig {
  RigCalibrationResult result;
  // Per registered camera the adjustment does not place: its name and why.
  std::vector<std::string> not_placed;
};

// `placed` with the registered cameras of `registration` adjusted into it. `obs` are the
// observations with the registered view pairs (WithRegisteredViewPairs). A registered camera is
// calibrated when the adjustment keeps at least options.registration.resection.min_inliers of its
// observations, leaves its rotation within kMaxRegisteredRotationChangeDeg of the resection's,
// and its covariance bounds its direction from camera 0 (options.max_direction_std_deg); it is
// rotation only when the covariance leaves its direction open (unless it was rotation only
// before), and keeps its status otherwise (RegisteredRig::not_placed says why). The placed cameras and frames take their adjusted poses; the unit of length is
// kept (a placed camera's distance from camera 0 is held), or set by a registered camera when
// camera 0 was the only one placed.
RegisteredRig AdjustRegisteredRig(const RigObservations& obs, const RigCalibrationResult& placed,
                                  const TrackRegistration& registration, const RigCalibrationOptions& options);

// A registered camera whose adjusted rotation leaves the resection's by more than this (deg) is
// pulled by the adjustment somewhere its own matches did not put it. Below it the adjustment
// corrects the resection: placed points at one depth in one part of the view let a resection's
// turn trade against its position, and registrations the adjustment then placed within 0.2 deg of
// the truth (at a stated direction deviation of 0.99-1.22 deg) had been turned 1.00-1.37 deg
// (BENCHMARKS.md, "Renders that move the calibrator across its limits").
constexpr double kMaxRegisteredRotationChangeDeg = 3.0;

}  // namespace rigsim
