// Calibrating a dataset as `rigsim calibrate` and `rigsim demo` do: its inputs read once and
// checked, every view's features detected once per kind and shared by the semantic modes
// (feature_cache.h), the calibration core run on them per mode (calibrator/calibrate_rig.h,
// in memory), and the result compared with the truth when the dataset has it
// (calibration_scores.h). No printing: warnings are returned for the caller to show.
//
// What a run writes to disk is calibration_outputs.h; the text tables are report_table.h.
#pragma once

#include <filesystem>
#include <map>
#include <memory>
#include <optional>
#include <string>
#include <utility>
#include <vector>

#include <Eigen/Core>

#include "calibrator/calibrate_rig.h"
#include "calibrator/features/features.h"
#include "calibrator/features/semantics.h"
#include "dataset/dataset.h"
#include "dataset/label_source.h"
#include "evaluation/match_precision.h"
#include "geometry/rig.h"
#include "labels/cityscapes.h"
#include "pipeline/calibration_scores.h"
#include "pipeline/intrinsics_error.h"
#include "pipeline/rig_masks.h"

namespace rigsim {

// Ground-truth overlap per unordered camera pair from overlap.json (empty when the file is
// absent): min of the two directions, i.e. the fraction that both cameras share.
using OverlapTable = std::map<std::pair<std::string, std::string>, double>;
OverlapTable ReadOverlap(const std::filesystem::path& overlap_json);

// A dataset's inputs to the calibration, read once, before the long run, so that bad input
// fails fast.
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

// What a calibration of a dataset is run with: the core's options and what the pipeline does
// around it (detection, labels, intrinsics, the comparison with the truth).
struct CalibrationRunOptions {
  // The calibration core's: matching, two-view estimates, the rig stages, a known distance.
  RigCalibrationOptions rig;
  // Keypoint detection (SIFT) and the erosion of the reliable-class mask.
  FeatureOptions features;
  // Classes the mask modes detect on.
  ReliableClasses reliable;
  // Where the label images of the semantic modes come from (dataset/label_source.h): the truth
  // in labels/, a user folder (ids or colours), or the truth through the segmentation-noise model.
  LabelSource labels;
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
  // Intrinsics as a user has them (`calibrate --intrinsics-error E`, intrinsics_error.h): the
  // intrinsics above (rig.json's or the given ones) with a seeded error of relative size E before
  // the calibrator sees them; the truth stays rig.json's. 0: none, the run is as without it.
  IntrinsicsErrorOptions intrinsics_error;
  // The rig's own vehicle hidden from detection in every mode (`calibrate --mask DIR`, read and
  // checked by ReadRigMasks); null: none.
  std::shared_ptr<const RigMasks> masks;
  // Compare with the truth when rig.json has every cam_from_rig (calibration_scores.h), with
  // match precision against the range images where depth/ has them.
  bool evaluate = true;
  MatchPrecisionOptions precision;

  // Throws std::invalid_argument naming the first bad field.
  void Check() const;
};

// `rig` with each camera's intrinsics (model, size, parameters) taken from the camera of the same
// name in `intrinsics`, e.g. a datasheet's rig.json (its poses are ignored). Throws
// std::invalid_argument starting with `source` when a camera of `rig` is not in it, or its image
// size differs from rig.json's (the photos' size).
Rig WithGivenIntrinsics(const Rig& rig, const Rig& intrinsics, const std::string& source);

// The rig the calibrator is given: rig.json's (`inputs.rig`), with options.intrinsics' cameras
// (WithGivenIntrinsics) and then options.intrinsics_error's error (WithIntrinsicsError).
Rig CalibratorRig(const CalibrationInputs& inputs, const CalibrationRunOptions& options);

// One camera pair's two-view inliers in the frame where it has the most, in pixels: what a
// person looks at to judge a pair (match_image.h draws them).
struct PairInlierSample {
  int pair = -1;  // index into the pairwise report's pairs
  std::string cam_a, cam_b;
  int frame = -1;  // index into the dataset's frames
  std::vector<std::pair<Eigen::Vector2d, Eigen::Vector2d>> points;  // (in cam_a, in cam_b)
  // Per point, right (1) or wrong (0) by the truth (calibration_scores.h); empty without it.
  std::vector<signed char> correct;
};

// What the pipeline measured around one semantic mode's calibration.
struct ModeRecord {
  double detect_time_s = 0.0;  // the mode's features, summed over the images
  // Per camera, the keypoints its mask removed (FeatureCache::RemovedByMask); empty without masks.
  std::vector<int> removed_by_mask;
  // Per camera pair with two-view inliers (the pairwise report's order, failed pairs left out).
  std::vector<PairInlierSample> inlier_samples;
  // Against the truth (CalibrationRunOptions::evaluate, rendered data); nullopt without it.
  std::optional<CalibrationScores> truth;
};

struct CalibrationRun {
  CalibrationInputs inputs;
  CalibrationRunOptions options;  // as run (options.labels: where labels came from)
  std::vector<SemanticMode> modes;
  bool labels_used = false;  // some mode needs labels (NeedsLabels)
  std::vector<RigCalibrationResult> results;  // the core's, one per mode, in `modes` order
  std::vector<ModeRecord> records;            // the same modes' records
  double seconds = 0.0;                       // wall time of the calibration

  // Mode m's scores against the truth; nullptr without them.
  const CalibrationScores* Truth(size_t m) const {
    return m < records.size() && records[m].truth ? &*records[m].truth : nullptr;
  }
};

// Checks that options.rig.known_distance names cameras of the rig, in the command line's words
// (--known-distance, naming rig.json, a close name and the cameras it has). Throws
// std::invalid_argument.
void CheckKnownDistance(const CalibrationInputs& inputs, const CalibrationRunOptions& options);

// Calibrates the rig of `inputs.dataset_dir` in each of `modes` (at least one), after
// CheckKnownDistance; the core's entry point (calibrator/calibrate_rig.h CalibrateRig) runs once
// per mode. With options.rig.keep_details, each result also keeps what a report shows of every
// stage (RigCalibrationResult::details, report/); off, the run costs nothing more. Throws
// std::invalid_argument on bad options (a known distance or --intrinsics naming cameras the rig
// does not have), std::runtime_error naming the file when an input is missing or inconsistent
// (an image absent or of the wrong size for its camera; labels absent when a mode needs them).
CalibrationRun CalibrateDataset(const CalibrationInputs& inputs, const CalibrationRunOptions& options,
                                const std::vector<SemanticMode>& modes);
// ReadCalibrationInputs, then the above.
CalibrationRun CalibrateDataset(const std::filesystem::path& dataset_dir, const CalibrationRunOptions& options,
                                const std::vector<SemanticMode>& modes);

// The names of the cameras without cam_from_rig, comma-separated ("" when every camera has one).
std::string CamerasWithoutPose(const Rig& rig);

}  // namespace rigsim
