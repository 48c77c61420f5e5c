#include "apps/rigsim/calibrate_support.h"

#include <chrono>
#include <cstdio>

#include "apps/rigsim/report_table.h"
#include "dataset/dataset.h"
#include "geometry/json_io.h"

namespace rigsim::cli {

CalibrationOptions CalibrateSettings::ToOptions() const {
  CalibrationOptions o;
  o.features.max_features = max_features;
  o.num_threads = threads;
  if (!reliable.empty()) o.reliable = ReliableClasses::FromNames(reliable);
  o.Check();
  return o;
}

std::vector<SemanticMode> CalibrateSettings::Modes() const {
  std::vector<SemanticMode> modes;
  for (const std::string& s : semantics) modes.push_back(SemanticModeFromName(s));
  if (modes.empty()) throw std::invalid_argument("--semantics: give at least one mode");
  return modes;
}

void AddCalibrateSettingsOptions(CLI::App& cmd, CalibrateSettings& s) {
  cmd.add_option("--semantics", s.semantics,
                 "semantic modes to compare on the same images: none (baseline), mask (features only on\n"
                 "reliable classes), gated (match only within a class), mask+gated")
      ->delimiter(',')
      ->capture_default_str();
  cmd.add_option("--reliable", s.reliable,
                 "Cityscapes class names to treat as reliable, comma-separated (default: static structure:\n"
                 "ground, road, sidewalk, parking, rail track, building, wall, fence, guard rail, bridge,\n"
                 "tunnel, pole, polegroup, traffic light, traffic sign)")
      ->delimiter(',');
  cmd.add_option("--max-features", s.max_features, "strongest SIFT keypoints kept per image")
      ->capture_default_str()
      ->check(CLI::PositiveNumber);
  cmd.add_option("--threads", s.threads, "worker threads, 0 = all cores")
      ->capture_default_str()
      ->check(CLI::NonNegativeNumber);
}

std::vector<CalibrationReport> CalibrateAndReport(const std::filesystem::path& dataset, const CalibrateSettings& settings,
                                                  const std::filesystem::path& evaluation_json) {
  const CalibrationOptions options = settings.ToOptions();
  const std::vector<SemanticMode> modes = settings.Modes();
  const auto start = std::chrono::steady_clock::now();
  std::fprintf(stderr, "calibrating %s (%zu semantic modes)...\n", dataset.string().c_str(), modes.size());
  const std::vector<CalibrationReport> reports = CalibrateDatasetPairs(dataset, options, modes);
  const double seconds = std::chrono::duration<double>(std::chrono::steady_clock::now() - start).count();
  json_io::WriteTextAtomic(evaluation_json, ReportToJson(reports).dump(2) + "\n");

  const OverlapTable overlap = ReadOverlap(DatasetLayout(dataset).OverlapJson());
  std::printf("\nRelative pose of every camera pair (matches of %d frame(s) pooled), against the rendered truth:\n\n",
              reports.empty() ? 0 : reports[0].num_frames);
  std::printf("%s\n", FormatPairTable(reports, overlap).c_str());
  std::printf("%s", FormatSummary(reports, overlap).c_str());
  std::printf("calibration took %.1f s; per-pair results in %s\n", seconds, evaluation_json.string().c_str());
  return reports;
}

}  // namespace rigsim::cli
