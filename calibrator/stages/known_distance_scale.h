// A rig estimate made metric by a known distance between two of its cameras, and the warning a
// result gives when it cannot be.
#pragma once

#include <string>

#include "calibrator/model/rig_observations.h"
#include "calibrator/model/rig_state.h"
#include "calibrator/stages/rig_options.h"
#include "calibrator/stages/rig_result.h"
#include "geometry/rigid3.h"

namespace rigsim {

// Lengths made metres by a known distance between two cameras (ScaleToKnownDistance).
struct MetricScale {
  double factor = 1.0;  // applied to every translation; 1 when nothing was scaled
  std::string scale;    // "metric: |A - B| = 0.5000 m"
  std::string why_not;  // why nothing was scaled; empty when scaled

  // The result's warning when nothing was scaled: "known distance ignored: " + why_not.
  std::string Warning() const;
};

// Removes the warning MetricScale::Warning() adds (a result scaled again says its own).
void DropKnownDistanceWarning(RigCalibrationResult* result);

// Scales the poses so that the known distance's two cameras (both must have a position) are
// `known.metres` apart.
MetricScale ScaleToKnownDistance(const RigObservations& obs, const KnownDistance& known,
                                 PerCamera<Rigid3d>* cam_from_rig, PerFrame<Rigid3d>* rig_from_world);

}  // namespace rigsim
