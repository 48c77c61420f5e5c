// What a sweep runs: a config file (JSON or YAML) names the parameters of a calibration
// experiment (scene, rig, lens, images, label noise, ...), the values to sweep, the seeds and the
// methods; it expands into cells, each a complete set of parameters.
//
//   name: lens-study
//   base: {rig: ring, cameras: 4, overlap: 30, width: 640, height: 360}  # defaults for every cell
//   seeds: [1, 2, 3]                          # every cell once per seed
//   methods: {semantics: [none, mask], features: [sift], peers: [colmap]}
//   #        time: [synchronised, estimated] calibrates each way too (capture times estimated)
//   grid: {overlap: [5, 15, 30, 50]}           # crossed: every combination of these axes
//   zip: {lens: [pinhole, fisheye], fisheye_fov: [90, 190]}  # taken together, value i with value i
//
// or, for several sweeps around one base, `studies: [{name, set, grid, zip}, ...]` (`set` fixes
// parameters for that study only). A cell that several studies share (the base point) runs once.
// `claims: {title, list: [{claim, metric, compare, holds, note}, ...]}` are what the summary
// tests, each semantic mode against `none` (default: the thesis's, ThesisClaimsJson()).
// Every parameter has a default (CellParamSpecs); a misspelt one is refused with a suggestion.
// The rig's parameters are those rigs/rig_params.h describes for make-rig too.
#pragma once

#include <cstdint>
#include <filesystem>
#include <string>
#include <vector>

#include <nlohmann/json.hpp>

#include "common/param_spec.h"

namespace rigsim {

// Every cell parameter (its name in the config and the results, type, default, range, help), in
// the order of the results' columns: the scene's, the rig's (rigs/rig_params.h, with the sweep's
// defaults), the render's, the rig's path, and the images' errors.
const std::vector<ParamSpec>& CellParamSpecs();

// Whether a cell holds `spec` only where its value is not the default (placement, ego_vehicle):
// parameters that came after sweeps had written their folders, kept out of the cells of a config
// that leaves them at their default so that its keys, records and results stay what they were.
bool HeldWhenSet(const ParamSpec& spec);

// The value of parameter `name` in a cell's `params`, its default where the cell does not hold it
// (HeldWhenSet). Throws std::out_of_range for a name that is no cell parameter.
nlohmann::ordered_json CellParam(const nlohmann::ordered_json& params, const std::string& name);

// A sweep axis: a parameter and the values it takes.
struct SweepAxis {
  std::string param;
  std::vector<nlohmann::ordered_json> values;
};

struct SweepStudy {
  std::string name;
  nlohmann::ordered_json set = nlohmann::ordered_json::object();  // parameters fixed for this study
  std::vector<SweepAxis> grid;                    // crossed
  std::vector<SweepAxis> zip;                     // taken together (equal lengths)
  // The parameters this study varies, grid first.
  std::vector<std::string> VariedParams() const;
};

// The peer tools a sweep can run beside rigsim: "colmap".
std::vector<std::string> SweepPeerNames();

// How rigsim takes the cameras' capture times (methods.time): `synchronised` (as they are: a
// camera capturing at another time than the first is not calibrated), `estimated` (each camera's
// time offset estimated in the bundle adjustment, calibrate --estimate-time-offsets) or
// `estimated+rolling-shutter` (each camera's readout time too, --rolling-shutter).
std::vector<std::string> SweepTimeNames();

// A way of calibrating a cell's images: rigsim in one semantic mode with one feature type and one
// way of taking capture times, or a peer tool.
struct SweepMethod {
  // "none", "mask", "orb:none" (feature type named unless SIFT), "none@estimated" (capture times
  // named unless synchronised), "colmap"
  std::string name;
  std::string tool;       // "rigsim" or "colmap"
  std::string semantics;  // rigsim: none, mask, gated, mask+gated
  std::string features;   // rigsim: sift, rootsift, orb, akaze
  std::string time;       // rigsim: synchronised, estimated, estimated+rolling-shutter (SweepTimeNames)
};

// The name of rigsim's method with these features, semantic mode and capture times.
std::string SweepMethodName(const std::string& features, const std::string& semantics, const std::string& time);

// A claim about the semantic modes, tested on a metric of the rows: each cell's row of a mode
// against its row without semantics, the difference (or ratio) judged by `holds`.
struct ClaimSpec {
  std::string claim;      // in words: "gives a larger share of correct matches"
  std::string metric;     // a metric of SweepMetricSpecs
  bool ratio = false;     // compare mode / none instead of mode - none
  std::string op;         // ">", ">=", "<" or "<=": holds when `difference op value`
  double value = 0.0;
  std::string note;       // said once above the claims' table (what the threshold means); may be empty
  bool Holds(double difference) const;
};

struct ClaimSet {
  std::string title;  // report.md's heading
  std::vector<ClaimSpec> claims;
};

struct SweepConfig {
  std::string name;
  std::filesystem::path source;  // the config file; relative scene paths are relative to its folder
  nlohmann::ordered_json base = nlohmann::ordered_json::object();
  std::vector<uint64_t> seeds = {1};
  std::vector<SweepMethod> methods;
  std::vector<SweepStudy> studies;
  ClaimSet claims;  // the thesis's unless the config gives its own
};

struct SweepCell {
  int index = 0;                    // position in the sweep (0-based), for people
  std::string key;                  // 16 hex digits of the parameters' hash: names the cell's files
  // Every parameter of CellParamSpecs, defaults filled in (but those HeldWhenSet at their
  // default: read them with CellParam), and "seed".
  nlohmann::ordered_json params;
  std::vector<std::string> studies; // the studies that include it
};

// Reads a .json, .yaml or .yml config. Throws std::runtime_error naming the file and the key
// (e.g. "sweep.yaml: studies[1].grid.overlpa: unknown parameter (did you mean 'overlap'?)").
SweepConfig ReadSweepConfig(const std::filesystem::path& path);
// The same from parsed JSON; `source` names it in errors.
SweepConfig ParseSweepConfig(const nlohmann::ordered_json& j, const std::string& source);
// YAML text as JSON (plain scalars become numbers, booleans and null as YAML 1.2 reads them;
// quoted ones stay strings). Throws std::runtime_error("<source>:<line>:<column>: ...").
nlohmann::ordered_json YamlToJson(const std::string& text, const std::string& source);

// The cells of every study, in study order, each study's combinations in order (the first axis
// varying slowest), seeds innermost; a cell already produced by an earlier study is not repeated.
std::vector<SweepCell> ExpandCells(const SweepConfig& config);

// Claims as a config writes them, and back (std::runtime_error naming `source` and the key).
nlohmann::ordered_json ClaimSetToJson(const ClaimSet& claims);
ClaimSet ParseClaimSet(const nlohmann::ordered_json& j, const std::string& source);

// Hash (16 hex digits) of what a sweep computes: the cells' parameters and the methods. Shards and
// resumed runs of one sweep share it.
std::string SweepHash(const SweepConfig& config);

// The config as JSON (what was read, normalised), recorded in the results.
nlohmann::ordered_json SweepConfigToJson(const SweepConfig& config);

}  // namespace rigsim
