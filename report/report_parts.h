// The pieces of WriteReport (report_writer.h), one file each: the camera views, the camera
// pairs, the 3D scene and the pipeline's stages. Internal to report/.
#pragma once

#include <filesystem>
#include <string>
#include <vector>

#include <nlohmann/json.hpp>

#include "pipeline/calibration_run.h"
#include "report/report_geometry.h"
#include "report/report_writer.h"

namespace rigsim::report_parts {

// What every part reads: the run, its options, the output folder, and each mode's estimate
// aligned to the truth (empty without the truth).
struct ReportContext {
  const CalibrationRun& run;
  const ReportOptions& options;
  std::filesystem::path dir;
  std::vector<AlignedEstimate> aligned;  // per mode, when run.inputs.truth
  std::vector<std::string> warnings;

  DatasetLayout Layout() const { return DatasetLayout(run.inputs.dataset_dir); }
  bool HasTruth() const { return !aligned.empty(); }
  int NumCameras() const { return static_cast<int>(run.inputs.rig.cameras.size()); }
  int NumFrames() const { return static_cast<int>(run.inputs.frames.frames.size()); }
  const RigCalibrationDetails* Details(size_t mode) const { return run.results.at(mode).details.get(); }
  // Per match of pair p in frame f, whether the truth calls it right (calibration_scores.h);
  // empty where it was not checked.
  const std::vector<char>& MatchCorrect(size_t mode, size_t p, int f) const {
    static const std::vector<char> kNone;
    const CalibrationScores* truth = run.Truth(mode);
    return truth && p < truth->match_correct.size() ? truth->match_correct[p].at(f) : kNone;
  }
};

// A data file the page loads with <script src>: `RIGSIM.put("<key>", <json>);`.
void WriteDataScript(const std::filesystem::path& path, const std::string& key, const nlohmann::json& value);

// {"rotation_wxyz": [...], "translation": [...]} (geometry/json_io.h).
nlohmann::json Pose(const Rigid3d& pose);

// Per camera and frame: images under img/ (photo, labels, instances, depth) and data/view_*.js
// (each mode's keypoints, which the mask keeps, ranges for the true correspondence). Returns
// the "views" array of the report's data, [camera][frame].
nlohmann::json WriteViews(ReportContext& ctx);

// Per camera pair: data/pair_*.js (every mode's matches with their flags per frame, the
// ground-truth overlap) and the "pairs" array; also the "selftest" reference (a pixel, its
// epipolar curves under the truth and the first mode's estimate, its true correspondence).
nlohmann::json WritePairs(ReportContext& ctx, nlohmann::json* selftest);

// The 3D scene: cameras with their fields of view, the true and the estimated poses, the
// trajectories, the triangulated points; data/scene.js with the glTF scene when given.
nlohmann::json SceneData(ReportContext& ctx);

// Per mode, the story of the calibration: keypoints per class, matches, the view graph,
// rotation averaging, bundle adjustment residuals, final errors; and the CLI's tables.
nlohmann::json PipelineData(ReportContext& ctx);

}  // namespace rigsim::report_parts
