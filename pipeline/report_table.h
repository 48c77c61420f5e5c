// Human-readable tables of calibration results: one row per camera pair and method, one per
// camera and method, and a summary line per method. What `rigsim calibrate` and `demo` print.
#pragma once

#include <string>

#include "pipeline/calibration_run.h"

namespace rigsim {

// Pairs with at least this much ground-truth overlap count as neighbours in the summary.
inline constexpr double kNeighbourOverlap = 0.05;

// One row per camera pair and method: matches, inliers, precision and errors against the truth,
// pair type and status.
std::string FormatPairTable(const CalibrationRun& run);
// One line per method: median errors over neighbouring pairs (at least kNeighbourOverlap of
// ground-truth overlap, every pair without it), precision, stage times.
std::string FormatSummary(const CalibrationRun& run);

// One row per camera and method: status, errors against the truth, observations.
std::string FormatRigTable(const CalibrationRun& run);
// One line per method: cameras calibrated, worst errors, reprojection RMS, scale.
std::string FormatRigSummary(const CalibrationRun& run);
// One row per camera and method with a capture time (RigCameraStats::time_offset_s or readout_s):
// its offset from camera 0 and its rolling-shutter readout (ms) with their standard deviations,
// how they were found, and their errors against the truth when known. "" when no camera has one.
std::string FormatTimeTable(const CalibrationRun& run);
// One row per camera and method with refined intrinsics (RigCameraStats::intrinsics): the change
// of fx, fy (percent) and cx, cy (px) from the given values with their standard deviations, and
// the errors against the truth when known.
std::string FormatIntrinsicsTable(const CalibrationRun& run);

}  // namespace rigsim
