// What the calibrate and demo commands share: calibration options on the command line, and
// running the calibrator with its tables printed and evaluation.json written.
#pragma once

#include <filesystem>
#include <string>
#include <vector>

#include <CLI/CLI.hpp>

#include "calibrator/pipeline.h"

namespace rigsim::cli {

struct CalibrateSettings {
  std::vector<std::string> semantics = {"none", "mask"};
  std::vector<std::string> reliable;  // empty = the defaults of labels/cityscapes.h
  int max_features = 8000;
  int threads = 0;
  CalibrationOptions ToOptions() const;
  std::vector<SemanticMode> Modes() const;
};

void AddCalibrateSettingsOptions(CLI::App& cmd, CalibrateSettings& settings);

// Calibrates every camera pair of the dataset in each mode, prints the pair table and the
// summary, and writes the reports to `evaluation_json`.
std::vector<CalibrationReport> CalibrateAndReport(const std::filesystem::path& dataset, const CalibrateSettings& settings,
                                                  const std::filesystem::path& evaluation_json);

}  // namespace rigsim::cli
