#include <cmath>
#include <cstdio>
#include <fstream>

#include <nlohmann/json.hpp>

#include "apps/rigsim/calibrate_support.h"
#include "apps/rigsim/commands.h"
#include "apps/rigsim/report_support.h"
#include "apps/rigsim/version.h"
#include "common/format.h"
#include "common/param_spec.h"
#include "dataset/dataset.h"
#include "pipeline/calibration_plan.h"
#include "pipeline/calibration_run.h"

namespace rigsim::cli {
namespace fs = std::filesystem;
using Json = nlohmann::json;

namespace {

// The semantic modes, label source and features a calibration folder was made with (its
// evaluation.json), in the order calibrate lists the modes; `features` is kept when the folder
// does not say (written before it did) or when `features_given`.
void TakeModesAndLabelsFrom(const fs::path& calibration, CalibrateSettings* settings, std::string* features,
                            bool features_given) {
  const fs::path path = calibration / "evaluation.json";
  std::ifstream in(path);
  if (!in) throw std::runtime_error(path.string() + ": cannot read (is " + calibration.string() + " a calibration folder?)");
  Json j;
  try {
    j = Json::parse(in);
  } catch (const Json::exception& e) {
    throw std::runtime_error(path.string() + ": not JSON: " + e.what());
  }
  if (!j.contains("methods") || !j["methods"].is_object() || j["methods"].empty()) {
    throw std::runtime_error(path.string() + ": no \"methods\": not written by rigsim calibrate");
  }
  settings->semantics.clear();
  for (const std::string& mode : NamesOf(kAllSemanticModes, SemanticModeName)) {
    if (j["methods"].contains(mode)) settings->semantics.push_back(mode);
  }
  if (settings->semantics.empty()) throw std::runtime_error(path.string() + ": no semantic mode rigsim knows");
  if (!features_given && j.contains("features") && j["features"].is_string()) *features = j["features"].get<std::string>();
  const Json& labels = j.value("label_source", Json::object());
  const std::string kind = labels.value("kind", "truth");
  if (kind == "folder") {
    settings->labels.labels = labels.value("folder", "");
  } else if (kind == "noisy") {
    settings->labels.labels = "noisy";
    const Json& noise = labels.value("noise", Json::object());
    settings->labels.noise.boundary_px = noise.value("boundary_px", settings->labels.noise.boundary_px);
    settings->labels.noise.confusion_rate = noise.value("confusion_rate", settings->labels.noise.confusion_rate);
    settings->labels.noise.blob_size_px = noise.value("blob_size_px", settings->labels.noise.blob_size_px);
    settings->labels.noise.seed = noise.value("seed", settings->labels.noise.seed);
  } else {
    settings->labels.labels = "truth";
  }
}

// Whether this run's estimate of each mode is the one saved in `calibration`; what differs.
std::vector<std::string> CompareWithSaved(const CalibrationRun& run, const fs::path& calibration) {
  std::vector<std::string> differences;
  for (const RigCalibrationResult& r : run.results) {
    const fs::path saved_path = calibration / r.semantic_mode / "rig.json";
    if (!fs::exists(saved_path)) {
      differences.push_back(saved_path.string() + " is missing");
      continue;
    }
    const Rig saved = ReadRig(saved_path);
    for (const RigCamera& rc : r.rig.cameras) {
      const int c = saved.FindCamera(rc.name);
      const auto& a = rc.cam_from_rig;
      const auto& b = c >= 0 ? saved.cameras[c].cam_from_rig : std::nullopt;
      const bool same = a.has_value() == b.has_value() &&
                        (!a || (a->rotation.angularDistance(b->rotation) < 1e-6 &&
                                (a->translation - b->translation).norm() < 1e-6 * std::max(1.0, a->translation.norm())));
      if (!same) differences.push_back(r.semantic_mode + ": " + rc.name);
    }
  }
  return differences;
}

}  // namespace

void AddReportCommand(CLI::App& app) {
  struct Args {
    std::string dataset, out, calibration, sweep, scene, features = "sift";
    bool force = false;
    ReportOptions report;
    CalibrateSettings settings;
  };
  auto args = std::make_shared<Args>();
  CLI::App* cmd = app.add_subcommand(
      "report",
      "Write a teaching report of DATASET's calibration: a folder whose index.html opens from disk in\n"
      "any current browser, offline: the scene and the rig in 3D (true and estimated frustums, fields\n"
      "of view, trajectory, triangulated points), every camera's views (labels, instances, depth,\n"
      "keypoints kept by the mask), every pair (matches right and wrong by the ground truth, a\n"
      "clicked point's epipolar curve under the estimate and the truth), the pipeline step by step\n"
      "and the numbers. Calibrates DATASET with the options below (as calibrate does), keeping every\n"
      "stage's details; --calibration DIR takes the semantic modes and labels of a calibration folder\n"
      "and checks that this run gives the same rig.");
  cmd->add_option("DATASET", args->dataset, "dataset folder (rig.json, images/, labels/, depth/ as render writes them)")
      ->required()
      ->check(CLI::ExistingDirectory);
  cmd->add_option("--out", args->out, "report folder to write (index.html and its files)")->required();
  cmd->add_flag("--force", args->force, "replace an existing report folder that rigsim wrote");
  cmd->add_option("--calibration", args->calibration,
                  "a calibration folder (rigsim calibrate's --out): report its semantic modes and label source")
      ->check(CLI::ExistingDirectory);
  cmd->add_option("--sweep", args->sweep, "a sweep's output folder: its plots, summary and report.md under Numbers")
      ->check(CLI::ExistingDirectory);
  cmd->add_option("--scene", args->scene,
                  "the scene (.glb) for the 3D view (default: frames.json's scene, or the shipped one of that name)")
      ->check(CLI::ExistingFile);
  cmd->add_option("--max-image-width", args->report.max_image_width, "images are scaled down to this width")
      ->capture_default_str()
      ->check(CLI::Range(64, 8192));
  cmd->add_option("--features", args->features, "keypoints and descriptors: sift, rootsift, orb or akaze (as calibrate)")
      ->capture_default_str()
      ->check(CLI::IsMember(NamesOf(kAllFeatureTypes, FeatureTypeName)));
  AddCalibrateSettingsOptions(*cmd, args->settings);
  AddLabelSourceOptions(*cmd, args->settings.labels);
  cmd->callback([args, cmd] {
    ReportPageFiles(args->report);  // the page's files are there before calibrating
    const fs::path dataset = args->dataset;
    if (!args->calibration.empty()) {
      TakeModesAndLabelsFrom(args->calibration, &args->settings, &args->features, cmd->count("--features") > 0);
    }
    // Planned as calibrate plans it: the default modes that need labels dropped, with a warning,
    // from a dataset without them; the inputs read and checked against the options.
    CalibrationRequest request;
    request.dataset = dataset;
    request.options = args->settings.ToOptions();
    request.options.features.type = FeatureTypeFromName(args->features);
    request.options.rig.keep_details = true;
    request.modes = args->settings.Modes();
    request.modes_given = !args->calibration.empty() || cmd->count("--semantics") > 0;
    // The report must not replace what it shows: the dataset, the calibration, the sweep, the scene.
    request.out = CalibrationOutputFolder(dataset, args->settings, args->out, args->force);
    OutputFolderRequest& out = request.out;
    out.option = "--out";
    out.written_by = "rigsim report";
    if (!args->calibration.empty()) out.inputs.push_back({args->calibration, "--calibration"});
    if (!args->sweep.empty()) out.inputs.push_back({args->sweep, "--sweep"});
    if (!args->scene.empty()) out.inputs.push_back({args->scene, "--scene"});
    CalibrationPlan plan = PlanCalibration(request, Warn);
    const CalibrationInputs& inputs = plan.inputs;
    args->report.scene = args->scene.empty() ? FindSceneOf(dataset, inputs.frames) : fs::path(args->scene);
    if (args->report.scene.empty()) {
      const std::string which =
          inputs.frames.scene.empty() ? "frames.json names no scene" : "the scene '" + inputs.frames.scene + "' of frames.json was not found";
      std::fprintf(stderr, "warning: %s: the 3D view shows the rig alone (give --scene FILE.glb)\n", which.c_str());
    }
    args->report.sweep_dir = args->sweep;
    args->report.tool_version = RIGSIM_VERSION_STRING;
    args->report.command = "rigsim report " + args->dataset + " --out " + args->out +
                           (args->calibration.empty() ? "" : " --calibration " + args->calibration) +
                           (args->features == "sift" ? "" : " --features " + args->features) +
                           (args->sweep.empty() ? "" : " --sweep " + args->sweep) +
                           (args->scene.empty() ? "" : " --scene " + args->scene);
    std::fprintf(stderr, "calibrating %s for the report (%s)...\n", dataset.string().c_str(),
                 Count(plan.modes.size(), "semantic mode").c_str());
    const CalibrationRun run = CalibrateShowingStages(plan);
    if (!args->calibration.empty()) {
      const std::vector<std::string> differences = CompareWithSaved(run, args->calibration);
      for (const std::string& d : differences) {
        std::fprintf(stderr, "warning: this run's estimate differs from %s's (%s): it was made with other options; "
                     "the report shows this run\n", args->calibration.c_str(), d.c_str());
      }
    }
    const fs::path index = WriteReportFolder(run, args->report, plan.out);
    std::printf("calibration took %.1f s; report: %s\n", run.seconds, index.string().c_str());
  });
}

}  // namespace rigsim::cli
