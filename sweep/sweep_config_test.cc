#include "sweep/sweep_config.h"

#include <algorithm>
#include <set>
#include <utility>

#include <gmock/gmock.h>
#include <gtest/gtest.h>

#include "pipeline/calibration_run.h"
#include "sweep/cell_runner.h"
#include "sweep/suites.h"
#include "testing/expect_error.h"

namespace rigsim {
namespace {

using Json = nlohmann::ordered_json;

// A call that reads `text` as sweep.json.
auto Parsing(const std::string& text) {
  return [j = Json::parse(text)] { ParseSweepConfig(j, "sweep.json"); };
}

TEST(SweepConfig, GridCrossesAxesZipPairsThemAndSeedsAreInnermost) {
  const Json j = Json::parse(R"({
    "name": "t", "seeds": [1, 2],
    "base": {"width": 320, "height": 180},
    "grid": {"overlap": [10, 20], "frames": [2, 3]},
    "zip": {"lens": ["pinhole", "fisheye"], "fisheye_fov": [90, 190]}})");
  const SweepConfig c = ParseSweepConfig(j, "sweep.json");
  const std::vector<SweepCell> cells = ExpandCells(c);
  ASSERT_EQ(cells.size(), 2u * 2u * 2u * 2u);
  // First axis slowest, zip next to last, seed innermost.
  EXPECT_EQ(cells[0].params["overlap"], 10.0);
  EXPECT_EQ(cells[0].params["frames"], 2);
  EXPECT_EQ(cells[0].params["lens"], "pinhole");
  EXPECT_EQ(cells[0].params["fisheye_fov"], 90.0);
  EXPECT_EQ(cells[0].params["seed"], 1);
  EXPECT_EQ(cells[1].params["seed"], 2);
  EXPECT_EQ(cells[2].params["lens"], "fisheye");
  EXPECT_EQ(cells[2].params["fisheye_fov"], 190.0);
  EXPECT_EQ(cells[4].params["frames"], 3);
  EXPECT_EQ(cells[8].params["overlap"], 20.0);
  // Base values and defaults are filled in.
  EXPECT_EQ(cells[5].params["width"], 320);
  EXPECT_EQ(cells[5].params["rig"], "ring");
  EXPECT_EQ(cells[5].params["scene_seed"], nullptr);
  for (size_t i = 0; i < cells.size(); ++i) {
    EXPECT_EQ(cells[i].index, static_cast<int>(i));
    EXPECT_EQ(cells[i].key.size(), 16u);
    for (size_t k = 0; k < i; ++k) EXPECT_NE(cells[i].key, cells[k].key);
  }
  // Methods default to none and mask with SIFT.
  ASSERT_EQ(c.methods.size(), 2u);
  EXPECT_EQ(c.methods[0].name, "none");
  EXPECT_EQ(c.methods[1].name, "mask");
}

TEST(SweepConfig, StudiesShareTheirCommonCellAndSetFixesParameters) {
  const Json j = Json::parse(R"({
    "base": {"overlap": 30},
    "methods": {"semantics": ["none"], "features": ["sift", "orb"], "peers": ["colmap"]},
    "studies": [
      {"name": "overlap", "grid": {"overlap": [15, 30]}},
      {"name": "frames", "grid": {"frames": [2, 3]}},
      {"name": "wide", "set": {"rig": "wide-baseline"}, "grid": {"baseline": [0.5, 2]}}]})");
  const SweepConfig c = ParseSweepConfig(j, "sweep.json");
  const std::vector<SweepCell> cells = ExpandCells(c);
  // overlap=30 with frames=3 (the default) is the base point of both first studies: one cell.
  ASSERT_EQ(cells.size(), 5u);
  EXPECT_EQ(cells[1].params["overlap"], 30.0);
  EXPECT_EQ(cells[1].studies, (std::vector<std::string>{"overlap", "frames"}));
  EXPECT_EQ(cells[3].params["rig"], "wide-baseline");
  EXPECT_EQ(cells[3].params["baseline"], 0.5);
  EXPECT_EQ(cells[4].params["baseline"], 2.0);  // an integer in the file is the same number
  std::vector<std::string> names;
  for (const SweepMethod& m : c.methods) names.push_back(m.name);
  EXPECT_EQ(names, (std::vector<std::string>{"none", "orb:none", "colmap"}));
}

// `sensor` takes the render's presets by name (ideal by default); a preset beside a photometric
// scale, or a misspelt preset, is refused naming the file.
TEST(SweepConfig, SensorIsAPresetNameAndExcludesPhotometric) {
  const SweepConfig c = ParseSweepConfig(Json::parse(R"({"grid": {"sensor": ["ideal", "automotive"]}})"), "sweep.json");
  const std::vector<SweepCell> cells = ExpandCells(c);
  ASSERT_EQ(cells.size(), 2u);
  EXPECT_EQ(cells[0].params["sensor"], "ideal");
  EXPECT_EQ(cells[1].params["sensor"], "automotive");
  EXPECT_EQ(ExpandCells(ParseSweepConfig(Json::parse(R"({"base": {"overlap": 20}})"), "s.json"))[0].params["sensor"], "ideal");
  EXPECT_THAT(Parsing(R"({"base": {"sensor": "automotve"}})"),
              ThrowsWith<std::runtime_error>("sweep.json: base.sensor: 'automotve' is not one of ideal, machine-vision, "
                                             "automotive, phone (did you mean 'automotive'?)"));
  EXPECT_THAT(Parsing(R"({"base": {"photometric": 1}, "grid": {"sensor": ["ideal", "phone"]}})"),
              ThrowsWith<std::runtime_error>("sweep.json: a cell has sensor phone and photometric 1: the sensor preset "
                                             "sets the photometric magnitudes itself; give photometric 0 with it"));
}

// `intrinsics_error` (0 by default) reaches each rigsim calibration of the cell with the cell's
// seed, as calibrate --intrinsics-error and --intrinsics-error-seed; out of 0 to 0.5 it is refused.
TEST(SweepConfig, IntrinsicsErrorReachesTheCalibrationWithTheCellsSeed) {
  const SweepConfig c =
      ParseSweepConfig(Json::parse(R"({"grid": {"intrinsics_error": [0, 0.02]}, "seeds": [3]})"), "sweep.json");
  const std::vector<SweepCell> cells = ExpandCells(c);
  ASSERT_EQ(cells.size(), 2u);
  const CalibrationRunOptions zero = CellCalibrationOptions(c.methods.at(0), cells[0].params, 1);
  const CalibrationRunOptions some = CellCalibrationOptions(c.methods.at(0), cells[1].params, 1);
  EXPECT_FALSE(zero.intrinsics_error.Enabled());
  EXPECT_EQ(some.intrinsics_error.error, 0.02);
  EXPECT_EQ(some.intrinsics_error.seed, 3u);
  EXPECT_EQ(ExpandCells(ParseSweepConfig(Json::parse(R"({"base": {"overlap": 20}})"), "s.json"))[0].params["intrinsics_error"], 0.0);
  EXPECT_THAT(Parsing(R"({"base": {"intrinsics_error": 0.6}})"),
              ThrowsWith<std::runtime_error>("sweep.json: base.intrinsics_error: 0.6 is outside 0 to 0.5"));
  EXPECT_THAT(Parsing(R"({"grid": {"intrinsics_error": [0.01, -0.01]}})"),
              ThrowsWith<std::runtime_error>("sweep.json: grid.intrinsics_error[1]: -0.01 is outside 0 to 0.5"));
}

TEST(SweepConfig, PlacementAndEgoVehicleAreTakenAndCheckedBeforeAnythingRuns) {
  const std::vector<SweepCell> cells = ExpandCells(ParseSweepConfig(Json::parse(R"({
    "base": {"ego_vehicle": true}, "grid": {"placement": ["structure", "road"]}})"), "sweep.json"));
  ASSERT_EQ(cells.size(), 2u);
  EXPECT_EQ(CellParam(cells[0].params, "placement"), "structure");
  EXPECT_EQ(CellParam(cells[1].params, "placement"), "road");
  EXPECT_EQ(CellParam(cells[1].params, "ego_vehicle"), true);
  EXPECT_EQ(CellRigSpec(cells[0].params, ".").placement.mode, PlacementMode::kStructure);
  EXPECT_EQ(CellRigSpec(cells[1].params, ".").placement.mode, PlacementMode::kRoad);
  EXPECT_NE(cells[0].key, cells[1].key);
  // Bad values stop the config where it is read, naming the file, the key and what is accepted.
  EXPECT_THAT(Parsing(R"({"base": {"placement": "roof"}})"),
              ThrowsWith<std::runtime_error>("sweep.json: base.placement: 'roof' is not one of structure, road"));
  EXPECT_THAT(Parsing(R"({"studies": [{"name": "s", "grid": {"ego_vehicle": [false, "yes"]}}]})"),
              ThrowsWith<std::runtime_error>("sweep.json: studies[0].grid.ego_vehicle[1]: must be true or false, got \"yes\""));
}

TEST(SweepConfig, ConfigsThatLeaveOutPlacementAndEgoVehicleKeepTheirKeys) {
  const auto cells = [](const std::string& text) { return ExpandCells(ParseSweepConfig(Json::parse(text), "sweep.json")); };
  const std::vector<SweepCell> without = cells(R"({"name": "t", "seeds": [7], "grid": {"overlap": [10, 20]}})");
  ASSERT_EQ(without.size(), 2u);
  // The keys this config's cells had before either parameter existed: they name the records of its
  // folders, which a run resumes from.
  EXPECT_EQ(without[0].key, "93b96ac75d25e87b");
  EXPECT_EQ(without[1].key, "906aae330a7c3764");
  // Given at their defaults, they are the same cells; set otherwise, other cells.
  const std::vector<SweepCell> defaults = cells(
      R"({"name": "t", "seeds": [7], "base": {"placement": "structure", "ego_vehicle": false}, "grid": {"overlap": [10, 20]}})");
  const std::vector<SweepCell> road = cells(R"({"name": "t", "seeds": [7], "base": {"placement": "road"}, "grid": {"overlap": [10, 20]}})");
  const std::vector<SweepCell> car = cells(R"({"name": "t", "seeds": [7], "base": {"ego_vehicle": true}, "grid": {"overlap": [10, 20]}})");
  for (size_t i = 0; i < without.size(); ++i) {
    EXPECT_FALSE(without[i].params.contains("placement"));
    EXPECT_FALSE(without[i].params.contains("ego_vehicle"));
    EXPECT_EQ(defaults[i].key, without[i].key);
    EXPECT_EQ(defaults[i].params, without[i].params);
    EXPECT_NE(road[i].key, without[i].key);
    EXPECT_NE(car[i].key, without[i].key);
    EXPECT_NE(road[i].key, car[i].key);
  }
}

TEST(SweepConfig, HashesDependOnWhatIsComputedOnly) {
  const Json a = Json::parse(R"({"name": "a", "grid": {"overlap": [10, 20]}})");
  Json b = a;
  b["name"] = "b";  // the name does not change what is computed
  EXPECT_EQ(SweepHash(ParseSweepConfig(a, "a.json")), SweepHash(ParseSweepConfig(b, "b.json")));
  Json c = a;
  c["grid"]["overlap"] = {10, 25};
  EXPECT_NE(SweepHash(ParseSweepConfig(a, "a.json")), SweepHash(ParseSweepConfig(c, "c.json")));
  Json d = a;
  d["methods"] = {{"semantics", {"none"}}};
  EXPECT_NE(SweepHash(ParseSweepConfig(a, "a.json")), SweepHash(ParseSweepConfig(d, "d.json")));
}

TEST(SweepConfig, CaptureTimesAreAMethodAxisCrossedWithTheModes) {
  const SweepConfig c = ParseSweepConfig(Json::parse(R"({
    "methods": {"semantics": ["none", "mask"], "time": ["synchronised", "estimated", "estimated+rolling-shutter"],
                "peers": ["colmap"]}})"),
                                         "sweep.json");
  std::vector<std::string> names;
  for (const SweepMethod& m : c.methods) names.push_back(m.name);
  EXPECT_EQ(names, (std::vector<std::string>{"none", "mask", "none@estimated", "mask@estimated",
                                             "none@estimated+rolling-shutter", "mask@estimated+rolling-shutter",
                                             "colmap"}));
  EXPECT_EQ(c.methods[0].time, "synchronised");
  EXPECT_EQ(c.methods[3].time, "estimated");
  EXPECT_EQ(c.methods[3].semantics, "mask");
  EXPECT_EQ(c.methods[4].time, "estimated+rolling-shutter");
  EXPECT_EQ(c.methods[6].time, "");  // a peer takes the images as they are
  EXPECT_EQ(SweepMethodName("orb", "none", "estimated"), "orb:none@estimated");
  // It reads back, and a config without `time` keeps its methods' names and its hash.
  const SweepConfig back = ParseSweepConfig(SweepConfigToJson(c), "sweep.json");
  EXPECT_EQ(SweepHash(back), SweepHash(c));
  EXPECT_EQ(back.methods.size(), c.methods.size());
  const Json plain = Json::parse(R"({"methods": {"semantics": ["none"]}})");
  Json synchronised = plain;
  synchronised["methods"]["time"] = {"synchronised"};
  EXPECT_EQ(SweepHash(ParseSweepConfig(plain, "a.json")), SweepHash(ParseSweepConfig(synchronised, "a.json")));
  EXPECT_FALSE(SweepConfigToJson(ParseSweepConfig(plain, "a.json"))["methods"].contains("time"));
  using E = std::runtime_error;
  EXPECT_THAT(Parsing(R"({"methods": {"time": ["estimate"]}})"),
              ThrowsExactly<E>("sweep.json: methods.time[0]: unknown time 'estimate' (did you mean 'estimated'?)"));
  EXPECT_THAT(Parsing(R"({"methods": {"time": ["async"]}})"),
              ThrowsExactly<E>("sweep.json: methods.time[0]: unknown time 'async'; give synchronised, "
                               "estimated, estimated+rolling-shutter"));
  EXPECT_THAT(Parsing(R"({"methods": {"tiem": ["estimated"]}})"),
              ThrowsExactly<E>("sweep.json: methods.tiem: unknown key (did you mean 'time'?)"));
}

TEST(SweepConfig, ItsJsonReadsBackAsTheSameSweep) {
  const SweepConfig c = ParseSweepConfig(Json::parse(R"({
    "name": "round", "seeds": [4, 2], "base": {"width": 320},
    "methods": {"semantics": ["mask", "none"], "features": ["orb", "sift"], "peers": ["colmap"]},
    "studies": [{"name": "a", "set": {"rig": "stereo"}, "grid": {"baseline": [0.2, 0.4]}},
                {"name": "b", "zip": {"lens": ["pinhole", "fisheye"], "fisheye_fov": [190, 150]}}]})"),
                                         "round.json");
  const SweepConfig back = ParseSweepConfig(SweepConfigToJson(c), "sweep.json");
  EXPECT_EQ(SweepHash(back), SweepHash(c));
  EXPECT_EQ(back.name, "round");
  ASSERT_EQ(back.methods.size(), c.methods.size());
  for (size_t i = 0; i < c.methods.size(); ++i) EXPECT_EQ(back.methods[i].name, c.methods[i].name);
  const std::vector<SweepCell> a = ExpandCells(c), b = ExpandCells(back);
  ASSERT_EQ(a.size(), b.size());
  for (size_t i = 0; i < a.size(); ++i) {
    EXPECT_EQ(a[i].key, b[i].key);
    EXPECT_EQ(a[i].studies, b[i].studies);
  }
  // A single top-level study keeps its name (the config's).
  const SweepConfig one = ParseSweepConfig(Json::parse(R"({"name": "solo", "grid": {"frames": [2, 3]}})"), "s.json");
  EXPECT_EQ(ParseSweepConfig(SweepConfigToJson(one), "sweep.json").studies[0].name, "solo");
}

TEST(SweepConfig, ErrorsNameTheFileTheKeyAndSuggestAFix) {
  using E = std::runtime_error;
  EXPECT_THAT(Parsing(R"({"grid": {"overlpa": [10]}})"),
              ThrowsExactly<E>("sweep.json: grid.overlpa: unknown parameter (did you mean 'overlap'?); "
                               "`rigsim sweep --list-params` lists them"));
  EXPECT_THAT(Parsing(R"({"base": {"rig": "rign"}})"),
              ThrowsExactly<E>("sweep.json: base.rig: 'rign' is not one of ring, stereo, surround, wide-baseline, "
                               "file (did you mean 'ring'?)"));
  EXPECT_THAT(Parsing(R"({"grid": {"overlap": [10, 200]}})"),
              ThrowsExactly<E>("sweep.json: grid.overlap[1]: 200 is outside 0 to 99"));
  EXPECT_THAT(Parsing(R"({"grid": {"cameras": [2.5]}})"),
              ThrowsExactly<E>("sweep.json: grid.cameras[0]: must be a whole number, got 2.5"));
  EXPECT_THAT(Parsing(R"({"zip": {"lens": ["pinhole"], "hfov": [60, 90]}})"),
              ThrowsExactly<E>("sweep.json: zip: 'hfov' has 2 values and 'lens' 1: zipped axes need as many"));
  EXPECT_THAT(Parsing(R"({"methods": {"semantics": ["mask+gatd"]}})"),
              ThrowsExactly<E>("sweep.json: methods.semantics[0]: unknown semantics 'mask+gatd' "
                               "(did you mean 'mask+gated'?)"));
  EXPECT_THAT(Parsing(R"({"sedes": [1]})"),
              ThrowsExactly<E>("sweep.json: sedes: unknown key (did you mean 'seeds'?); a config has name, "
                               "description, base, seeds, methods, grid, zip, studies and claims"));
  EXPECT_THAT(Parsing(R"({"studies": [{"grid": {"frames": [2]}}]})"),
              ThrowsExactly<E>("sweep.json: studies[0]: a study needs a name"));
  EXPECT_THAT(Parsing(R"({"grid": {"frames": [2, 2]}})"),
              ThrowsExactly<E>("sweep.json: grid.frames: value 2 is listed twice"));
  EXPECT_THAT(Parsing(R"({"base": {"seed": 3}})"),
              ThrowsExactly<E>("sweep.json: base.seed: give seeds with the top-level 'seeds' list, not as a parameter"));
  // A zipped axis may repeat a value; the same combination twice is refused.
  EXPECT_NO_THROW(Parsing(R"({"zip": {"lens": ["pinhole", "fisheye"], "fisheye_fov": [190, 190]}})")());
  EXPECT_THAT(Parsing(R"({"zip": {"lens": ["fisheye", "fisheye"], "fisheye_fov": [190, 190]}})"),
              ThrowsExactly<E>("sweep.json: zip: values [\"fisheye\",190.0] are listed twice"));
}

TEST(SweepConfig, YamlReadsLikeJson) {
  const Json y = YamlToJson(R"(
name: lens
seeds: 2
base: {width: 320, scene: "1"}
grid:
  overlap: [10, 20.5]
  animated: [true, false]
  hfov: [~]
)",
                            "sweep.yaml");
  EXPECT_EQ(y["seeds"], 2);
  EXPECT_EQ(y["base"]["width"], 320);
  EXPECT_TRUE(y["base"]["width"].is_number_integer());
  EXPECT_EQ(y["base"]["scene"], "1");  // quoted: stays text
  EXPECT_EQ(y["grid"]["overlap"][1], 20.5);
  EXPECT_EQ(y["grid"]["animated"][0], true);
  EXPECT_TRUE(y["grid"]["hfov"][0].is_null());
  const SweepConfig c = ParseSweepConfig(y, "sweep.yaml");
  EXPECT_EQ(c.seeds, (std::vector<uint64_t>{1, 2}));
  EXPECT_THAT([] { YamlToJson("grid: [1, 2\n", "bad.yaml"); },
              testing::ThrowsMessage<std::runtime_error>(testing::StartsWith("bad.yaml:")));
}

}  // namespace
}  // namespace rigsim

namespace rigsim {
namespace {

// The params of a suite's study's cells.
std::vector<nlohmann::ordered_json> StudyCells(const SweepConfig& config, const std::string& study) {
  std::vector<nlohmann::ordered_json> params;
  for (const SweepCell& c : ExpandCells(config)) {
    if (std::find(c.studies.begin(), c.studies.end(), study) != c.studies.end()) params.push_back(c.params);
  }
  return params;
}

TEST(Suites, ThesisOverlapGoesToNoneAcrossFramesAndPaths) {
  const SweepConfig full = ParseSweepConfig(SuiteConfig("thesis", "full"), "--suite thesis");
  std::set<double> overlaps;
  std::set<int> frames;
  std::set<std::string> paths;
  for (const nlohmann::ordered_json& p : StudyCells(full, "overlap")) {
    overlaps.insert(p["overlap"].get<double>());
    frames.insert(p["frames"].get<int>());
    paths.insert(p["trajectory"].get<std::string>());
    EXPECT_EQ(p["hfov"], 85.0);  // four cameras part all round at 0 %
  }
  EXPECT_EQ(overlaps, (std::set<double>{0, 2, 5, 15, 30, 50}));
  EXPECT_EQ(frames, (std::set<int>{3, 12, 30}));
  EXPECT_EQ(paths, (std::set<std::string>{"straight", "circle", "handheld"}));
  EXPECT_EQ(StudyCells(full, "overlap").size(), 6u * 3 * 3 * 3);  // x 3 seeds
  // Small stays quick: three frames, none and 15 %, two paths, one seed.
  const SweepConfig small = ParseSweepConfig(SuiteConfig("thesis", "small"), "--suite thesis");
  EXPECT_EQ(StudyCells(small, "overlap").size(), 4u);
  for (const SweepCell& c : ExpandCells(small)) {
    const bool dynamics = std::find(c.studies.begin(), c.studies.end(), "dynamics") != c.studies.end();
    EXPECT_EQ(c.params["frames"], dynamics ? 6 : 3);
  }
}

TEST(Suites, ThesisDynamicsMovesTheWorldAndTheCapturesOnAPathThatShowsTime) {
  const SweepConfig full = ParseSweepConfig(SuiteConfig("thesis", "full"), "--suite thesis");
  std::set<double> traffic, offsets, readouts;
  for (const nlohmann::ordered_json& p : StudyCells(full, "dynamics")) {
    EXPECT_EQ(p["animated"], true);
    EXPECT_EQ(p["trajectory"], "handheld");  // a circle at constant speed hides capture times
    traffic.insert(p["traffic"].get<double>());
    offsets.insert(p["time_offset_ms"].get<double>());
    readouts.insert(p["readout_ms"].get<double>());
  }
  EXPECT_EQ(traffic, (std::set<double>{0, 0.5, 1}));
  EXPECT_EQ(offsets, (std::set<double>{0, 10, 30}));
  EXPECT_EQ(readouts, (std::set<double>{0, 30}));
  const SweepConfig small = ParseSweepConfig(SuiteConfig("thesis", "small"), "--suite thesis");
  EXPECT_EQ(StudyCells(small, "dynamics").size(), 2u);
}

TEST(Suites, MotionTakesTheUsersRigThroughEveryPathAndFrameCount) {
  SuiteInputs inputs;
  inputs.rig_file = "/somewhere/my_rig.json";
  inputs.scene = "plaza";
  const SweepConfig full = ParseSweepConfig(SuiteConfig("motion", "full", inputs), "--suite motion");
  std::set<std::pair<int, std::string>> points;
  for (const SweepCell& c : ExpandCells(full)) {
    EXPECT_EQ(c.params["rig"], "file");
    EXPECT_EQ(c.params["rig_file"], "/somewhere/my_rig.json");
    EXPECT_EQ(c.params["scene"], "plaza");
    points.insert({c.params["frames"].get<int>(), c.params["trajectory"].get<std::string>()});
  }
  EXPECT_EQ(points.size(), 3u * 5);
  EXPECT_TRUE(points.count({30, "handheld"}));
  EXPECT_TRUE(points.count({3, "figure-eight"}));
  EXPECT_EQ(full.studies.size(), 3u);  // a plot per frame count
  // Either size runs every path over three seeds: a path places a rig in a share of runs.
  const SweepConfig small = ParseSweepConfig(SuiteConfig("motion", "small", inputs), "--suite motion");
  EXPECT_EQ(small.seeds.size(), 3u);
  EXPECT_EQ(full.seeds.size(), 3u);
  EXPECT_EQ(ExpandCells(small).size(), 2u * 5 * 3);
  // Without a rig it is refused; the thesis suite takes none.
  EXPECT_THROW(SuiteConfig("motion", "small"), std::invalid_argument);
  EXPECT_THROW(SuiteConfig("thesis", "small", inputs), std::invalid_argument);
  EXPECT_THROW(SuiteConfig("motoin", "small", inputs), std::invalid_argument);
}

// The suites render through the automotive preset unless told otherwise, without the rig's car;
// `ideal` gives the config without a sensor, whose cells are the same as before there was one.
TEST(Suites, RenderThroughTheAutomotiveSensorUnlessAskedForIdeal) {
  SuiteInputs motion;
  motion.rig_file = "/somewhere/my_rig.json";
  for (const auto& [name, inputs] : {std::pair<std::string, SuiteInputs>{"thesis", {}}, {"motion", motion}}) {
    SCOPED_TRACE(name);
    EXPECT_EQ(std::string(kSuiteDefaultSensor), "automotive");
    const SweepConfig automotive = ParseSweepConfig(SuiteConfig(name, "small", inputs), "--suite " + name);
    for (const SweepCell& c : ExpandCells(automotive)) {
      EXPECT_EQ(c.params.at("sensor"), "automotive") << c.key;
      EXPECT_EQ(CellParam(c.params, "ego_vehicle"), false) << c.key;
    }
    SuiteInputs ideal = inputs;
    ideal.sensor = "ideal";
    const Json ideal_json = SuiteConfig(name, "small", ideal);
    EXPECT_FALSE(ideal_json["base"].contains("sensor"));
    const std::vector<SweepCell> ideal_cells = ExpandCells(ParseSweepConfig(ideal_json, "--suite " + name));
    ASSERT_EQ(ideal_cells.size(), ExpandCells(automotive).size());
    for (size_t i = 0; i < ideal_cells.size(); ++i) {
      EXPECT_EQ(ideal_cells[i].params.at("sensor"), "ideal");
      EXPECT_NE(ideal_cells[i].key, ExpandCells(automotive)[i].key);  // another render: another cell
    }
    SuiteInputs car = inputs;
    car.ego_vehicle = true;
    for (const SweepCell& c : ExpandCells(ParseSweepConfig(SuiteConfig(name, "small", car), "--suite " + name))) {
      EXPECT_EQ(c.params.at("ego_vehicle"), true) << c.key;
      EXPECT_EQ(c.params.at("sensor"), "automotive") << c.key;
    }
    SuiteInputs typo = inputs;
    typo.sensor = "automotve";
    EXPECT_THAT([&] { SuiteConfig(name, "small", typo); },
                ThrowsWith<std::invalid_argument>("--sensor: unknown sensor preset 'automotve' (did you mean 'automotive'?)",
                                                  "ideal"));
  }
}

}  // namespace
}  // namespace rigsim
