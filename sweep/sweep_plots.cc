#include "sweep/sweep_plots.h"

#include <cctype>
#include <cstdio>
#include <fstream>
#include <map>
#include <optional>
#include <stdexcept>

#include "common/run_program.h"
#include "sweep/sweep_metrics.h"

namespace rigsim {

namespace fs = std::filesystem;

std::string PlotFileStem(const std::string& study) {
  std::string s;
  for (char c : study) s += std::isalnum(static_cast<unsigned char>(c)) || c == '-' || c == '_' ? c : '_';
  return s.empty() ? "study" : s;
}

namespace {

std::string Num(const std::optional<double>& v) {
  if (!v) return "?";
  char buf[32];
  std::snprintf(buf, sizeof buf, "%.6g", *v);
  return buf;
}

// gnuplot string literal (double quotes, escaped).
std::string Quoted(const std::string& s) {
  std::string q = "\"";
  for (char c : s) {
    if (c == '"' || c == '\\') q += '\\';
    q += c;
  }
  return q + "\"";
}

std::string AxisLabel(const nlohmann::ordered_json& values) {
  std::string label;
  for (const auto& [k, v] : values.items()) {
    label += (label.empty() ? "" : " / ") + FormatParamValue(v);
  }
  return label;
}

void WriteFile(const fs::path& path, const std::string& text) {
  std::ofstream out(path, std::ios::binary | std::ios::trunc);
  out << text;
  if (!out) throw std::runtime_error(path.string() + ": cannot write");
}

// A metric drawn in a plot: its column in the data (1-based; errorbars take three) and how.
struct Series {
  const MetricSpec* metric;
  MetricPlot::Style style;
  int column = 0;
};

struct PlotSeries {
  const SweepPlotSpec* plot;
  std::vector<Series> series;  // the plot's line (or error bars) first, then its dashed companions
};

// The plots that have metrics, in SweepPlotSpecs' order, with their data columns after x.
std::vector<PlotSeries> PlotsWithSeries() {
  std::vector<PlotSeries> plots;
  int column = 2;
  for (const SweepPlotSpec& plot : SweepPlotSpecs()) {
    PlotSeries ps{&plot, {}};
    for (bool dashed : {false, true}) {
      for (const SummarisedMetric& m : SummarisedMetrics()) {
        if (!m.spec->plot || m.spec->plot->plot != plot.name) continue;
        if ((m.spec->plot->style == MetricPlot::Style::kDashed) != dashed) continue;
        ps.series.push_back({m.spec, m.spec->plot->style, column});
        column += m.spec->plot->style == MetricPlot::Style::kErrorBars ? 3 : 1;
      }
    }
    if (!ps.series.empty()) plots.push_back(std::move(ps));
  }
  return plots;
}

// The data columns of one summary row: each series' value (error bars: median, min, max).
std::string SeriesValues(const std::vector<PlotSeries>& plots, const SummaryRow& r) {
  std::vector<std::optional<double>> values;
  for (const PlotSeries& p : plots) {
    for (const Series& s : p.series) {
      if (s.metric->summary.kind != SummaryKind::kMedian) {
        values.push_back(r.Total(s.metric->name));
        continue;
      }
      const MetricSpread& spread = r.Spread(s.metric->name);
      values.push_back(spread.median);
      if (s.style == MetricPlot::Style::kErrorBars) values.insert(values.end(), {spread.min, spread.max});
    }
  }
  std::string line;
  for (const std::optional<double>& v : values) line.append(" ").append(Num(v));
  return line;
}

// One method's part of a plot command: its series from `src`, in colour `colour`.
std::string MethodPlot(const PlotSeries& p, const std::string& src, const std::string& title, const std::string& colour) {
  std::string out;
  for (const Series& s : p.series) {
    const std::string c = std::to_string(s.column);
    out += (out.empty() ? "" : ", \\\n     ") + src;
    switch (s.style) {
      case MetricPlot::Style::kLine:
        out += " using 1:" + c + " with linespoints lw 2 pt 7" + colour + " title " + title;
        break;
      case MetricPlot::Style::kDashed:
        out += " using 1:" + c + " with lines dt 2" + colour + " notitle";
        break;
      case MetricPlot::Style::kErrorBars:
        out += " using 1:" + c + ":" + std::to_string(s.column + 1) + ":" + std::to_string(s.column + 2) +
               " with yerrorlines lw 2 pt 7" + colour + " title " + title;
        break;
    }
  }
  return out;
}

// Whether some row of the study has a value of the plot's main series.
bool HasValue(const PlotSeries& p, const std::vector<SummaryRow>& summary, const std::string& study) {
  const MetricSpec& metric = *p.series.front().metric;
  if (metric.summary.kind != SummaryKind::kMedian) return true;  // shares and sums are always there
  for (const SummaryRow& r : summary) {
    if (r.study == study && r.Spread(metric.name).median) return true;
  }
  return false;
}

}  // namespace

SweepPlots WriteSweepPlots(const SweepConfig& config, const std::vector<SummaryRow>& summary, const fs::path& out_dir) {
  SweepPlots result;
  const fs::path dir = out_dir / "plots";
  fs::create_directories(dir);
  const std::string gnuplot = FindProgram("gnuplot");
  if (gnuplot.empty()) {
    result.warnings.push_back("gnuplot is not installed (apt-get install gnuplot-nox): plots/ has the data and "
                              "gnuplot scripts but no images");
  }
  const std::vector<PlotSeries> plots = PlotsWithSeries();
  std::string labels;
  for (const PlotSeries& p : plots) {
    for (const Series& s : p.series) labels += " " + s.metric->plot->data_label;
  }
  for (const SweepStudy& study : config.studies) {
    const std::vector<std::string> varied = study.VariedParams();
    if (varied.empty()) continue;
    const std::string stem = PlotFileStem(study.name);
    // Points in the study's order; rows per method.
    std::map<int, nlohmann::ordered_json> points;
    for (const SummaryRow& r : summary) {
      if (r.study == study.name) points[r.point_index] = r.point_values;
    }
    const int num_methods = static_cast<int>(config.methods.size());
    std::string data;
    for (int m = 0; m < num_methods; ++m) {
      data += "# method " + config.methods[m].name + "\n# x" + labels + "\n";
      for (const SummaryRow& r : summary) {
        if (r.study != study.name || r.method != config.methods[m].name) continue;
        // Methods side by side around each point, so their bars do not hide each other.
        const double x = r.point_index + (m - (num_methods - 1) / 2.0) * 0.06;
        data += Num(x) + SeriesValues(plots, r) + "\n";
      }
      data += "\n\n";
    }
    WriteFile(dir / (stem + ".dat"), data);

    std::string xtics = "set xtics (";
    for (const auto& [i, values] : points) {
      xtics += (i ? ", " : "") + Quoted(AxisLabel(values)) + " " + std::to_string(i);
    }
    xtics += ")\n";
    std::string xlabel;
    for (const std::string& p : varied) xlabel += (xlabel.empty() ? "" : " / ") + p;
    const std::string common = "set datafile missing \"?\"\nset grid ytics\nset key outside right top\n" +
                               std::string("set xrange [-0.5:") + std::to_string(points.size() - 0.5) + "]\n" + xtics +
                               "set xlabel " + Quoted(xlabel) + "\n";
    std::string script = "# Drawn by rigsim sweep; run `gnuplot " + stem + ".gp` in this folder to redraw.\n";
    for (const auto& [ext, terminal] : std::vector<std::pair<std::string, std::string>>{
             {"png", "pngcairo size 960,540 font \"sans,11\""}, {"svg", "svg size 960,540 font \"sans,11\""}}) {
      script += "set terminal " + terminal + "\n";
      for (const PlotSeries& p : plots) {
        std::string command = "plot ";
        for (int m = 0; m < num_methods; ++m) {
          command += (m ? ", \\\n     " : "") + MethodPlot(p, Quoted(stem + ".dat") + " index " + std::to_string(m),
                                                          Quoted(config.methods[m].name), " lc " + std::to_string(m + 1));
        }
        // gnuplot refuses to scale an axis without a point: an empty plot says why instead.
        const std::string empty = HasValue(p, summary, study.name)
                                      ? ""
                                      : "set yrange [0.01:10]\nset label 1 \"no value: no method gave one in this "
                                        "study\" at graph 0.5, 0.5 center\n";
        script += "set output " + Quoted(stem + "_" + p.plot->name + "." + ext) + "\n" + common + "set title " +
                  Quoted(study.name + ": " + p.plot->title) + "\nset ylabel " + Quoted(p.plot->ylabel) + "\n" +
                  p.plot->y_axis + empty + command + "\nunset logscale y\nunset label 1\n";
      }
      script += "unset output\n";
    }
    WriteFile(dir / (stem + ".gp"), script);
    if (gnuplot.empty()) continue;
    const fs::path log = dir / (stem + ".log");
    fs::remove(log);
    const ProgramRun run = RunProgram({gnuplot, stem + ".gp"}, log, dir);
    if (run.exit_code != 0) {
      result.warnings.push_back("gnuplot failed on plots/" + stem + ".gp (see plots/" + stem + ".log)" +
                                (run.error.empty() ? "" : ": " + run.error));
      continue;
    }
    fs::remove(dir / (stem + ".log"));
    for (const PlotSeries& p : plots) result.images.push_back("plots/" + stem + "_" + p.plot->name + ".png");
  }
  return result;
}

}  // namespace rigsim
