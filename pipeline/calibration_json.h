// The JSON records of a calibration run (calibration_run.h) that evaluation.json and
// <mode>/pairs.json hold: what the calibrator says of every pair and camera and, when the run has
// the truth (calibration_scores.h), the errors, verdicts and match precision beside it. Unknowns
// are null. The pieces are public so that other reports (an HTML page, a sweep over datasets)
// build the same records from the same code.
#pragma once

#include <nlohmann/json.hpp>

#include "calibrator/calibrate_rig.h"
#include "calibrator/estimators/intrinsics_refinement.h"
#include "calibrator/stages/pairwise.h"
#include "dataset/label_source.h"
#include "evaluation/intrinsics_errors.h"
#include "geometry/camera.h"
#include "pipeline/calibration_run.h"
#include "pipeline/calibration_scores.h"
#include "pipeline/report_table.h"

namespace rigsim {

// The scale in words, as evaluation.json and the tables give it: the result's (e.g. "unit scale:
// |centre of cam1| = 1"), and for a unit scale how to make it metric with calibrate's option.
std::string ScaleText(const RigCalibrationResult& result);

// One pair's entry of the pairwise report: cam_a, cam_b, success (Solved), rotation_only,
// pair_type ("general", "planar", "rotation-only"; null on failure), failure_reason (PairStatus),
// matches, inliers, homography_inliers, cheirality, the pose; with `truth` its errors,
// within_tolerance and match precision (null and 0 otherwise).
nlohmann::json PairResultToJson(const PairResult& pair, const PairAgainstTruth* truth);

// One mode's pairwise report: {"summary", "timing", "num_cameras", "num_frames", "pairs"}. The
// summary has pose AUC at 1, 2, 5, 10 deg (evaluation/verdicts.h PoseErrorDeg; pairs the
// calibrator does not stand by count as infinite) and rotation AUC, with the truth.
nlohmann::json PairwiseReportJson(const CalibrationReport& report, const CalibrationScores* truth, double detect_time_s);

// One mode's rig result: {"summary", "timing", "cameras", "rig_from_world_per_frame", "edges",
// "position_starts", "warnings"}. Per camera: name, status, calibrated, position_known,
// rotation_wxyz, cam_from_rig, centre_in_rig, observations, direction_std_deg, intrinsics and,
// with the truth, its errors and within_tolerance (a "rotation only" camera: rotation_wxyz set,
// position_known false, cam_from_rig and centre_in_rig null; one placed but for one axis besides:
// open_axis, centre_across_axis and, with the truth, across_axis_direction_error_deg).
nlohmann::json RigResultJson(const RigCalibrationResult& result, const CalibrationScores* truth, double detect_time_s);

// A camera's "intrinsics" entry: {"model", "param_names", "given", "refined", "stddev",
// "focal_change_percent", "principal_point_change_px", errors against the truth or null}.
nlohmann::json RefinedIntrinsicsToJson(const RefinedIntrinsics& r, const Camera& camera, const IntrinsicsErrors* truth);

// evaluation.json's "label_source": kind, description, whether a mode used the labels, and the
// folder (absolute) or the noise model.
nlohmann::json LabelSourceJson(const LabelSource& source, bool used);

// pairs.json of mode m: every camera pair's entry of the pairwise report with its pair_type
// (failed when there is no estimate), the ground-truth overlap (null when unknown) and
// "rig_edge", what the rig stage made of it (null when it has no edge).
nlohmann::json PairsJson(const CalibrationRun& run, size_t m, const nlohmann::json& label_source);

// evaluation.json's "intrinsics_error" (a run with CalibrationRunOptions::intrinsics_error): E,
// the seed, what they mean, and per camera the intrinsics the calibrator was given against
// rig.json's (the truth of a rendered dataset): "given" and "true" fx, fy, cx, cy, both full
// parameter lists, the focal error (percent, given - true) and the principal point's (px, x and y).
nlohmann::json IntrinsicsErrorJson(const CalibrationRun& run);

// evaluation.json without "label_source" and the "outputs" records: per method the pairwise
// report with the rig result of the same method under "rig", and "intrinsics_error" when the
// calibrator was given intrinsics with an error, "masks" when the rig's masks were used.
nlohmann::json EvaluationJson(const CalibrationRun& run);
// evaluation.json's "masks" (present only with them): the folder, per camera its mask file, the
// share of the image it hides and, per mode, the keypoints it removed; null without masks.
nlohmann::json RigMasksJson(const CalibrationRun& run);

// The rig stage's edge of a pairwise pair (same camera names), nullptr when it has none.
const RigEdgeStats* RigEdgeOf(const RigCalibrationResult& result, const PairResult& pair);

}  // namespace rigsim
