// What the calibrate, demo and report commands share: calibration options on the command line, and
// running the calibration library (pipeline/) with its tables printed and its results committed.
#pragma once

#include <filesystem>
#include <string>
#include <vector>

#include <CLI/CLI.hpp>

#include "apps/rigsim/segment_support.h"
#include "dataset/label_source.h"
#include "dataset/output_folder.h"
#include "pipeline/calibration_plan.h"
#include "pipeline/calibration_run.h"

namespace rigsim::cli {

// Where the semantic modes get their labels (dataset/label_source.h): --labels truth|noisy|DIR and
// the --label-noise-* options of the noise model.
struct LabelSettings {
  std::string labels = "truth";
  SegmentationNoiseOptions noise = DefaultNoise();
  // The noise options as given on the command line (set by AddLabelSourceOptions), to refuse them
  // without --labels noisy.
  std::vector<const CLI::Option*> noise_options;

  static SegmentationNoiseOptions DefaultNoise() {
    SegmentationNoiseOptions n;
    n.boundary_px = 3;
    n.confusion_rate = 0.1;
    n.seed = 1;
    return n;
  }
  // The label source (pipeline/calibration_plan.h LabelSourceNamed): throws std::invalid_argument
  // on noise options without --labels noisy or bad values, std::runtime_error naming a label folder
  // that does not exist.
  LabelSource ToSource() const;
};

void AddLabelSourceOptions(CLI::App& cmd, LabelSettings& settings);

struct CalibrateSettings {
  // Numeric options are bound to these fields directly, so the library's defaults are the CLI's.
  CalibrationRunOptions options;
  std::vector<std::string> semantics = {"none", "mask"};
  const CLI::Option* semantics_option = nullptr;  // set by AddCalibrateSettingsOptions: given or default
  std::vector<std::string> reliable;        // empty = the defaults of labels/cityscapes.h
  std::vector<std::string> known_distance;  // CAM_A CAM_B METRES, or empty
  std::string intrinsics;                   // --intrinsics FILE (a rig.json), or empty: the dataset's
  std::string intrinsics_sd;                // --intrinsics-sd F,P, or empty: the intrinsics count as exact
  LabelSettings labels;                     // options.labels, resolved by ToOptions
  // --segmenter MODEL.onnx: labels from a network run on the photos first (by the pipeline,
  // pipeline/calibration_plan.h), written to OUT/segmentation/; in place of --labels.
  SegmenterSettings segmenter;
  // --mask DIR: the rig's own vehicle hidden in every mode (pipeline/rig_masks.h), or empty.
  std::string mask;
  // The options with the names above resolved; throws std::invalid_argument on bad values.
  CalibrationRunOptions ToOptions() const;
  std::vector<SemanticMode> Modes() const;
};

void AddCalibrateSettingsOptions(CLI::App& cmd, CalibrateSettings& settings);

// --intrinsics-sd's value, "F,P": the focal lengths' standard deviation as a fraction and the
// principal point's in pixels. Throws std::invalid_argument saying what is wrong with `text`.
GivenIntrinsicsDeviation ParseIntrinsicsSd(const std::string& text);
// --mask DIR into settings.mask (calibrate's; a rendered demo has no vehicle to hide).
void AddMaskOption(CLI::App& cmd, CalibrateSettings& settings);

// The output folder of a calibration of `dataset` with `settings` (calibrate's; the report's
// adds its own inputs), with every input it reads: the photos, labels and rig it calibrates
// must not be replaced. Named "--out" unless `out_dir` is the default, DATASET/calibration.
OutputFolderRequest CalibrationOutputFolder(const std::filesystem::path& dataset, const CalibrateSettings& settings,
                                            const std::filesystem::path& out_dir, bool force);

// "warning: `warning`" on stderr, as the calibrating commands give their warnings.
void Warn(const std::string& warning);

// CalibrateDataset(plan), each stage shown on stderr as it begins (progress.h StageLine), the
// line cleared before anything else is written, whether it returns or throws.
CalibrationRun CalibrateShowingStages(CalibrationPlan& plan);

// Calibrates the rig of `dataset` in each semantic mode (pipeline/calibration_plan.h, which checks
// the inputs first and drops the default modes that need labels when the dataset has none), writes
// the results into `out_dir` (pipeline/calibration_outputs.h; atomically, replaced only with
// `force`) and prints the network's progress, the pair and camera tables and a summary, warnings
// to stderr. Returns the run (with
// each stage's details when settings.options.rig.keep_details, for a report).
CalibrationRun CalibrateAndReport(const std::filesystem::path& dataset, const CalibrateSettings& settings,
                                  const std::filesystem::path& out_dir, bool force);

// Throws Unfinished (exit code 3) naming, per semantic mode, the cameras without a full pose, so
// that a script sees a rig that was not (fully) calibrated; the results are written by then.
void ThrowUnlessEveryCameraCalibrated(const std::vector<RigCalibrationResult>& results);

}  // namespace rigsim::cli
