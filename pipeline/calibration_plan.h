// `rigsim calibrate`'s run of a dataset, up to and around the calibration itself: where the labels
// come from (the truth, the truth made noisy, a folder, or a segmentation network run on the
// photos first), which semantic modes run, and every check of the inputs, made before anything is
// written so that bad input fails fast and leaves nothing behind. The caller stages the output
// folder, shows the warnings and progress, and writes the results (calibration_outputs.h).
#pragma once

#include <filesystem>
#include <functional>
#include <memory>
#include <string>
#include <vector>

#include "dataset/label_source.h"
#include "dataset/output_folder.h"
#include "pipeline/calibration_run.h"
#include "pipeline/segmentation_run.h"

namespace rigsim {

// The label source `labels` names: "truth", "noisy" (with `noise`) or a folder, checked.
// `noise_option_given` names a noise option the user gave ("--label-noise-seed"), or is empty:
// refused without noisy labels. Throws std::invalid_argument in the command line's words,
// std::runtime_error naming a label folder that does not exist.
LabelSource LabelSourceNamed(const std::string& labels, const SegmentationNoiseOptions& noise,
                             const std::string& noise_option_given = "");

// What a calibration of a dataset is asked to do.
struct CalibrationRequest {
  std::filesystem::path dataset;
  CalibrationRunOptions options;  // options.labels: the label source unless a network gives them
  std::vector<SemanticMode> modes;
  // The modes were named by the user: those that need labels are refused, not dropped, when the
  // dataset has none.
  bool modes_given = false;
  // Labels from a network run on the photos first, in place of options.labels (which must then be
  // the truth's default): its model file, or empty; and its options, parsed from the command line
  // only when some mode needs labels (a network that is not used is not checked).
  std::filesystem::path segmenter_model;
  std::function<SegmenterOptions()> segmenter_options;
  OutputFolderRequest out;  // checked before anything is read
  // The rig's own vehicle hidden in every mode: a folder of <camera>.png masks (rig_masks.h), or
  // empty for none.
  std::filesystem::path mask_dir;
};

// A request with every input read and checked.
struct CalibrationPlan {
  std::filesystem::path dataset;
  CalibrationRunOptions options;
  std::vector<SemanticMode> modes;  // those that run
  bool labels_used = false;         // some mode needs labels
  CalibrationInputs inputs;
  OutputFolderRequest out;
  std::shared_ptr<const Segmenter> segmenter;  // nullptr without a network, or when no mode needs labels
  std::vector<SegmentedPhoto> photos;          // what the network segments
  std::string label_text;                      // where the labels come from, for the terminal
};

// Resolves the modes against the dataset's labels, loads the network, checks the output folder,
// reads the inputs and the rig's masks (ReadRigMasks, into options.masks) and checks the options
// against them: the known distance (CheckKnownDistance),
// capture times estimated only from frames at distinct times and not with refined intrinsics. Warnings go to
// `warn` as they arise, before an error that follows them. Throws std::invalid_argument on options
// that do not fit the inputs, std::runtime_error naming the file on input that cannot be used.
CalibrationPlan PlanCalibration(const CalibrationRequest& request, const std::function<void(const std::string&)>& warn);

// Runs the plan's network over its photos into `staging_dir`/segmentation/ and takes its labels
// from there. `progress(done, total)` after each photo; an exception from it stops the run.
SegmentDatasetSummary SegmentLabels(CalibrationPlan* plan, const std::filesystem::path& staging_dir,
                                    const std::function<void(int done, int total)>& progress);

// Calibrates the planned run (CalibrateDataset; the plan's checks are not made again). The result
// names a network's labels where they are once the output folder is committed.
CalibrationRun CalibrateDataset(const CalibrationPlan& plan);

}  // namespace rigsim
