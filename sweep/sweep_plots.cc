#include "sweep/sweep_plots.h"

#include <cctype>
#include <cstdio>
#include <fstream>
#include <map>
#include <stdexcept>

#include "common/run_program.h"

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
      data += "# method " + config.methods[m].name + "\n# x success_2deg success_1deg median_rot min_rot max_rot\n";
      for (const SummaryRow& r : summary) {
        if (r.study != study.name || r.method != config.methods[m].name) continue;
        // Methods side by side around each point, so their bars do not hide each other.
        const double x = r.point_index + (m - (num_methods - 1) / 2.0) * 0.06;
        data += Num(x) + " " + Num(r.success_2deg) + " " + Num(r.success_1deg) + " " +
                Num(r.median_rotation_error_deg.median) + " " + Num(r.median_rotation_error_deg.min) + " " +
                Num(r.median_rotation_error_deg.max) + "\n";
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
    std::string success_plot = "plot ", error_plot = "plot ";
    for (int m = 0; m < num_methods; ++m) {
      const std::string src = Quoted(stem + ".dat") + " index " + std::to_string(m);
      const std::string title = Quoted(config.methods[m].name);
      const std::string colour = " lc " + std::to_string(m + 1);
      success_plot += (m ? ", \\\n     " : "") + src + " using 1:2 with linespoints lw 2 pt 7" + colour + " title " +
                      title + ", \\\n     " + src + " using 1:3 with lines dt 2" + colour + " notitle";
      error_plot += (m ? ", \\\n     " : "") + src + " using 1:4:5:6 with yerrorlines lw 2 pt 7" + colour +
                    " title " + title;
    }
    const std::string success_setup = common + "set title " + Quoted(study.name + ": calibration success") +
                                      "\nset ylabel \"share of seeds: every camera within 2 deg (dashed: 1 deg)\"\n"
                                      "set yrange [-0.05:1.05]\n";
    const std::string error_setup = common + "set title " + Quoted(study.name + ": rotation error") +
                                    "\nset ylabel \"median rotation error of the cameras (deg)\"\nset logscale y\n"
                                    "set yrange [*:*]\n";
    std::string script = "# Drawn by rigsim sweep; run `gnuplot " + stem + ".gp` in this folder to redraw.\n";
    for (const auto& [ext, terminal] : std::vector<std::pair<std::string, std::string>>{
             {"png", "pngcairo size 960,540 font \"sans,11\""}, {"svg", "svg size 960,540 font \"sans,11\""}}) {
      script += "set terminal " + terminal + "\nset output " + Quoted(stem + "_success." + ext) + "\n" + success_setup +
                success_plot + "\nunset logscale y\nset output " + Quoted(stem + "_rotation_error." + ext) + "\n" +
                error_setup + error_plot + "\nunset logscale y\nunset output\n";
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
    result.images.push_back("plots/" + stem + "_success.png");
    result.images.push_back("plots/" + stem + "_rotation_error.png");
  }
  return result;
}

}  // namespace rigsim
