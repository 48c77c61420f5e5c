#include "sweep/sweep_summary.h"

#include <gtest/gtest.h>

#include "sweep/sweep_report.h"

namespace rigsim {
namespace {

using Json = nlohmann::ordered_json;

// Two overlaps x two seeds, methods none and mask; metrics made up so the answers are known.
struct Fixture {
  SweepConfig config = ParseSweepConfig(Json::parse(R"({"seeds": [1, 2], "grid": {"overlap": [10, 20]}})"), "t.json");
  std::vector<SweepCell> cells = ExpandCells(config);
  std::vector<CellRecord> records;

  Fixture() {
    // precision none/mask, cross-class wrong none/mask, match time none/mask, auc5 none/mask, success2 none/mask
    const double table[4][10] = {
        {0.50, 0.60, 40, 10, 2.0, 1.0, 0.80, 0.82, 1, 1},  // overlap 10 seed 1
        {0.40, 0.45, 30, 20, 2.0, 1.5, 0.70, 0.60, 0, 0},  // overlap 10 seed 2
        {0.70, 0.65, 10, 12, 1.0, 1.2, 0.90, 0.91, 1, 1},  // overlap 20 seed 1
        {0.60, 0.62, 20, 10, 1.0, 0.5, 0.95, 0.95, 1, 1},  // overlap 20 seed 2
    };
    for (int c = 0; c < 4; ++c) {
      CellRecord r;
      r.key = cells[c].key;
      r.params = cells[c].params;
      r.cell_metrics = {{"overlap_pct", 8.0 + 10 * (c / 2)}};
      for (int m = 0; m < 2; ++m) {
        MethodRow row;
        row.method = m == 0 ? "none" : "mask";
        row.metrics = {{"match_precision", table[c][0 + m]},
                       {"cross_class_wrong", table[c][2 + m]},
                       {"time_match_s", table[c][4 + m]},
                       {"time_total_s", 10.0},
                       {"auc_pairs_5deg", table[c][6 + m]},
                       {"success_2deg", table[c][8 + m]},
                       {"success_1deg", 0},
                       {"median_rotation_error_deg", 0.1 * (c + 1) + m}};
        if (c == 1 && m == 0) {  // two cameras placed but for one axis, the worse 3.5 deg off across it
          row.metrics["cameras_open_axis"] = 2;
          row.metrics["max_across_axis_direction_error_deg"] = 3.5;
        }
        r.rows.push_back(row);
      }
      records.push_back(r);
    }
  }
};

TEST(SweepSummary, GroupsCellsByStudyPointAndMethod) {
  const Fixture f;
  const std::vector<SummaryRow> rows = Summarise(f.config, f.cells, f.records);
  ASSERT_EQ(rows.size(), 4u);  // 2 points x 2 methods
  EXPECT_EQ(rows[0].point, "overlap=10");
  EXPECT_EQ(rows[0].method, "none");
  EXPECT_EQ(rows[1].method, "mask");
  EXPECT_EQ(rows[2].point, "overlap=20");
  EXPECT_EQ(rows[0].cells, 2);
  EXPECT_DOUBLE_EQ(rows[0].Total("success_2deg"), 0.5);
  EXPECT_DOUBLE_EQ(rows[2].Total("success_2deg"), 1.0);
  EXPECT_DOUBLE_EQ(*rows[0].Spread("match_precision").median, 0.45);
  EXPECT_DOUBLE_EQ(*rows[0].Spread("match_precision").min, 0.40);
  EXPECT_DOUBLE_EQ(*rows[0].Spread("match_precision").max, 0.50);
  EXPECT_DOUBLE_EQ(*rows[1].Spread("median_rotation_error_deg").median, 1.15);  // (1.1 + 1.2) / 2
  EXPECT_DOUBLE_EQ(*rows[2].Spread("overlap_pct").median, 18.0);
  const std::string csv = SummaryCsv(rows);
  EXPECT_EQ(csv.substr(0, csv.find('\n')).substr(0, 30), "study,point,method,cells,faile");
  EXPECT_NE(csv.find("\nt,overlap=10,none,2,0,0,0.5,0,0,0,0,0,0,2,0.75,0.15,0.1,0.2,,3.5,"), std::string::npos) << csv;
  EXPECT_DOUBLE_EQ(rows[0].Total("cameras_open_axis"), 2.0);  // summed over the seeds
  EXPECT_EQ(rows[0].Spread("max_across_axis_direction_error_deg").count, 1);
  EXPECT_FALSE(rows[1].Spread("max_across_axis_direction_error_deg").median.has_value());
}

TEST(SweepSummary, PlacementSaysInHowManySeedsEveryCameraWasPlaced) {
  // One path, three seeds: every camera within 1 deg in one, within 5 deg in two; cameras posed
  // 4, 4 and 1 of 4.
  SweepConfig config = ParseSweepConfig(
      Json::parse(R"({"seeds": 3, "methods": {"semantics": ["none"]}, "studies": [
        {"name": "12 frames", "grid": {"trajectory": ["figure-eight", "loop"]}}]})"),
      "t.json");
  const std::vector<SweepCell> cells = ExpandCells(config);
  ASSERT_EQ(cells.size(), 6u);
  std::vector<CellRecord> records;
  const int posed[6] = {4, 4, 1, 4, 4, 4};
  const int within1[6] = {1, 0, 0, 1, 1, 1}, within5[6] = {1, 1, 0, 1, 1, 1};
  for (size_t c = 0; c < cells.size(); ++c) {
    CellRecord r;
    r.key = cells[c].key;
    r.params = cells[c].params;
    MethodRow row;
    row.method = "none";
    row.metrics = {{"cameras", 4}, {"cameras_posed", posed[c]}, {"success_1deg", within1[c]},
                   {"success_5deg", within5[c]}};
    if (c == 5) {
      row.status = "failed";
      row.metrics = Json::object();
    }
    r.rows.push_back(row);
    records.push_back(r);
  }
  const std::vector<SummaryRow> rows = Summarise(config, cells, records);
  ASSERT_EQ(rows.size(), 2u);
  EXPECT_EQ(rows[0].Count("success_1deg"), 1);
  EXPECT_EQ(rows[0].Count("success_5deg"), 2);
  EXPECT_EQ(CamerasPosedText(rows[0]), "4/4, 4/4, 1/4");
  EXPECT_EQ(PlacementLines(rows),
            (std::vector<std::string>{
                "12 frames:",
                "  figure-eight: placed every camera within 1° / 5° in 1 / 2 of 3 seeds (cameras posed 4/4, 4/4, 1/4)",
                "  loop: placed every camera within 1° / 5° in 2 / 2 of 3 seeds (cameras posed 4/4, 4/4, -)"}));
  // With the cameras judged for overconfident (rigsim's rows), the line counts them.
  std::vector<CellRecord> judged = records;
  for (size_t c = 0; c < 3; ++c) {
    judged[c].rows[0].metrics["confidently_wrong"] = 0;
    judged[c].rows[0].metrics["overconfident"] = c == 1 ? 2 : 0;
    judged[c].rows[0].metrics["cameras_stating_sd"] = 3;
  }
  EXPECT_EQ(PlacementLines(Summarise(config, cells, judged))[1],
            "  figure-eight: placed every camera within 1° / 5° in 1 / 2 of 3 seeds (cameras posed 4/4, 4/4, 1/4); "
            "confidently wrong 0, overconfident 2 of 9 cameras stating a deviation");
  EXPECT_EQ(ConfidenceLine(Summarise(config, cells, judged)),
            "cameras confidently wrong 0; overconfident 2 of 9 cameras stating a deviation (3 sd and 0.05 deg)");
  EXPECT_EQ(ConfidenceLine(rows), "cameras confidently wrong 0; overconfident: no method stated a standard deviation");
  // The study's table in report.md says the same.
  const std::vector<ClaimResult> claims;
  SweepReportInput input;
  input.config = &config;
  input.cells = &cells;
  input.records = &records;
  input.summary = &rows;
  input.claims = &claims;
  const std::string report = SweepReportMarkdown(input);
  EXPECT_NE(report.find("| swept values | method | cells | failed | cameras posed | all within 1° | all within 2° | "
                        "all within 5° |"),
            std::string::npos)
      << report;
  EXPECT_NE(report.find("| trajectory=figure-eight | none | 3 | 0 | 4/4, 4/4, 1/4 | 1 of 3 | 0 of 3 | 2 of 3 |"),
            std::string::npos)
      << report;
  // Beyond five seeds the least, most and median.
  SummaryRow many;
  for (int p : {4, 2, 4, 3, 4, 4}) many.cameras_posed.push_back(std::make_pair(p, 4));
  EXPECT_EQ(CamerasPosedText(many), "2/4 to 4/4, median 4/4");
}

TEST(SweepSummary, ClaimsPairEachCellsMethodWithItsBaseline) {
  const Fixture f;
  const std::vector<ClaimResult> claims = TestClaims(f.config, f.cells, f.records);
  ASSERT_EQ(claims.size(), 5u);  // mask vs none: five claims
  // Precision differences: +0.10, +0.05, -0.05, +0.02 -> median +0.035, held, 3 of 4.
  EXPECT_EQ(claims[0].metric, "match_precision");
  EXPECT_TRUE(claims[0].held);
  EXPECT_EQ(claims[0].pairs, 4);
  EXPECT_EQ(claims[0].favourable, 3);
  EXPECT_NEAR(*claims[0].median_difference, 0.035, 1e-12);
  EXPECT_NEAR(*claims[0].low, -0.05, 1e-12);
  // Per point: overlap=20 has median (-0.05 + 0.02) / 2 < 0: the claim fails there.
  EXPECT_EQ(claims[0].fails_at, (std::vector<std::string>{"t: overlap=20"}));
  // Cross-class wrong: -30, -10, +2, -10 -> median -10, held.
  EXPECT_TRUE(claims[1].held);
  EXPECT_DOUBLE_EQ(*claims[1].median_difference, -10.0);
  // Match time ratios 0.5, 0.75, 1.2, 0.5 -> median 0.625, faster.
  EXPECT_TRUE(claims[2].held);
  EXPECT_DOUBLE_EQ(*claims[2].median_difference, 0.625);
  EXPECT_EQ(claims[2].difference_kind, "ratio");
  // Total time equal: ratio 1, not faster.
  EXPECT_FALSE(claims[3].held);
  // AUC differences +0.02, -0.10, +0.01, 0 -> median +0.005, equal or better.
  EXPECT_TRUE(claims[4].held);
  EXPECT_EQ(claims[4].favourable, 3);
}

// The summary is made from the metric table: every summarised metric has its columns in
// summary.csv, its entry in summary.json and its column in report.md, in the table's order.
TEST(SweepSummary, EverySummarisedMetricReachesTheCsvTheJsonAndTheReport) {
  const Fixture f;
  const std::vector<SummaryRow> rows = Summarise(f.config, f.cells, f.records);
  const std::string csv = SummaryCsv(rows);
  const std::string header = csv.substr(0, csv.find('\n'));
  const Json json = SummaryToJson(rows);
  SweepReportInput report;
  const std::vector<ClaimResult> claims = TestClaims(f.config, f.cells, f.records);
  report.config = &f.config;
  report.cells = &f.cells;
  report.records = &f.records;
  report.summary = &rows;
  report.claims = &claims;
  const std::string md = SweepReportMarkdown(report);
  const std::vector<SummarisedMetric> metrics = SummarisedMetrics();
  ASSERT_FALSE(metrics.empty());
  size_t last_column = 0, last_heading = 0;
  for (const SummarisedMetric& m : metrics) {
    const size_t column = header.find("," + m.spec->name);
    ASSERT_NE(column, std::string::npos) << m.spec->name;
    EXPECT_GT(column, last_column) << m.spec->name;
    last_column = column;
    EXPECT_TRUE(json[0].contains(m.spec->name)) << m.spec->name;
    const size_t heading = md.find("| " + m.spec->summary.heading + " |");
    ASSERT_NE(heading, std::string::npos) << m.spec->name;
    EXPECT_GT(heading, last_heading) << m.spec->name;
    last_heading = heading;
  }
  // And the summarised metrics are the table's, nothing else.
  size_t summarised = 0;
  for (const MethodMetricSpec& m : SweepMetricSpecs()) summarised += m.summary.kind != SummaryKind::kNone;
  for (const CellMetricSpec& m : CellMetricSpecs()) summarised += m.summary.kind != SummaryKind::kNone;
  EXPECT_EQ(metrics.size(), summarised);
}

TEST(SweepSummary, ClaimsAreTheConfigsOwnWhenItGivesThem) {
  Fixture f;
  f.config.claims = ParseClaimSet(Json::parse(R"({"title": "Mine", "list": [
      {"claim": "matches more", "metric": "match_precision", "compare": "difference", "holds": ">= 0.2"}]})"),
                                  "t.json");
  const std::vector<ClaimResult> claims = TestClaims(f.config, f.cells, f.records);
  ASSERT_EQ(claims.size(), 1u);
  EXPECT_EQ(claims[0].claim, "matches more");
  EXPECT_FALSE(claims[0].held);        // median difference +0.035
  EXPECT_EQ(claims[0].favourable, 0);  // no cell gains 0.2
  f.config.claims.claims.clear();
  EXPECT_TRUE(TestClaims(f.config, f.cells, f.records).empty());
}

// report.md says what the images went through: the sensor preset and the rig's own car, per cell.
TEST(SweepSummary, TheReportSaysWhichSensorAndWhetherTheRigsCarRenderedInEachCell) {
  const auto report = [](const std::string& config_json) {
    const SweepConfig config = ParseSweepConfig(Json::parse(config_json), "t.json");
    const std::vector<SweepCell> cells = ExpandCells(config);
    const std::vector<CellRecord> records(cells.size());
    const std::vector<SummaryRow> rows;
    const std::vector<ClaimResult> claims;
    SweepReportInput input;
    input.config = &config;
    input.cells = &cells;
    input.records = &records;
    input.summary = &rows;
    input.claims = &claims;
    return SweepReportMarkdown(input);
  };
  const std::string automotive = report(R"({"base": {"sensor": "automotive"}, "grid": {"overlap": [10, 20]}})");
  EXPECT_NE(automotive.find("Images: sensor preset `automotive` in every cell (`render --sensor`"), std::string::npos)
      << automotive;
  EXPECT_EQ(automotive.find("renders without a sensor model"), std::string::npos) << automotive;
  EXPECT_NE(automotive.find("The rig's own car (`ego_vehicle`, as `make-rig --ego-vehicle`): in no cell.\n"), std::string::npos)
      << automotive;
  const std::string ideal = report(R"({"grid": {"overlap": [10, 20]}})");
  EXPECT_NE(ideal.find("Images: sensor preset `ideal` in every cell: renders without a sensor model"), std::string::npos)
      << ideal;
  const std::string cars = report(R"({"base": {"sensor": "automotive", "ego_vehicle": true}, "grid": {"overlap": [10, 20]}})");
  EXPECT_NE(cars.find("The rig's own car (`ego_vehicle`, as `make-rig --ego-vehicle`): around the rig in every cell.\n"),
            std::string::npos)
      << cars;
  const std::string mixed = report(R"({"seeds": [1, 2, 3], "grid": {"ego_vehicle": [false, true], "sensor": ["ideal", "phone"]}})");
  EXPECT_NE(mixed.find("Images: sensor preset `ideal` in 6 cells, `phone` in 6 cells (`render --sensor`"), std::string::npos)
      << mixed;
  EXPECT_NE(mixed.find("): around the rig in 6 of 12 cells.\n"), std::string::npos) << mixed;
}

TEST(SweepSummary, NoClaimsWithoutTheBaseline) {
  Fixture f;
  f.config.methods.erase(f.config.methods.begin());  // only mask
  EXPECT_TRUE(TestClaims(f.config, f.cells, f.records).empty());
}

}  // namespace
}  // namespace rigsim
