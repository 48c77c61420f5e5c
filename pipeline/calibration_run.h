// Calibrating a dataset as `rigsim calibrate` and `rigsim demo` do: its inputs read and checked,
// the rig calibrated in several semantic modes on the same images (calibrator/rig_calibration.h),
// everything a report, an export or a comparison with the truth needs kept together. No printing:
// warnings are returned for the caller to show.
//
// What a run writes to disk is calibration_outputs.h; the text tables are report_table.h.
#pragma once

#include <filesystem>
#include <optional>
#include <string>
#include <vector>

#include "calibrator/rig_calibration.h"
#include "dataset/dataset.h"
#include "geometry/rig.h"
#include "pipeline/report_table.h"

namespace rigsim {

// A dataset's inputs to the calibration, read before the long run so that bad input fails fast.
struct CalibrationInputs {
  std::filesystem::path dataset_dir;
  Rig rig;                  // rig.json as read: intrinsics, cam_from_rig where known
  std::optional<Rig> truth;  // `rig` when it has every camera's cam_from_rig (rendered data)
  FramesFile frames;         // frames.json, or the image stems of the first camera
  OverlapTable overlap;      // ground-truth overlap.json; empty when absent
  // What the user should know before the run: cameras whose model does not cover their image
  // (geometry/camera_validation.h), a rig.json with the truth of some cameras only.
  std::vector<std::string> warnings;
};

// Reads rig.json, the frames and overlap.json. Throws std::runtime_error naming the file on
// input that cannot be read.
CalibrationInputs ReadCalibrationInputs(const std::filesystem::path& dataset_dir);

struct CalibrationRun {
  CalibrationInputs inputs;
  RigCalibrationOptions options;  // as run (options.pairwise.labels: where labels came from)
  std::vector<SemanticMode> modes;
  bool labels_used = false;  // some mode needs labels (NeedsLabels)
  std::vector<RigCalibrationResult> results;  // one per mode, in `modes` order
  double seconds = 0.0;                       // wall time of the calibration
};

// Calibrates the rig of `inputs.dataset_dir` in each of `modes` (at least one); features are
// detected once and shared. With options.keep_details, each result also keeps what a report
// shows of every stage (RigCalibrationResult::details, report/); off, the run costs nothing more.
// Throws like CalibrateRig (calibrator/rig_calibration.h).
CalibrationRun CalibrateDataset(const CalibrationInputs& inputs, const RigCalibrationOptions& options,
                                const std::vector<SemanticMode>& modes);
// ReadCalibrationInputs, then the above.
CalibrationRun CalibrateDataset(const std::filesystem::path& dataset_dir, const RigCalibrationOptions& options,
                                const std::vector<SemanticMode>& modes);

// The names of the cameras without cam_from_rig, comma-separated ("" when every camera has one).
std::string CamerasWithoutPose(const Rig& rig);

}  // namespace rigsim
