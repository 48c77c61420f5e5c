// What the calibrate and demo commands share: calibration options on the command line, and
// running the rig calibration with its tables printed and its results written.
#pragma once

#include <filesystem>
#include <string>
#include <vector>

#include <CLI/CLI.hpp>

#include "calibrator/rig_calibration.h"
#include "dataset/label_source.h"

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
  // Throws std::invalid_argument on noise options without --labels noisy or bad values,
  // std::runtime_error naming a label folder that does not exist.
  LabelSource ToSource() const;
};

void AddLabelSourceOptions(CLI::App& cmd, LabelSettings& settings);

struct CalibrateSettings {
  // Numeric options are bound to these fields directly, so the library's defaults are the CLI's.
  RigCalibrationOptions options;
  std::vector<std::string> semantics = {"none", "mask"};
  std::vector<std::string> reliable;        // empty = the defaults of labels/cityscapes.h
  std::vector<std::string> known_distance;  // CAM_A CAM_B METRES, or empty
  LabelSettings labels;                     // options.pairwise.labels, resolved by ToOptions
  // The options with the names above resolved; throws std::invalid_argument on bad values.
  RigCalibrationOptions ToOptions() const;
  std::vector<SemanticMode> Modes() const;
};

void AddCalibrateSettingsOptions(CLI::App& cmd, CalibrateSettings& settings);

// Checks what can be checked before a long run: rig.json parses and every camera covers its
// image (geometry/camera_validation.h; warnings to stderr). Throws std::runtime_error naming the file.
// Warns too when rig.json has the truth of some cameras only (no comparison is made).
void CheckCalibrationInputs(const std::filesystem::path& dataset);

// The names of the cameras without cam_from_rig, comma-separated.
std::string CamerasWithoutPose(const Rig& rig);

// Calibrates the rig of `dataset` in each semantic mode, prints the pair and camera tables and a
// summary, and writes into `out_dir` (atomically; replaced only with `force`):
//   evaluation.json        "label_source" (kind, folder or noise, whether a mode used labels) and
//                          per method: pairwise summary and pairs, the rig result ("rig") and
//                          "outputs" (files written, cameras exported and omitted, notes)
//   <mode>/rig.json        the estimated rig: every camera, cam_from_rig only for calibrated ones
//   <mode>/camchain.yaml   Kalibr; <mode>/opencv.yaml  cv::FileStorage; <mode>/colmap/  COLMAP text
//                          model of every frame with a rig pose (the calibration's world is the
//                          rig frame at frame 0). The writers of `rigsim export` (exports/),
//                          given only the cameras with a full pose: a camera "not connected" or
//                          "rotation only" is left out with a warning and listed in
//                          evaluation.json. A model Kalibr cannot express skips camchain.yaml
//                          with a note, not the run.
//   <mode>/pairs.json      per camera pair: pair_type (general, planar, rotation-only, failed),
//                          matches, inliers, median residual (deg), errors against the truth when
//                          rig.json has it, ground-truth overlap, and the rig stage's use of it
std::vector<RigCalibrationResult> CalibrateAndReport(const std::filesystem::path& dataset, const CalibrateSettings& settings,
                                                     const std::filesystem::path& out_dir, bool force);

// Throws Unfinished (exit code 3) naming, per semantic mode, the cameras without a full pose, so
// that a script sees a rig that was not (fully) calibrated; the results are written by then.
void ThrowUnlessEveryCameraCalibrated(const std::vector<RigCalibrationResult>& results);

}  // namespace rigsim::cli
