// Pairwise calibration of a dataset: features per image, matches per camera pair and frame,
// matches of all frames pooled per pair (the rig is rigid, so the relative pose is the same in
// every frame), one two-view estimate per pair; compared with the truth when the dataset has it.
//
// Several semantic modes can run on the same images in one call: features are detected once
// per image and kind (unmasked for none/gated, masked for mask/mask+gated) and shared.
//
// Stages (pairwise.cc, each a function of its inputs and the options): check the inputs (every
// photo there and of its camera's size), detect features, screen the pairs, match them per
// frame, pool the frames and estimate each pair, match each camera between consecutive frames
// (temporal pairs), and compare with the truth (pose errors, match precision).
//
// Reads (dataset/dataset.h): rig.json (intrinsics; cam_from_rig optional), frames.json or the
// image stems of the first camera, images/<cam>/<frame>.*, labels when a mode needs them
// (labels/<cam>/<frame>.png or CalibrationOptions::labels), depth/<cam>/<frame>.exr when present
// (match precision).
// Assumes synchronised capture: camera time offsets are not modelled here.
#pragma once

#include <cstdint>
#include <filesystem>
#include <optional>
#include <string>
#include <utility>
#include <vector>

#include <Eigen/Core>

#include <nlohmann/json.hpp>

#include "evaluation/match_precision.h"
#include "calibrator/features.h"
#include "calibrator/matching.h"
#include "calibrator/semantics.h"
#include "calibrator/two_view.h"
#include "calibrator/view_graph.h"
#include "dataset/label_source.h"
#include "geometry/rig.h"
#include "geometry/rigid3.h"
#include "labels/cityscapes.h"

namespace rigsim {

struct CalibrationOptions {
  // Mode of the single-mode CalibrateDatasetPairs; the multi-mode one takes its list instead.
  SemanticMode semantic_mode = SemanticMode::kNone;
  // Keypoint detection (SIFT) and the erosion of the reliable-class mask.
  FeatureOptions features;
  // Matching; gate_by_class is overridden by each semantic mode.
  MatchOptions matching;
  // Relative pose of each pair.
  TwoViewOptions two_view;
  // Classes the mask modes detect on.
  ReliableClasses reliable;
  // Where the label images of the semantic modes come from (dataset/label_source.h): the truth
  // in labels/, a user folder (ids or colours), or the truth through the segmentation-noise model.
  LabelSource labels;
  // Match precision against ground-truth range images.
  MatchPrecisionOptions precision;
  // Intrinsics to calibrate with instead of rig.json's, e.g. a datasheet's (`rigsim calibrate
  // --intrinsics FILE`): each camera's model and parameters from the camera of the same name in
  // `rig`; `source` names it in errors. rig.json's intrinsics stay the truth (what a rendered
  // dataset's images and depth were made with): matches and refined intrinsics are checked
  // against them.
  struct GivenIntrinsics {
    Rig rig;
    std::string source;
  };
  std::optional<GivenIntrinsics> intrinsics;
  // Compare with the truth when rig.json has every cam_from_rig and depth images exist.
  bool evaluate = true;
  // With match data requested and two or more frames: also match each camera with itself between
  // consecutive frames (same features, matching and two-view estimate as the pairs). The rig's
  // motion links the scales of the camera pairs (rig_calibration.h); costs one matching per
  // camera and frame step.
  bool temporal_matches = true;
  // Pair screening: before matching every frame of a camera pair, match only the strongest
  // `screen_features` keypoints of two of its frames (the first and the middle one) and fit a
  // two-view model; a pair that fails is not matched further and is reported as screened out.
  // Cameras in a rig share views with a few neighbours only (a 6-camera ring: 6 of 15 pairs), so
  // this skips most of the matching cost. 0 matches every pair in full.
  int screen_features = 2048;
  // Worker threads (TBB); 0 = all cores. OpenCV's own threading is switched off meanwhile so the
  // two do not oversubscribe the machine.
  int num_threads = 0;
  // Keep, in PairwiseMatchData, every match with its inlier and ground-truth flags and every
  // keypoint's class: what a report shows of the matching (pipeline/, report/). Costs memory only.
  bool keep_match_details = false;

  // Throws std::invalid_argument naming the first bad field.
  void Check() const;
};

// rig.json's rig with the intrinsics the calibration uses (CalibrationOptions::intrinsics when
// given). Throws std::invalid_argument when they lack a camera of the rig or differ in size.
Rig CalibrationRig(const Rig& rig_json, const CalibrationOptions& options);

// One camera pair in the pairwise report: its two-view outcome, errors against the truth and cost.
struct PairResult {
  std::string cam_a, cam_b;
  int frames = 0;  // frames pooled
  // Matches pooled over the frames (two_view.num_matches), the estimate and its inliers; a pair
  // screened out (CalibrationOptions::screen_features) has failure_reason set and no matches.
  TwoViewEstimate two_view;
  // Why the rig stage did not trust the pair's pose (it disagreed with the rig the other pairs
  // make, or its rotation was an outlier of rotation averaging); empty when it did, or before it ran.
  std::string left_out_by_rig;
  // Solved, and kept by the rig stage: what the calibrator stands by.
  bool Solved() const { return two_view.success && left_out_by_rig.empty(); }

  // Ground truth, when rig.json has the poses.
  std::optional<Rigid3d> cam_b_from_cam_a_gt;  // metric
  std::optional<double> rotation_error_deg;
  std::optional<double> translation_direction_error_deg;
  // Match precision (evaluation.h), when depth images exist; counts pooled over frames.
  std::optional<double> match_precision;
  int matches_evaluated = 0;
  int matches_correct = 0;
  int matches_at_infinity = 0;
  // Of the evaluated matches, those joining two different true classes (labels/ of the dataset),
  // and of those the correct ones; nullopt without label images.
  std::optional<int> cross_class_matches;
  int cross_class_correct = 0;
  std::optional<double> inlier_precision;  // precision of the two-view inliers only
  int inliers_evaluated = 0;
  int inliers_correct = 0;

  // Cost.
  int64_t distance_evaluations = 0;  // descriptor comparisons (what gating saves)
  double match_time_s = 0.0;         // summed over frames
  double pose_time_s = 0.0;
  double screen_time_s = 0.0;        // CalibrationOptions::screen_features
};

struct CalibrationReport {
  std::string semantic_mode;
  int num_cameras = 0;
  int num_frames = 0;
  double mean_keypoints_per_image = 0.0;
  std::vector<PairResult> pairs;  // every camera pair (a < b in rig order)
  // Time per stage, summed over the work items (images, pairs x frames, pairs), so that modes
  // compare fairly whatever the thread count and whatever features they share.
  double detect_time_s = 0.0;
  double screen_time_s = 0.0;
  double match_time_s = 0.0;
  double pose_time_s = 0.0;
  // Temporal matching (CalibrationOptions::temporal_matches), summed over cameras and frame steps;
  // zero when not run.
  double temporal_match_time_s = 0.0;
  double temporal_pose_time_s = 0.0;
};

// Runs one semantic mode (options.semantic_mode). Throws std::runtime_error naming the file when
// an input is missing or inconsistent (image absent or of the wrong size for its camera; labels
// absent when the mode needs them).
CalibrationReport CalibrateDatasetPairs(const std::filesystem::path& dataset_dir, const CalibrationOptions& options);

// What the rig stage needs from a pairwise run of one mode: the keypoints and, per pair and
// frame, which of them the two-view estimate kept as inliers.
struct PairwiseMatchData {
  // Keypoint positions [frame][camera][keypoint] of the features the mode used.
  std::vector<std::vector<std::vector<Eigen::Vector2d>>> keypoints;
  // [pair (CalibrationReport::pairs order)][frame]: (keypoint index in cam_a, in cam_b) of every
  // match after the ratio test and mutual check, in the order the two-view estimate saw them
  // (empty for a pair screened out), and of its inliers (empty for a failed pair). The matches
  // let a later stage estimate the pair again (other intrinsics).
  std::vector<std::vector<std::vector<std::pair<int, int>>>> matches;
  std::vector<std::vector<std::vector<std::pair<int, int>>>> inliers;
  // Per camera and frame step (camera-major: camera * (frames - 1) + k), the camera between frames
  // k and k+1: its two-view estimate and inliers. Empty with one frame or temporal_matches off.
  std::vector<TemporalPairEstimate> temporal;

  // With CalibrationOptions::keep_match_details only (empty otherwise):
  // [frame][camera][keypoint]: the class at the keypoint (kUnlabeledId without labels).
  std::vector<std::vector<std::vector<uint8_t>>> keypoint_classes;
  // [pair][frame][match]: 1 when the two-view estimate kept the match as an inlier.
  std::vector<std::vector<std::vector<char>>> match_inlier;
  // [pair][frame][match]: 1 when the match is correct by the ground truth (evaluation.h
  // CheckMatches, as in the match precision); empty where it was not checked (no truth or depth).
  std::vector<std::vector<std::vector<char>>> match_correct;
};

// Runs several modes on the same images, sharing the detected features. Reports in `modes` order.
// With `match_data`, also returns each mode's keypoints and per-frame inliers (in `modes` order).
std::vector<CalibrationReport> CalibrateDatasetPairs(const std::filesystem::path& dataset_dir,
                                                     const CalibrationOptions& options,
                                                     const std::vector<SemanticMode>& modes,
                                                     std::vector<PairwiseMatchData>* match_data = nullptr);

// What the calibrator says of the pair: "ok", the two-view failure reason, or "left out by the rig:
// <why>" (PairResult::left_out_by_rig).
std::string PairStatus(const PairResult& pair);

// The pair's pose against the truth (evaluation/verdicts.h kPairTolerance): nullopt without
// the truth, false for a failed pair; a rotation-only pair is judged on its rotation.
std::optional<bool> PairWithinTolerance(const PairResult& pair);

// One pair's entry of ReportToJson below.
nlohmann::json PairResultToJson(const PairResult& pair);

// evaluation.json: {"methods": {"<mode>": {"summary": {...}, "timing": {...}, "pairs": [{...}]}}}.
// Per pair: cam_a, cam_b, success, rotation_only, pair_type ("general", "planar",
// "rotation-only"; null on failure), failure_reason, matches, inliers, homography_inliers,
// rotation_error_deg, translation_direction_error_deg, match_precision, ... (null when unknown).
// The summary has pose AUC at 1, 2, 5, 10 deg (pose error = max of rotation and translation
// direction errors; failures and rotation-only pairs count as infinite) and rotation AUC.
nlohmann::json ReportToJson(const std::vector<CalibrationReport>& reports);

}  // namespace rigsim
