#include "pipeline/report_table.h"

#include <gtest/gtest.h>

#include "pipeline/pipeline_test_support.h"

namespace rigsim {
namespace {

PairResult Pair(const std::string& a, const std::string& b, bool success) {
  PairResult p;
  p.cam_a = a;
  p.cam_b = b;
  p.two_view.success = success;
  p.two_view.num_matches = 100;
  p.two_view.num_inliers = success ? 80 : 0;
  if (!success) p.two_view.failure_reason = "too few inliers";
  return p;
}

// Three pairs of which cam0-cam2 failed; the others 0.1 and 0.3 deg off the truth.
CalibrationRun PairsRun(const OverlapTable& overlap) {
  RigCalibrationResult r;
  r.semantic_mode = "none";
  r.pairwise.pairs = {Pair("cam0", "cam1", true), Pair("cam0", "cam2", false), Pair("cam1", "cam2", true)};
  CalibrationRun run;
  run.inputs.overlap = overlap;
  run.results = {r};
  run.records.resize(1);
  CalibrationScores truth;
  truth.pairs.resize(3);
  truth.pairs[0].rotation_error_deg = 0.1;
  truth.pairs[2].rotation_error_deg = 0.3;
  run.records[0].truth = truth;
  return run;
}

TEST(FormatPairTable, OneRowPerPairAndMethod) {
  OverlapTable overlap;
  overlap[{"cam0", "cam1"}] = 0.34;
  const std::string table = FormatPairTable(PairsRun(overlap));
  EXPECT_NE(table.find("cam0-cam1"), std::string::npos) << table;
  EXPECT_NE(table.find("34%"), std::string::npos) << table;
  EXPECT_NE(table.find("0.100 deg"), std::string::npos) << table;
  EXPECT_NE(table.find("too few inliers"), std::string::npos) << table;
  EXPECT_EQ(std::count(table.begin(), table.end(), '\n'), 4) << table;  // header and 3 pairs
}

// A solved pair whose matches fit a rival pose as well says so in its status.
TEST(FormatPairTable, APairWithARivalPoseSaysSo) {
  CalibrationRun run = PairsRun({});
  ASSERT_TRUE(run.results[0].pairwise.pairs[0].Solved());
  EXPECT_EQ(FormatPairTable(run).find("another pose fits its matches as well"), std::string::npos);
  run.results[0].pairwise.pairs[0].two_view.rival = RivalPose{133.0, 2.1, 300, 166, 176};
  const std::string table = FormatPairTable(run);
  EXPECT_NE(table.find("another pose fits its matches as well: baseline 133 deg away, turned 2.1 deg"),
            std::string::npos)
      << table;
}

// A pair the rig uses whose own rotation is more than a camera's tolerance (1 deg) from the rig's
// says so, and that the rig's poses are the ones to take; one within it, or left out (its status
// says why already), does not.
TEST(FormatPairTable, AUsedPairFarFromTheRigSaysSo) {
  CalibrationRun run = PairsRun({});
  RigEdgeStats near, far;
  near.cam_a = "cam0";
  near.cam_b = "cam1";
  near.outcome = EdgeOutcome::kUsed;
  near.rotation_disagreement_deg = 0.8;
  far = near;
  far.cam_a = "cam1";
  far.cam_b = "cam2";
  far.rotation_disagreement_deg = 2.33;
  run.results[0].edges = {near, far};
  const std::string note = "deg from the rig's (the rig's poses, from every pair and track, are the ones to use)";
  std::string table = FormatPairTable(run);
  EXPECT_EQ(table.find("its rotation is 0.8 deg from the rig's"), std::string::npos) << table;
  EXPECT_NE(table.find("its rotation is 2.3 " + note), std::string::npos) << table;
  EXPECT_EQ(table.find(note), table.rfind(note)) << table;  // the far pair only
  run.results[0].edges[1].outcome = EdgeOutcome::kRotationOutlier;
  table = FormatPairTable(run);
  EXPECT_EQ(table.find(note), std::string::npos) << table;
}

// A ring's many pairs that see nothing in common are one line, not a row each per method.
TEST(FormatPairTable, PairsScreenedOutInEveryMethodShareOneLine) {
  CalibrationRun run = PairsRun({});
  run.results.push_back(run.results[0]);
  run.results[1].semantic_mode = "mask";
  run.records.resize(2);
  for (RigCalibrationResult& r : run.results) r.pairwise.pairs[1].screened_out = true;
  run.results[1].pairwise.pairs[2].screened_out = true;  // only in one method: keeps its rows
  const std::string table = FormatPairTable(run);
  EXPECT_EQ(table.find("cam0-cam2 "), std::string::npos) << table;
  EXPECT_NE(table.find("1 pair screened out in every method (no shared view found among the strongest keypoints; "
                       "pairs.json says why for each): cam0-cam2\n"),
            std::string::npos)
      << table;
  EXPECT_NE(table.find("cam1-cam2 "), std::string::npos) << table;
  EXPECT_EQ(std::count(table.begin(), table.end(), '\n'), 6) << table;  // header, 2 pairs x 2 methods, the line
}

TEST(FormatSummary, CountsOnlyOverlappingPairsWhenOverlapIsKnown) {
  OverlapTable overlap;
  overlap[{"cam0", "cam1"}] = overlap[{"cam1", "cam0"}] = 0.34;
  overlap[{"cam1", "cam2"}] = overlap[{"cam2", "cam1"}] = 0.01;  // below kNeighbourOverlap
  EXPECT_NE(FormatSummary(PairsRun(overlap)).find("none: 1/1 pairs of at least 5% overlap solved (and 1 pair below 5%, not in the medians)"), std::string::npos);
  EXPECT_NE(FormatSummary(PairsRun({})).find("none: 2/3 pairs solved, median rotation error 0.2000 deg"), std::string::npos)
      << FormatSummary(PairsRun({}));
}

TEST(FormatRigTable, OneRowPerCameraAndMethod) {
  RigCalibrationResult r;
  r.semantic_mode = "mask";
  r.rig.cameras = {{"cam0", Camera(CameraModelId::kPinhole, 64, 48, {50, 50, 32, 24}), Rigid3d(), 0.0},
                   {"cam1", Camera(CameraModelId::kPinhole, 64, 48, {50, 50, 32, 24}), std::nullopt, 0.0}};
  r.camera_status = {{CameraOutcome::kCalibrated, PositionOutcome::kPlaced, "reference: rig frame"},
                     {CameraOutcome::kNotConnected, PositionOutcome::kNotObservable, "cam0-cam1: two-view failed"}};
  r.camera_stats.assign(2, {});
  r.scale = "no scale";
  CalibrationRun run = RunOf({r});
  CalibrationScores truth;
  truth.cameras.resize(2);
  truth.cameras[0].rotation_error_deg = 0.0;
  run.records[0].truth = truth;
  const std::string table = FormatRigTable(run);
  EXPECT_NE(table.find("not connected"), std::string::npos) << table;
  EXPECT_NE(FormatRigSummary(run).find("mask: 1/2 cameras calibrated, worst rotation error -, worst translation direction error -, no bundle "
                                        "adjustment (no camera joined cam0)"), std::string::npos)
      << FormatRigSummary(run);
}

// The summary says when the stated deviations count the residual coordinates the fit takes up and
// residuals of one image region as moving together, and by how much that widens them (the square
// root of the variance factor).
TEST(FormatRigSummary, SaysWhenResidualsMoveTogetherByRegion) {
  RigCalibrationResult r;
  r.semantic_mode = "none";
  r.rig.cameras = {{"cam0", Camera(CameraModelId::kPinhole, 64, 48, {50, 50, 32, 24}), Rigid3d(), 0.0}};
  r.camera_status = {{CameraOutcome::kCalibrated, PositionOutcome::kPlaced, "reference: rig frame"}};
  r.camera_stats.assign(1, {});
  r.num_observations = 500;
  r.reprojection_rms_px = 0.3;
  r.residual_correlation = 4.0;
  const std::string summary = FormatRigSummary(RunOf({r}));
  EXPECT_NE(summary.find("(residuals counted over what the fit leaves free and by image region: deviations x2.0)"), std::string::npos)
      << summary;
  r.residual_correlation = 1.05;
  EXPECT_EQ(FormatRigSummary(RunOf({r})).find("deviations x"), std::string::npos);
}

// The status is what tells a user what to change; the table once cut it at a column width
// ("the tracks leave the positi...").
TEST(FormatRigTable, StatusIsPrintedWhole) {
  RigCalibrationResult r;
  r.semantic_mode = "none";
  r.rig.cameras = {{"cam0", Camera(CameraModelId::kPinhole, 64, 48, {50, 50, 32, 24}), Rigid3d(), 0.0},
                   {"cam1", Camera(CameraModelId::kPinhole, 64, 48, {50, 50, 32, 24}), std::nullopt, 0.0}};
  const std::string why =
      "not observable: the tracks leave the positions undetermined (second smallest "
      "eigenvalue 15.1 times the smallest); to place it: more frames, a path that turns (the rig turned 2.0 deg), "
      "more overlap between neighbouring cameras, or a higher resolution";
  r.camera_status = {{CameraOutcome::kCalibrated, PositionOutcome::kPlaced, "reference: rig frame"},
                     {CameraOutcome::kRotationOnly, PositionOutcome::kNotObservable, why}};
  r.camera_stats.assign(2, {});
  const std::string table = FormatRigTable(RunOf({r}));
  EXPECT_NE(table.find("rotation only: position " + why + "\n"), std::string::npos) << table;
}

// A camera placed but for one axis has no full pose; t_dir_err gives the direction of its centre
// across the axis against the truth, and the status says so.
TEST(FormatRigTable, ACameraPlacedButForOneAxisShowsItsDirectionAcrossTheAxis) {
  RigCalibrationResult r;
  r.semantic_mode = "none";
  const Camera cam(CameraModelId::kPinhole, 64, 48, {50, 50, 32, 24});
  r.rig.cameras = {{"cam0", cam, Rigid3d(), 0.0}, {"cam1", cam, std::nullopt, 0.0}};
  r.camera_status = {{CameraOutcome::kCalibrated, PositionOutcome::kPlaced, "reference: rig frame"},
                     {CameraOutcome::kOpenAlongAxis, PositionOutcome::kOpenAlongTurnAxis, "its height is open"}};
  r.camera_stats.assign(2, {});
  CalibrationRun run = RunOf({r});
  CalibrationScores truth;
  truth.cameras.resize(2);
  truth.cameras[0].rotation_error_deg = 0.0;
  truth.cameras[1].rotation_error_deg = 0.25;
  truth.cameras[1].across_axis_direction_error_deg = 6.5;
  run.records[0].truth = truth;
  const std::string table = FormatRigTable(run);
  const std::string row = table.substr(table.find("cam1"));
  EXPECT_NE(row.find("6.50 deg"), std::string::npos) << table;
  EXPECT_NE(row.find("placed but for one axis: its height is open (t_dir_err: its centre across the axis) (outside "
                     "tolerance against the truth)\n"),
            std::string::npos)
      << table;
  EXPECT_NE(FormatRigSummary(run).find("worst translation direction error -, worst direction across an open axis 6.50 deg"),
            std::string::npos)
      << FormatRigSummary(run);
}

// Offsets and readouts are printed with their standard deviations and how they were found;
// a run without them prints no table.
TEST(FormatTimeTable, OffsetsAndReadoutsWithTheirStandardDeviations) {
  RigCalibrationResult r;
  r.semantic_mode = "none";
  const Camera cam(CameraModelId::kPinhole, 64, 48, {50, 50, 32, 24});
  r.rig.cameras = {{"cam0", cam, Rigid3d(), 0.0}, {"cam1", cam, std::nullopt, 0.0}, {"cam2", cam, Rigid3d(), 0.0}};
  r.camera_status.assign(3, {CameraOutcome::kCalibrated, PositionOutcome::kPlaced, ""});
  r.camera_stats.assign(3, {});
  CalibrationRun run = RunOf({r});
  EXPECT_EQ(FormatTimeTable(run), "");
  run.results[0].camera_stats[1].time_offset_s = 0.0301;
  run.results[0].camera_stats[1].time_offset_stddev_s = 0.0004;
  const std::string measured = FormatTimeTable(run);
  EXPECT_NE(measured.find("+30.10 +- 0.40 ms"), std::string::npos) << measured;
  EXPECT_NE(measured.find("measured by the synchronisation check"), std::string::npos) << measured;
  EXPECT_EQ(measured.find("cam2"), std::string::npos) << measured;  // nothing measured for it
  // An offset another start moves as far at no worse a cost is where a solve stopped, not a measurement.
  run.results[0].camera_stats[1].time_offset_undetermined = true;
  const std::string undetermined = FormatTimeTable(run);
  EXPECT_NE(undetermined.find("not determined"), std::string::npos) << undetermined;
  EXPECT_EQ(undetermined.find("+30.10"), std::string::npos) << undetermined;
  run.results[0].camera_stats[1].time_offset_undetermined = false;

  run.options.rig.capture_time.estimate_offsets = run.options.rig.capture_time.estimate_readout = true;
  run.results[0].camera_stats[0].time_offset_s = 0.0;
  run.results[0].camera_stats[0].readout_s = 0.02;
  run.results[0].camera_stats[0].readout_stddev_s = 0.001;
  CalibrationScores truth;
  truth.cameras.resize(3);
  truth.cameras[1].time_offset_error_s = -0.0002;
  run.records[0].truth = truth;
  const std::string estimated = FormatTimeTable(run);
  const std::string cam0 = estimated.substr(estimated.find("cam0"));
  EXPECT_NE(cam0.find("0 (reference)"), std::string::npos) << estimated;
  EXPECT_NE(cam0.find("+20.00 +- 1.00 ms"), std::string::npos) << estimated;
  const std::string cam1 = estimated.substr(estimated.find("cam1"));
  EXPECT_NE(cam1.find("0.20 ms"), std::string::npos) << estimated;
  EXPECT_NE(cam1.find("estimated in the bundle adjustment"), std::string::npos) << estimated;
}

// A standard deviation is printed only where it says something: not when unknown ("+-nan") or
// when it rounds to zero at the change's precision ("+- 0.000%").
TEST(FormatIntrinsicsTable, GivesAStandardDeviationOnlyWhereItSaysSomething) {
  RigCalibrationResult r;
  r.semantic_mode = "none";
  r.rig.cameras = {{"cam0", Camera(CameraModelId::kPinhole, 64, 48, {50, 50, 32, 24}), Rigid3d(), 0.0},
                   {"cam1", Camera(CameraModelId::kPinhole, 64, 48, {50, 50, 32, 24}), Rigid3d(), 0.0}};
  r.camera_stats.assign(2, {});
  r.camera_stats[0].intrinsics = RefinedIntrinsics{{50, 50, 32, 24}, {50.5, 50.5, 32.25, 24}, {}};
  r.camera_stats[1].intrinsics = RefinedIntrinsics{{50, 50, 32, 24}, {50.5, 50.5, 32.25, 24}, {0.25, 1e-5, 0.5, 0.001}};
  const std::string table = FormatIntrinsicsTable(RunOf({r}));
  EXPECT_EQ(table.find("nan"), std::string::npos) << table;
  EXPECT_NE(table.find("+1.000%"), std::string::npos) << table;         // cam0: no standard deviation known
  EXPECT_NE(table.find("+1.000 +- 0.500%"), std::string::npos) << table;  // cam1's fx: 0.25 of 50
  EXPECT_EQ(table.find("+- 0.000"), std::string::npos) << table;         // cam1's fy: 1e-5 of 50
  EXPECT_NE(table.find("+0.25 +- 0.50 px"), std::string::npos) << table;
  EXPECT_EQ(table.find("+- 0.00 px"), std::string::npos) << table;       // cam1's cy: 0.001 px
}

}  // namespace
}  // namespace rigsim
