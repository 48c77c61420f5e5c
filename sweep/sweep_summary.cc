#include "sweep/sweep_summary.h"

#include <algorithm>
#include <cmath>
#include <cstdio>
#include <map>
#include <set>

#include "common/format.h"

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
    for (const std::string& p : varied) v[p] = CellParam(cells[i].params, p);
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

double SummaryRow::Total(const std::string& metric) const {
  const auto it = totals.find(metric);
  return it == totals.end() ? 0.0 : it->second;
}

int SummaryRow::Count(const std::string& metric) const {
  return static_cast<int>(std::lround(Total(metric) * cells));
}

const MetricSpread& SummaryRow::Spread(const std::string& metric) const {
  static const MetricSpread none;
  const auto it = spreads.find(metric);
  return it == spreads.end() ? none : it->second;
}

std::vector<SummaryRow> Summarise(const SweepConfig& config, const std::vector<SweepCell>& cells,
                                  const std::vector<CellRecord>& records) {
  const std::vector<SummarisedMetric> metrics = SummarisedMetrics();
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
        for (const SummarisedMetric& m : metrics) row.totals[m.spec->name] = 0.0;
        for (size_t c : sp.cells[p]) {
          const MethodRow* r = RowOf(records[c], method.name);
          if (!r) continue;
          ++row.cells;
          if (r->status != "ok") ++row.failed;
          const std::optional<double> posed = Number(r->metrics, "cameras_posed"), all = Number(r->metrics, "cameras");
          row.cameras_posed.push_back(posed && all
                                          ? std::optional<std::pair<int, int>>({static_cast<int>(*posed), static_cast<int>(*all)})
                                          : std::nullopt);
          for (const SummarisedMetric& m : metrics) {
            const std::optional<double> v = Number(m.of_cell ? records[c].cell_metrics : r->metrics, m.spec->name);
            if (m.spec->summary.kind == SummaryKind::kMedian) {
              if (v) values[m.spec->name].push_back(*v);
            } else {
              row.totals[m.spec->name] += v.value_or(0.0);
            }
          }
        }
        for (const SummarisedMetric& m : metrics) {
          if (m.spec->summary.kind == SummaryKind::kMedian) {
            row.totals.erase(m.spec->name);
            row.spreads[m.spec->name] = Spread(values[m.spec->name]);
          } else if (m.spec->summary.kind == SummaryKind::kShare && row.cells > 0) {
            row.totals[m.spec->name] /= row.cells;
          }
        }
        rows.push_back(std::move(row));
      }
    }
  }
  return rows;
}

Json SummaryToJson(const std::vector<SummaryRow>& rows) {
  const std::vector<SummarisedMetric> metrics = SummarisedMetrics();
  Json out = Json::array();
  for (const SummaryRow& r : rows) {
    Json j = {{"study", r.study},   {"point", r.point},   {"point_values", r.point_values},
              {"method", r.method}, {"cells", r.cells},   {"failed", r.failed}};
    for (const SummarisedMetric& m : metrics) {
      const std::string& name = m.spec->name;
      switch (m.spec->summary.kind) {
        case SummaryKind::kShare: j[name] = r.Total(name); break;
        case SummaryKind::kSum: j[name] = static_cast<int64_t>(r.Total(name)); break;
        case SummaryKind::kMedian: j[name] = SpreadJson(r.Spread(name)); break;
        case SummaryKind::kNone: break;
      }
    }
    Json posed = Json::array();
    for (const auto& p : r.cameras_posed) posed.push_back(p ? Json::array({p->first, p->second}) : Json(nullptr));
    j["cameras_posed"] = posed;
    out.push_back(std::move(j));
  }
  return out;
}

std::string CamerasPosedText(const SummaryRow& row) {
  const auto text = [](const std::optional<std::pair<int, int>>& p) {
    return p ? std::to_string(p->first) + "/" + std::to_string(p->second) : std::string("-");
  };
  std::string out;
  if (row.cameras_posed.size() <= 5) {
    for (const auto& p : row.cameras_posed) out += (out.empty() ? "" : ", ") + text(p);
    return out.empty() ? "-" : out;
  }
  // Least, most and median by the share posed, a run without a count (failed) counting as none.
  std::vector<std::pair<double, std::optional<std::pair<int, int>>>> by_share;
  for (const auto& p : row.cameras_posed) by_share.push_back({p && p->second > 0 ? double(p->first) / p->second : -1.0, p});
  std::stable_sort(by_share.begin(), by_share.end(),
                   [](const auto& a, const auto& b) { return a.first < b.first; });
  return text(by_share.front().second) + " to " + text(by_share.back().second) + ", median " +
         text(by_share[(by_share.size() - 1) / 2].second);
}

namespace {

// The cameras confidently wrong, and overconfident of those judged, when the method states
// standard deviations (rigsim does; a peer does not).
std::string JudgedLine(const SummaryRow& r) {
  const int64_t judged = static_cast<int64_t>(r.Total("cameras_stating_sd"));
  if (judged == 0) return "";
  return "; confidently wrong " + std::to_string(static_cast<int64_t>(r.Total("confidently_wrong"))) +
         ", overconfident " + std::to_string(static_cast<int64_t>(r.Total("overconfident"))) + " of " +
         Count(judged, "camera") + " stating a deviation";
}

}  // namespace

std::string ConfidenceLine(const std::vector<SummaryRow>& rows) {
  double wrong = 0, overconfident = 0, judged = 0;
  for (const SummaryRow& r : rows) {
    wrong += r.Total("confidently_wrong");
    overconfident += r.Total("overconfident");
    judged += r.Total("cameras_stating_sd");
  }
  const std::string head = "cameras confidently wrong " + std::to_string(static_cast<int64_t>(wrong)) + "; ";
  if (judged == 0) return head + "overconfident: no method stated a standard deviation";
  return head + "overconfident " + std::to_string(static_cast<int64_t>(overconfident)) + " of " +
         Count(static_cast<int64_t>(judged), "camera") + " stating a deviation (3 sd and 0.05 deg)";
}

std::vector<std::string> PlacementLines(const std::vector<SummaryRow>& rows) {
  std::vector<std::string> lines;
  std::set<std::string> methods;
  for (const SummaryRow& r : rows) methods.insert(r.method);
  std::string study;
  for (const SummaryRow& r : rows) {
    if (r.study != study || lines.empty()) {
      study = r.study;
      lines.push_back(study + ":");
    }
    // A path alone names its point; several swept values are named with their parameters.
    std::string label = r.point;
    if (r.point_values.size() == 1) label = FormatParamValue(r.point_values.begin().value());
    if (methods.size() > 1) label += ", " + r.method;
    lines.push_back("  " + label + ": placed every camera within 1° / 5° in " + std::to_string(r.Count("success_1deg")) +
                    " / " + std::to_string(r.Count("success_5deg")) + " of " + std::to_string(r.cells) + " seeds (cameras posed " +
                    CamerasPosedText(r) + ")" + JudgedLine(r));
  }
  return lines;
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
  const std::vector<SummarisedMetric> metrics = SummarisedMetrics();
  std::string out = "study,point,method,cells,failed";
  for (const SummarisedMetric& m : metrics) {
    out += "," + m.spec->name;
    if (m.spec->summary.csv_range) out += "," + m.spec->name + "_min," + m.spec->name + "_max";
  }
  out += "\n";
  for (const SummaryRow& r : rows) {
    out += quote(r.study) + "," + quote(r.point) + "," + quote(r.method) + "," + std::to_string(r.cells) + "," +
           std::to_string(r.failed);
    for (const SummarisedMetric& m : metrics) {
      const std::string& name = m.spec->name;
      if (m.spec->summary.kind == SummaryKind::kSum) {
        out += "," + std::to_string(static_cast<int64_t>(r.Total(name)));
      } else if (m.spec->summary.kind == SummaryKind::kShare) {
        out += "," + num(r.Total(name));
      } else {
        const MetricSpread& s = r.Spread(name);
        out += "," + num(s.median);
        if (m.spec->summary.csv_range) out += "," + num(s.min) + "," + num(s.max);
      }
    }
    out += "\n";
  }
  return out;
}

std::vector<ClaimResult> TestClaims(const SweepConfig& config, const std::vector<SweepCell>& cells,
                                    const std::vector<CellRecord>& records) {
  std::vector<ClaimResult> results;
  const auto has = [&](const std::string& name) {
    return std::any_of(config.methods.begin(), config.methods.end(),
                       [&](const SweepMethod& m) { return m.name == name; });
  };
  for (const SweepMethod& method : config.methods) {
    if (method.tool != "rigsim" || method.semantics == "none") continue;
    const std::string baseline = SweepMethodName(method.features, "none", method.time);
    if (!has(baseline)) continue;
    for (const ClaimSpec& spec : config.claims.claims) {
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
          cr.favourable += spec.Holds(*d);
        }
      }
      cr.pairs = static_cast<int>(all.size());
      if (!all.empty()) {
        const MetricSpread s = Spread(all);
        cr.median_difference = s.median;
        cr.low = s.min;
        cr.high = s.max;
        cr.decided = true;
        cr.held = spec.Holds(*s.median);
      }
      for (const SweepStudy& study : config.studies) {
        const StudyPoints sp = PointsOf(study, cells);
        if (study.VariedParams().empty()) continue;
        for (size_t p = 0; p < sp.values.size(); ++p) {
          std::vector<double> at;
          for (size_t c : sp.cells[p]) {
            if (const auto d = compare(c)) at.push_back(*d);
          }
          if (!at.empty() && !spec.Holds(Median(at))) cr.fails_at.push_back(study.name + ": " + PointLabel(sp.values[p]));
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
