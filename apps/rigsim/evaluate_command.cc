// rigsim evaluate DATASET ESTIMATE, or ESTIMATE --truth RIG: scores a rig estimate of any tool
// against a rendered dataset's truth or a rig file's (a surveyed rig's, for real photos).
#include <algorithm>
#include <cstdio>
#include <filesystem>
#include <stdexcept>
#include <string>

#include "apps/rigsim/commands.h"
#include "apps/rigsim/parse_errors.h"
#include "common/param_spec.h"
#include "dataset/dataset.h"
#include "dataset/output_file.h"
#include "evaluation/rig_estimate.h"
#include "evaluation/rig_scores.h"
#include "geometry/json_io.h"
#include "geometry/rig.h"
#include "pipeline/calibration_run.h"
#include "rigs/rig_import.h"

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

// The truth of `rigsim evaluate ESTIMATE --truth RIG`: RIG's cameras that ESTIMATE names, in
// ESTIMATE's order (so that its reference camera is the gauge; RIG's order for a COLMAP model,
// which has none); what only one side has is named in `not_scored`. Throws naming both sets when no camera matches, or a matched camera without a
// pose in RIG.
Rig TruthFromRigFile(const fs::path& rig_file, const fs::path& estimate, nlohmann::json* not_scored) {
  const Rig imported = ImportRig(rig_file);
  const std::string what = rig_file.string() + " (" + std::string(RigFileFormatName(DetectRigFileFormat(rig_file))) + ")";
  const EstimateCameras cameras = ReadEstimateCameras(estimate);
  const auto list = [](const std::vector<std::string>& names) {
    std::string out;
    for (const std::string& n : names) out += (out.empty() ? "" : ", ") + n;
    return out.empty() ? std::string("none") : out;
  };
  std::vector<std::string> truth_names;
  for (const RigCamera& c : imported.cameras) truth_names.push_back(c.name);
  Rig truth = imported;
  std::vector<std::string> only_truth, only_estimate;
  if (cameras.named) {
    truth.cameras.clear();
    for (const std::string& name : cameras.names) {
      const int c = imported.FindCamera(name);
      if (c < 0) {
        only_estimate.push_back(name);
      } else if (cameras.ordered) {
        truth.cameras.push_back(imported.cameras[c]);
      }
    }
    for (const std::string& name : truth_names) {
      const bool in_estimate = std::find(cameras.names.begin(), cameras.names.end(), name) != cameras.names.end();
      if (!in_estimate) only_truth.push_back(name);
      if (in_estimate && !cameras.ordered) truth.cameras.push_back(imported.cameras[imported.FindCamera(name)]);
    }
    if (truth.cameras.empty()) {
      throw std::runtime_error("--truth " + what + ": no camera of it is in " + estimate.string() +
                               ": the truth has " + list(truth_names) + "; the estimate has " + list(cameras.names) +
                               " (cameras are matched by name)");
    }
  }
  std::vector<std::string> unposed;
  for (const RigCamera& c : truth.cameras) {
    if (!c.cam_from_rig) unposed.push_back(c.name);
  }
  if (!unposed.empty()) {
    throw std::runtime_error("--truth " + what + ": has no pose (cam_from_rig) for " + list(unposed) +
                             "; the truth needs every scored camera's");
  }
  *not_scored = {{"only_in_truth", only_truth}, {"only_in_estimate", only_estimate}};
  return truth;
}

// --truth-sd ROT_DEG,POS_M; "" is an exact truth.
TruthAccuracy ParseTruthSd(const std::string& text) {
  if (text.empty()) return {};
  const std::optional<std::array<double, 2>> values = NumberPair(text);
  if (!values || (*values)[0] < 0.0 || (*values)[1] < 0.0) {
    throw std::runtime_error("--truth-sd " + text + ": needs two numbers, ROT_DEG,POS_M, each 0 or more (e.g. "
                             "0.02,0.003: the truth has each camera's orientation to 0.02 deg and its position to 3 mm)");
  }
  return {(*values)[0], (*values)[1]};
}

}  // namespace

void AddEvaluateCommand(CLI::App& app) {
  struct Args {
    std::string first, second, truth, json, scale = "auto", truth_sd;
    bool force = false;
  };
  auto args = std::make_shared<Args>();
  CLI::App* cmd = app.add_subcommand(
      "evaluate",
      "Score a rig estimate against the truth, the same way whichever tool made it. Two forms:\n"
      "  rigsim evaluate DATASET ESTIMATE     the truth DATASET was rendered with (DATASET/rig.json)\n"
      "  rigsim evaluate ESTIMATE --truth RIG a surveyed rig's truth, e.g. to score a calibration of real\n"
      "                                       photos: RIG is any file make-rig --type file --rig-file reads\n"
      "                                       (rig.json, Kalibr camchain, COLMAP rigs, DGP/DDAD calibration\n"
      "                                       JSON, nuScenes calibrated_sensor); cameras are matched by name,\n"
      "                                       and those on one side only are listed as not scored\n"
      "ESTIMATE is one of:\n"
      "  a rig.json (rigsim's format: cameras with cam_from_rig)\n"
      "  a calibration folder written by `rigsim calibrate` (every semantic mode in it)\n"
      "  a COLMAP text model of the dataset's photos (a folder with images.txt, or the mapper's sparse/\n"
      "    folder: its largest sub-model), images named <cam>/<frame>.png as under DATASET/images\n"
      "  a Kalibr camchain.yaml (cameras by rostopic /<name>/image_raw, else in order)\n"
      "Per camera and camera pair: rotation error, translation-direction error, position error after\n"
      "fitting the scale (none when the estimate is metric), pose error = max(rotation, direction);\n"
      "the AUC of the pose errors at 1, 2, 5 and 10 deg. Gauge: the first camera is the rig frame\n"
      "(with --truth: the estimate's first camera that the truth has; a COLMAP model's: the truth's\n"
      "first it has). When the estimate states\n"
      "standard deviations (a calibration folder), each error over its deviation (rot/sd, dir/sd) and\n"
      "the cameras overconfident: an error beyond 3 sd and 0.05 deg (the sd counting the truth's own\n"
      "with --truth-sd).\n"
      "Exit code 0 when scored (whatever the errors), 1 on bad input.");
  cmd->add_option("DATASET", args->first, "rendered dataset (its rig.json holds the true poses); with --truth: ESTIMATE");
  cmd->add_option("ESTIMATE", args->second, "rig.json, calibration folder, COLMAP model or Kalibr camchain.yaml");
  cmd->add_option("--truth", args->truth,
                  "the true rig, instead of a rendered DATASET: any file make-rig --type file --rig-file reads")
      ->check(CLI::ExistingPath);
  cmd->add_option("--truth-sd", args->truth_sd,
                  "ROT_DEG,POS_M: how well the truth itself is known, one standard deviation: each camera's\n"
                  "orientation (deg) and its position along each axis (m), e.g. a survey's 0.02,0.003. An error\n"
                  "is then judged against the estimate's stated deviation and the truth's together (a relative\n"
                  "rotation sqrt(2) ROT_DEG, a direction sqrt(2) POS_M over the cameras' distance): a truth\n"
                  "coarser than the estimate cannot call it overconfident. Default 0: exact, as a render's");
  cmd->add_option("--json", args->json, "also write the scores as JSON to this file (- for standard output; see --force)");
  cmd->add_flag("--force", args->force, "replace an existing --json file");
  cmd->add_option("--scale", args->scale,
                  "auto (a calibration folder says whether it is metric; COLMAP and a bare rig.json are not,\n"
                  "Kalibr is), metric (translations in metres: no scale fitted) or fit")
      ->capture_default_str()
      ->check(CLI::IsMember({"auto", "metric", "fit"}));
  cmd->callback([args] {
    const TruthAccuracy truth_accuracy = ParseTruthSd(args->truth_sd);
    const bool with_truth = !args->truth.empty();
    if (with_truth && !args->second.empty()) {
      throw std::runtime_error("evaluate: --truth replaces DATASET: give ESTIMATE only (rigsim evaluate ESTIMATE --truth "
                               "RIG), or DATASET ESTIMATE without --truth");
    }
    if (args->first.empty() || (!with_truth && args->second.empty())) {
      throw std::runtime_error(with_truth ? "evaluate: ESTIMATE is required (rigsim evaluate ESTIMATE --truth RIG)"
                                          : "evaluate: needs DATASET ESTIMATE, or ESTIMATE --truth RIG");
    }
    const std::string dataset = with_truth ? "" : args->first;
    const std::string estimate = with_truth ? args->first : args->second;
    if (!fs::exists(estimate)) throw std::runtime_error("ESTIMATE " + estimate + ": no such file or folder");
    if (!with_truth && !fs::is_directory(dataset)) {
      throw std::runtime_error("DATASET " + dataset + ": not a folder (a rendered dataset; to score against a rig "
                               "file, give ESTIMATE --truth RIG)");
    }
    const DatasetLayout layout(dataset);
    const fs::path truth_file = with_truth ? fs::path(args->truth) : layout.RigJson();
    if (!args->json.empty() && args->json != "-") {
      std::vector<CommandInput> inputs = {{truth_file, with_truth ? "--truth" : "the dataset's rig.json"},
                                            {estimate, "ESTIMATE"}};
      if (!with_truth) inputs.push_back({layout.FramesJson(), "the dataset's frames.json"});
      CheckReplaceableFile({args->json, "--json", OutputFileKind::kJson, inputs, args->force});
    }
    nlohmann::json not_scored;
    Rig truth;
    FramesFile frames;
    if (with_truth) {
      truth = TruthFromRigFile(truth_file, estimate, &not_scored);
      frames = ReadEstimateCameras(estimate).colmap_frames;
    } else {
      truth = ReadRig(layout.RigJson());
      if (!truth.HasAllPoses()) {
        throw std::runtime_error(layout.RigJson().string() +
                                 ": has no true pose (cam_from_rig) for some cameras; evaluate needs a rendered "
                                 "dataset, whose rig.json holds every camera's (or a rig file with --truth)");
      }
      frames = layout.ReadFramesOrScan(truth.cameras.at(0).name);
    }
    const EstimateScale scale = args->scale == "metric" ? EstimateScale::kMetric
                                : args->scale == "fit"  ? EstimateScale::kFit
                                                        : EstimateScale::kAuto;
    std::vector<RigEstimate> estimates = with_truth ? ReadRigEstimates(estimate, truth, frames, scale, true)
                                                    : ReadRigEstimates(estimate, truth, frames, scale);
    InCalibrateOrder(&estimates);
    std::vector<RigScores> scores;
    nlohmann::json methods = nlohmann::json::object();
    for (RigEstimate& e : estimates) {
      for (const char* side : {"only_in_truth", "only_in_estimate"}) {
        if (!with_truth || not_scored[side].empty()) continue;
        std::string names;
        for (const auto& n : not_scored[side]) names += (names.empty() ? "" : ", ") + n.get<std::string>();
        e.notes.push_back(std::string("not scored, only in the ") + (side[8] == 't' ? "truth" : "estimate") + ": " + names);
      }
      scores.push_back(ScoreRig(truth, e, truth_accuracy));
      nlohmann::json j = RigScoresToJson(scores.back());
      if (!e.details.is_null()) j["reported"] = e.details;
      methods[e.method] = std::move(j);
    }
    std::printf("%s against the truth %s %s (gauge: %s is the rig frame):\n\n", estimate.c_str(),
                with_truth ? "in" : "of", with_truth ? args->truth.c_str() : dataset.c_str(),
                truth.cameras[0].name.c_str());
    std::printf("%s", FormatRigScores(scores).c_str());
    for (const RigEstimate& e : estimates) std::printf("%s", DetailsLine(e).c_str());
    nlohmann::json out;
    if (with_truth) {
      out = {{"truth", fs::absolute(args->truth).lexically_normal().string()},
             {"estimate", fs::absolute(estimate).lexically_normal().string()},
             {"not_scored", not_scored},
             {"methods", methods}};
    } else {
      out = {{"dataset", fs::absolute(dataset).lexically_normal().string()},
             {"estimate", fs::absolute(estimate).lexically_normal().string()},
             {"methods", methods}};
    }
    if (args->json == "-") {
      std::printf("%s\n", out.dump(2).c_str());
    } else if (!args->json.empty()) {
      json_io::WriteTextAtomic(args->json, out.dump(2) + "\n");
      std::printf("scores written to %s\n", args->json.c_str());
    }
  });
}

}  // namespace rigsim::cli
