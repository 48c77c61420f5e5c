// A sweep's results summarised per study, per value of what the study sweeps, and per method,
// metric by metric as their table says (sweep/sweep_metrics.h); and the config's claims (the
// thesis's, unless it gives its own) tested on them.
//
// A group is one study's cells with the same swept values: one cell per seed. Rates and means are
// over the group's cells; a "spread" is the range (min..max) of the per-seed values.
#pragma once

#include <map>
#include <optional>
#include <string>
#include <vector>

#include <nlohmann/json.hpp>

#include "sweep/sweep_config.h"
#include "sweep/sweep_metrics.h"
#include "sweep/sweep_results.h"

namespace rigsim {

struct MetricSpread {
  std::optional<double> median, min, max;  // over the group's cells with a value
  int count = 0;                           // cells with a value
};

struct SummaryRow {
  std::string study;
  std::string point;              // the swept values, e.g. "overlap=5" or "lens=fisheye, fisheye_fov=190"
  int point_index = 0;            // position of the point in the study (plots' x order)
  nlohmann::ordered_json point_values;    // {param: value}
  std::string method;
  int cells = 0;
  int failed = 0;                 // rows with status "failed"
  // Every summarised metric (SummarisedMetrics) by name: a share of the cells or a sum
  // (SummaryKind::kShare, kSum) in `totals`, a median and range (kMedian) in `spreads`.
  std::map<std::string, double> totals;
  std::map<std::string, MetricSpread> spreads;
  // Per cell, in seed order: the cameras given a full pose and the rig's cameras; nullopt for a
  // run without them (a failed one).
  std::vector<std::optional<std::pair<int, int>>> cameras_posed;

  // How many of the cells a 0/1 metric (SummaryKind::kShare) is 1 in.
  int Count(const std::string& metric) const;

  double Total(const std::string& metric) const;               // 0 when not summarised
  const MetricSpread& Spread(const std::string& metric) const;  // empty when not summarised
};

// Rows per study, point (in the study's order) and method (config order).
std::vector<SummaryRow> Summarise(const SweepConfig& config, const std::vector<SweepCell>& cells,
                                  const std::vector<CellRecord>& records);

nlohmann::ordered_json SummaryToJson(const std::vector<SummaryRow>& rows);

// The cameras posed per seed, "4/4, 4/4, 1/4" ("-" for a failed run); with more than five seeds
// their least, most and median, "1/4 to 4/4, median 4/4".
std::string CamerasPosedText(const SummaryRow& row);

// What a study point says about placing the rig, one line per study point and method (motion
// suite: per path), under a line per study: "  circle: placed every camera within 1° / 5° in
// 1 / 2 of 3 seeds (cameras posed 4/4, 4/4, 1/4)". The method follows the point when the sweep
// has more than one.
std::vector<std::string> PlacementLines(const std::vector<SummaryRow>& rows);
// One line for every sweep, over all its rows: "cameras confidently wrong 0; overconfident 5 of
// 72 cameras stating a deviation", or that no method states one.
std::string ConfidenceLine(const std::vector<SummaryRow>& rows);
std::string SummaryCsv(const std::vector<SummaryRow>& rows);

// One claim of the config (SweepConfig::claims), tested by pairing each cell's `method` row with
// its `baseline` row.
struct ClaimResult {
  std::string claim;          // what is claimed, in words
  std::string metric;         // the metric compared
  std::string method, baseline;
  bool decided = false;       // enough paired cells to say
  bool held = false;
  int pairs = 0;              // cells where both rows have the metric
  int favourable = 0;         // of those, where the claim holds
  std::optional<double> median_difference, low, high;  // method - baseline (or ratio), median and range
  std::string difference_kind;  // "difference" or "ratio"
  std::vector<std::string> fails_at;  // study points whose median goes against the claim
};

// The config's claims for every rigsim method whose semantic mode is not `none`, against the
// method with the same features and no semantics (needs both in the config).
std::vector<ClaimResult> TestClaims(const SweepConfig& config, const std::vector<SweepCell>& cells,
                                    const std::vector<CellRecord>& records);
nlohmann::ordered_json ClaimsToJson(const std::vector<ClaimResult>& claims);

}  // namespace rigsim
