#include "sweep/sweep_config.h"

#include <cmath>
#include <cstdlib>
#include <cstdio>
#include <fstream>
#include <map>
#include <set>
#include <sstream>
#include <stdexcept>

#include <yaml-cpp/yaml.h>

#include "calibrator/features/features.h"
#include "calibrator/features/semantics.h"
#include "common/did_you_mean.h"
#include "common/stable_hash.h"
#include "pipeline/intrinsics_error.h"
#include "procedural/presets.h"
#include "renderer/sensor_model.h"
#include "rigs/rig_params.h"
#include "sweep/suites.h"
#include "sweep/sweep_metrics.h"

namespace rigsim {

namespace fs = std::filesystem;
using Json = nlohmann::ordered_json;

namespace {

// Appends the sweep's rig parameters of `group`.
void AddRigParams(RigParamGroup group, std::vector<ParamSpec>& specs) {
  for (const RigParam& p : RigParams()) {
    if (p.in_sweep && p.group == group) specs.push_back(p.SweepSpec());
  }
}

std::vector<ParamSpec> MakeCellParamSpecs() {
  using K = ParamSpec::Kind;
  std::vector<ParamSpec> specs = {
      {"scene", K::kText, "street", {}, 0, 0,
       "scene preset (" + JoinNames(NamesOf(AllScenePresets(), ScenePresetName)) +
           ") or a .glb/.gltf file (relative to the config file)"},
      {"scene_seed", K::kInt, nullptr, {}, 0, 2147483647, "seed of a preset scene; default: the cell's seed"},
      {"animated", K::kBool, false, {}, 0, 0,
       "preset scenes move: people walk, cars drive (traffic), buses drive to their stop, trees sway (see time_offset_ms)"},
      {"traffic", K::kNumber, kDefaultTraffic, {}, 0, kMaxTraffic,
       "animated preset scenes: moving cars per 100 m of lane (street 240 m, parking 120 m; the plaza's bus drives "
       "when above 0); 0: no vehicle moves"},
  };
  AddRigParams(RigParamGroup::kRig, specs);
  specs.push_back({"ego_vehicle", K::kBool, false, {}, 0, 0,
                   "the rig's own car around it, as make-rig --ego-vehicle: a body sized from where the cameras are, "
                   "labelled ego vehicle, with glossy paint; render shows it in every view that sees it"});
  AddRigParams(RigParamGroup::kImage, specs);
  AddRigParams(RigParamGroup::kMounting, specs);
  specs.push_back({"spp", K::kInt, 2, {}, 1, 256, "samples per pixel"});
  AddRigParams(RigParamGroup::kPath, specs);
  for (ParamSpec p : std::vector<ParamSpec>{
           {"photometric", K::kNumber, 0.0, {}, 0, 3,
            "per-camera exposure, white balance, vignetting and noise: 0 none, 1 render --photometric's spread"},
           {"sensor", K::kChoice, "ideal", SensorPresetNames(), 0, 0,
            "the cameras' sensor and lens, as render --sensor: " + JoinNames(SensorPresetNames()) +
                " (exposure, white balance, vignetting, defocus, noise, JPEG from datasheets; with photometric 0)"},
           {"label_boundary", K::kInt, 0, {}, 0, 64, "label noise: class boundaries shift by up to this (px)"},
           {"label_confusion", K::kNumber, 0.0, {}, 0, 1, "label noise: share of blobs given a confusable class"},
           {"intrinsics_error", K::kNumber, 0.0, {}, 0, IntrinsicsErrorOptions::kMaxError,
            "rigsim's calibrations are given intrinsics off the rendered ones by this relative error, as calibrate "
            "--intrinsics-error, drawn from the cell's seed (0.01: focal lengths about 1 % off; colmap keeps the true ones)"},
           {"time_offset_ms", K::kNumber, 0.0, {}, 0, 1000,
            "camera c captures c times this after camera 0 (ms): the rig moves on along its path in between, "
            "and so do animated objects"},
           {"readout_ms", K::kNumber, 0.0, {}, 0, 1000,
            "rolling shutter: every camera reads its rows top to bottom over this time (ms); 0 = global shutter"},
       }) {
    specs.push_back(std::move(p));
  }
  return specs;
}

}  // namespace

const std::vector<ParamSpec>& CellParamSpecs() {
  static const std::vector<ParamSpec> specs = MakeCellParamSpecs();
  return specs;
}

bool HeldWhenSet(const ParamSpec& spec) { return spec.name == "placement" || spec.name == "ego_vehicle"; }

Json CellParam(const Json& params, const std::string& name) {
  if (const auto it = params.find(name); it != params.end()) return *it;
  for (const ParamSpec& s : CellParamSpecs()) {
    if (s.name == name) return s.default_value;
  }
  throw std::out_of_range("no cell parameter '" + name + "'");
}

std::vector<std::string> SweepPeerNames() { return {"colmap"}; }

std::vector<std::string> SweepTimeNames() { return {"synchronised", "estimated", "estimated+rolling-shutter"}; }

std::string SweepMethodName(const std::string& features, const std::string& semantics, const std::string& time) {
  return (features == "sift" ? semantics : features + ":" + semantics) + (time == "synchronised" ? "" : "@" + time);
}

std::vector<std::string> SweepStudy::VariedParams() const {
  std::vector<std::string> names;
  for (const SweepAxis& a : grid) names.push_back(a.param);
  for (const SweepAxis& a : zip) names.push_back(a.param);
  return names;
}

namespace {

[[noreturn]] void Fail(const std::string& source, const std::string& where, const std::string& what) {
  throw std::runtime_error(source + ": " + (where.empty() ? "" : where + ": ") + what);
}

std::vector<std::string> ParamNames() {
  std::vector<std::string> names;
  for (const ParamSpec& s : CellParamSpecs()) names.push_back(s.name);
  return names;
}

const ParamSpec& FindParam(const std::string& name, const std::string& source, const std::string& where) {
  for (const ParamSpec& s : CellParamSpecs()) {
    if (s.name == name) return s;
  }
  if (name == "seed") Fail(source, where, "give seeds with the top-level 'seeds' list, not as a parameter");
  Fail(source, where, "unknown parameter" + DidYouMean(name, ParamNames()) +
                          "; `rigsim sweep --list-params` lists them");
}

// A value checked against its parameter and normalised (numbers as doubles, so 30 and 30.0 are
// one cell).
Json CheckValue(const ParamSpec& spec, const Json& v, const std::string& source, const std::string& where) {
  try {
    return CheckParamValue(spec, v);
  } catch (const std::invalid_argument& e) {
    Fail(source, where, e.what());
  }
}

Json CheckParams(const Json& j, const std::string& source, const std::string& where) {
  if (!j.is_object()) Fail(source, where, "must be a mapping of parameter names to values");
  Json out = Json::object();
  for (const auto& [k, v] : j.items()) {
    const std::string w = where + "." + k;
    out[k] = CheckValue(FindParam(k, source, w), v, source, w);
  }
  return out;
}

// `repeats`: a zipped axis may repeat a value (its neighbours tell the points apart).
std::vector<SweepAxis> ParseAxes(const Json& j, const std::string& source, const std::string& where, bool repeats) {
  if (!j.is_object()) Fail(source, where, "must map parameter names to lists of values");
  std::vector<SweepAxis> axes;
  for (const auto& [k, v] : j.items()) {
    const std::string w = where + "." + k;
    const ParamSpec& spec = FindParam(k, source, w);
    if (!v.is_array() || v.empty()) Fail(source, w, "must be a non-empty list of values");
    SweepAxis axis{k, {}};
    std::set<std::string> seen;
    for (size_t i = 0; i < v.size(); ++i) {
      Json value = CheckValue(spec, v[i], source, w + "[" + std::to_string(i) + "]");
      if (!seen.insert(value.dump()).second && !repeats) Fail(source, w, "value " + value.dump() + " is listed twice");
      axis.values.push_back(std::move(value));
    }
    axes.push_back(std::move(axis));
  }
  return axes;
}

std::string Join(const std::string& where, const std::string& key) { return where.empty() ? key : where + "." + key; }

SweepStudy ParseStudy(const Json& j, const std::string& source, const std::string& where, const std::string& name) {
  static const std::vector<std::string> keys = {"name", "set", "grid", "zip"};
  SweepStudy study;
  study.name = name;
  for (const auto& [k, v] : j.items()) {
    if (k == "name") {
      if (!v.is_string() || v.get<std::string>().empty()) Fail(source, where + ".name", "must be a non-empty text");
      study.name = v.get<std::string>();
    } else if (k == "set") {
      study.set = CheckParams(v, source, Join(where, "set"));
    } else if (k == "grid") {
      study.grid = ParseAxes(v, source, Join(where, "grid"), false);
    } else if (k == "zip") {
      study.zip = ParseAxes(v, source, Join(where, "zip"), true);
    } else if (where.rfind("studies", 0) == 0) {
      Fail(source, where + "." + k, "unknown key" + DidYouMean(k, keys) + "; a study has name, set, grid and zip");
    }
  }
  for (size_t i = 1; i < study.zip.size(); ++i) {
    if (study.zip[i].values.size() != study.zip[0].values.size()) {
      Fail(source, Join(where, "zip"), "'" + study.zip[i].param + "' has " + std::to_string(study.zip[i].values.size()) +
                                       " values and '" + study.zip[0].param + "' " +
                                       std::to_string(study.zip[0].values.size()) + ": zipped axes need as many");
    }
  }
  std::set<std::string> tuples;
  for (size_t i = 0; !study.zip.empty() && i < study.zip[0].values.size(); ++i) {
    Json tuple = Json::array();
    for (const SweepAxis& axis : study.zip) tuple.push_back(axis.values[i]);
    if (!tuples.insert(tuple.dump()).second) Fail(source, Join(where, "zip"), "values " + tuple.dump() + " are listed twice");
  }
  std::set<std::string> varied;
  for (const std::string& p : study.VariedParams()) {
    if (!varied.insert(p).second) Fail(source, where, "'" + p + "' is swept twice (in grid and zip)");
    if (study.set.contains(p)) Fail(source, where, "'" + p + "' is both set and swept");
  }
  return study;
}

std::vector<SweepMethod> ParseMethods(const Json& j, const std::string& source) {
  static const std::vector<std::string> keys = {"semantics", "features", "time", "peers"};
  static const std::vector<std::string> modes = NamesOf(kAllSemanticModes, SemanticModeName);
  static const std::vector<std::string> features = NamesOf(kAllFeatureTypes, FeatureTypeName);
  static const std::vector<std::string> times = SweepTimeNames();
  static const std::vector<std::string> peers = SweepPeerNames();
  std::vector<std::string> sem = {"none", "mask"}, feat = {"sift"}, time = {"synchronised"}, peer;
  if (!j.is_null()) {
    if (!j.is_object()) Fail(source, "methods", "must be a mapping with semantics, features, time and peers");
    for (const auto& [k, v] : j.items()) {
      const std::vector<std::string>* allowed = k == "semantics" ? &modes : k == "features" ? &features
                                                : k == "time"      ? &times
                                                : k == "peers"     ? &peers : nullptr;
      if (!allowed) Fail(source, "methods." + k, "unknown key" + DidYouMean(k, keys));
      if (!v.is_array()) Fail(source, "methods." + k, "must be a list");
      std::vector<std::string> names;
      for (size_t i = 0; i < v.size(); ++i) {
        const std::string w = "methods." + k + "[" + std::to_string(i) + "]";
        if (!v[i].is_string()) Fail(source, w, "must be a name");
        const std::string n = v[i].get<std::string>();
        if (std::find(allowed->begin(), allowed->end(), n) == allowed->end()) {
          const std::string suggestion = DidYouMean(n, *allowed);
          Fail(source, w, "unknown " + k + " '" + n + "'" + (suggestion.empty() ? "; give " + JoinNames(*allowed) : suggestion));
        }
        if (std::find(names.begin(), names.end(), n) != names.end()) Fail(source, w, "'" + n + "' is listed twice");
        names.push_back(n);
      }
      (k == "semantics" ? sem : k == "features" ? feat : k == "time" ? time : peer) = names;
    }
  }
  // rigsim's methods are every feature type, way of taking capture times and mode crossed; the
  // peers take the images as they are.
  std::vector<SweepMethod> methods;
  for (const std::string& f : feat) {
    for (const std::string& t : time) {
      for (const std::string& s : sem) methods.push_back({SweepMethodName(f, s, t), "rigsim", s, f, t});
    }
  }
  for (const std::string& p : peer) methods.push_back({p, p, "", "", ""});
  if (methods.empty()) Fail(source, "methods", "no method to run: give semantics (and features) or peers");
  return methods;
}

// A config without claims tests the thesis's.
const ClaimSet& DefaultClaims() {
  static const ClaimSet claims = ParseClaimSet(ThesisClaimsJson(), "--suite thesis");
  return claims;
}

std::vector<uint64_t> ParseSeeds(const Json& j, const std::string& source) {
  if (j.is_number_integer()) {
    const int64_t n = j.get<int64_t>();
    if (n < 1 || n > 1000) Fail(source, "seeds", "a count of seeds must be 1..1000");
    std::vector<uint64_t> seeds;
    for (int64_t i = 1; i <= n; ++i) seeds.push_back(static_cast<uint64_t>(i));
    return seeds;
  }
  if (!j.is_array() || j.empty()) Fail(source, "seeds", "give a list of seeds ([1, 2, 3]) or their count (3)");
  std::vector<uint64_t> seeds;
  for (size_t i = 0; i < j.size(); ++i) {
    if (!j[i].is_number_integer() || j[i].get<int64_t>() < 0 || j[i].get<int64_t>() > 2147483647) {
      Fail(source, "seeds[" + std::to_string(i) + "]", "must be a whole number 0..2147483647");
    }
    const uint64_t s = j[i].get<uint64_t>();
    if (std::find(seeds.begin(), seeds.end(), s) != seeds.end()) Fail(source, "seeds", std::to_string(s) + " is listed twice");
    seeds.push_back(s);
  }
  return seeds;
}

Json YamlNodeToJson(const YAML::Node& node, const std::string& source) {
  switch (node.Type()) {
    case YAML::NodeType::Null:
    case YAML::NodeType::Undefined:
      return nullptr;
    case YAML::NodeType::Sequence: {
      Json a = Json::array();
      for (const YAML::Node& n : node) a.push_back(YamlNodeToJson(n, source));
      return a;
    }
    case YAML::NodeType::Map: {
      Json o = Json::object();
      for (const auto& kv : node) o[kv.first.as<std::string>()] = YamlNodeToJson(kv.second, source);
      return o;
    }
    case YAML::NodeType::Scalar: {
      const std::string s = node.Scalar();
      if (node.Tag() == "!") return s;  // quoted: a string whatever it looks like
      if (s == "~" || s == "null" || s == "Null" || s == "NULL") return nullptr;
      if (s == "true" || s == "True" || s == "TRUE") return true;
      if (s == "false" || s == "False" || s == "FALSE") return false;
      // Numbers as JSON reads them (so 30 is an integer and 30.0 a number), else text.
      const Json number = Json::parse(s, nullptr, false);
      if (number.is_number()) return number;
      return s;
    }
  }
  return nullptr;
}

}  // namespace

bool ClaimSpec::Holds(double d) const {
  if (op == ">") return d > value;
  if (op == ">=") return d >= value;
  if (op == "<") return d < value;
  return d <= value;
}

ClaimSet ParseClaimSet(const Json& j, const std::string& source) {
  static const std::vector<std::string> keys = {"title", "list"};
  static const std::vector<std::string> claim_keys = {"claim", "metric", "compare", "holds", "note"};
  if (!j.is_object()) Fail(source, "claims", "must be a mapping with a title and a list of claims");
  ClaimSet set;
  for (const auto& [k, v] : j.items()) {
    if (std::find(keys.begin(), keys.end(), k) == keys.end()) Fail(source, "claims." + k, "unknown key" + DidYouMean(k, keys));
  }
  if (!j.contains("title") || !j["title"].is_string() || j["title"].get<std::string>().empty()) {
    Fail(source, "claims.title", "must be a non-empty text (report.md's heading)");
  }
  set.title = j["title"].get<std::string>();
  if (!j.contains("list") || !j["list"].is_array()) Fail(source, "claims.list", "must be a list of claims");
  std::vector<std::string> metrics;
  for (const MethodMetricSpec& m : SweepMetricSpecs()) metrics.push_back(m.name);
  for (size_t i = 0; i < j["list"].size(); ++i) {
    const Json& c = j["list"][i];
    const std::string where = "claims.list[" + std::to_string(i) + "]";
    if (!c.is_object()) Fail(source, where, "a claim is a mapping (claim, metric, compare, holds, note)");
    for (const auto& [k, v] : c.items()) {
      if (std::find(claim_keys.begin(), claim_keys.end(), k) == claim_keys.end()) {
        Fail(source, where + "." + k, "unknown key" + DidYouMean(k, claim_keys));
      }
      if (!v.is_string()) Fail(source, where + "." + k, "must be a text");
    }
    ClaimSpec spec;
    spec.claim = c.value("claim", "");
    if (spec.claim.empty()) Fail(source, where + ".claim", "say what is claimed");
    spec.metric = c.value("metric", "");
    if (std::find(metrics.begin(), metrics.end(), spec.metric) == metrics.end()) {
      Fail(source, where + ".metric", "'" + spec.metric + "' is no metric of the results" + DidYouMean(spec.metric, metrics));
    }
    const std::string compare = c.value("compare", "difference");
    if (compare != "difference" && compare != "ratio") Fail(source, where + ".compare", "give difference or ratio");
    spec.ratio = compare == "ratio";
    // "> 0", ">= -0.02", "< 1": a comparison and a number.
    const std::string holds = c.value("holds", "");
    const size_t number = holds.find_first_not_of("<>= ");
    spec.op = holds.substr(0, std::min(number, holds.find(' ')));
    char* end = nullptr;
    spec.value = number == std::string::npos ? 0.0 : std::strtod(holds.c_str() + number, &end);
    if ((spec.op != ">" && spec.op != ">=" && spec.op != "<" && spec.op != "<=") || number == std::string::npos ||
        *end != '\0') {
      Fail(source, where + ".holds", "give a comparison and a number, e.g. \"> 0\" or \"<= 1\" (got '" + holds + "')");
    }
    spec.note = c.value("note", "");
    set.claims.push_back(std::move(spec));
  }
  return set;
}

Json ClaimSetToJson(const ClaimSet& set) {
  Json list = Json::array();
  for (const ClaimSpec& c : set.claims) {
    char value[32];
    std::snprintf(value, sizeof value, "%g", c.value);
    Json j = {{"claim", c.claim},
              {"metric", c.metric},
              {"compare", c.ratio ? "ratio" : "difference"},
              {"holds", c.op + " " + value}};
    if (!c.note.empty()) j["note"] = c.note;
    list.push_back(std::move(j));
  }
  return {{"title", set.title}, {"list", list}};
}

Json YamlToJson(const std::string& text, const std::string& source) {
  try {
    return YamlNodeToJson(YAML::Load(text), source);
  } catch (const YAML::Exception& e) {
    throw std::runtime_error(source + ":" + std::to_string(e.mark.line + 1) + ":" + std::to_string(e.mark.column + 1) +
                             ": invalid YAML: " + e.msg);
  }
}

SweepConfig ParseSweepConfig(const Json& j, const std::string& source) {
  static const std::vector<std::string> keys = {"name",    "description", "base",    "seeds", "methods",
                                                "grid",    "zip",         "studies", "claims"};
  if (!j.is_object()) Fail(source, "", "a sweep config is a mapping (name, base, seeds, methods, grid/zip or studies)");
  for (const auto& [k, v] : j.items()) {
    if (std::find(keys.begin(), keys.end(), k) == keys.end()) {
      Fail(source, k, "unknown key" + DidYouMean(k, keys) + "; a config has " +
                          "name, description, base, seeds, methods, grid, zip, studies and claims");
    }
  }
  SweepConfig config;
  config.source = source;
  config.name = fs::path(source).stem().string();
  if (j.contains("name")) {
    if (!j["name"].is_string() || j["name"].get<std::string>().empty()) Fail(source, "name", "must be a non-empty text");
    config.name = j["name"].get<std::string>();
  }
  if (j.contains("base")) config.base = CheckParams(j["base"], source, "base");
  if (j.contains("seeds")) config.seeds = ParseSeeds(j["seeds"], source);
  config.methods = ParseMethods(j.contains("methods") ? j["methods"] : Json(nullptr), source);
  config.claims = j.contains("claims") ? ParseClaimSet(j["claims"], source) : DefaultClaims();
  const bool top_axes = j.contains("grid") || j.contains("zip");
  if (j.contains("studies")) {
    if (top_axes) Fail(source, "studies", "give either studies or a top-level grid/zip, not both");
    const Json& s = j["studies"];
    if (!s.is_array() || s.empty()) Fail(source, "studies", "must be a non-empty list");
    std::set<std::string> names;
    for (size_t i = 0; i < s.size(); ++i) {
      const std::string where = "studies[" + std::to_string(i) + "]";
      if (!s[i].is_object()) Fail(source, where, "a study is a mapping (name, set, grid, zip)");
      if (!s[i].contains("name")) Fail(source, where, "a study needs a name");
      SweepStudy study = ParseStudy(s[i], source, where, "");
      if (!names.insert(study.name).second) Fail(source, where + ".name", "'" + study.name + "' names two studies");
      config.studies.push_back(std::move(study));
    }
  } else {
    config.studies.push_back(ParseStudy(j, source, "", config.name));
  }
  // A sensor preset brings its own photometric magnitudes: a cell takes one or the other.
  for (const SweepCell& cell : ExpandCells(config)) {
    const std::string sensor = cell.params.at("sensor").get<std::string>();
    if (sensor != "ideal" && cell.params.at("photometric").get<double>() > 0) {
      Fail(source, "", "a cell has sensor " + sensor + " and photometric " + FormatParamValue(cell.params.at("photometric")) +
                           ": the sensor preset sets the photometric magnitudes itself; give photometric 0 with it");
    }
  }
  return config;
}

SweepConfig ReadSweepConfig(const fs::path& path) {
  std::ifstream in(path, std::ios::binary);
  if (!in) throw std::runtime_error(path.string() + ": cannot read the sweep config");
  std::stringstream text;
  text << in.rdbuf();
  const std::string ext = path.extension().string();
  Json j;
  if (ext == ".yaml" || ext == ".yml") {
    j = YamlToJson(text.str(), path.string());
  } else if (ext == ".json") {
    try {
      j = Json::parse(text.str());
    } catch (const Json::parse_error& e) {
      throw std::runtime_error(path.string() + ": invalid JSON: " + e.what());
    }
  } else {
    throw std::runtime_error(path.string() + ": a sweep config is a .json, .yaml or .yml file");
  }
  SweepConfig config = ParseSweepConfig(j, path.string());
  config.source = path;
  return config;
}

namespace {

// Every combination of a study's axes: the grid axes crossed (first axis slowest), the zip axes
// as one more axis.
std::vector<Json> Combinations(const SweepStudy& study) {
  std::vector<Json> combos = {Json::object()};
  for (const SweepAxis& axis : study.grid) {
    std::vector<Json> next;
    for (const Json& c : combos) {
      for (const Json& v : axis.values) {
        Json n = c;
        n[axis.param] = v;
        next.push_back(std::move(n));
      }
    }
    combos = std::move(next);
  }
  if (!study.zip.empty()) {
    std::vector<Json> next;
    for (const Json& c : combos) {
      for (size_t i = 0; i < study.zip[0].values.size(); ++i) {
        Json n = c;
        for (const SweepAxis& axis : study.zip) n[axis.param] = axis.values[i];
        next.push_back(std::move(n));
      }
    }
    combos = std::move(next);
  }
  return combos;
}

}  // namespace

std::vector<SweepCell> ExpandCells(const SweepConfig& config) {
  std::vector<SweepCell> cells;
  std::map<std::string, size_t> by_key;
  for (const SweepStudy& study : config.studies) {
    for (const Json& combo : Combinations(study)) {
      for (uint64_t seed : config.seeds) {
        Json params = Json::object();
        for (const ParamSpec& spec : CellParamSpecs()) {
          const Json* v = &spec.default_value;
          if (config.base.contains(spec.name)) v = &config.base[spec.name];
          if (study.set.contains(spec.name)) v = &study.set[spec.name];
          if (combo.contains(spec.name)) v = &combo[spec.name];
          if (HeldWhenSet(spec) && *v == spec.default_value) continue;
          params[spec.name] = spec.kind == ParamSpec::Kind::kNumber && v->is_number() ? Json(v->get<double>()) : *v;
        }
        params["seed"] = seed;
        const std::string key = StableHash(params.dump());
        if (const auto it = by_key.find(key); it != by_key.end()) {
          std::vector<std::string>& s = cells[it->second].studies;
          if (std::find(s.begin(), s.end(), study.name) == s.end()) s.push_back(study.name);
          continue;
        }
        by_key[key] = cells.size();
        cells.push_back({static_cast<int>(cells.size()), key, std::move(params), {study.name}});
      }
    }
  }
  return cells;
}

Json SweepConfigToJson(const SweepConfig& config) {
  Json studies = Json::array();
  for (const SweepStudy& s : config.studies) {
    Json grid = Json::object(), zip = Json::object();
    for (const SweepAxis& a : s.grid) grid[a.param] = a.values;
    for (const SweepAxis& a : s.zip) zip[a.param] = a.values;
    studies.push_back({{"name", s.name}, {"set", s.set}, {"grid", grid}, {"zip", zip}});
  }
  // The methods as a config names them: rigsim's are every feature type crossed with every mode.
  Json semantics = Json::array(), features = Json::array(), time = Json::array(), peers = Json::array();
  const auto add = [](Json& list, const std::string& v) {
    if (std::find(list.begin(), list.end(), Json(v)) == list.end()) list.push_back(v);
  };
  for (const SweepMethod& m : config.methods) {
    if (m.tool == "rigsim") {
      add(semantics, m.semantics);
      add(features, m.features);
      add(time, m.time);
    } else {
      add(peers, m.tool);
    }
  }
  Json methods = {{"semantics", semantics}, {"features", features}};
  // Synchronised alone is left out, as a config that does not name capture times leaves it out.
  if (time != Json::array({"synchronised"}) && !time.empty()) methods["time"] = time;
  methods["peers"] = peers;
  Json j = {{"name", config.name},
            {"base", config.base},
            {"seeds", config.seeds},
            {"methods", methods},
            {"studies", studies}};
  // The default claims are left out, as a config that names none leaves them out.
  if (ClaimSetToJson(config.claims) != ClaimSetToJson(DefaultClaims())) j["claims"] = ClaimSetToJson(config.claims);
  return j;
}

std::string SweepHash(const SweepConfig& config) {
  Json what = Json::array();
  for (const SweepCell& c : ExpandCells(config)) what.push_back(c.params);
  Json methods = Json::array();
  for (const SweepMethod& m : config.methods) methods.push_back(m.name);
  return StableHash(Json{{"cells", what}, {"methods", methods}}.dump());
}

}  // namespace rigsim
