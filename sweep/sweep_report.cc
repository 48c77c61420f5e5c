#include "sweep/sweep_report.h"

#include <algorithm>
#include <cstdio>
#include <map>
#include <string>
#include <utility>
#include <vector>

#include "common/format.h"
#include "sweep/sweep_metrics.h"
#include "sweep/sweep_plots.h"

namespace rigsim {

namespace {

std::string Fmt(double v, const char* format = "%.3g") {
  char buf[64];
  std::snprintf(buf, sizeof buf, format, v);
  return buf;
}

std::string MedianRange(const MetricSpread& s, const char* format, const std::string& unit = "") {
  if (!s.median) return "-";
  std::string out = Fmt(*s.median, format) + unit;
  if (s.count > 1 && *s.min != *s.max) out += " (" + Fmt(*s.min, format) + "-" + Fmt(*s.max, format) + ")";
  return out;
}

std::string Cell(std::string s) {
  std::replace(s.begin(), s.end(), '|', '/');
  return s;
}

// Whether the table says `metric` is a whole number.
bool IsCount(const std::string& metric) {
  for (const MethodMetricSpec& m : SweepMetricSpecs()) {
    if (m.name == metric) return m.count;
  }
  return false;
}

std::string ClaimSection(const ClaimSet& set, const std::vector<ClaimResult>& claims) {
  if (claims.empty()) return "";
  std::string notes;
  for (const ClaimSpec& c : set.claims) {
    if (!c.note.empty() && notes.find(c.note) == std::string::npos) notes += " " + c.note;
  }
  std::string md =
      "## " + set.title + "\n\n"
      "Semantic masking, compared with no semantics on the same images (each cell's method row paired with its "
      "baseline row): a claim *holds* when the median over the paired cells favours it. Differences are method "
      "minus baseline; ratios method over baseline; the range is over all paired cells." + notes + "\n\n"
      "| method vs baseline | claim | metric | held | median (range) | cells in favour | does not hold at |\n"
      "|---|---|---|---|---|---|---|\n";
  for (const ClaimResult& c : claims) {
    const char* format = IsCount(c.metric) ? "%.0f" : "%.3g";
    std::string value = "-";
    if (c.median_difference) {
      value = Fmt(*c.median_difference, format) + " (" + Fmt(*c.low, format) + " to " + Fmt(*c.high, format) + ")";
      if (c.difference_kind == "ratio") value = Fmt(*c.median_difference, "%.2f") + "x (" + Fmt(*c.low, "%.2f") + "-" + Fmt(*c.high, "%.2f") + "x)";
    }
    std::string where;
    for (size_t i = 0; i < c.fails_at.size() && i < 6; ++i) where += (i ? "; " : "") + c.fails_at[i];
    if (c.fails_at.size() > 6) where += "; ... (" + std::to_string(c.fails_at.size()) + " in all)";
    md += "| " + c.method + " vs " + c.baseline + " | " + c.claim + " | " + c.metric + " | " +
          (c.decided ? (c.held ? "**held**" : "**not held**") : "undecided (no paired cells)") + " | " + value + " | " +
          std::to_string(c.favourable) + "/" + std::to_string(c.pairs) + " | " + Cell(where.empty() ? "-" : where) +
          " |\n";
  }
  return md + "\n";
}

std::string StudySection(const SweepStudy& study, const std::vector<SummaryRow>& summary,
                         const std::vector<std::string>& plots) {
  std::string md = "## Study: " + study.name + "\n\n";
  const std::vector<std::string> varied = study.VariedParams();
  if (!study.set.empty()) md += "Fixed for this study: `" + study.set.dump() + "`.\n\n";
  for (const std::string& p : plots) {
    if (p.rfind("plots/" + PlotFileStem(study.name) + "_", 0) == 0) md += "![" + p + "](" + p + ")\n";
  }
  const std::vector<SummarisedMetric> metrics = SummarisedMetrics();
  md += "\n| " + std::string(varied.empty() ? "point" : "swept values") + " | method | cells | failed | cameras posed |";
  std::string rule = "|---|---|---|---|---|";
  for (const SummarisedMetric& m : metrics) {
    md += " " + m.spec->summary.heading + " |";
    rule += "---|";
  }
  md += "\n" + rule + "\n";
  for (const SummaryRow& r : summary) {
    if (r.study != study.name) continue;
    md += "| " + Cell(r.point) + " | " + r.method + " | " + std::to_string(r.cells) + " | " + std::to_string(r.failed) + " | " +
          CamerasPosedText(r) + " |";
    for (const SummarisedMetric& m : metrics) {
      const MetricSummary& how = m.spec->summary;
      switch (how.kind) {
        case SummaryKind::kShare:
          md += " " + std::to_string(r.Count(m.spec->name)) + " of " + std::to_string(r.cells) + " |";
          break;
        case SummaryKind::kSum: md += " " + std::to_string(static_cast<int64_t>(r.Total(m.spec->name))) + " |"; break;
        case SummaryKind::kMedian:
          md += " " + MedianRange(r.Spread(m.spec->name), how.format.c_str(), how.unit) + " |";
          break;
        case SummaryKind::kNone: break;
      }
    }
    md += "\n";
  }
  return md + "\n";
}

// How many cells have each value of `value(cell)`, in the order of the cells: "`a` in every cell"
// or "`a` in 2 cells, `b` in 1 cell".
template <class Value>
std::string CellsWith(const std::vector<SweepCell>& cells, Value&& value) {
  std::vector<std::pair<std::string, int>> counts;
  for (const SweepCell& cell : cells) {
    const std::string v = value(cell);
    auto it = std::find_if(counts.begin(), counts.end(), [&](const auto& c) { return c.first == v; });
    if (it == counts.end()) {
      counts.push_back({v, 1});
    } else {
      ++it->second;
    }
  }
  if (counts.size() == 1) return counts[0].first + " in every cell";
  std::string line;
  for (size_t i = 0; i < counts.size(); ++i) {
    line += std::string(i == 0 ? "" : ", ") + counts[i].first + " in " + Count(counts[i].second, "cell");
  }
  return line;
}

// What the images went through: the sensor preset (render --sensor) and whether the rig's own car
// (make-rig --ego-vehicle) was around the rig, per cell.
std::string ImagesLines(const std::vector<SweepCell>& cells) {
  if (cells.empty()) return "";
  const auto sensor = [](const SweepCell& cell) { return "`" + CellParam(cell.params, "sensor").get<std::string>() + "`"; };
  const bool all_ideal = std::all_of(cells.begin(), cells.end(), [&](const SweepCell& c) { return sensor(c) == "`ideal`"; });
  std::string md = "Images: sensor preset " + CellsWith(cells, sensor) + (all_ideal ? ": renders without a sensor model" : "") +
                   " (`render --sensor`; the presets' values and sources: docs/scenes-and-rigs.md).\n\n";
  const size_t cars = size_t(std::count_if(cells.begin(), cells.end(), [](const SweepCell& c) {
    return CellParam(c.params, "ego_vehicle").get<bool>();
  }));
  md += "The rig's own car (`ego_vehicle`, as `make-rig --ego-vehicle`): " +
        (cars == 0 ? std::string("in no cell") :
         cars == cells.size() ? std::string("around the rig in every cell") :
         "around the rig in " + std::to_string(cars) + " of " + Count(cells.size(), "cell")) + ".\n\n";
  return md;
}

}  // namespace

std::string SweepReportMarkdown(const SweepReportInput& in) {
  const SweepConfig& config = *in.config;
  int failed_rows = 0, rows = 0;
  std::map<std::string, int> reasons;
  std::string failures;
  for (size_t c = 0; c < in.records->size(); ++c) {
    for (const MethodRow& r : (*in.records)[c].rows) {
      ++rows;
      if (r.status == "ok") continue;
      ++failed_rows;
      if (++reasons[r.failure_reason] <= 3) {
        failures += "- cell " + std::to_string((*in.cells)[c].index) + " (`" + (*in.cells)[c].key + "`), " + r.method +
                    ": " + r.failure_reason + "\n";
      }
    }
  }
  std::string methods;
  for (const SweepMethod& m : config.methods) methods += (methods.empty() ? "" : ", ") + m.name;
  std::string md = "# Sweep: " + config.name + "\n\n";
  md += std::to_string(in.cells->size()) + " cells (" + std::to_string(config.studies.size()) + " studies, " +
        std::to_string(config.seeds.size()) + " seeds each), methods " + methods + ": " + std::to_string(rows) +
        " results, " + std::to_string(failed_rows) + " of them failed runs. Sweep hash `" + in.sweep_hash + "`.\n\n";
  if (!in.command.empty()) md += "Run again (finished cells are kept): `" + in.command + "`\n\n";
  md += ImagesLines(*in.cells);
  md += "Every cell is rendered once and calibrated by every method; a camera counts as within N deg when it has a "
        "full pose whose rotation and translation-direction errors against the truth are both at most N deg. "
        "*Confidently wrong*: cameras reported with a full pose that are more than 5 deg off, or placed but for one "
        "axis (*open along an axis*: no full pose, never within N deg) with their rotation or the direction of their "
        "centre across the axis more than 5 deg off. *Cameras posed*: per seed, the cameras given a full pose of the rig's cameras. *All within N°*: in how many of the point's seeds every camera was. Other values are medians over a point's seeds, with their range in brackets. Files: `results.csv` and `results.jsonl` (a row per cell and "
        "method), `summary.csv`, `summary.json`, `plots/`.\n\n";
  md += ClaimSection(config.claims, *in.claims);
  for (const SweepStudy& study : config.studies) md += StudySection(study, *in.summary, in.plot_images);
  if (failed_rows > 0) md += "## Failed runs\n\n" + failures + "\n";
  md += "## Columns of results.csv\n\n| column | meaning |\n|---|---|\n";
  md += "| cell, key, studies, seed | the cell's number, its key (names `cells/<key>.json`), its studies, its seed |\n";
  for (const ParamSpec& p : CellParamSpecs()) {
    // A parameter held only where it is set is a column when some cell sets it (sweep_results.cc).
    const auto set = [&](const SweepCell& c) { return c.params.contains(p.name); };
    if (HeldWhenSet(p) && std::none_of(in.cells->begin(), in.cells->end(), set)) continue;
    md += "| " + p.name + " | " + Cell(p.help) + " |\n";
  }
  for (const MetricSpec& m : CellMetricSpecs()) md += "| " + m.name + " | " + Cell(m.help) + " |\n";
  md += "| method, tool, semantics, features, time | how the cell was calibrated (time: how rigsim took the cameras' "
        "capture times, synchronised or estimated) |\n"
        "| status, failure_reason | `ok`, or `failed` with why |\n";
  for (const MetricSpec& m : SweepMetricSpecs()) md += "| " + m.name + " | " + Cell(m.help) + " |\n";
  return md;
}

}  // namespace rigsim
