// Human-readable tables of calibration results: one row per camera pair and method, one per
// camera and method, and a summary line per method. What `rigsim calibrate` and `demo` print.
#pragma once

#include <filesystem>
#include <map>
#include <string>
#include <utility>
#include <vector>

#include "calibrator/pairwise.h"
#include "calibrator/rig_calibration.h"

namespace rigsim {

// Ground-truth overlap per unordered camera pair from overlap.json (empty when the file is
// absent): min of the two directions, i.e. the fraction that both cameras share.
using OverlapTable = std::map<std::pair<std::string, std::string>, double>;
OverlapTable ReadOverlap(const std::filesystem::path& overlap_json);

// Pairs with at least this much ground-truth overlap count as neighbours in the summary.
inline constexpr double kNeighbourOverlap = 0.05;

std::string FormatPairTable(const std::vector<CalibrationReport>& reports, const OverlapTable& overlap);
// One line per method: median errors over neighbouring pairs, precision, stage times.
std::string FormatSummary(const std::vector<CalibrationReport>& reports, const OverlapTable& overlap);

// One row per camera and method: status, errors against the truth, observations.
std::string FormatRigTable(const std::vector<RigCalibrationResult>& results);
// One line per method: cameras calibrated, worst errors, reprojection RMS, scale.
std::string FormatRigSummary(const std::vector<RigCalibrationResult>& results);
// One row per camera and method with refined intrinsics (RigCameraStats::intrinsics): the change
// of fx, fy (percent) and cx, cy (px) from the given values with their standard deviations, and
// the errors against the truth when known.
std::string FormatIntrinsicsTable(const std::vector<RigCalibrationResult>& results);

}  // namespace rigsim
