// The files of a calibration run (calibration_run.h), as `rigsim calibrate` writes them:
//
//   evaluation.json        "label_source" (kind, folder or noise, whether a mode used labels) and
//                          per method: pairwise summary and pairs, the rig result ("rig") and
//                          "outputs" (files written, cameras exported and omitted, notes)
//   <mode>/rig.json        the estimated rig: every camera, cam_from_rig only for calibrated ones,
//                          the time offsets measured, and the estimate's gauge (estimate_gauge.h)
//   <mode>/frames.json     the estimate's rig pose per frame, in its gauge (no pose: left out)
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
//                          (match_image.h), right and wrong by the truth when the run has it
//
// The JSON records are calibration_json.h's.
#pragma once

#include <filesystem>
#include <optional>
#include <string>
#include <utility>
#include <vector>

#include <nlohmann/json.hpp>

#include "calibrator/calibrate_rig.h"
#include "dataset/dataset.h"
#include "geometry/estimate_gauge.h"
#include "geometry/rig.h"
#include "pipeline/calibration_run.h"

namespace rigsim {

// Which cameras and frames the exports of one mode's estimate get: camchain.yaml, opencv.yaml and
// colmap/ hold the cameras with a full pose only; colmap/ the frames with a rig pose.
struct ExportSelection {
  Rig calibrated;  // the cameras with cam_from_rig, in rig order
  std::vector<std::string> cameras_exported;
  std::vector<std::pair<std::string, CameraStatus>> cameras_omitted;  // (name, what the calibration made of it)
  // Frames with a rig pose, rig_from_world = the estimate's (the calibration's world is the rig
  // frame at frame 0; without estimated frame poses only frame 0 has one, the identity).
  FramesFile colmap_frames;
  std::vector<std::string> colmap_frames_omitted;  // frame names without a rig pose
};
ExportSelection SelectExports(const RigCalibrationResult& result, const FramesFile& frames);

// The estimate's rig pose at `frame` (the calibration's world is the rig frame at frame 0; without
// estimated frame poses only frame 0 has one, the identity); nullopt for a frame without one.
std::optional<Rigid3d> EstimatedRigFromWorld(const RigCalibrationResult& result, size_t frame);

// What one mode's estimate is relative to: the rig frame is camera 0's, the world the rig frame at
// the first frame, lengths as the result's scale says; its trajectory is frames.json beside rig.json.
EstimateGauge GaugeOf(const RigCalibrationResult& result);
// The estimate as rig.json holds it: the result's rig, with the time offset the synchronisation
// check measured for each camera it found unsynchronised (such a camera has no pose; a
// synchronised camera keeps the timing its pose was estimated with).
Rig EstimatedRig(const RigCalibrationResult& result);
// The frames with the estimate's rig pose (frames without one have none), otherwise as `frames`.
FramesFile EstimatedFrames(const RigCalibrationResult& result, const FramesFile& frames);

// Writes every file above into `dir`, an existing folder (the caller stages and commits it, see
// dataset/dataset.h StagedOutput). Returns the notes on what was left out, each prefixed with its
// mode ("mask: camchain.yaml not written: ..."); they are in evaluation.json too.
std::vector<std::string> WriteCalibrationResults(const CalibrationRun& run, const std::filesystem::path& dir);

}  // namespace rigsim
