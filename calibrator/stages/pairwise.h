// The pairwise stage of a rig calibration, in memory: features of every view in; per camera pair
// the matches of every frame, pooled (the rig is rigid, so the relative pose is the same in every
// frame) into one two-view estimate; per camera the matches between consecutive frames (the
// rig's motion as that camera saw it). No file is read and no truth is seen: pipeline/ reads a
// dataset, detects the features (features.h DetectFeaturesInImages) and compares with the truth.
//
// Stages (pairwise.cc, each a function of its inputs and the options): screen the pairs, match
// them per frame, pool the frames and estimate each pair, match each camera between consecutive
// frames (temporal pairs).
// Assumes synchronised capture: camera time offsets are not modelled here.
#pragma once

#include <cstdint>
#include <optional>
#include <span>
#include <string>
#include <utility>
#include <vector>

#include <Eigen/Core>

#include "calibrator/estimators/two_view.h"
#include "calibrator/features/features.h"
#include "calibrator/features/matching.h"
#include "calibrator/model/correspondences.h"
#include "calibrator/model/view_graph.h"
#include "geometry/camera.h"

namespace rigsim {

struct PairwiseOptions {
  // Matching; gate_by_class is the gated semantic modes'.
  MatchOptions matching;
  // Relative pose of each pair.
  TwoViewOptions two_view;
  // With two or more frames: also match each camera with itself between consecutive frames (same
  // matching and two-view estimate as the pairs). The rig's motion links the scales of the camera
  // pairs (rig_calibration.h); costs one matching per camera and frame step.
  bool temporal_matches = true;
  // Pair screening: before matching every frame of a camera pair, match only the strongest
  // `screen_features` keypoints of two of its frames (the first and the middle one) and fit a
  // two-view model; a pair that fails is not matched further and is reported as screened out.
  // Cameras in a rig share views with a few neighbours only (a 6-camera ring: 6 of 15 pairs), so
  // this skips most of the matching cost. 0 matches every pair in full.
  int screen_features = 2048;
  // Worker threads (TBB); 0 = all cores (parallel_scope.h).
  int num_threads = 0;
  // Keep, in PairwiseMatchData, every match's inlier flag and every keypoint's class: what a
  // report shows of the matching (pipeline/, report/). Costs memory only.
  bool keep_match_details = false;

  // Throws std::invalid_argument naming the first bad field.
  void Check() const;
};

// A rig's views as the calibration takes them: the cameras, with the intrinsics to calibrate
// with, and every view's features (features.h; with each keypoint's class for the gated modes).
struct RigViews {
  std::vector<std::string> camera_names;
  std::vector<Camera> cameras;
  int num_frames = 0;
  // View (camera c, frame f) is features[c * num_frames + f]; not owned.
  std::span<const FeatureSet> features;
  // Each frame's timestamp (s); empty when unknown. Per camera: its rolling shutter reads the
  // bottom row first; empty: every one top to bottom (rig_calibration.h capture times).
  std::vector<double> frame_times_s;
  std::vector<char> readout_bottom_to_top;

  const FeatureSet& Of(int camera, int frame) const { return features[camera * num_frames + frame]; }
  // Throws std::invalid_argument on fewer than two cameras, no frame, or sizes that disagree.
  void Check() const;
};

// What the calibrator says of a camera pair.
enum class PairOutcome {
  kSolved,         // a two-view estimate, kept by the rig stage: what the calibrator stands by
  kScreenedOut,    // not matched in full: screening found no shared view (PairwiseOptions::screen_features)
  kTwoViewFailed,  // matched, but no two-view estimate (TwoViewEstimate::failure_reason says why)
  kLeftOutByRig,   // estimated, but the rig stage did not trust it (PairResult::left_out_by_rig says why)
};

// One camera pair in the pairwise report: its two-view outcome and cost.
struct PairResult {
  std::string cam_a, cam_b;
  int frames = 0;  // frames pooled
  // Matches pooled over the frames (two_view.num_matches), the estimate and its inliers; a pair
  // screened out has failure_reason set and no matches.
  TwoViewEstimate two_view;
  bool screened_out = false;  // PairwiseOptions::screen_features
  // Why the rig stage did not trust the pair's pose (it disagreed with the rig the other pairs
  // make, or its rotation was an outlier of rotation averaging); nullopt when it did, or before it ran.
  std::optional<std::string> left_out_by_rig;

  PairOutcome Outcome() const;
  bool Solved() const { return Outcome() == PairOutcome::kSolved; }

  // Cost.
  int64_t distance_evaluations = 0;  // descriptor comparisons (what gating saves)
  double match_time_s = 0.0;         // summed over frames
  double pose_time_s = 0.0;
  double screen_time_s = 0.0;        // PairwiseOptions::screen_features
};

struct CalibrationReport {
  int num_cameras = 0;
  int num_frames = 0;
  double mean_keypoints_per_image = 0.0;
  std::vector<PairResult> pairs;  // every camera pair (a < b in rig order)
  // Time per stage, summed over the work items (pairs x frames, pairs), so that modes compare
  // fairly whatever the thread count.
  double screen_time_s = 0.0;
  double match_time_s = 0.0;
  double pose_time_s = 0.0;
  // Temporal matching (PairwiseOptions::temporal_matches), summed over cameras and frame steps;
  // zero when not run.
  double temporal_match_time_s = 0.0;
  double temporal_pose_time_s = 0.0;
};

// What the rig stage needs from the pairwise stage: the keypoints and, per pair and frame, the
// matches and which of them the two-view estimate kept as inliers.
struct PairwiseMatchData {
  // Keypoint positions [frame][camera][keypoint] of the features the mode used.
  FrameKeypoints keypoints;
  // [pair (CalibrationReport::pairs order)][frame]: (keypoint index in cam_a, in cam_b) of every
  // match after the ratio test and mutual check, in the order the two-view estimate saw them
  // (empty for a pair screened out), and of its inliers (empty for a failed pair). The matches
  // let a later stage estimate the pair again (other intrinsics).
  std::vector<std::vector<std::vector<std::pair<int, int>>>> matches;
  std::vector<std::vector<std::vector<std::pair<int, int>>>> inliers;
  // Per camera and frame step (camera-major: camera * (frames - 1) + k), the camera between frames
  // k and k+1: its two-view estimate and inliers. Empty with one frame or temporal_matches off.
  std::vector<TemporalPairEstimate> temporal;

  // With PairwiseOptions::keep_match_details only (empty otherwise):
  // [frame][camera][keypoint]: the class at the keypoint (0 without labels).
  std::vector<std::vector<std::vector<uint8_t>>> keypoint_classes;
  // [pair][frame][match]: 1 when the two-view estimate kept the match as an inlier.
  std::vector<std::vector<std::vector<char>>> match_inlier;
};

struct PairwiseResult {
  CalibrationReport report;
  PairwiseMatchData matches;
};

// The stages above on `views`. Deterministic whatever the thread count.
PairwiseResult MatchRigPairs(const RigViews& views, const PairwiseOptions& options);

// Pools one pair's matches over the frames, estimates the relative pose (two_view.h) and keeps
// its inliers per frame: the pairwise stage's step for one pair, for callers that bring
// their own correspondences.
std::pair<PairEstimate, PairMatches> EstimatePairFromMatches(
    const std::vector<Camera>& cameras, const FrameKeypoints& keypoints, int cam_a, int cam_b,
    const std::vector<std::vector<std::pair<int, int>>>& matches_per_frame, const TwoViewOptions& options);

// What the calibrator says of the pair, in words: "ok", the two-view failure reason (a screened-out
// pair's says so), or "left out by the rig: <why>" (PairResult::left_out_by_rig).
std::string PairStatus(const PairResult& pair);

}  // namespace rigsim
