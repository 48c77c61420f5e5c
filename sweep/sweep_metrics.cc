#include "sweep/sweep_metrics.h"

#include <algorithm>
#include <cstdint>
#include <cstdio>

#include "calibrator/calibrate_rig.h"
#include "evaluation/colmap_peer.h"
#include "evaluation/rig_scores.h"
#include "evaluation/verdicts.h"
#include "pipeline/calibration_run.h"
#include "pipeline/calibration_scores.h"

namespace rigsim {

using Json = nlohmann::ordered_json;

namespace {

Json OptionalJson(const std::optional<double>& v) { return v ? Json(*v) : Json(nullptr); }

// The position of `deg` in kAucThresholdsDeg.
int AucIndex(double deg) {
  const double* end = std::end(kAucThresholdsDeg);
  return static_cast<int>(std::find(std::begin(kAucThresholdsDeg), end, deg) - std::begin(kAucThresholdsDeg));
}

std::string Deg(double deg) {
  char buf[16];
  std::snprintf(buf, sizeof buf, "%g", deg);
  return buf;
}

// rigsim's matches of the overlapping pairs, pooled over frames, as the ground truth judges them.
struct MatchTotals {
  int64_t matches = 0, evaluated = 0, correct = 0, cross = 0, cross_correct = 0;
  bool has_cross = false;  // true labels were there to tell the classes
};
MatchTotals MatchTotalsOf(const MethodRun& run) {
  MatchTotals t;
  for (const PairResult& pair : run.rigsim->pairwise.pairs) t.matches += pair.two_view.num_matches;
  if (!run.record || !run.record->truth) return t;
  const PooledMatchPrecision pooled = PoolMatchPrecision(*run.record->truth);
  t.evaluated = pooled.evaluated;
  t.correct = pooled.correct;
  t.has_cross = pooled.cross_class.has_value();
  t.cross = pooled.cross_class.value_or(0);
  t.cross_correct = pooled.cross_class_correct;
  return t;
}

// A metric of rigsim's matches: absent from a peer's row.
template <class F>
std::function<std::optional<Json>(const MethodRun&)> FromMatches(F f) {
  return [f](const MethodRun& run) -> std::optional<Json> {
    if (!run.rigsim) return std::nullopt;
    return f(MatchTotalsOf(run));
  };
}

// A metric of the scores: every row has it.
template <class F>
std::function<std::optional<Json>(const MethodRun&)> FromScores(F f) {
  return [f](const MethodRun& run) -> std::optional<Json> { return Json(f(*run.scores)); };
}

// A metric of the scores of rigsim's calibration: absent from a peer's row (no peer places a camera
// but for one axis).
template <class F>
std::function<std::optional<Json>(const MethodRun&)> FromRigsimScores(F f) {
  return [f](const MethodRun& run) -> std::optional<Json> {
    if (!run.rigsim) return std::nullopt;
    return Json(f(*run.scores));
  };
}

MetricSummary Share(std::string heading) {
  return {SummaryKind::kShare, SummaryGroup::kOutcome, std::move(heading), "", "", false};
}
MetricSummary Median(SummaryGroup group, std::string heading, std::string format, std::string unit = "") {
  return {SummaryKind::kMedian, group, std::move(heading), std::move(format), std::move(unit), false};
}

std::vector<MethodMetricSpec> MakeSweepMetricSpecs() {
  using G = SummaryGroup;
  using S = MetricPlot::Style;
  std::vector<MethodMetricSpec> m;
  const auto add = [&m](std::string name, std::string help, bool count, MetricSummary summary,
                        std::optional<MetricPlot> plot, std::function<std::optional<Json>(const MethodRun&)> compute) {
    MethodMetricSpec s;
    s.name = std::move(name);
    s.help = std::move(help);
    s.count = count;
    s.summary = std::move(summary);
    s.plot = std::move(plot);
    s.compute = std::move(compute);
    m.push_back(std::move(s));
  };
  add("cameras", "cameras in the rig", true, {}, {}, FromScores([](const RigScores& s) { return s.cameras.size(); }));
  add("cameras_posed", "cameras the method gave a full pose (rotation and position)", true, {}, {},
      FromScores([](const RigScores& s) { return s.cameras_posed; }));
  add("cameras_rotation_only", "cameras given a rotation and nothing of their position", true, {}, {},
      FromScores([](const RigScores& s) { return s.cameras_rotation_only; }));
  add("success_1deg",
      "1 when every camera has a full pose within 1 deg (pose error: max of rotation and translation-direction error), "
      "else 0",
      true, Share("all within 1°"), MetricPlot{"success", S::kDashed, "success_1deg"},
      FromScores([](const RigScores& s) { return s.success_1deg ? 1 : 0; }));
  add("success_2deg", "the same within 2 deg", true, Share("all within 2°"), MetricPlot{"success", S::kLine, "success_2deg"},
      FromScores([](const RigScores& s) { return s.success_2deg ? 1 : 0; }));
  add("success_5deg", "the same within 5 deg", true, Share("all within 5°"), {}, FromScores([](const RigScores& s) {
        std::vector<double> others;
        for (size_t c = 1; c < s.cameras.size(); ++c) others.push_back(s.cameras[c].pose_error_deg);
        return RigSucceeds(!s.cameras.empty() && s.cameras[0].posed, others, 5.0) ? 1 : 0;
      }));
  add("confidently_wrong",
      "cameras reported with a full pose whose pose error exceeds 5 deg (posed if synchronised included where the "
      "truth's camera captured with camera 0), or placed but for one axis with their rotation or direction across "
      "the axis more than 5 deg off",
      true,
      {SummaryKind::kSum, G::kOutcome, "confidently wrong", "", "", false}, {},
      FromScores([](const RigScores& s) { return s.confidently_wrong; }));
  add("overconfident",
      "cameras whose rotation error, or with a full pose direction error, exceeds both 3 times the standard "
      "deviation the method states for it and 0.05 deg (rigsim states them; peers state none)",
      true, {SummaryKind::kSum, G::kOutcome, "overconfident", "", "", false}, {},
      FromScores([](const RigScores& s) { return s.overconfident; }));
  add("cameras_stating_sd",
      "cameras other than the reference with an error and a standard deviation stated for it: those judged for "
      "overconfident",
      true, {SummaryKind::kSum, G::kOutcome, "stating a deviation", "", "", false}, {},
      FromScores([](const RigScores& s) { return s.cameras_stating_sd; }));
  add("cameras_if_synchronised",
      "cameras given a full pose that holds only if they captured with camera 0 (the rig's path cannot show a time "
      "offset; rigsim's rows only)",
      true, {SummaryKind::kSum, G::kOutcome, "posed if synchronised", "", "", false}, {},
      FromRigsimScores([](const RigScores& s) { return s.cameras_if_synchronised; }));
  add("wrong_if_synchronised",
      "cameras posed if synchronised whose pose error exceeds 5 deg (the estimate stated the condition; confidently "
      "wrong too where the truth's camera captured with camera 0)",
      true, {SummaryKind::kSum, G::kOutcome, "wrong if synchronised", "", "", false}, {},
      FromRigsimScores([](const RigScores& s) { return s.wrong_if_synchronised; }));
  add("cameras_open_axis",
      "cameras placed but for one axis: a planar motion fixed their rotation and their centre across its turn axis, "
      "not along it (no full pose; rigsim's rows only)",
      true, {SummaryKind::kSum, G::kOutcome, "open along an axis", "", "", false}, {},
      FromRigsimScores([](const RigScores& s) { return s.cameras_open_axis; }));
  add("max_rotation_error_deg", "worst rotation error of the cameras with a rotation", false, {}, {},
      FromScores([](const RigScores& s) { return OptionalJson(s.max_rotation_error_deg); }));
  MetricSummary rotation = Median(G::kError, "median rotation error", "%.3g", "°");
  rotation.csv_range = true;
  add("median_rotation_error_deg", "median rotation error of the cameras with a rotation (camera 0 excluded)", false,
      rotation, MetricPlot{"rotation_error", S::kErrorBars, "median_rot min_rot max_rot"},
      FromScores([](const RigScores& s) { return OptionalJson(s.median_rotation_error_deg); }));
  add("max_translation_direction_error_deg", "worst error of the direction of a camera's centre from camera 0's", false,
      {}, {}, FromScores([](const RigScores& s) { return OptionalJson(s.max_direction_error_deg); }));
  add("median_translation_direction_error_deg", "median of the same", false,
      Median(G::kError, "median direction error", "%.3g", "°"), {},
      FromScores([](const RigScores& s) { return OptionalJson(s.median_direction_error_deg); }));
  add("max_across_axis_direction_error_deg",
      "worst error of the direction of a camera placed but for one axis: its centre across the axis, against the "
      "true centre from camera 0's with the component along the axis removed (none on the axis; rigsim's rows only)",
      false, Median(G::kError, "worst across-axis direction error", "%.3g", "°"), {},
      FromRigsimScores([](const RigScores& s) { return OptionalJson(s.max_across_axis_direction_error_deg); }));
  add("max_position_error_m", "worst camera position error after aligning the scale (metric estimates: none)", false, {},
      {}, FromScores([](const RigScores& s) { return OptionalJson(s.max_position_error_m); }));
  const int five = AucIndex(5.0);
  add("auc_cameras_5deg", "AUC of the cameras' pose errors up to 5 deg (missing cameras count as failures)", false, {}, {},
      FromScores([five](const RigScores& s) { return s.auc_cameras[five]; }));
  for (size_t t = 0; t < std::size(kAucThresholdsDeg); ++t) {
    const std::string deg = Deg(kAucThresholdsDeg[t]);
    add("auc_pairs_" + deg + "deg",
        (t == 0 ? "AUC of the relative pose errors of every camera pair up to " : "... up to ") + deg + " deg", false,
        int(t) == five ? Median(G::kOutcome, "AUC@5° (pairs)", "%.2f") : MetricSummary{}, {},
        FromScores([t](const RigScores& s) { return s.auc_pairs[t]; }));
  }
  add("matches", "matches of the overlapping pairs, pooled over frames", true, {}, {},
      FromMatches([](const MatchTotals& t) { return Json(t.matches); }));
  add("match_precision", "share of those matches that are correct by the ground-truth depth", false,
      Median(G::kMatches, "match precision", "%.2f"), {}, FromMatches([](const MatchTotals& t) {
        return t.evaluated > 0 ? Json(double(t.correct) / t.evaluated) : Json(nullptr);
      }));
  add("cross_class_matches", "matches joining keypoints of two different classes (true labels)", true, {}, {},
      FromMatches([](const MatchTotals& t) { return t.has_cross ? Json(t.cross) : Json(nullptr); }));
  add("cross_class_wrong", "of those, wrong by the ground truth", true,
      Median(G::kMatches, "wrong cross-class matches", "%.0f"), {},
      FromMatches([](const MatchTotals& t) { return t.has_cross ? Json(t.cross - t.cross_correct) : Json(nullptr); }));
  add("cross_class_right", "of those, right by the ground truth (a class boundary, not an error)", true, {}, {},
      FromMatches([](const MatchTotals& t) { return t.has_cross ? Json(t.cross_correct) : Json(nullptr); }));
  add("wrong_matches", "matches wrong by the ground truth", true, {}, {},
      FromMatches([](const MatchTotals& t) { return t.evaluated > 0 ? Json(t.evaluated - t.correct) : Json(nullptr); }));
  add("time_detect_s", "feature detection, summed over images", false, {}, {}, [](const MethodRun& run) -> std::optional<Json> {
    if (!run.rigsim) return run.colmap->extract_time_s;
    return run.record ? Json(run.record->detect_time_s) : Json(nullptr);
  });
  add("time_match_s", "matching, summed over pairs and frames", false, Median(G::kTime, "match time", "%.3g", " s"), {},
      [](const MethodRun& run) -> std::optional<Json> {
        if (!run.rigsim) return run.colmap->match_time_s;
        const CalibrationReport& p = run.rigsim->pairwise;
        return p.screen_time_s + p.match_time_s + p.temporal_match_time_s;
      });
  add("time_total_s", "wall time of the whole method (calibration, or the peer's run)", false,
      Median(G::kTime, "total time", "%.3g", " s"), {},
      [](const MethodRun& run) -> std::optional<Json> { return run.time_total_s; });
  return m;
}

std::vector<CellMetricSpec> MakeCellMetricSpecs() {
  std::vector<CellMetricSpec> m(3);
  // The camera pairs that share a view: more than 1% of it.
  const auto shared = [](const CellRun& run) {
    std::vector<double> overlaps;
    for (const auto& [pair, overlap] : run.overlap) {
      if (overlap > 0.01) overlaps.push_back(overlap);
    }
    return overlaps;
  };
  m[0].name = "overlap_pct";
  m[0].help = "mean ground-truth overlap of the camera pairs that share a view (over 1%), percent";
  m[0].summary = Median(SummaryGroup::kRender, "overlap achieved", "%.0f", "%");
  m[0].compute = [shared](const CellRun& run) {
    const std::vector<double> o = shared(run);
    double sum = 0.0;
    for (double v : o) sum += v;
    return o.empty() ? Json(nullptr) : Json(100.0 * sum / o.size());
  };
  m[1].name = "overlapping_pairs";
  m[1].help = "camera pairs that share a view (over 1%)";
  m[1].count = true;
  m[1].compute = [shared](const CellRun& run) { return Json(shared(run).size()); };
  m[2].name = "render_time_s";
  m[2].help = "wall time of the cell's render";
  m[2].compute = [](const CellRun& run) { return Json(run.render_time_s); };
  return m;
}

}  // namespace

const std::vector<MethodMetricSpec>& SweepMetricSpecs() {
  static const std::vector<MethodMetricSpec> specs = MakeSweepMetricSpecs();
  return specs;
}

const std::vector<CellMetricSpec>& CellMetricSpecs() {
  static const std::vector<CellMetricSpec> specs = MakeCellMetricSpecs();
  return specs;
}

std::vector<SummarisedMetric> SummarisedMetrics() {
  std::vector<SummarisedMetric> out;
  for (const MethodMetricSpec& m : SweepMetricSpecs()) {
    if (m.summary.kind != SummaryKind::kNone) out.push_back({&m, false});
  }
  for (const CellMetricSpec& m : CellMetricSpecs()) {
    if (m.summary.kind != SummaryKind::kNone) out.push_back({&m, true});
  }
  std::stable_sort(out.begin(), out.end(), [](const SummarisedMetric& a, const SummarisedMetric& b) {
    return a.spec->summary.group < b.spec->summary.group;
  });
  return out;
}

const std::vector<SweepPlotSpec>& SweepPlotSpecs() {
  static const std::vector<SweepPlotSpec> plots = {
      {"success", "calibration success", "share of seeds: every camera within 2 deg (dashed: 1 deg)",
       "set yrange [-0.05:1.05]\n"},
      {"rotation_error", "rotation error", "median rotation error of the cameras (deg)", "set logscale y\nset yrange [*:*]\n"},
  };
  return plots;
}

Json MethodMetrics(const MethodRun& run) {
  Json metrics = Json::object();
  for (const MethodMetricSpec& m : SweepMetricSpecs()) {
    if (std::optional<Json> v = m.compute(run)) metrics[m.name] = std::move(*v);
  }
  return metrics;
}

Json CellMetrics(const CellRun& run) {
  Json metrics = Json::object();
  for (const CellMetricSpec& m : CellMetricSpecs()) metrics[m.name] = m.compute(run);
  return metrics;
}

}  // namespace rigsim
