// Plots of a sweep's summary, drawn by gnuplot (Debian's gnuplot-nox): per study, against the
// values it sweeps, one line per method,
//   plots/<study>_success.{png,svg}         share of seeds with every camera within 2 deg (and 1 deg dashed)
//   plots/<study>_rotation_error.{png,svg}  median rotation error of the cameras (log scale), the
//                                           bars spanning its range over seeds
// beside the data and script that drew them (<study>.dat, <study>.gp), so a user can restyle a plot.
#pragma once

#include <filesystem>
#include <string>
#include <vector>

#include "sweep/sweep_config.h"
#include "sweep/sweep_summary.h"

namespace rigsim {

struct SweepPlots {
  std::vector<std::string> images;    // written, relative to the output folder (PNG; an SVG beside each)
  std::vector<std::string> warnings;  // e.g. gnuplot missing: the data and scripts are still written
};

// The file stem of a study's plots: its name with anything but letters, digits, '-' and '_' as '_'.
std::string PlotFileStem(const std::string& study);

// Writes OUT/plots/. Studies that sweep nothing get no plot.
SweepPlots WriteSweepPlots(const SweepConfig& config, const std::vector<SummaryRow>& summary,
                           const std::filesystem::path& out_dir);

}  // namespace rigsim
