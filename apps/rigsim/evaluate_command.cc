// rigsim evaluate DATASET ESTIMATE: scores a rig estimate of any tool against the dataset's truth.
#include <algorithm>
#include <cstdio>
#include <filesystem>
#include <string>

#include "apps/rigsim/commands.h"
#include "common/param_spec.h"
#include "dataset/dataset.h"
#include "dataset/output_file.h"
#include "evaluation/rig_estimate.h"
#include "evaluation/rig_scores.h"
#include "geometry/json_io.h"
#include "geometry/rig.h"
#include "pipeline/calibration_run.h"

namespace rigsim::cli {

namespace {

namespace fs = std::filesystem;

// One line of what a calibration reported about its matches and its time, when it did.
std::string DetailsLine(const RigEstimate& e) {
  if (e.details.is_null()) return "";
  const auto& pairwise = e.details.value("pairwise", nlohmann::json::object());
  const auto& timing = e.details.value("timing", nlohmann::json::object());
  const auto& rig_timing = e.details.value("rig_timing", nlohmann::json::object());
  const auto seconds = [](const nlohmann::json& j, const char* key) { return j.value(key, 0.0); };
  char line[512];
  std::string precision = "-";
  if (pairwise.contains("match_precision") && pairwise["match_precision"].is_number()) {
    precision = std::to_string(static_cast<int>(100.0 * pairwise["match_precision"].get<double>() + 0.5)) + "%";
  }
  double rig = 0.0;
  for (const auto& [key, value] : rig_timing.items()) {
    if (key.ends_with("_time_s") && value.is_number() && key.find("detect") == std::string::npos && key.find("match") == std::string::npos &&
        key.find("pose") == std::string::npos && key.find("screen") == std::string::npos) {
      rig += value.get<double>();
    }
  }
  std::snprintf(line, sizeof line,
                "%s: %lld matches, %s correct by the ground truth; time detect %.2f s, screen %.2f s, match %.2f s, "
                "pose %.2f s (summed over threads), rig stages %.2f s\n",
                e.method.c_str(), pairwise.value("matches", 0LL), precision.c_str(), seconds(timing, "detect_time_s"),
                seconds(timing, "screen_time_s"), seconds(timing, "match_time_s") + seconds(timing, "temporal_match_time_s"),
                seconds(timing, "pose_time_s") + seconds(timing, "temporal_pose_time_s"), rig);
  return line;
}

// A calibration folder's semantic modes in the order calibrate runs and prints them (none, mask,
// gated, mask+gated); its evaluation.json lists them by name. Other estimates keep their place.
void InCalibrateOrder(std::vector<RigEstimate>* estimates) {
  const std::vector<std::string> modes = NamesOf(kAllSemanticModes, SemanticModeName);
  const auto rank = [&](const RigEstimate& e) { return std::find(modes.begin(), modes.end(), e.method) - modes.begin(); };
  std::stable_sort(estimates->begin(), estimates->end(),
                   [&](const RigEstimate& a, const RigEstimate& b) { return rank(a) < rank(b); });
}

}  // namespace

void AddEvaluateCommand(CLI::App& app) {
  struct Args {
    std::string dataset, estimate, json, scale = "auto";
    bool force = false;
  };
  auto args = std::make_shared<Args>();
  CLI::App* cmd = app.add_subcommand(
      "evaluate",
      "Score a rig estimate against the truth DATASET was rendered with, the same way whichever tool made\n"
      "it. ESTIMATE is one of:\n"
      "  a rig.json (rigsim's format: cameras with cam_from_rig)\n"
      "  a calibration folder written by `rigsim calibrate` (every semantic mode in it)\n"
      "  a COLMAP text model of the dataset's photos (a folder with images.txt, or the mapper's sparse/\n"
      "    folder: its largest sub-model), images named <cam>/<frame>.png as under DATASET/images\n"
      "  a Kalibr camchain.yaml (cameras by rostopic /<name>/image_raw, else in order)\n"
      "Per camera and camera pair: rotation error, translation-direction error, position error after\n"
      "fitting the scale (none when the estimate is metric), pose error = max(rotation, direction);\n"
      "the AUC of the pose errors at 1, 2, 5 and 10 deg. Gauge: the first camera is the rig frame.\n"
      "Exit code 0 when scored (whatever the errors), 1 on bad input.");
  cmd->add_option("DATASET", args->dataset, "rendered dataset (its rig.json holds the true poses)")
      ->required()
      ->check(CLI::ExistingDirectory);
  cmd->add_option("ESTIMATE", args->estimate, "rig.json, calibration folder, COLMAP model or Kalibr camchain.yaml")
      ->required()
      ->check(CLI::ExistingPath);
  cmd->add_option("--json", args->json, "also write the scores as JSON to this file (- for standard output; see --force)");
  cmd->add_flag("--force", args->force, "replace an existing --json file");
  cmd->add_option("--scale", args->scale,
                  "auto (a calibration folder says whether it is metric; COLMAP and a bare rig.json are not,\n"
                  "Kalibr is), metric (translations in metres: no scale fitted) or fit")
      ->capture_default_str()
      ->check(CLI::IsMember({"auto", "metric", "fit"}));
  cmd->callback([args] {
    const DatasetLayout layout(args->dataset);
    if (!args->json.empty() && args->json != "-") {
      CheckReplaceableFile({args->json, "--json", OutputFileKind::kJson,
                            {{layout.RigJson(), "the dataset's rig.json"},
                             {layout.FramesJson(), "the dataset's frames.json"},
                             {args->estimate, "ESTIMATE"}},
                            args->force});
    }
    const Rig truth = ReadRig(layout.RigJson());
    if (!truth.HasAllPoses()) {
      throw std::runtime_error(layout.RigJson().string() +
                               ": has no true pose (cam_from_rig) for some cameras; evaluate needs a rendered "
                               "dataset, whose rig.json holds every camera's");
    }
    const FramesFile frames = layout.ReadFramesOrScan(truth.cameras.at(0).name);
    const EstimateScale scale = args->scale == "metric" ? EstimateScale::kMetric
                                : args->scale == "fit"  ? EstimateScale::kFit
                                                        : EstimateScale::kAuto;
    std::vector<RigEstimate> estimates = ReadRigEstimates(args->estimate, truth, frames, scale);
    InCalibrateOrder(&estimates);
    std::vector<RigScores> scores;
    nlohmann::json methods = nlohmann::json::object();
    for (const RigEstimate& e : estimates) {
      scores.push_back(ScoreRig(truth, e));
      nlohmann::json j = RigScoresToJson(scores.back());
      if (!e.details.is_null()) j["reported"] = e.details;
      methods[e.method] = std::move(j);
    }
    std::printf("%s against the truth of %s (gauge: %s is the rig frame):\n\n", args->estimate.c_str(),
                args->dataset.c_str(), truth.cameras[0].name.c_str());
    std::printf("%s", FormatRigScores(scores).c_str());
    for (const RigEstimate& e : estimates) std::printf("%s", DetailsLine(e).c_str());
    const nlohmann::json out = {{"dataset", fs::absolute(args->dataset).lexically_normal().string()},
                                {"estimate", fs::absolute(args->estimate).lexically_normal().string()},
                                {"methods", methods}};
    if (args->json == "-") {
      std::printf("%s\n", out.dump(2).c_str());
    } else if (!args->json.empty()) {
      json_io::WriteTextAtomic(args->json, out.dump(2) + "\n");
      std::printf("scores written to %s\n", args->json.c_str());
    }
  });
}

}  // namespace rigsim::cli
