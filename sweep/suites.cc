#include "sweep/suites.h"

#include <algorithm>
#include <stdexcept>

#include "calibrator/features/semantics.h"
#include "common/did_you_mean.h"
#include "common/param_spec.h"
#include "procedural/presets.h"
#include "renderer/sensor_model.h"
#include "rigs/trajectories.h"

namespace rigsim {

using Json = nlohmann::ordered_json;

std::vector<std::string> SuiteNames() { return {"thesis", "motion"}; }
std::vector<std::string> SuiteSizes() { return {"small", "full"}; }

Json ThesisClaimsJson() {
  return Json::parse(R"({
    "title": "The thesis's claims",
    "list": [
      {"claim": "gives a larger share of correct matches", "metric": "match_precision", "compare": "difference",
       "holds": "> 0"},
      {"claim": "gives fewer wrong matches between different classes", "metric": "cross_class_wrong",
       "compare": "difference", "holds": "< 0"},
      {"claim": "makes matching faster", "metric": "time_match_s", "compare": "ratio", "holds": "< 1"},
      {"claim": "makes calibration faster", "metric": "time_total_s", "compare": "ratio", "holds": "< 1"},
      {"claim": "keeps pose accuracy equal or better", "metric": "auc_pairs_5deg", "compare": "difference",
       "holds": ">= -0.02", "note": "Accuracy counts as equal when the AUC of the pair errors at 5 deg is within 0.02."}
    ]
  })");
}

namespace {

// Where the thesis's unreliable classes really move: animated worlds (people walk, cars drive at the
// traffic density, trees sway) seen by cameras that do not capture together or roll their
// shutters, on a handheld path whose changing motion shows capture times (a circle at constant
// speed hides them).
Json Dynamics(bool full) {
  Json study = {{"name", "dynamics"}, {"set", {{"animated", true}, {"trajectory", "handheld"}, {"frames", 6}}}};
  study["grid"] = full ? Json::parse(R"({"traffic": [0, 0.5, 1], "time_offset_ms": [0, 10, 30], "readout_ms": [0, 30]})")
                       : Json::parse(R"({"traffic": [1], "time_offset_ms": [0, 30]})");
  return study;
}

Json Thesis(bool full) {
  // The base point: a 4-camera ring on the street at 30% overlap, driving a left turn over three
  // frames (a turning path fixes each camera's place in the rig), at 640x360.
  Json config = Json::parse(R"({
    "name": "thesis",
    "description": "The thesis's four claims about semantic masking, across overlap, baseline, lens, label noise and scenes",
    "base": {"scene": "street", "rig": "ring", "cameras": 4, "overlap": 30, "width": 640, "height": 360,
             "frames": 3, "spp": 2, "trajectory": "circle", "circle_radius": 12, "step": 2}
  })");
  config["claims"] = ThesisClaimsJson();
  if (full) {
    config["seeds"] = 3;
    config["methods"] = {{"semantics", NamesOf(kAllSemanticModes, SemanticModeName)}, {"peers", {"colmap"}}};
    // Overlap down to none, across the motion that links cameras without it (hfov 85: four
    // cameras part all round at 0 %).
    config["studies"] = Json::parse(R"([
      {"name": "overlap", "set": {"hfov": 85},
       "grid": {"overlap": [0, 2, 5, 15, 30, 50], "frames": [3, 12, 30], "trajectory": ["straight", "circle", "handheld"]}},
      {"name": "baseline", "set": {"rig": "wide-baseline", "convergence": 30}, "grid": {"baseline": [0.1, 0.5, 2, 5]}},
      {"name": "lens", "zip": {"lens": ["pinhole", "opencv", "fisheye", "fisheye"], "fisheye_fov": [190, 190, 150, 190]}},
      {"name": "label-noise", "zip": {"label_boundary": [0, 3, 6, 10], "label_confusion": [0, 0.1, 0.2, 0.3]}}
    ])");
    config["studies"].push_back({{"name", "scene"}, {"grid", {{"scene", NamesOf(AllScenePresets(), ScenePresetName)}}}});
    config["studies"].push_back(Dynamics(true));
  } else {
    config["seeds"] = 1;
    config["methods"] = {{"semantics", {"none", "mask"}}, {"peers", {"colmap"}}};
    config["studies"] = Json::parse(R"([
      {"name": "overlap", "set": {"hfov": 85}, "grid": {"overlap": [0, 15], "trajectory": ["circle", "handheld"]}},
      {"name": "baseline", "set": {"rig": "wide-baseline", "convergence": 30}, "grid": {"baseline": [0.5, 2]}},
      {"name": "lens", "zip": {"lens": ["pinhole", "fisheye"], "fisheye_fov": [190, 190]}},
      {"name": "label-noise", "zip": {"label_boundary": [0, 6], "label_confusion": [0, 0.2]}},
      {"name": "scene", "grid": {"scene": ["street", "plaza"]}}
    ])");
    config["studies"].push_back(Dynamics(false));
  }
  return config;
}

Json Motion(bool full, const SuiteInputs& inputs) {
  if (inputs.rig_file.empty()) {
    throw std::invalid_argument("--suite motion: give --rig RIG.json, the rig to try (a rig.json as rigsim make-rig "
                                "writes it: every camera's intrinsics and cam_from_rig)");
  }
  Json config = Json::parse(R"({
    "name": "motion",
    "base": {"scene": "street", "rig": "file", "frames": 12, "spp": 2, "trajectory": "circle", "circle_radius": 6,
             "step": 2, "tilt": 10}
  })");
  config["description"] = "Which path calibrates the rig of " + inputs.rig_file + ", and how well";
  config["base"]["rig_file"] = inputs.rig_file;
  if (!inputs.scene.empty()) config["base"]["scene"] = inputs.scene;
  // Three seeds at either size: whether a path places the rig is a share of runs, which one seed
  // cannot show.
  config["seeds"] = 3;
  config["methods"] = full ? Json{{"semantics", {"none", "mask"}}, {"peers", {"colmap"}}} : Json{{"semantics", {"none"}}};
  // One study per frame count, each across the paths: a plot per frame count, a point per path.
  config["studies"] = Json::array();
  for (int frames : full ? std::vector<int>{3, 12, 30} : std::vector<int>{3, 12}) {
    config["studies"].push_back({{"name", std::to_string(frames) + " frames"},
                                 {"set", {{"frames", frames}}},
                                 {"grid", {{"trajectory", NamesOf(kNamedTrajectoryKinds, TrajectoryKindName)}}}});
  }
  return config;
}

}  // namespace

Json SuiteConfig(const std::string& name, const std::string& size, const SuiteInputs& inputs) {
  if (name != "thesis" && name != "motion") {
    throw std::invalid_argument("--suite: unknown suite '" + name + "'; the built-in suites are: " +
                                JoinNames(SuiteNames()) + DidYouMean(name, SuiteNames()));
  }
  if (size != "small" && size != "full") {
    throw std::invalid_argument("--size: give small or full (got '" + size + "')" + DidYouMean(size, SuiteSizes()));
  }
  const std::vector<std::string> sensors = SensorPresetNames();
  if (std::find(sensors.begin(), sensors.end(), inputs.sensor) == sensors.end()) {
    throw std::invalid_argument("--sensor: unknown sensor preset '" + inputs.sensor + "'" + DidYouMean(inputs.sensor, sensors) +
                                "; the presets are: " + JoinNames(sensors));
  }
  if (name == "thesis" && (!inputs.rig_file.empty() || !inputs.scene.empty())) {
    throw std::invalid_argument("--rig and --scene apply to --suite motion only; the thesis suite has its own rigs and scenes");
  }
  Json config = name == "motion" ? Motion(size == "full", inputs) : Thesis(size == "full");
  // `ideal` is the sensor parameter's default: left out, the cells are the same as without a sensor.
  if (inputs.sensor != "ideal") config["base"]["sensor"] = inputs.sensor;
  if (inputs.ego_vehicle) config["base"]["ego_vehicle"] = true;
  return config;
}

}  // namespace rigsim
