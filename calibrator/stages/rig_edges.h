#pragma once

#include <string>
#include <utility>

#include "calibrator/model/rig_observations.h"
#include "calibrator/stages/rig_options.h"
#include "calibrator/stages/rig_result.h"

namespace rigsim {

// Each used edge's two-view estimate against the rig's: how far its rotation is from the rig's
// R_b R_a^T and, when both cameras have a position, its translation direction from the rig's.
void CompareEdgesWithRig(const RigObservations& obs, RigCalibrationResult* result);

// The used edge that disagrees most with the rig beyond the options' thresholds, and why; -1 when
// none does.
std::pair<int, std::string> MostDisagreeingEdge(const RigCalibrationResult& r, const RigCalibrationOptions& options);

}  // namespace rigsim
