// What the pipeline's tests share: a calibration result built by hand, without images.
#pragma once

#include "calibrator/calibrate_rig.h"
#include "dataset/dataset.h"
#include "pipeline/calibration_run.h"

namespace rigsim {

// Three cameras of which cam2 got a rotation only, three frames of which the estimate posed the
// first two; pairs cam0-cam1 (solved, an edge in use), cam0-cam2 (failed, an inactive edge) and
// cam1-cam2 (solved and planar, no rig edge). Semantic mode "mask", unit scale.
RigCalibrationResult ThreeCameraResult();
// Frames 000000, 000001, 000002 without poses.
FramesFile ThreeFrames();
// A run of `results` on ThreeFrames and the first result's rig, without the truth.
CalibrationRun RunOf(const std::vector<RigCalibrationResult>& results);

}  // namespace rigsim
