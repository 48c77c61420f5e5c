#include "sweep/sweep_results.h"

#include <filesystem>

#include <gtest/gtest.h>

#include "calibrator/calibrate_rig.h"
#include "evaluation/colmap_peer.h"
#include "evaluation/rig_scores.h"
#include "pipeline/calibration_run.h"
#include "testing/temp_dir.h"

namespace rigsim {
namespace {

namespace fs = std::filesystem;
using Json = nlohmann::ordered_json;

TEST(SweepResults, CsvHasEveryParameterAndMetricQuotedAsRfc4180) {
  const SweepConfig config = ParseSweepConfig(Json::parse(R"({"grid": {"frames": [2]}})"), "t.json");
  const std::vector<SweepCell> cells = ExpandCells(config);
  CellRecord record;
  record.cell_metrics = {{"overlap_pct", 31.25}};
  MethodRow ok{"none", "ok", "", {{"match_precision", 0.6123456789}, {"cameras", 4}}};
  MethodRow failed{"mask", "failed", "no model, \"registered\" 0", Json::object()};
  std::vector<Json> rows = {ResultRow(cells[0], config.methods[0], record, ok),
                            ResultRow(cells[0], config.methods[1], record, failed)};
  const std::string csv = ResultsCsv(rows);
  const std::string header = csv.substr(0, csv.find('\n'));
  EXPECT_EQ(header.substr(0, 40), "cell,key,studies,seed,scene,scene_seed,a");
  for (const ParamSpec& p : CellParamSpecs()) {
    // A parameter held where it is set is no column of a sweep that leaves it out.
    EXPECT_EQ(header.find("," + p.name + ",") != std::string::npos, !HeldWhenSet(p)) << p.name;
  }
  for (const MetricSpec& m : SweepMetricSpecs()) EXPECT_NE(header.find("," + m.name), std::string::npos) << m.name;
  EXPECT_NE(csv.find(",31.25,"), std::string::npos);
  EXPECT_NE(csv.find(",0.612346,"), std::string::npos);  // 6 significant digits
  EXPECT_NE(csv.find(",failed,\"no model, \"\"registered\"\" 0\","), std::string::npos) << csv;
  // JSON Lines keep full precision and the same column order.
  const std::string jsonl = ResultsJsonl(rows);
  const Json first = Json::parse(jsonl.substr(0, jsonl.find('\n')));
  EXPECT_DOUBLE_EQ(first["match_precision"].get<double>(), 0.6123456789);
  EXPECT_EQ(jsonl.substr(0, 9), "{\"cell\":0");
  EXPECT_TRUE(first["max_rotation_error_deg"].is_null());
}

TEST(SweepResults, PlacementIsAColumnWhenSomeCellSetsIt) {
  const SweepConfig config = ParseSweepConfig(Json::parse(R"({"grid": {"placement": ["structure", "road"]}})"), "t.json");
  const std::vector<SweepCell> cells = ExpandCells(config);
  ASSERT_EQ(cells.size(), 2u);
  const CellRecord record;
  const MethodRow ok{"none", "ok", "", Json::object()};
  const std::vector<Json> rows = {ResultRow(cells[0], config.methods[0], record, ok),
                                  ResultRow(cells[1], config.methods[0], record, ok)};
  const std::string csv = ResultsCsv(rows);
  EXPECT_NE(csv.find(",placement,"), std::string::npos) << csv;
  EXPECT_EQ(csv.find(",ego_vehicle,"), std::string::npos) << csv;
  // The cell that leaves it at its default reads as the default, not as an empty field.
  EXPECT_NE(csv.find(",structure,"), std::string::npos) << csv;
  EXPECT_NE(csv.find(",road,"), std::string::npos) << csv;
  const std::string jsonl = ResultsJsonl(rows);
  EXPECT_EQ(Json::parse(jsonl.substr(0, jsonl.find('\n')))["placement"], "structure");
}

// The rows are made from the metric table: a run gives every metric of the table, in its order
// (a peer leaves out rigsim's matches), and every one has its column.
TEST(SweepResults, ARunGivesEveryMetricOfTheTableInItsOrder) {
  RigScores scores;
  scores.cameras.resize(3);
  scores.median_rotation_error_deg = 0.25;
  scores.cameras_open_axis = 1;
  scores.max_across_axis_direction_error_deg = 2.5;
  RigCalibrationResult rigsim;
  ModeRecord record;
  record.detect_time_s = 1.5;
  const Json rigsim_row = MethodMetrics({&scores, &rigsim, nullptr, 12.5, &record});
  std::vector<std::string> names;
  for (const auto& [name, value] : rigsim_row.items()) names.push_back(name);
  std::vector<std::string> table;
  for (const MethodMetricSpec& m : SweepMetricSpecs()) table.push_back(m.name);
  EXPECT_EQ(names, table);
  EXPECT_EQ(rigsim_row["cameras"], 3);
  EXPECT_EQ(rigsim_row["median_rotation_error_deg"], 0.25);
  EXPECT_TRUE(rigsim_row["max_rotation_error_deg"].is_null());
  EXPECT_EQ(rigsim_row["time_total_s"], 12.5);
  EXPECT_EQ(rigsim_row["time_detect_s"], 1.5);
  EXPECT_TRUE(rigsim_row["match_precision"].is_null());  // no truth in the record
  EXPECT_EQ(rigsim_row["cameras_open_axis"], 1);
  EXPECT_EQ(rigsim_row["max_across_axis_direction_error_deg"], 2.5);
  RigScores placed = scores;
  placed.cameras_open_axis = 0;
  placed.max_across_axis_direction_error_deg.reset();
  const Json placed_row = MethodMetrics({&placed, &rigsim, nullptr, 12.5, &record});
  EXPECT_EQ(placed_row["cameras_open_axis"], 0);
  EXPECT_TRUE(placed_row["max_across_axis_direction_error_deg"].is_null());  // no such camera: unknown, not 0
  ColmapPeerResult colmap;
  colmap.match_time_s = 2.0;
  const Json colmap_row = MethodMetrics({&scores, nullptr, &colmap, 30.0});
  EXPECT_FALSE(colmap_row.contains("matches"));
  EXPECT_FALSE(colmap_row.contains("match_precision"));
  EXPECT_FALSE(colmap_row.contains("cameras_open_axis"));  // no peer places a camera but for one axis
  EXPECT_FALSE(colmap_row.contains("max_across_axis_direction_error_deg"));
  EXPECT_EQ(colmap_row["time_match_s"], 2.0);
  CellRun render;
  render.overlap = {{{"cam0", "cam1"}, 0.3}, {{"cam1", "cam2"}, 0.005}};
  render.render_time_s = 4.0;
  const Json cell = CellMetrics(render);
  EXPECT_DOUBLE_EQ(cell["overlap_pct"].get<double>(), 30.0);
  EXPECT_EQ(cell["overlapping_pairs"], 1);
  EXPECT_EQ(cell.size(), CellMetricSpecs().size());
}

// The sweep's overconfident metric counts the cameras ScoreRig finds beyond their stated
// deviations, and cameras_stating_sd those judged; a peer's row judges none.
TEST(SweepResults, OverconfidentCountsTheCamerasBeyondTheirStatedDeviations) {
  Rig truth;
  const Camera cam(CameraModelId::kPinhole, 64, 48, {50, 50, 31.5, 23.5});
  for (int c = 0; c < 3; ++c) truth.cameras.push_back({"cam" + std::to_string(c), cam, Rigid3d(Eigen::Quaterniond::Identity(), Eigen::Vector3d(-c, 0, 0))});
  RigEstimate e;
  e.method = "none";
  for (const RigCamera& c : truth.cameras) {
    e.cam_from_rig.push_back(std::nullopt);
    e.rotation_only.push_back(c.cam_from_rig->rotation);
    e.open_axis.push_back(std::nullopt);
  }
  e.cam_from_rig[0] = truth.cameras[0].cam_from_rig;
  e.rotation_only[0].reset();
  // cam1 and cam2 both 0.4 deg off in rotation: cam1 states 0.1 (4 sd), cam2 0.2 (2 sd).
  const Eigen::Quaterniond off(Eigen::AngleAxisd(DegToRad(0.4), Eigen::Vector3d::UnitY()));
  for (int c : {1, 2}) e.rotation_only[c] = off * *e.rotation_only[c];
  e.rotation_std_deg = {std::nullopt, 0.1, 0.2};
  const RigScores scores = ScoreRig(truth, e);
  RigCalibrationResult rigsim;
  ModeRecord record;
  const Json row = MethodMetrics({&scores, &rigsim, nullptr, 1.0, &record});
  EXPECT_EQ(row["overconfident"], 1);
  EXPECT_EQ(row["cameras_stating_sd"], 2);
  e.rotation_std_deg.clear();  // as a peer: nothing stated
  const RigScores peer = ScoreRig(truth, e);
  const ColmapPeerResult colmap;
  const Json peer_row = MethodMetrics({&peer, nullptr, &colmap, 1.0});
  EXPECT_EQ(peer_row["overconfident"], 0);
  EXPECT_EQ(peer_row["cameras_stating_sd"], 0);
}

TEST(SweepResults, AFinishedCellIsReadBackOnlyWhenItMatchesTheConfig) {
  const TempDir scratch;
  const fs::path out = scratch / "out";
  const SweepConfig config = ParseSweepConfig(Json::parse(R"({"grid": {"frames": [2, 3]}})"), "t.json");
  const std::vector<SweepCell> cells = ExpandCells(config);
  CellRecord record;
  record.key = cells[0].key;
  record.params = cells[0].params;
  record.rows = {{"none", "ok", "", {{"cameras", 4}}}, {"mask", "ok", "", {{"cameras", 4}}}};
  WriteCellRecord(out, record);
  EXPECT_TRUE(ReadFinishedCell(out, cells[0], config.methods).has_value());
  EXPECT_FALSE(ReadFinishedCell(out, cells[1], config.methods).has_value());  // never written
  // A config with one more method needs the cell again.
  std::vector<SweepMethod> more = config.methods;
  more.push_back({"gated", "rigsim", "gated", "sift"});
  EXPECT_FALSE(ReadFinishedCell(out, cells[0], more).has_value());
  // A damaged file counts as absent, not as an error.
  WriteFile(CellRecordPath(out, cells[0].key), "{\"key\": ");
  EXPECT_FALSE(ReadFinishedCell(out, cells[0], config.methods).has_value());
  EXPECT_TRUE(fs::is_empty(out / "cells") == false);
  for (const auto& e : fs::directory_iterator(out / "cells")) {
    EXPECT_EQ(e.path().extension(), ".json") << "a temporary file was left: " << e.path();
  }
}

}  // namespace
}  // namespace rigsim
