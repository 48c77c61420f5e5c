#include "pipeline/calibration_json.h"

#include <gtest/gtest.h>

#include "evaluation/pose_errors.h"
#include "evaluation/rig_estimate.h"
#include "evaluation/rig_scores.h"
#include "pipeline/pipeline_test_support.h"
#include "testing/temp_dir.h"

namespace rigsim {
namespace {

using Json = nlohmann::json;

// ThreeCameraResult's scores against a truth: cam1 0.3 deg and 1 deg off, cam2's rotation 2 deg
// off; the solved pairs off by `pair_errors` (rotation, direction).
CalibrationScores ScoresOf(const std::vector<std::pair<double, double>>& pair_errors = {{0.3, 1.0}, {0, 0}, {0.5, 2.0}}) {
  CalibrationScores s;
  for (size_t p = 0; p < 3; ++p) {
    PairAgainstTruth t;
    t.cam_b_from_cam_a = Rigid3d(Eigen::Quaterniond::Identity(), Eigen::Vector3d(1, 0, 0));
    if (p != 1) {  // the failed pair has no errors
      t.rotation_error_deg = pair_errors[p].first;
      t.translation_direction_error_deg = pair_errors[p].second;
    }
    s.pairs.push_back(t);
  }
  s.cameras.resize(3);
  s.cameras[0].rotation_error_deg = 0.0;
  s.cameras[1].rotation_error_deg = 0.3;
  s.cameras[1].translation_direction_error_deg = 1.0;
  s.cameras[2].rotation_error_deg = 2.0;
  return s;
}

TEST(PairsJson, JoinsEveryPairToItsRigEdge) {
  CalibrationRun run = RunOf({ThreeCameraResult()});
  run.inputs.overlap[{"cam0", "cam1"}] = run.inputs.overlap[{"cam1", "cam0"}] = 0.3;
  const RigCalibrationResult& r = run.results[0];
  const Json j = PairsJson(run, 0, LabelSourceJson(LabelSource::Truth(), true));
  EXPECT_EQ(j["semantic_mode"], "mask");
  EXPECT_EQ(j["num_frames"], 3);
  EXPECT_EQ(j["label_source"]["kind"], "truth");
  ASSERT_EQ(j["pairs"].size(), 3u);
  const Json& solved = j["pairs"][0];
  EXPECT_EQ(solved["pair_type"], "general");
  EXPECT_DOUBLE_EQ(solved["overlap"].get<double>(), 0.3);
  EXPECT_EQ(solved["rig_edge"]["used"], true);
  EXPECT_EQ(solved["rig_edge"]["status"], "used");
  EXPECT_DOUBLE_EQ(solved["rig_edge"]["rotation_residual_deg"].get<double>(), 0.25);
  EXPECT_TRUE(solved["rotation_error_deg"].is_null()) << "no truth";
  EXPECT_TRUE(solved["within_tolerance"].is_null()) << "no truth";
  const Json& failed = j["pairs"][1];
  EXPECT_EQ(failed["pair_type"], "failed");
  EXPECT_TRUE(failed["overlap"].is_null());
  EXPECT_EQ(failed["rig_edge"]["used"], false);
  EXPECT_TRUE(failed["rig_edge"]["rotation_residual_deg"].is_null());
  const Json& planar = j["pairs"][2];
  EXPECT_EQ(planar["pair_type"], "planar");
  EXPECT_TRUE(planar["rig_edge"].is_null());
  EXPECT_EQ(RigEdgeOf(r, r.pairwise.pairs[2]), nullptr);
  EXPECT_EQ(RigEdgeOf(r, r.pairwise.pairs[0]), &r.edges[0]);
}

TEST(EvaluationJson, HasThePairwiseReportAndTheRigPerMethod) {
  RigCalibrationResult none = ThreeCameraResult();
  none.semantic_mode = "none";
  const Json j = EvaluationJson(RunOf({none, ThreeCameraResult()}));
  ASSERT_TRUE(j.contains("methods"));
  for (const char* mode : {"none", "mask"}) {
    const Json& m = j["methods"][mode];
    EXPECT_EQ(m["pairs"].size(), 3u) << mode;
    EXPECT_EQ(m["summary"]["pairs_succeeded"], 2) << mode;
    EXPECT_EQ(m["summary"]["pairs_planar"], 1) << mode;
    EXPECT_EQ(m["num_frames"], 3) << mode;
    ASSERT_TRUE(m.contains("rig")) << mode;
    EXPECT_FALSE(m["rig"].contains("pairwise")) << "the pairwise report is the method's own entry";
    EXPECT_EQ(m["rig"]["summary"]["cameras_calibrated"], 2) << mode;
    EXPECT_EQ(m["rig"]["cameras"][2]["position_known"], false) << mode;
    EXPECT_EQ(m["rig"]["edges"].size(), 2u) << mode;
    // Without the truth every verdict and error is unknown.
    EXPECT_TRUE(m["summary"]["pairs_within_tolerance"].is_null()) << mode;
    EXPECT_TRUE(m["rig"]["summary"]["cameras_within_tolerance"].is_null()) << mode;
    EXPECT_TRUE(m["rig"]["cameras"][1]["rotation_error_deg"].is_null()) << mode;
  }
}

TEST(RigResultJson, NamesEveryCameraAndEdgeAndTheTruthBesideThem) {
  const RigCalibrationResult r = ThreeCameraResult();
  const CalibrationScores truth = ScoresOf();
  const Json m = RigResultJson(r, &truth, 1.5);
  ASSERT_EQ(m["cameras"].size(), 3u);
  EXPECT_EQ(m["cameras"][1]["calibrated"], true);
  EXPECT_EQ(m["cameras"][2]["calibrated"], false);
  EXPECT_TRUE(m["cameras"][2]["cam_from_rig"].is_null());
  EXPECT_TRUE(m["cameras"][2]["rotation_wxyz"].is_array());
  EXPECT_DOUBLE_EQ(m["cameras"][1]["rotation_error_deg"].get<double>(), 0.3);
  EXPECT_EQ(m["cameras"][1]["within_tolerance"], true);
  EXPECT_EQ(m["cameras"][2]["within_tolerance"], false);  // its rotation is 2 deg off
  EXPECT_EQ(m["edges"].size(), 2u);
  EXPECT_EQ(m["summary"]["cameras_calibrated"], 2);
  EXPECT_EQ(m["summary"]["cameras_within_tolerance"], 2);
  EXPECT_EQ(m["summary"]["cameras_calibrated_outside_tolerance"], 0);
  EXPECT_EQ(m["summary"]["metric_scale"], false);
  EXPECT_DOUBLE_EQ(m["summary"]["max_rotation_error_deg"].get<double>(), 2.0);
  EXPECT_DOUBLE_EQ(m["timing"]["detect_time_s"].get<double>(), 1.5);
  ASSERT_EQ(m["rig_from_world_per_frame"].size(), 2u);
  EXPECT_EQ(m["rig_from_world_per_frame"][0]["rotation_wxyz"], Json({1.0, 0.0, 0.0, 0.0}));  // frame 0 is the world
}

// ThreeCameraResult with cam2 placed but for the rig's y axis, its centre across it turned
// `turn_deg` about the axis from `truth`'s (at 0.7 times its length: an estimate is up to scale).
RigCalibrationResult OpenAxisResult(const Rig& truth, double turn_deg) {
  RigCalibrationResult r = ThreeCameraResult();
  const Eigen::Vector3d up = Eigen::Vector3d::UnitY();
  r.camera_status[2] = {CameraOutcome::kOpenAlongAxis, PositionOutcome::kOpenAlongTurnAxis, "its height is open"};
  r.cam_from_rig_rotation[2] = truth.cameras[2].cam_from_rig->rotation;
  r.open_axis = {std::nullopt, std::nullopt, up};
  const Eigen::Vector3d centre = truth.cameras[2].cam_from_rig->SourceOriginInTarget();
  r.partial_centre = {std::nullopt, std::nullopt,
                      0.7 * (Eigen::AngleAxisd(DegToRad(turn_deg), up) * AcrossAxis(up, centre))};
  return r;
}

// A camera placed but for one axis is scored on the direction of its centre across the axis
// (ScorePoses), written to evaluation.json beside that centre, and read back by `rigsim evaluate`
// (ReadRigEstimates) to the same error.
TEST(EvaluationJson, ACameraPlacedButForOneAxisIsScoredApartAndReadBackAsSuch) {
  Rig truth = ThreeCameraResult().rig;
  const Eigen::Quaterniond r2(Eigen::AngleAxisd(DegToRad(120), Eigen::Vector3d::UnitY()));
  truth.cameras[2].cam_from_rig = Rigid3d(r2, -(r2 * Eigen::Vector3d(0.6, -0.3, 0.4)));  // 0.3 m above cam0
  const RigCalibrationResult r = OpenAxisResult(truth, 4.0);
  const CalibrationScores scores = ScorePoses(truth, ThreeFrames(), r);
  ASSERT_TRUE(scores.cameras[2].across_axis_direction_error_deg.has_value());
  EXPECT_NEAR(*scores.cameras[2].across_axis_direction_error_deg, 4.0, 1e-9);
  EXPECT_FALSE(scores.cameras[2].translation_direction_error_deg.has_value());
  EXPECT_NEAR(scores.cameras[2].rotation_error_deg.value(), 0.0, 1e-6);
  const Json m = RigResultJson(r, &scores, 0.0);
  const Json& cam2 = m["cameras"][2];
  EXPECT_EQ(cam2["calibrated"], false);
  EXPECT_TRUE(cam2["open_axis"].is_array());
  EXPECT_NEAR(cam2["across_axis_direction_error_deg"].get<double>(), 4.0, 1e-9);
  EXPECT_EQ(cam2["within_tolerance"], true);  // rotation and direction across the axis within 1 and 5 deg
  EXPECT_FALSE(m["cameras"][1].contains("across_axis_direction_error_deg"));  // placed: its own direction error
  EXPECT_NEAR(m["summary"]["max_across_axis_direction_error_deg"].get<double>(), 4.0, 1e-9);
  EXPECT_EQ(m["summary"]["cameras_calibrated"], 2);  // kept out of calibrated
  EXPECT_EQ(m["summary"]["cameras_calibrated_outside_tolerance"], 0);
  EXPECT_EQ(RigResultJson(r, nullptr, 0.0)["cameras"][2]["across_axis_direction_error_deg"], nullptr);  // no truth

  // What evaluate reads of the folder scores the same.
  CalibrationRun run = RunOf({r});
  run.records[0].truth = scores;
  const TempDir dir;
  WriteFile(dir / "evaluation.json", EvaluationJson(run).dump());
  std::filesystem::create_directories(dir / "mask");
  WriteRig(r.rig, dir / "mask" / "rig.json");
  const std::vector<RigEstimate> read = ReadRigEstimates(dir, truth, ThreeFrames());
  ASSERT_EQ(read.size(), 1u);
  ASSERT_TRUE(read[0].open_axis[2].has_value());
  const RigScores rescored = ScoreRig(truth, read[0]);
  EXPECT_EQ(rescored.cameras_open_axis, 1);
  EXPECT_NEAR(rescored.cameras[2].across_axis_direction_error_deg.value(),
              *scores.cameras[2].across_axis_direction_error_deg, 1e-9);
  // And so does what the sweep and the report score of the result itself.
  EXPECT_NEAR(ScoreRig(truth, RigEstimateOf(r)).cameras[2].across_axis_direction_error_deg.value(), 4.0, 1e-9);
  // Beyond 5 deg it is outside the tolerance and, claimed placed, confidently wrong.
  const RigCalibrationResult off = OpenAxisResult(truth, 6.0);
  const CalibrationScores off_scores = ScorePoses(truth, ThreeFrames(), off);
  EXPECT_EQ(RigResultJson(off, &off_scores, 0.0)["cameras"][2]["within_tolerance"], false);
  EXPECT_EQ(ScoreRig(truth, RigEstimateOf(off)).confidently_wrong, 1);
}

// A camera whose rotation is 4 stated sd off is overconfident in evaluation.json, with its ratio;
// one 2 sd off is not; the same verdict comes from what the sweep scores (ScoreRig of the result)
// and from what `rigsim evaluate` reads back of the folder.
TEST(EvaluationJson, OverconfidentCamerasCarryTheirRatioAndAgreeWithTheSweepAndEvaluate) {
  RigCalibrationResult r = ThreeCameraResult();
  Rig truth = r.rig;
  const Eigen::Quaterniond r2(Eigen::AngleAxisd(DegToRad(120), Eigen::Vector3d::UnitY()));
  truth.cameras[2].cam_from_rig = Rigid3d(r2, -(r2 * Eigen::Vector3d(0.6, 0.0, 0.4)));
  // cam1's true rotation 0.4 deg from the estimate's.
  truth.cameras[1].cam_from_rig->rotation =
      Eigen::Quaterniond(Eigen::AngleAxisd(DegToRad(0.4), Eigen::Vector3d::UnitX())) * truth.cameras[1].cam_from_rig->rotation;
  r.camera_stats[1].rotation_std_deg = 0.1;
  CalibrationScores scores = ScorePoses(truth, ThreeFrames(), r);
  Json m = RigResultJson(r, &scores, 0.0);
  EXPECT_EQ(m["cameras"][1]["overconfident"], true) << m["cameras"][1];
  EXPECT_NEAR(m["cameras"][1]["error_sd_ratio"]["rotation"].get<double>(), 4.0, 1e-6);
  EXPECT_TRUE(m["cameras"][1]["error_sd_ratio"]["direction"].is_null());  // no direction sd stated
  EXPECT_TRUE(m["cameras"][2]["overconfident"].is_null());               // nothing stated for cam2
  EXPECT_TRUE(m["cameras"][0]["overconfident"].is_null());               // the reference
  EXPECT_EQ(m["summary"]["cameras_overconfident"], 1);
  EXPECT_EQ(m["summary"]["cameras_stating_sd"], 1);
  EXPECT_TRUE(RigResultJson(r, nullptr, 0.0)["cameras"][1]["overconfident"].is_null());  // no truth
  const RigScores swept = ScoreRig(truth, RigEstimateOf(r));
  EXPECT_EQ(swept.overconfident, 1);
  EXPECT_EQ(swept.cameras_stating_sd, 1);

  CalibrationRun run = RunOf({r});
  run.records[0].truth = scores;
  const TempDir dir;
  WriteFile(dir / "evaluation.json", EvaluationJson(run).dump());
  std::filesystem::create_directories(dir / "mask");
  WriteRig(r.rig, dir / "mask" / "rig.json");
  const std::vector<RigEstimate> read = ReadRigEstimates(dir, truth, ThreeFrames());
  ASSERT_EQ(read.size(), 1u);
  EXPECT_EQ(ScoreRig(truth, read[0]).cameras[1].overconfident, true);

  r.camera_stats[1].rotation_std_deg = 0.2;  // 2 sd
  scores = ScorePoses(truth, ThreeFrames(), r);
  m = RigResultJson(r, &scores, 0.0);
  EXPECT_EQ(m["cameras"][1]["overconfident"], false);
  EXPECT_EQ(m["summary"]["cameras_overconfident"], 0);
  EXPECT_EQ(ScoreRig(truth, RigEstimateOf(r)).overconfident, 0);
}

// The worst error over no camera is unknown, not zero: a rig whose positions the data do not
// determine has no direction errors, and evaluation.json says null.
TEST(RigResultJson, WorstErrorOverNoCameraIsNull) {
  CalibrationScores truth = ScoresOf();
  for (CameraAgainstTruth& c : truth.cameras) c.translation_direction_error_deg.reset();
  const Json summary = RigResultJson(ThreeCameraResult(), &truth, 0.0)["summary"];
  EXPECT_TRUE(summary["max_translation_direction_error_deg"].is_null()) << summary;
  EXPECT_TRUE(summary["max_rotation_error_deg"].is_number()) << summary;
  for (CameraAgainstTruth& c : truth.cameras) c.rotation_error_deg.reset();
  const Json none = RigResultJson(ThreeCameraResult(), &truth, 0.0)["summary"];
  EXPECT_TRUE(none["max_rotation_error_deg"].is_null()) << none;
}

// What the images say (success) and the verdict against the truth (within_tolerance) are apart:
// the 2-camera ring at 15 % overlap had a pair at 6.2 deg rotation and 30.5 deg direction error
// marked success, and counted so.
TEST(PairwiseReportJson, APairReportedSolvedButFarOffIsNotWithinTolerance) {
  RigCalibrationResult r = ThreeCameraResult();
  const CalibrationScores truth = ScoresOf({{6.2, 30.5}, {0, 0}, {0.3, 1.0}});
  const CalibrationReport& rep = r.pairwise;
  EXPECT_EQ(PairWithinTolerance(rep.pairs[0], &truth.pairs[0]), false);
  EXPECT_EQ(PairWithinTolerance(rep.pairs[1], &truth.pairs[1]), false);  // failed: no pose to be right
  EXPECT_EQ(PairWithinTolerance(rep.pairs[2], &truth.pairs[2]), true);
  PairAgainstTruth beyond = truth.pairs[2];
  beyond.translation_direction_error_deg = 12.0;
  EXPECT_EQ(PairWithinTolerance(rep.pairs[2], &beyond), false);  // direction beyond 5 deg
  PairResult rotation_only = rep.pairs[2];
  rotation_only.two_view.rotation_only = true;  // claims no direction: judged on its rotation
  EXPECT_EQ(PairWithinTolerance(rotation_only, &beyond), true);
  EXPECT_FALSE(PairWithinTolerance(rep.pairs[2], nullptr).has_value());  // photos: no truth

  const Json m = PairwiseReportJson(rep, &truth, 0.0);
  EXPECT_EQ(m["pairs"][0]["success"], true);
  EXPECT_EQ(m["pairs"][0]["within_tolerance"], false);
  EXPECT_EQ(m["pairs"][2]["within_tolerance"], true);
  EXPECT_EQ(m["summary"]["pairs_succeeded"], 2);
  EXPECT_EQ(m["summary"]["pairs_within_tolerance"], 1);
  EXPECT_EQ(m["summary"]["pairs_succeeded_outside_tolerance"], 1);
  EXPECT_EQ(m["summary"]["tolerance"]["rotation_deg"], 2.0);
  EXPECT_TRUE(m["summary"]["pose_auc"]["5"].is_number());
}

// A pair the rig left out is no longer what the calibrator stands by: not a success in
// evaluation.json, with the rig's reason (the surround rig's 160 deg pair stayed "ok" there).
TEST(PairResultToJson, APairTheRigLeftOutIsNoSuccess) {
  PairResult pr = ThreeCameraResult().pairwise.pairs[0];
  pr.left_out_by_rig = "disagrees with the rig: its rotation is 5.00 deg off the rig's";
  const Json j = PairResultToJson(pr, nullptr);
  EXPECT_FALSE(j["success"].get<bool>());
  EXPECT_EQ(j["failure_reason"], "left out by the rig: " + *pr.left_out_by_rig);
}

// The core states the scale; the pipeline says, in the command line's words, how to make a unit
// scale metric.
TEST(ScaleText, TellsHowToMakeAUnitScaleMetric) {
  RigCalibrationResult r = ThreeCameraResult();
  EXPECT_EQ(ScaleText(r), "unit scale: |centre of cam1| = 1 (--known-distance CAM_A CAM_B METRES makes it metric)");
  r.scale_kind = ScaleKind::kMetric;
  r.scale = "metric: |cam0 - cam1| = 0.5000 m";
  EXPECT_EQ(ScaleText(r), r.scale);
}

TEST(RefinedIntrinsicsToJson, HasTheErrorsOnlyWithTheTruth) {
  const Camera camera(CameraModelId::kPinhole, 640, 480, {505, 505, 320, 240});
  const RefinedIntrinsics r{{500, 500, 319.5, 239.5}, {505, 505, 320, 240}, {1, 1, 0.5, 0.5}};
  const Json given_only = RefinedIntrinsicsToJson(r, camera, nullptr);
  EXPECT_EQ(given_only["model"], "PINHOLE");
  EXPECT_NEAR(given_only["focal_change_percent"][0].get<double>(), 1.0, 1e-12);
  EXPECT_TRUE(given_only["focal_error_percent"].is_null());
  const std::optional<IntrinsicsErrors> errors = ScoreIntrinsics(r.given, r.refined, camera);
  ASSERT_TRUE(errors.has_value());
  const Json with_truth = RefinedIntrinsicsToJson(r, camera, &*errors);
  EXPECT_DOUBLE_EQ(with_truth["focal_error_percent"].get<double>(), 0.0);
  EXPECT_NEAR(with_truth["given_focal_error_percent"].get<double>(), 100.0 * 5 / 505, 1e-9);
}

TEST(LabelSourceJson, NamesTheNoiseModel) {
  SegmentationNoiseOptions noise;
  noise.seed = 7;
  const Json j = LabelSourceJson(LabelSource::Noisy(noise), false);
  EXPECT_EQ(j["kind"], "noisy");
  EXPECT_EQ(j["used"], false);
  EXPECT_EQ(j["noise"]["seed"], 7);
  EXPECT_FALSE(j.contains("folder"));
}

}  // namespace
}  // namespace rigsim
