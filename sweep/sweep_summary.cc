#include "sweep/sweep_summary.h"

#include <algorithm>
#include <cmath>
#include <cstdio>
#include <functional>
#include <map>

namespace rigsim {

using Json = nlohmann::ordered_json;

namespace {

std::optional<double> Number(const Json& metrics, const std::string& name) {
  const auto it = metrics.find(name);
  if (it == metrics.end() || !it->is_number()) return std::nullopt;
  return it->get<double>();
}

double Median(std::vector<double> v) {
  std::sort(v.begin(), v.end());
  const size_t n = v.size();
  return n % 2 ? v[n / 2] : 0.5 * (v[n / 2 - 1] + v[n / 2]);
}

MetricSpread Spread(const std::vector<double>& values) {
  MetricSpread s;
  s.count = static_cast<int>(values.size());
  if (values.empty()) return s;
  s.median = Median(values);
  s.min = *std::min_element(values.begin(), values.end());
  s.max = *std::max_element(values.begin(), values.end());
  return s;
}

std::string PointLabel(const Json& values) {
  std::string label;
  for (const auto& [k, v] : values.items()) {
    label += (label.empty() ? "" : ", ") + k + "=" + FormatParamValue(v);
  }
  return label.empty() ? "base" : label;
}

// Each study's points (the distinct values of what it sweeps) in the order its cells come, and
// the cells of each point.
struct StudyPoints {
  std::vector<Json> values;
  std::vector<std::vector<size_t>> cells;  // indices into the cell list
};

StudyPoints PointsOf(const SweepStudy& study, const std::vector<SweepCell>& cells) {
  StudyPoints sp;
  const std::vector<std::string> varied = study.VariedParams();
  for (size_t i = 0; i < cells.size(); ++i) {
    if (std::find(cells[i].studies.begin(), cells[i].studies.end(), study.name) == cells[i].studies.end()) continue;
    Json v = Json::object();
    for (const std::string& p : varied) v[p] = cells[i].params.at(p);
    auto it = std::find(sp.values.begin(), sp.values.end(), v);
    if (it == sp.values.end()) {
      sp.values.push_back(v);
      sp.cells.emplace_back();
      it = sp.values.end() - 1;
    }
    sp.cells[it - sp.values.begin()].push_back(i);
  }
  return sp;
}

const MethodRow* RowOf(const CellRecord& record, const std::string& method) {
  for (const MethodRow& r : record.rows) {
    if (r.method == method) return &r;
  }
  return nullptr;
}

Json SpreadJson(const MetricSpread& s) {
  auto opt = [](const std::optional<double>& v) { return v ? Json(*v) : Json(nullptr); };
  return {{"median", opt(s.median)}, {"min", opt(s.min)}, {"max", opt(s.max)}, {"count", s.count}};
}

}  // namespace

std::vector<SummaryRow> Summarise(const SweepConfig& config, const std::vector<SweepCell>& cells,
                                  const std::vector<CellRecord>& records) {
  std::vector<SummaryRow> rows;
  for (const SweepStudy& study : config.studies) {
    const StudyPoints sp = PointsOf(study, cells);
    for (size_t p = 0; p < sp.values.size(); ++p) {
      for (const SweepMethod& method : config.methods) {
        SummaryRow row;
        row.study = study.name;
        row.point = PointLabel(sp.values[p]);
        row.point_index = static_cast<int>(p);
        row.point_values = sp.values[p];
        row.method = method.name;
        std::map<std::string, std::vector<double>> values;
        auto add = [&](const std::string& name, const Json& metrics) {
          if (const auto v = Number(metrics, name)) values[name].push_back(*v);
        };
        for (size_t c : sp.cells[p]) {
          const MethodRow* r = RowOf(records[c], method.name);
          if (!r) continue;
          ++row.cells;
          if (r->status != "ok") ++row.failed;
          row.success_1deg += Number(r->metrics, "success_1deg").value_or(0.0);
          row.success_2deg += Number(r->metrics, "success_2deg").value_or(0.0);
          row.confidently_wrong += static_cast<int>(Number(r->metrics, "confidently_wrong").value_or(0.0));
          for (const char* m : {"auc_pairs_5deg", "median_rotation_error_deg", "median_translation_direction_error_deg",
                                "match_precision", "cross_class_wrong", "time_match_s", "time_total_s"}) {
            add(m, r->metrics);
          }
          add("overlap_pct", records[c].cell_metrics);
        }
        if (row.cells > 0) {
          row.success_1deg /= row.cells;
          row.success_2deg /= row.cells;
        }
        row.auc_pairs_5deg = Spread(values["auc_pairs_5deg"]);
        row.median_rotation_error_deg = Spread(values["median_rotation_error_deg"]);
        row.median_translation_direction_error_deg = Spread(values["median_translation_direction_error_deg"]);
        row.match_precision = Spread(values["match_precision"]);
        row.cross_class_wrong = Spread(values["cross_class_wrong"]);
        row.time_match_s = Spread(values["time_match_s"]);
        row.time_total_s = Spread(values["time_total_s"]);
        row.overlap_pct = Spread(values["overlap_pct"]);
        rows.push_back(std::move(row));
      }
    }
  }
  return rows;
}

Json SummaryToJson(const std::vector<SummaryRow>& rows) {
  Json out = Json::array();
  for (const SummaryRow& r : rows) {
    out.push_back({{"study", r.study},
                   {"point", r.point},
                   {"point_values", r.point_values},
                   {"method", r.method},
                   {"cells", r.cells},
                   {"failed", r.failed},
                   {"success_1deg", r.success_1deg},
                   {"success_2deg", r.success_2deg},
                   {"confidently_wrong", r.confidently_wrong},
                   {"auc_pairs_5deg", SpreadJson(r.auc_pairs_5deg)},
                   {"median_rotation_error_deg", SpreadJson(r.median_rotation_error_deg)},
                   {"median_translation_direction_error_deg", SpreadJson(r.median_translation_direction_error_deg)},
                   {"match_precision", SpreadJson(r.match_precision)},
                   {"cross_class_wrong", SpreadJson(r.cross_class_wrong)},
                   {"time_match_s", SpreadJson(r.time_match_s)},
                   {"time_total_s", SpreadJson(r.time_total_s)},
                   {"overlap_pct", SpreadJson(r.overlap_pct)}});
  }
  return out;
}

std::string SummaryCsv(const std::vector<SummaryRow>& rows) {
  auto num = [](const std::optional<double>& v) {
    if (!v) return std::string();
    char buf[32];
    std::snprintf(buf, sizeof buf, "%.6g", *v);
    return std::string(buf);
  };
  auto quote = [](const std::string& s) {
    if (s.find_first_of(",\"") == std::string::npos) return s;
    std::string q = "\"";
    for (char c : s) q += c == '"' ? std::string("\"\"") : std::string(1, c);
    return q + "\"";
  };
  std::string out =
      "study,point,method,cells,failed,success_1deg,success_2deg,confidently_wrong,auc_pairs_5deg,"
      "median_rotation_error_deg,median_rotation_error_deg_min,median_rotation_error_deg_max,"
      "median_translation_direction_error_deg,match_precision,cross_class_wrong,time_match_s,time_total_s,overlap_pct\n";
  for (const SummaryRow& r : rows) {
    out += quote(r.study) + "," + quote(r.point) + "," + quote(r.method) + "," + std::to_string(r.cells) + "," +
           std::to_string(r.failed) + "," + num(r.success_1deg) + "," + num(r.success_2deg) + "," +
           std::to_string(r.confidently_wrong) + "," + num(r.auc_pairs_5deg.median) + "," +
           num(r.median_rotation_error_deg.median) + "," + num(r.median_rotation_error_deg.min) + "," +
           num(r.median_rotation_error_deg.max) + "," + num(r.median_translation_direction_error_deg.median) + "," +
           num(r.match_precision.median) + "," + num(r.cross_class_wrong.median) + "," + num(r.time_match_s.median) +
           "," + num(r.time_total_s.median) + "," + num(r.overlap_pct.median) + "\n";
  }
  return out;
}

namespace {

struct ClaimSpec {
  std::string claim;
  std::string metric;
  bool ratio = false;           // compare method / baseline instead of method - baseline
  // Whether a difference (or ratio) supports the claim.
  std::function<bool(double)> holds;
};

}  // namespace

std::vector<ClaimResult> TestThesisClaims(const SweepConfig& config, const std::vector<SweepCell>& cells,
                                          const std::vector<CellRecord>& records) {
  const std::vector<ClaimSpec> specs = {
      {"gives a larger share of correct matches", "match_precision", false, [](double d) { return d > 0; }},
      {"gives fewer wrong matches between different classes", "cross_class_wrong", false,
       [](double d) { return d < 0; }},
      {"makes matching faster", "time_match_s", true, [](double r) { return r < 1; }},
      {"makes calibration faster", "time_total_s", true, [](double r) { return r < 1; }},
      {"keeps pose accuracy equal or better", "auc_pairs_5deg", false, [](double d) { return d >= -0.02; }},
  };
  std::vector<ClaimResult> results;
  const auto has = [&](const std::string& name) {
    return std::any_of(config.methods.begin(), config.methods.end(),
                       [&](const SweepMethod& m) { return m.name == name; });
  };
  for (const SweepMethod& method : config.methods) {
    if (method.tool != "rigsim" || method.semantics == "none") continue;
    const std::string baseline = method.features == "sift" ? "none" : method.features + ":none";
    if (!has(baseline)) continue;
    for (const ClaimSpec& spec : specs) {
      ClaimResult cr;
      cr.claim = spec.claim;
      cr.metric = spec.metric;
      cr.method = method.name;
      cr.baseline = baseline;
      cr.difference_kind = spec.ratio ? "ratio" : "difference";
      auto compare = [&](size_t c) -> std::optional<double> {
        const MethodRow* m = RowOf(records[c], method.name);
        const MethodRow* b = RowOf(records[c], baseline);
        if (!m || !b) return std::nullopt;
        const auto vm = Number(m->metrics, spec.metric), vb = Number(b->metrics, spec.metric);
        if (!vm || !vb) return std::nullopt;
        if (spec.ratio) return *vb > 0 ? std::optional<double>(*vm / *vb) : std::nullopt;
        return *vm - *vb;
      };
      std::vector<double> all;
      for (size_t c = 0; c < cells.size(); ++c) {
        if (const auto d = compare(c)) {
          all.push_back(*d);
          cr.favourable += spec.holds(*d);
        }
      }
      cr.pairs = static_cast<int>(all.size());
      if (!all.empty()) {
        const MetricSpread s = Spread(all);
        cr.median_difference = s.median;
        cr.low = s.min;
        cr.high = s.max;
        cr.decided = true;
        cr.held = spec.holds(*s.median);
      }
      for (const SweepStudy& study : config.studies) {
        const StudyPoints sp = PointsOf(study, cells);
        if (study.VariedParams().empty()) continue;
        for (size_t p = 0; p < sp.values.size(); ++p) {
          std::vector<double> at;
          for (size_t c : sp.cells[p]) {
            if (const auto d = compare(c)) at.push_back(*d);
          }
          if (!at.empty() && !spec.holds(Median(at))) cr.fails_at.push_back(study.name + ": " + PointLabel(sp.values[p]));
        }
      }
      results.push_back(std::move(cr));
    }
  }
  return results;
}

Json ClaimsToJson(const std::vector<ClaimResult>& claims) {
  Json out = Json::array();
  auto opt = [](const std::optional<double>& v) { return v ? Json(*v) : Json(nullptr); };
  for (const ClaimResult& c : claims) {
    out.push_back({{"claim", c.claim},
                   {"metric", c.metric},
                   {"method", c.method},
                   {"baseline", c.baseline},
                   {"decided", c.decided},
                   {"held", c.held},
                   {"pairs", c.pairs},
                   {"favourable", c.favourable},
                   {"comparison", c.difference_kind},
                   {"median", opt(c.median_difference)},
                   {"min", opt(c.low)},
                   {"max", opt(c.high)},
                   {"fails_at", c.fails_at}});
  }
  return out;
}

}  // namespace rigsim
