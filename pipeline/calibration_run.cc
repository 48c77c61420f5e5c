#include "pipeline/calibration_run.h"

#include <algorithm>
#include <chrono>
#include <stdexcept>

#include "geometry/camera_validation.h"

namespace rigsim {

CalibrationInputs ReadCalibrationInputs(const std::filesystem::path& dataset_dir) {
  const DatasetLayout layout(dataset_dir);
  CalibrationInputs in;
  in.dataset_dir = dataset_dir;
  in.overlap = ReadOverlap(layout.OverlapJson());
  in.rig = ReadRig(layout.RigJson());
  in.warnings = CheckRigCoversImages(in.rig, layout.RigJson().string());
  const size_t posed = in.rig.PosedCameras().cameras.size();
  if (posed > 0 && posed < in.rig.cameras.size()) {
    in.warnings.push_back(layout.RigJson().string() + ": cam_from_rig given for " + std::to_string(posed) + " of " +
                          std::to_string(in.rig.cameras.size()) + " cameras (not for " + CamerasWithoutPose(in.rig) +
                          "): the estimate is not compared with the truth, which needs every camera's");
  }
  if (in.rig.HasAllPoses()) in.truth = in.rig;
  if (!in.rig.cameras.empty()) in.frames = layout.ReadFramesOrScan(in.rig.cameras[0].name);
  return in;
}

CalibrationRun CalibrateDataset(const CalibrationInputs& inputs, const RigCalibrationOptions& options,
                                const std::vector<SemanticMode>& modes) {
  if (modes.empty()) throw std::invalid_argument("CalibrateDataset: no semantic mode given");
  CalibrationRun run;
  run.inputs = inputs;
  run.options = options;
  run.modes = modes;
  run.labels_used = std::any_of(modes.begin(), modes.end(), NeedsLabels);
  const auto start = std::chrono::steady_clock::now();
  run.results = CalibrateRig(inputs.dataset_dir, options, modes);
  run.seconds = std::chrono::duration<double>(std::chrono::steady_clock::now() - start).count();
  return run;
}

CalibrationRun CalibrateDataset(const std::filesystem::path& dataset_dir, const RigCalibrationOptions& options,
                                const std::vector<SemanticMode>& modes) {
  return CalibrateDataset(ReadCalibrationInputs(dataset_dir), options, modes);
}

std::string CamerasWithoutPose(const Rig& rig) {
  std::string names;
  for (const RigCamera& rc : rig.cameras) {
    if (!rc.cam_from_rig) names += (names.empty() ? "" : ", ") + rc.name;
  }
  return names;
}

}  // namespace rigsim
