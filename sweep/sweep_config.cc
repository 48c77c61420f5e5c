#include "sweep/sweep_config.h"

#include <cmath>
#include <cstdio>
#include <fstream>
#include <map>
#include <set>
#include <sstream>
#include <stdexcept>

#include <yaml-cpp/yaml.h>

#include "common/did_you_mean.h"
#include "common/stable_hash.h"

namespace rigsim {

namespace fs = std::filesystem;
using Json = nlohmann::ordered_json;

const std::vector<ParamSpec>& CellParamSpecs() {
  using K = ParamSpec::Kind;
  static const std::vector<ParamSpec> specs = {
      {"scene", K::kText, "street", {}, 0, 0,
       "scene preset (street, plaza, parking) or a .glb/.gltf file (relative to the config file)"},
      {"scene_seed", K::kInt, nullptr, {}, 0, 2147483647, "seed of a preset scene; default: the cell's seed"},
      {"animated", K::kBool, false, {}, 0, 0,
       "preset scenes move: people walk, cars drive (traffic), buses drive to their stop, trees sway (see time_offset_ms)"},
      {"traffic", K::kNumber, 2.0, {}, 0, 15,
       "animated preset scenes: moving cars per 100 m of lane (street 240 m, parking 120 m; the plaza's bus drives "
       "when above 0); 0: no vehicle moves"},
      {"rig", K::kChoice, "ring", {"ring", "stereo", "surround", "wide-baseline"}, 0, 0, "rig type (make-rig)"},
      {"cameras", K::kInt, 4, {}, 2, 16, "ring: number of cameras"},
      {"overlap", K::kNumber, nullptr, {}, 1, 95,
       "ring: ground-truth overlap of neighbours (percent), solved where the rig stands; unset: spacing"},
      {"spacing", K::kNumber, 60.0, {}, 1, 180, "ring: yaw between neighbours (deg), when overlap is unset"},
      {"radius", K::kNumber, 0.5, {}, 0, 10, "ring: radius (m)"},
      {"baseline", K::kNumber, nullptr, {}, 0.01, 100,
       "stereo, wide-baseline: distance between the cameras (m); unset: 0.12 and 2.0"},
      {"convergence", K::kNumber, 30.0, {}, 0, 120, "wide-baseline: angle between the optical axes (deg)"},
      {"hfov", K::kNumber, nullptr, {}, 10, 170,
       "horizontal field of view of the perspective lenses (deg); unset: the rig's default"},
      {"lens", K::kChoice, "preset", {"preset", "pinhole", "opencv", "fisheye"}, 0, 0,
       "preset: the rig type's own lenses (ring: cam1 barrel-distorted); pinhole, opencv (k1 = distortion, "
       "k2 = -0.24 k1) or fisheye (Kannala-Brandt over fisheye_fov): every camera"},
      {"distortion", K::kNumber, -0.25, {}, -1, 1, "opencv lens: k1 (negative: barrel)"},
      {"fisheye_fov", K::kNumber, 190.0, {}, 60, 240,
       "fisheye lens, and the surround rig's side cameras: horizontal field of view (deg)"},
      {"width", K::kInt, 640, {}, 32, 8192, "image width (px)"},
      {"height", K::kInt, 360, {}, 32, 8192, "image height (px)"},
      {"spp", K::kInt, 2, {}, 1, 256, "samples per pixel"},
      {"frames", K::kInt, 3, {}, 1, 100, "frames along the trajectory"},
      {"trajectory", K::kChoice, "circle", {"circle", "straight"}, 0, 0, "path of the rig over the frames"},
      {"step", K::kNumber, 2.0, {}, 0, 100, "distance travelled between frames (m)"},
      {"circle_radius", K::kNumber, 12.0, {}, 1, 10000, "circle: radius of the path (m), turning left"},
      {"photometric", K::kNumber, 0.0, {}, 0, 3,
       "per-camera exposure, white balance, vignetting and noise: 0 none, 1 render --photometric's spread"},
      {"label_boundary", K::kInt, 0, {}, 0, 64, "label noise: class boundaries shift by up to this (px)"},
      {"label_confusion", K::kNumber, 0.0, {}, 0, 1, "label noise: share of blobs given a confusable class"},
      {"time_offset_ms", K::kNumber, 0.0, {}, 0, 1000,
       "camera c captures c times this after camera 0 (ms): moves animated objects, not the rig"},
  };
  return specs;
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

std::string Describe(const Json& v) { return v.dump(); }

// A value checked against its parameter and normalised (numbers as doubles, so 30 and 30.0 are
// one cell).
Json CheckValue(const ParamSpec& spec, const Json& v, const std::string& source, const std::string& where) {
  using K = ParamSpec::Kind;
  if (v.is_null()) {
    if (!spec.default_value.is_null()) Fail(source, where, "'" + spec.name + "' cannot be unset (null)");
    return nullptr;
  }
  switch (spec.kind) {
    case K::kInt: {
      if (!v.is_number_integer()) Fail(source, where, "must be a whole number, got " + Describe(v));
      const double x = v.get<double>();
      if (x < spec.min || x > spec.max) {
        Fail(source, where, Describe(v) + " is outside " + std::to_string(int64_t(spec.min)) + ".." +
                                std::to_string(int64_t(spec.max)));
      }
      return v.get<int64_t>();
    }
    case K::kNumber: {
      if (!v.is_number()) Fail(source, where, "must be a number, got " + Describe(v));
      const double x = v.get<double>();
      if (!std::isfinite(x) || x < spec.min || x > spec.max) {
        std::ostringstream range;
        range << spec.min << ".." << spec.max;
        Fail(source, where, Describe(v) + " is outside " + range.str());
      }
      return x;
    }
    case K::kBool:
      if (!v.is_boolean()) Fail(source, where, "must be true or false, got " + Describe(v));
      return v;
    case K::kChoice: {
      if (!v.is_string()) Fail(source, where, "must be one of the names listed by --list-params, got " + Describe(v));
      const std::string s = v.get<std::string>();
      for (const std::string& c : spec.choices) {
        if (c == s) return v;
      }
      std::string all;
      for (const std::string& c : spec.choices) all += (all.empty() ? "" : ", ") + c;
      Fail(source, where, "'" + s + "' is not one of " + all + DidYouMean(s, spec.choices));
    }
    case K::kText:
      if (!v.is_string() || v.get<std::string>().empty()) Fail(source, where, "must be a non-empty text");
      return v;
  }
  return v;
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
  static const std::vector<std::string> keys = {"semantics", "features", "peers"};
  static const std::vector<std::string> modes = {"none", "mask", "gated", "mask+gated"};
  static const std::vector<std::string> features = {"sift", "rootsift", "orb", "akaze"};
  static const std::vector<std::string> peers = {"colmap"};
  std::vector<std::string> sem = {"none", "mask"}, feat = {"sift"}, peer;
  if (!j.is_null()) {
    if (!j.is_object()) Fail(source, "methods", "must be a mapping with semantics, features and peers");
    for (const auto& [k, v] : j.items()) {
      const std::vector<std::string>* allowed = k == "semantics" ? &modes : k == "features" ? &features
                                                : k == "peers"   ? &peers : nullptr;
      if (!allowed) Fail(source, "methods." + k, "unknown key" + DidYouMean(k, keys));
      if (!v.is_array()) Fail(source, "methods." + k, "must be a list");
      std::vector<std::string> names;
      for (size_t i = 0; i < v.size(); ++i) {
        const std::string w = "methods." + k + "[" + std::to_string(i) + "]";
        if (!v[i].is_string()) Fail(source, w, "must be a name");
        const std::string n = v[i].get<std::string>();
        if (std::find(allowed->begin(), allowed->end(), n) == allowed->end()) {
          Fail(source, w, "unknown " + k + " '" + n + "'" + DidYouMean(n, *allowed));
        }
        if (std::find(names.begin(), names.end(), n) != names.end()) Fail(source, w, "'" + n + "' is listed twice");
        names.push_back(n);
      }
      (k == "semantics" ? sem : k == "features" ? feat : peer) = names;
    }
  }
  std::vector<SweepMethod> methods;
  for (const std::string& f : feat) {
    for (const std::string& s : sem) methods.push_back({f == "sift" ? s : f + ":" + s, "rigsim", s, f});
  }
  for (const std::string& p : peer) methods.push_back({p, p, "", ""});
  if (methods.empty()) Fail(source, "methods", "no method to run: give semantics (and features) or peers");
  return methods;
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

Json YamlToJson(const std::string& text, const std::string& source) {
  try {
    return YamlNodeToJson(YAML::Load(text), source);
  } catch (const YAML::Exception& e) {
    throw std::runtime_error(source + ":" + std::to_string(e.mark.line + 1) + ":" + std::to_string(e.mark.column + 1) +
                             ": invalid YAML: " + e.msg);
  }
}

SweepConfig ParseSweepConfig(const Json& j, const std::string& source) {
  static const std::vector<std::string> keys = {"name", "description", "base", "seeds", "methods", "grid", "zip", "studies"};
  if (!j.is_object()) Fail(source, "", "a sweep config is a mapping (name, base, seeds, methods, grid/zip or studies)");
  for (const auto& [k, v] : j.items()) {
    if (std::find(keys.begin(), keys.end(), k) == keys.end()) {
      Fail(source, k, "unknown key" + DidYouMean(k, keys) + "; a config has " +
                          "name, description, base, seeds, methods, grid, zip and studies");
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

std::string FormatParamValue(const Json& v) {
  if (v.is_null()) return "unset";
  if (v.is_string()) return v.get<std::string>();
  if (v.is_number_float()) {
    char buf[32];
    std::snprintf(buf, sizeof buf, "%g", v.get<double>());
    return buf;
  }
  return v.dump();
}

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
  Json semantics = Json::array(), features = Json::array(), peers = Json::array();
  const auto add = [](Json& list, const std::string& v) {
    if (std::find(list.begin(), list.end(), Json(v)) == list.end()) list.push_back(v);
  };
  for (const SweepMethod& m : config.methods) {
    if (m.tool == "rigsim") {
      add(semantics, m.semantics);
      add(features, m.features);
    } else {
      add(peers, m.tool);
    }
  }
  return {{"name", config.name},
          {"base", config.base},
          {"seeds", config.seeds},
          {"methods", {{"semantics", semantics}, {"features", features}, {"peers", peers}}},
          {"studies", studies}};
}

std::string SweepHash(const SweepConfig& config) {
  Json what = Json::array();
  for (const SweepCell& c : ExpandCells(config)) what.push_back(c.params);
  Json methods = Json::array();
  for (const SweepMethod& m : config.methods) methods.push_back(m.name);
  return StableHash(Json{{"cells", what}, {"methods", methods}}.dump());
}

}  // namespace rigsim
