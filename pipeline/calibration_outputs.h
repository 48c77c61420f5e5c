// The files of a calibration run (calibration_run.h), as `rigsim calibrate` writes them:
//
//   evaluation.json        "label_source" (kind, folder or noise, whether a mode used labels) and
//                          per method: pairwise summary and pairs, the rig result ("rig") and
//                          "outputs" (files written, cameras exported and omitted, notes)
//   <mode>/rig.json        the estimated rig: every camera, cam_from_rig only for calibrated ones
//   <mode>/camchain.yaml   Kalibr; <mode>/opencv.yaml  cv::FileStorage; <mode>/colmap/  COLMAP text
//                          model of every frame with a rig pose (the calibration's world is the
//                          rig frame at frame 0). The writers of `rigsim export` (exports/),
//                          given only the cameras with a full pose: a camera "not connected" or
//                          "rotation only" is left out with a note and listed in
//                          evaluation.json. A model Kalibr cannot express skips camchain.yaml
//                          with a note, not the run.
//   <mode>/pairs.json      per camera pair: pair_type (general, planar, rotation-only, failed),
//                          matches, inliers, median residual (deg), errors against the truth when
//                          rig.json has it, ground-truth overlap, and the rig stage's use of it
//   <mode>/rig_topdown.svg the rig seen from above, the estimate over the truth when known
//   <mode>/matches/        <cam_a>-<cam_b>.jpg: each solved pair's inliers over its photos
//
// The pieces are public so that other reports (an HTML page, a sweep over datasets) build the
// same records from the same code.
#pragma once

#include <filesystem>
#include <string>
#include <utility>
#include <vector>

#include <nlohmann/json.hpp>

#include "calibrator/rig_calibration.h"
#include "dataset/dataset.h"
#include "dataset/label_source.h"
#include "geometry/rig.h"
#include "pipeline/calibration_run.h"
#include "pipeline/report_table.h"

namespace rigsim {

// Which cameras and frames the exports of one mode's estimate get: camchain.yaml, opencv.yaml and
// colmap/ hold the cameras with a full pose only; colmap/ the frames with a rig pose.
struct ExportSelection {
  Rig calibrated;  // the cameras with cam_from_rig, in rig order
  std::vector<std::string> cameras_exported;
  std::vector<std::pair<std::string, std::string>> cameras_omitted;  // (name, camera status)
  // Frames with a rig pose, rig_from_world = the estimate's (the calibration's world is the rig
  // frame at frame 0; without estimated frame poses only frame 0 has one, the identity).
  FramesFile colmap_frames;
  std::vector<std::string> colmap_frames_omitted;  // frame names without a rig pose
};
ExportSelection SelectExports(const RigCalibrationResult& result, const FramesFile& frames);

// The rig stage's edge of a pairwise pair (same camera names), nullptr when it has none.
const RigEdgeStats* RigEdgeOf(const RigCalibrationResult& result, const PairResult& pair);

// evaluation.json's "label_source": kind, description, whether a mode used the labels, and the
// folder (absolute) or the noise model.
nlohmann::json LabelSourceJson(const LabelSource& source, bool used);

// pairs.json of one mode: every camera pair's entry of the pairwise report with its pair_type
// (failed when there is no estimate), the ground-truth overlap (null when unknown) and
// "rig_edge", what the rig stage made of it (null when it has no edge).
nlohmann::json PairsJson(const RigCalibrationResult& result, const nlohmann::json& label_source,
                         const OverlapTable& overlap);

// evaluation.json without "label_source" and the "outputs" records: per method the pairwise
// report (ReportToJson) with the rig result of the same method under "rig".
nlohmann::json EvaluationJson(const std::vector<RigCalibrationResult>& results);

// Writes every file above into `dir`, an existing folder (the caller stages and commits it, see
// dataset/dataset.h StagedOutput). Returns the notes on what was left out, each prefixed with its
// mode ("mask: camchain.yaml not written: ..."); they are in evaluation.json too.
std::vector<std::string> WriteCalibrationResults(const CalibrationRun& run, const std::filesystem::path& dir);

}  // namespace rigsim
