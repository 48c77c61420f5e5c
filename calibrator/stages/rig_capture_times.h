// The rig stage's last step on capture times (calibrator/capture_time.h): the synchronisation
// check of a result taken as synchronised, and each camera's offset and readout (estimated or
// measured) into the result, with the status of a camera whose capture time the images leave open.
#pragma once

#include <vector>

#include "calibrator/estimators/capture_time.h"
#include "calibrator/estimators/multi_frame_rig.h"
#include "calibrator/model/rig_observations.h"
#include "calibrator/stages/rig_result.h"

namespace rigsim {

// The synchronisation check of a result taken as synchronised (CaptureTimeOptions), on the bundle
// adjustment `ba` before it is scaled; with offsets estimated, the restarts of those offsets
// (RestartFromMovedOffsets); empty when neither applies (the check off, a static rig, frames
// without distinct times, no bundle adjustment).
std::vector<CameraSynchronisation> CheckCaptureTimes(const RigObservations& obs, const CaptureTimeOptions& options,
                                                     const RigBundleAdjustmentOptions& bundle_adjustment,
                                                     bool rig_moving, const std::vector<ViewTrack>& tracks,
                                                     int scale_camera, const MultiFrameBundleAdjustmentResult& ba);

// Estimated, each camera's offset and readout go into its stats and the rig (a camera whose offset
// the path cannot show is not calibrated); not estimated, the check's verdicts take the pose of every
// camera that did not capture with camera 0, and a warning names those whose timing the path hides.
void SetCaptureTimes(const RigObservations& obs, const CaptureTimeOptions& options,
                     const MultiFrameBundleAdjustmentResult& ba, const std::vector<CameraSynchronisation>& checked,
                     RigCalibrationResult* result);

// Removes the warning SetCaptureTimes writes about the cameras whose capture time the rig's path
// hides, so that a result judged again (a registered rig) names the cameras of its own check.
void DropHiddenTimeWarning(RigCalibrationResult* result);

// Moves that warning after every other: it speaks of all the cameras placed, so it follows the
// warnings of a registration round that placed more.
void PutHiddenTimeWarningLast(RigCalibrationResult* result);

}  // namespace rigsim
