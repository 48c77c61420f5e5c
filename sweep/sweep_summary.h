// A sweep's results summarised per study, per value of what the study sweeps, and per method;
// and the thesis's four claims about semantic masking tested on them.
//
// A group is one study's cells with the same swept values: one cell per seed. Rates and means are
// over the group's cells; a "spread" is the range (min..max) of the per-seed values.
#pragma once

#include <optional>
#include <string>
#include <vector>

#include <nlohmann/json.hpp>

#include "sweep/sweep_config.h"
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
  double success_1deg = 0.0;      // share of cells
  double success_2deg = 0.0;
  int confidently_wrong = 0;      // cameras, summed over cells
  MetricSpread auc_pairs_5deg;
  MetricSpread median_rotation_error_deg;
  MetricSpread median_translation_direction_error_deg;
  MetricSpread match_precision;
  MetricSpread cross_class_wrong;
  MetricSpread time_match_s;
  MetricSpread time_total_s;
  MetricSpread overlap_pct;       // achieved, from the render
};

// Rows per study, point (in the study's order) and method (config order).
std::vector<SummaryRow> Summarise(const SweepConfig& config, const std::vector<SweepCell>& cells,
                                  const std::vector<CellRecord>& records);

nlohmann::ordered_json SummaryToJson(const std::vector<SummaryRow>& rows);
std::string SummaryCsv(const std::vector<SummaryRow>& rows);

// One claim of the thesis, tested by pairing each cell's `method` row with its `baseline` row.
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

// The thesis's claims for every semantic method other than `none`, against `none` (needs both in
// the config): more correct matches (match precision), fewer wrong cross-class matches, faster
// matching and calibration, and pose accuracy equal or better (AUC of the pair errors at 5 deg
// within 0.02, or higher).
std::vector<ClaimResult> TestThesisClaims(const SweepConfig& config, const std::vector<SweepCell>& cells,
                                          const std::vector<CellRecord>& records);
nlohmann::ordered_json ClaimsToJson(const std::vector<ClaimResult>& claims);

}  // namespace rigsim
