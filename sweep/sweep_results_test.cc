#include "sweep/sweep_results.h"

#include <filesystem>

#include <gtest/gtest.h>

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
  for (const ParamSpec& p : CellParamSpecs()) EXPECT_NE(header.find("," + p.name + ","), std::string::npos) << p.name;
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
