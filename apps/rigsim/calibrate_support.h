// What the calibrate and demo commands share: calibration options on the command line, and
// running the rig calibration with its tables printed and its results written.
#pragma once

#include <filesystem>
#include <string>
#include <vector>

#include <CLI/CLI.hpp>

#include "calibrator/rig_calibration.h"

namespace rigsim::cli {

struct CalibrateSettings {
  // Numeric options are bound to these fields directly, so the library's defaults are the CLI's.
  RigCalibrationOptions options;
  std::vector<std::string> semantics = {"none", "mask"};
  std::vector<std::string> reliable;        // empty = the defaults of labels/cityscapes.h
  std::vector<std::string> known_distance;  // CAM_A CAM_B METRES, or empty
  // The options with the names above resolved; throws std::invalid_argument on bad values.
  RigCalibrationOptions ToOptions() const;
  std::vector<SemanticMode> Modes() const;
};

void AddCalibrateSettingsOptions(CLI::App& cmd, CalibrateSettings& settings);

// Checks what can be checked before a long run: rig.json parses and every camera covers its
// image (geometry/camera_validation.h; warnings to stderr). Throws std::runtime_error naming the file.
void CheckCalibrationInputs(const std::filesystem::path& dataset);

// Calibrates the rig of `dataset` in each semantic mode, prints the pair and camera tables and a
// summary, and writes into `out_dir` (atomically; replaced only with `force`):
//   evaluation.json        per method: pairwise summary and pairs, and the rig result ("rig")
//   <mode>/rig.json        the estimated rig (intrinsics as given, cam_from_rig estimated)
std::vector<RigCalibrationResult> CalibrateAndReport(const std::filesystem::path& dataset, const CalibrateSettings& settings,
                                                     const std::filesystem::path& out_dir, bool force);

}  // namespace rigsim::cli
