// The controller's passes with the motion stage (stages/motion_links.h): the rig stage
// (stages/rig_calibration.h) without the links and with them, and which result is kept; then
// registration through tracks (stages/track_registration.h) of the cameras still unplaced.
#pragma once

#include "calibrator/model/rig_observations.h"
#include "calibrator/stages/motion_links.h"
#include "calibrator/stages/rig_options.h"
#include "calibrator/stages/rig_result.h"

namespace rigsim {

// The rig stages on `obs` (EstimateRig), with the motion links (FindMotionLinks through `match`)
// where a camera is left without a full pose and the rig moved, kept when they place more cameras
// and the views the new rig predicts to meet, matched afresh, contradict it for none of its cameras
// (CheckPredictedViews). Where the stages before a bundle adjustment already show it
// (EstimateRigUnlessUnplaced stops), the pass with the links runs next and is the result when it
// places every camera, without a full pass without them; otherwise the full pass runs, and the
// links only where its result needs them. Then, while a camera is left without a full pose,
// registration through tracks (stages/track_registration.h; RigCalibrationOptions::registration),
// kept when the rig adjusted with it places more cameras and moves none placed before. Throws like
// EstimateRig.
RigCalibrationResult EstimateRigWithMotionLinks(const RigObservations& obs, const ViewPairMatcher& match,
                                                const RigCalibrationOptions& options);

}  // namespace rigsim
