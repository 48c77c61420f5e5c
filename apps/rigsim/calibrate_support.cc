#include "apps/rigsim/calibrate_support.h"

#include <chrono>
#include <cstdio>

#include "apps/rigsim/report_table.h"
#include "dataset/dataset.h"
#include "geometry/camera_validation.h"
#include "geometry/json_io.h"

namespace rigsim::cli {

RigCalibrationOptions CalibrateSettings::ToOptions() const {
  RigCalibrationOptions o = options;
  if (!reliable.empty()) o.pairwise.reliable = ReliableClasses::FromNames(reliable);
  if (!known_distance.empty()) {
    if (known_distance.size() != 3) throw std::invalid_argument("--known-distance takes CAM_A CAM_B METRES");
    double metres = 0.0;
    try {
      metres = std::stod(known_distance[2]);
    } catch (const std::exception&) {
      throw std::invalid_argument("--known-distance: '" + known_distance[2] + "' is not a number of metres");
    }
    o.known_distance = KnownDistance{known_distance[0], known_distance[1], metres};
  }
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
  cmd.add_option("--known-distance", s.known_distance,
                 "CAM_A CAM_B METRES: distance between two camera centres, the only source of metric\n"
                 "scale; without it the result has unit scale")
      ->expected(3);
  FeatureOptions& features = s.options.pairwise.features;
  cmd.add_option("--max-features", features.max_features, "strongest SIFT keypoints kept per image")
      ->capture_default_str()
      ->check(CLI::PositiveNumber);
  cmd.add_option("--sift-contrast", features.contrast_threshold,
                 "SIFT contrast threshold; lower finds more, weaker keypoints")
      ->capture_default_str()
      ->check(CLI::PositiveNumber);
  cmd.add_option("--ratio", s.options.pairwise.matching.ratio,
                 "Lowe's ratio test: keep a match when best < ratio x second best")
      ->capture_default_str()
      ->check(CLI::Range(0.1, 1.0));
  cmd.add_option("--max-error-px", s.options.pairwise.two_view.max_error_px,
                 "inlier threshold of the robust relative-pose fit (px)")
      ->capture_default_str()
      ->check(CLI::PositiveNumber);
  if (cmd.get_option_no_throw("--threads") == nullptr) {
    cmd.add_option("--threads", s.options.pairwise.num_threads, "worker threads, 0 = all cores")
        ->capture_default_str()
        ->check(CLI::NonNegativeNumber);
  }
}

void CheckCalibrationInputs(const std::filesystem::path& dataset) {
  const DatasetLayout layout(dataset);
  const Rig rig = ReadRig(layout.RigJson());
  for (const std::string& w : CheckRigCoversImages(rig, layout.RigJson().string())) {
    std::fprintf(stderr, "warning: %s\n", w.c_str());
  }
}

namespace {

// evaluation.json: the pairwise report of each method (ReportToJson) with the rig result of the
// same method under "rig".
json_io::Json EvaluationJson(const std::vector<RigCalibrationResult>& results) {
  std::vector<CalibrationReport> pairwise;
  for (const RigCalibrationResult& r : results) pairwise.push_back(r.pairwise);
  json_io::Json evaluation = ReportToJson(pairwise);
  const json_io::Json rig = RigCalibrationToJson(results);
  for (const RigCalibrationResult& r : results) {
    json_io::Json entry = rig["methods"][r.semantic_mode];
    entry.erase("pairwise");  // already the method's own entry
    evaluation["methods"][r.semantic_mode]["rig"] = entry;
  }
  return evaluation;
}

}  // namespace

std::vector<RigCalibrationResult> CalibrateAndReport(const std::filesystem::path& dataset, const CalibrateSettings& settings,
                                                     const std::filesystem::path& out_dir, bool force) {
  const RigCalibrationOptions options = settings.ToOptions();
  const std::vector<SemanticMode> modes = settings.Modes();
  // Everything that can be checked cheaply is checked before the long run, so that bad input
  // fails fast and leaves nothing behind.
  const OverlapTable overlap = ReadOverlap(DatasetLayout(dataset).OverlapJson());
  CheckCalibrationInputs(dataset);
  StagedOutput staged(out_dir, force);

  const auto start = std::chrono::steady_clock::now();
  std::fprintf(stderr, "calibrating %s (%zu semantic modes)...\n", dataset.string().c_str(), modes.size());
  const std::vector<RigCalibrationResult> results = CalibrateRig(dataset, options, modes);
  const double seconds = std::chrono::duration<double>(std::chrono::steady_clock::now() - start).count();

  json_io::WriteTextAtomic(staged.staging_dir() / "evaluation.json", EvaluationJson(results).dump(2) + "\n");
  for (const RigCalibrationResult& r : results) {
    const std::filesystem::path dir = staged.staging_dir() / r.semantic_mode;
    std::filesystem::create_directories(dir);
    WriteRig(r.rig, dir / "rig.json");
  }
  staged.Commit();

  std::vector<CalibrationReport> pairwise;
  for (const RigCalibrationResult& r : results) pairwise.push_back(r.pairwise);
  std::printf("\nRelative pose of every camera pair (matches of %d frame(s) pooled):\n\n",
              pairwise.empty() ? 0 : pairwise[0].num_frames);
  std::printf("%s\n", FormatPairTable(pairwise, overlap).c_str());
  std::printf("%s\n", FormatSummary(pairwise, overlap).c_str());
  std::printf("Rig: every camera's pose (gauge: %s is the rig frame; errors after aligning it):\n\n",
              results.empty() || results[0].rig.cameras.empty() ? "camera 0" : results[0].rig.cameras[0].name.c_str());
  std::printf("%s\n", FormatRigTable(results).c_str());
  std::printf("%s", FormatRigSummary(results).c_str());
  std::printf("calibration took %.1f s; results in %s\n", seconds, out_dir.string().c_str());
  return results;
}

}  // namespace rigsim::cli
