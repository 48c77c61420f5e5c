// A calibration compared with the truth (a rendered dataset's rig.json, range and label images):
// the errors, match precision and verdicts that evaluation.json, pairs.json, the calibrate tables,
// the match images and the report state. Measured with evaluation/ (pose_errors.h,
// match_precision.h, intrinsics_errors.h, rig_scores.h) and judged by evaluation/verdicts.h; the
// calibrator never sees the truth.
#pragma once

#include <cstdint>
#include <filesystem>
#include <optional>
#include <vector>

#include "calibrator/calibrate_rig.h"
#include "calibrator/stages/pairwise.h"
#include "dataset/dataset.h"
#include "evaluation/intrinsics_errors.h"
#include "evaluation/match_precision.h"
#include "evaluation/rig_estimate.h"
#include "geometry/rig.h"
#include "geometry/rigid3.h"

namespace rigsim {

// One camera pair of the pairwise report against the truth.
struct PairAgainstTruth {
  Rigid3d cam_b_from_cam_a;  // the true relative pose (metric)
  // Of a successful two-view estimate.
  std::optional<double> rotation_error_deg;
  std::optional<double> translation_direction_error_deg;
  // Match precision (match_precision.h), when depth/ has range images of both cameras; counts
  // pooled over frames.
  std::optional<double> match_precision;
  int matches_evaluated = 0;
  int matches_correct = 0;
  int matches_at_infinity = 0;
  // Of the evaluated matches, those joining two different true classes (labels/ of the dataset),
  // and of those the correct ones; nullopt without label images.
  std::optional<int> cross_class_matches;
  int cross_class_correct = 0;
  // Precision of the two-view inliers only; cleared when the rig estimated the pair again (its
  // inliers then differ from those checked).
  std::optional<double> inlier_precision;
  int inliers_evaluated = 0;
  int inliers_correct = 0;
};

// One camera against the truth, with camera 0 as the rig frame.
struct CameraAgainstTruth {
  // For a camera with a pose; the rotation error also for a "rotation only" camera.
  std::optional<double> rotation_error_deg;
  // Angle between the estimated and true directions of the camera centre from camera 0's.
  std::optional<double> translation_direction_error_deg;
  std::optional<double> position_error_m;  // metric results only
  // Given and refined intrinsics against the true ones (RigCameraStats::intrinsics).
  std::optional<IntrinsicsErrors> intrinsics;
  // The estimated (or, by the synchronisation check, measured) time offset from camera 0 and
  // readout time against rig.json's (the offset relative to camera 0's), in seconds.
  std::optional<double> time_offset_error_s, readout_error_s;
  // Of a camera placed but for one axis: the angle between its centre across the axis and the true
  // one's (evaluation/rig_scores.h CameraErrors).
  std::optional<double> across_axis_direction_error_deg;
  // The rotation error and (with a full pose) the direction error over the standard deviations the
  // calibration states for them, and the verdict on them (evaluation/verdicts.h Overconfident);
  // nullopt where none is stated (camera 0, a camera not placed).
  std::optional<double> rotation_sd_ratio, direction_sd_ratio;
  std::optional<bool> overconfident;
};

// One semantic mode's calibration against the truth.
struct CalibrationScores {
  std::vector<PairAgainstTruth> pairs;      // the pairwise report's order
  std::vector<CameraAgainstTruth> cameras;  // rig order
  // [pair][frame][match]: 1 when the match is correct by the truth (match_precision.h
  // CheckMatches); empty where it was not checked (no range images).
  std::vector<std::vector<std::vector<char>>> match_correct;
};

// The pairs' and cameras' errors of `result` against `truth` (every cam_from_rig known; the
// same cameras in the same order), without match precision. A pair of cameras that capture at
// different times on a moving rig is judged against its relative pose at their capture times
// (averaged over `frames`, as the pair pools them); a camera against its mounting.
CalibrationScores ScorePoses(const Rig& truth, const FramesFile& frames, const RigCalibrationResult& result);

// Match precision of every mode's pairs against the range images of `dataset_dir` (depth/), each
// read once however many modes and pairs use it, with cross-class counts where labels/ has the
// true classes: fills (*scores)[m].pairs and match_correct from (*matches)[m], the pairwise stage's
// match data of the mode whose result is results[m]. Each view is judged at its capture time
// (dataset/capture_poses.h: the frames' rig poses, the cameras' offsets and readouts in `truth`).
// Nothing when depth/ has no range image.
// Throws std::runtime_error naming a range image of the wrong size.
void ScoreMatches(const std::filesystem::path& dataset_dir, const Rig& truth, const FramesFile& frames,
                  const std::vector<RigCalibrationResult>& results, const std::vector<PairwiseMatchData>& matches,
                  const MatchPrecisionOptions& options, std::vector<CalibrationScores>* scores);

// Match precision pooled over a mode's pairs, as evaluation.json's pairwise summary and the sweep's
// rows report it.
struct PooledMatchPrecision {
  int64_t evaluated = 0;
  int64_t correct = 0;
  std::optional<int64_t> cross_class;  // nullopt when no pair knew its true classes
  int64_t cross_class_correct = 0;
  // correct / evaluated; nullopt when nothing was evaluated.
  std::optional<double> Precision() const;
};
PooledMatchPrecision PoolMatchPrecision(const CalibrationScores& scores);

// The truth's verdict on each two-view inlier of `pair` in `frame` (1 right, 0 wrong), in the
// order of matches.inliers[pair][frame]; empty where ScoreMatches did not check the matches.
std::vector<signed char> InlierVerdicts(const CalibrationScores& scores, const PairwiseMatchData& matches, int pair,
                                        int frame);

// The verdicts (evaluation/verdicts.h) of a pair's two-view estimate and of a camera's pose:
// nullopt without the truth; false for a failed pair or a camera without an estimate; a
// rotation-only estimate is judged on its rotation, a camera placed but for one axis on its rotation
// and the direction of its centre across the axis.
std::optional<bool> PairWithinTolerance(const PairResult& pair, const PairAgainstTruth* truth);
std::optional<bool> CameraWithinTolerance(const CameraAgainstTruth* truth);

// What `rigsim evaluate` scores of a calibration (evaluation/rig_estimate.h): per camera the full
// pose, or the rotation only with, for a camera placed but for one axis, its open axis and centre
// across it; the method is the semantic mode.
RigEstimate RigEstimateOf(const RigCalibrationResult& result);

}  // namespace rigsim
