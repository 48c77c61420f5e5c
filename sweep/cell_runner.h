// What a sweep cell is made of and how it is run: the scene (a preset generated once per seed, or
// a file), the rig (rigs/rig_spec.h, placed in the scene), the render (renderer/render_dataset.h),
// each method's calibration (rigsim's pipeline in one semantic mode and feature type, run on its
// own so that its wall time is its own; or COLMAP), and the scores (evaluation/rig_scores.h).
#pragma once

#include <filesystem>
#include <string>
#include <vector>

#include "rigs/rig_spec.h"
#include "sweep/sweep_config.h"
#include "sweep/sweep_runner.h"

namespace rigsim {

struct CalibrationRunOptions;  // pipeline/calibration_run.h

struct CellRunnerOptions {
  // Scene files named in the config are relative to this folder (the config's).
  std::filesystem::path config_dir;
  // Preset scenes are generated into this folder once and reused (OUT/scenes).
  std::filesystem::path scene_dir;
  int num_threads = 0;  // 0 = all cores
};

// The rig, its path and its placement options of a cell's parameters; a relative rig_file is
// relative to `config_dir` (the config's folder).
RigSpec CellRigSpec(const nlohmann::ordered_json& params, const std::filesystem::path& config_dir);

// Reads every rig file the cells name (rig: file), once each, so that a bad one stops the sweep
// before anything renders. Throws std::runtime_error naming the file and the problem, or
// std::invalid_argument naming the cell whose rig parameters do not fit together.
void CheckCellRigFiles(const std::vector<SweepCell>& cells, const std::filesystem::path& config_dir);

// The options rigsim's method `method` calibrates a cell with (`params` its parameters): the
// feature type, the capture-time mode, label noise (label_boundary, label_confusion) and the
// intrinsics' error (intrinsics_error), each drawn from the cell's seed.
CalibrationRunOptions CellCalibrationOptions(const SweepMethod& method, const nlohmann::ordered_json& params,
                                             int num_threads);

// Renders a cell, calibrates it by every method of the config and scores each against the truth.
// A method that fails gets a row with status "failed" and the reason; a render that fails (no
// place for the rig in the scene, say) fails every method of the cell the same way.
CellRunner MakeCellRunner(const SweepConfig& config, const CellRunnerOptions& options);

}  // namespace rigsim
