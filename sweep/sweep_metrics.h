// The metrics of a sweep, each described once: its name (a column of results.csv), what it means,
// how a run gives it, and how the summary (summary.csv, summary.json, report.md) and the plots
// show it. The results rows, their columns, the summary, the report's tables and the plots are all
// made from these tables: a new metric is one entry in SweepMetricSpecs() or CellMetricSpecs()
// (sweep/sweep_metrics.cc).
#pragma once

#include <functional>
#include <map>
#include <optional>
#include <string>
#include <vector>

#include <nlohmann/json.hpp>

namespace rigsim {

struct RigScores;
struct RigCalibrationResult;
struct ColmapPeerResult;
struct ModeRecord;

// What one method's run on a cell gives, for its metrics to read.
struct MethodRun {
  const RigScores* scores = nullptr;             // the estimate scored against the truth
  const RigCalibrationResult* rigsim = nullptr;  // rigsim's calibration; null for a peer
  const ColmapPeerResult* colmap = nullptr;      // the COLMAP peer's run; null for rigsim
  double time_total_s = 0.0;                     // wall time of the whole method
  // rigsim's: feature detection time and its matches checked against the truth (pipeline/).
  const ModeRecord* record = nullptr;
};

// What a cell's render gives, for the cell's metrics (shared by its methods' rows).
struct CellRun {
  std::map<std::pair<std::string, std::string>, double> overlap;  // ground-truth overlap of each camera pair
  double render_time_s = 0.0;
};

// How a study point's cells (one per seed) summarise a metric.
enum class SummaryKind {
  kNone,    // not in the summary
  kShare,   // the mean of a 0/1 value over the cells, a missing value counting 0 ("all within 2 deg")
  kSum,     // the sum over the cells (a count)
  kMedian,  // the median over the cells with a value, and its range
};

// Where the summary puts a metric: report.md's table and summary.csv group them in this order.
enum class SummaryGroup { kOutcome, kError, kMatches, kTime, kRender };

struct MetricSummary {
  SummaryKind kind = SummaryKind::kNone;
  SummaryGroup group = SummaryGroup::kOutcome;
  std::string heading;           // report.md's column
  std::string format = "%.3g";   // a value in report.md (kMedian)
  std::string unit;              // after a value in report.md ("°", " s")
  bool csv_range = false;        // summary.csv adds <name>_min and <name>_max
};

// A metric drawn in one of the plots (SweepPlotSpecs): one line per method.
struct MetricPlot {
  enum class Style { kLine, kDashed, kErrorBars };  // kDashed: a lighter companion of the plot's line
  std::string plot;                                 // SweepPlotSpec::name
  Style style = Style::kLine;
  std::string data_label;                           // its column(s) in plots/<study>.dat
};

struct MetricSpec {
  std::string name;
  std::string help;
  bool count = false;  // a whole number (the claims print its differences without decimals)
  MetricSummary summary;
  std::optional<MetricPlot> plot;
};

// A metric of a method's row and how a run gives it: nullopt when the run has no such thing (a
// peer's matches: the row leaves it out), null when it is unknown.
struct MethodMetricSpec : MetricSpec {
  std::function<std::optional<nlohmann::ordered_json>(const MethodRun&)> compute;
};
struct CellMetricSpec : MetricSpec {
  std::function<nlohmann::ordered_json(const CellRun&)> compute;
};

// Every metric of a method's row, in the order of the results' columns.
const std::vector<MethodMetricSpec>& SweepMetricSpecs();
// What a cell's render measured, shared by its methods' rows, in the order of the results' columns.
const std::vector<CellMetricSpec>& CellMetricSpecs();

// A metric the summary shows, in the summary's order (by group, then as the tables list them).
struct SummarisedMetric {
  const MetricSpec* spec = nullptr;
  bool of_cell = false;  // read from the cell's metrics, not the method's row
};
std::vector<SummarisedMetric> SummarisedMetrics();

// One plot per study (plots/<study>_<name>.{png,svg}), against the values the study sweeps.
struct SweepPlotSpec {
  std::string name;    // file name suffix: "success"
  std::string title;   // after the study's name: "calibration success"
  std::string ylabel;
  std::string y_axis;  // gnuplot lines setting the y axis
};
const std::vector<SweepPlotSpec>& SweepPlotSpecs();

// The metrics of a method's row from its run, in the table's order.
nlohmann::ordered_json MethodMetrics(const MethodRun& run);
// The metrics of a cell from its render, in the table's order.
nlohmann::ordered_json CellMetrics(const CellRun& run);

}  // namespace rigsim
