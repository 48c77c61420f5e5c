// rigsim sweep and rigsim evaluate through the built binary: a tiny sweep end to end (render,
// calibrate, score, results, plots, report), resuming, and Ctrl-C in the middle of a cell.
#include <algorithm>
#include <csignal>
#include <filesystem>
#include <fstream>
#include <set>
#include <sstream>
#include <thread>
#include <utility>

#include <gtest/gtest.h>
#include <nlohmann/json.hpp>

#include "testing/temp_dir.h"
#include "tests/rigsim_cli.h"

namespace rigsim {
namespace {

namespace fs = std::filesystem;

// Two cells of a 2-camera ring on the street at 320x180, two frames, SIFT without and with the
// semantic mask: seconds per cell.
void WriteTinyConfig(const fs::path& path) {
  WriteFile(path, R"(# a tiny sweep for the test suite
name: tiny
base: {rig: ring, cameras: 2, spacing: 40, width: 320, height: 180, frames: 2, spp: 1}
methods: {semantics: [none, mask]}
grid:
  radius: [0.3, 0.6]
)");
}

int CountLines(const std::string& text) { return static_cast<int>(std::count(text.begin(), text.end(), '\n')); }

TEST(SweepCli, ATinySweepRunsEndToEndAndResumes) {
  const TempDir dir;
  WriteTinyConfig(dir / "tiny.yaml");
  const fs::path out = dir / "out";
  const CliResult run = RunRigsim({"sweep", (dir / "tiny.yaml").string(), "--out", out.string()}, dir / "run1",
                                  std::chrono::seconds(300));
  ASSERT_EQ(run.code, 0) << run.err;
  EXPECT_NE(run.out.find("sweep tiny: 2 cells (2 run now, 0 from an earlier run)"), std::string::npos) << run.out;
  const std::string csv = ReadFile(out / "results.csv");
  EXPECT_EQ(CountLines(csv), 1 + 2 * 2) << csv;  // header + 2 cells x 2 methods
  EXPECT_NE(csv.find(",none,rigsim,none,sift,synchronised,ok,"), std::string::npos) << csv;
  EXPECT_NE(csv.find(",mask,rigsim,mask,sift,synchronised,ok,"), std::string::npos) << csv;
  // Every row is scored against the truth: the rig has two cameras.
  std::istringstream jsonl(ReadFile(out / "results.jsonl"));
  std::string line;
  int rows = 0;
  while (std::getline(jsonl, line)) {
    const nlohmann::json row = nlohmann::json::parse(line);
    EXPECT_EQ(row["cameras"], 2);
    EXPECT_TRUE(row["overlap_pct"].is_number()) << line;
    EXPECT_TRUE(row["auc_pairs_5deg"].is_number()) << line;
    EXPECT_TRUE(row["time_total_s"].is_number()) << line;
    EXPECT_TRUE(row["cross_class_matches"].is_number()) << line;  // the dataset has true labels
    EXPECT_LE(row["cross_class_wrong"].get<int>(), row["cross_class_matches"].get<int>());
    ++rows;
  }
  EXPECT_EQ(rows, 4);
  const std::string report = ReadFile(out / "report.md");
  EXPECT_NE(report.find("# Sweep: tiny"), std::string::npos);
  EXPECT_NE(report.find("Images: sensor preset `ideal` in every cell: renders without a sensor model"), std::string::npos)
      << report;
  EXPECT_NE(report.find("| radius=0.3 | none |"), std::string::npos) << report;
  EXPECT_NE(report.find("## The thesis's claims"), std::string::npos);  // none and mask: the claims are tested
  EXPECT_TRUE(fs::exists(out / "plots" / "tiny_success.png"));
  EXPECT_FALSE(fs::exists(out / "work"));
  EXPECT_FALSE(fs::exists(out / "datasets"));  // deleted after each cell without --keep-datasets

  // Again: both cells are found finished, nothing is rendered, the results are the same rows.
  const std::string rows_before = ReadFile(out / "results.jsonl");
  const CliResult again = RunRigsim({"sweep", (dir / "tiny.yaml").string(), "--out", out.string()}, dir / "run2");
  ASSERT_EQ(again.code, 0) << again.err;
  EXPECT_NE(again.out.find("(0 run now, 2 from an earlier run)"), std::string::npos) << again.out;
  EXPECT_EQ(ReadFile(out / "results.jsonl"), rows_before);
}

// The sweep parameter `sensor`: each cell renders with its preset (sensor.json in the kept
// dataset), and the results name the preset that ran.
TEST(SweepCli, TheSensorParameterReachesTheRender) {
  const TempDir dir;
  WriteFile(dir / "sensors.yaml", R"(name: sensors
base: {rig: ring, cameras: 2, spacing: 40, width: 320, height: 180, frames: 2, spp: 1}
methods: {semantics: [none]}
grid:
  sensor: [ideal, automotive]
)");
  const fs::path out = dir / "out";
  const CliResult run = RunRigsim({"sweep", (dir / "sensors.yaml").string(), "--out", out.string(), "--keep-datasets"},
                                  dir / "run", std::chrono::seconds(300));
  ASSERT_EQ(run.code, 0) << run.err;
  std::set<std::string> presets;
  std::istringstream jsonl(ReadFile(out / "results.jsonl"));
  std::string line;
  while (std::getline(jsonl, line)) {
    const nlohmann::json row = nlohmann::json::parse(line);
    presets.insert(row.at("sensor").get<std::string>());
    const fs::path sensor_json = out / "datasets" / row.at("key").get<std::string>() / "dataset" / "sensor.json";
    if (row.at("sensor") == "ideal") {
      EXPECT_FALSE(fs::exists(sensor_json));
    } else {
      ASSERT_TRUE(fs::exists(sensor_json)) << sensor_json;
      EXPECT_EQ(nlohmann::json::parse(ReadFile(sensor_json)).at("preset"), "automotive");
    }
  }
  EXPECT_EQ(presets, (std::set<std::string>{"ideal", "automotive"}));
  const std::string report = ReadFile(out / "report.md");
  EXPECT_NE(report.find("sensor=automotive"), std::string::npos) << report;
  EXPECT_NE(report.find("Images: sensor preset `ideal` in 1 cell, `automotive` in 1 cell (`render --sensor`"),
            std::string::npos)
      << report;
}

// A sweep resumes only its own results: another config's are replaced only with --force.
TEST(SweepCli, AnotherConfigsResultsAreReplacedOnlyWithForce) {
  const TempDir dir;
  WriteTinyConfig(dir / "tiny.yaml");
  std::string other = ReadFile(dir / "tiny.yaml");
  other.replace(other.find("[0.3, 0.6]"), 10, "[0.4]");
  WriteFile(dir / "other.yaml", other);
  const fs::path out = dir / "out";
  // --slurm --dry-run prepares the folder (sweep.json) and runs no cell.
  auto sweep = [&](const std::string& config, const std::vector<std::string>& extra, const std::string& log) {
    std::vector<std::string> args = {"sweep", (dir / config).string(), "--out", out.string(), "--slurm", "--dry-run"};
    args.insert(args.end(), extra.begin(), extra.end());
    return RunRigsim(args, dir / log);
  };
  const CliResult first = sweep("tiny.yaml", {}, "first");
  ASSERT_EQ(first.code, 0) << first.err;
  const std::string record = ReadFile(out / "sweep.json");
  const CliResult refused = sweep("other.yaml", {}, "refused");
  EXPECT_EQ(refused.code, 1);
  EXPECT_NE(refused.err.find("error: --out " + out.string() + ": holds the results of another sweep (tiny, another config"),
            std::string::npos)
      << refused.err;
  EXPECT_EQ(ReadFile(out / "sweep.json"), record);
  EXPECT_EQ(sweep("tiny.yaml", {}, "same").code, 0);
  const CliResult forced = sweep("other.yaml", {"--force"}, "forced");
  EXPECT_EQ(forced.code, 0) << forced.err;
  EXPECT_NE(ReadFile(out / "sweep.json"), record);
}

TEST(SweepCli, EstimatedCaptureTimesReachTheCalibration) {
  // Two frames cannot show capture times: the estimated method's row fails with calibrate's reason,
  // the synchronised one calibrates.
  const TempDir dir;
  WriteFile(dir / "time.yaml", R"(name: time
base: {rig: ring, cameras: 2, spacing: 40, width: 320, height: 180, frames: 2, spp: 1}
methods: {semantics: [none], time: [synchronised, estimated]}
grid: {radius: [0.3]}
)");
  const fs::path out = dir / "out";
  const CliResult run = RunRigsim({"sweep", (dir / "time.yaml").string(), "--out", out.string()}, dir / "run",
                                  std::chrono::seconds(300));
  ASSERT_EQ(run.code, 0) << run.err;
  std::istringstream jsonl(ReadFile(out / "results.jsonl"));
  std::vector<nlohmann::json> rows;
  for (std::string line; std::getline(jsonl, line);) rows.push_back(nlohmann::json::parse(line));
  ASSERT_EQ(rows.size(), 2u);
  EXPECT_EQ(rows[0]["method"], "none");
  EXPECT_EQ(rows[0]["time"], "synchronised");
  EXPECT_EQ(rows[0]["status"], "ok");
  EXPECT_EQ(rows[1]["method"], "none@estimated");
  EXPECT_EQ(rows[1]["time"], "estimated");
  EXPECT_EQ(rows[1]["status"], "failed");
  EXPECT_NE(rows[1]["failure_reason"].get<std::string>().find("at least three frames"), std::string::npos) << rows[1];
}

TEST(SweepCli, CtrlCLosesOnlyTheCellInProgress) {
  const TempDir dir;
  WriteTinyConfig(dir / "tiny.yaml");
  const fs::path out = dir / "out";
  RigsimProcess sweep({"sweep", (dir / "tiny.yaml").string(), "--out", out.string()}, dir / "interrupted");
  // Interrupt while the first cell is being rendered or calibrated.
  for (int i = 0; i < 600 && !fs::exists(out / "work"); ++i) std::this_thread::sleep_for(std::chrono::milliseconds(50));
  ASSERT_TRUE(fs::exists(out / "work")) << sweep.err();
  ::kill(sweep.pid(), SIGINT);
  EXPECT_EQ(sweep.Wait(), 130) << sweep.err();
  EXPECT_FALSE(fs::exists(out / "work"));  // the cell in progress left nothing
  int finished = 0;
  for (const auto& e : fs::directory_iterator(out / "cells")) {
    EXPECT_EQ(e.path().extension(), ".json") << "a half-written record: " << e.path();
    ++finished;
  }
  EXPECT_LE(finished, 1);
  const CliResult rest = RunRigsim({"sweep", (dir / "tiny.yaml").string(), "--out", out.string()}, dir / "resumed",
                                   std::chrono::seconds(300));
  ASSERT_EQ(rest.code, 0) << rest.err;
  EXPECT_EQ(CountLines(ReadFile(out / "results.csv")), 1 + 2 * 2);
}

TEST(SweepCli, BadConfigsAreRefusedNamingTheFileAndKey) {
  const TempDir dir;
  WriteFile(dir / "bad.yaml", "grid: {overlpa: [10, 20]}\n");
  const CliResult bad = RunRigsim({"sweep", (dir / "bad.yaml").string(), "--out", (dir / "out").string()}, dir / "bad");
  EXPECT_EQ(bad.code, 1);
  EXPECT_NE(bad.err.find("bad.yaml: grid.overlpa: unknown parameter (did you mean 'overlap'?)"), std::string::npos)
      << bad.err;
  EXPECT_FALSE(fs::exists(dir / "out"));
  // A folder of other files is never written into.
  fs::create_directories(dir / "mine");
  WriteFile(dir / "mine" / "thesis.tex", "text");
  WriteTinyConfig(dir / "tiny.yaml");
  const CliResult foreign = RunRigsim({"sweep", (dir / "tiny.yaml").string(), "--out", (dir / "mine").string(), "--force"},
                                      dir / "foreign");
  EXPECT_EQ(foreign.code, 1);
  EXPECT_NE(foreign.err.find("holds files that rigsim did not write"), std::string::npos) << foreign.err;
  EXPECT_EQ(ReadFile(dir / "mine" / "thesis.tex"), "text");
}

TEST(EvaluateCli, EveryEstimateFormatOfTheTruthScoresPerfectly) {
  const TempDir dir;
  ASSERT_EQ(RunRigsim({"make-rig", "ring", "--cameras", "3", "--width", "160", "--height", "96", "--frames", "2",
                       "--out", (dir / "rig").string()},
                      dir / "make-rig")
                .code,
            0);
  ASSERT_EQ(RunRigsim({"render", "--scene", std::string(RIGSIM_SOURCE_DIR) + "/assets/scenes/street.glb", "--rig",
                       (dir / "rig" / "rig.json").string(), "--frames", (dir / "rig" / "frames.json").string(), "--out",
                       (dir / "data").string()},
                      dir / "render")
                .code,
            0);
  ASSERT_EQ(RunRigsim({"export", (dir / "data").string(), "--format", "all", "--out", (dir / "export").string()},
                      dir / "export")
                .code,
            0);
  for (const fs::path& estimate : {dir / "data" / "rig.json", dir / "export" / "camchain.yaml", dir / "export" / "colmap"}) {
    const CliResult r = RunRigsim({"evaluate", (dir / "data").string(), estimate.string(), "--json",
                                   (dir / "scores.json").string(), "--force"},
                                  dir / "evaluate");
    ASSERT_EQ(r.code, 0) << estimate << r.err;
    EXPECT_NE(r.out.find("3/3 cameras with a full pose"), std::string::npos) << r.out;
    const nlohmann::json scores = nlohmann::json::parse(ReadFile(dir / "scores.json"));
    const nlohmann::json& summary = scores["methods"].begin().value()["summary"];
    EXPECT_NEAR(summary["max_rotation_error_deg"].get<double>(), 0.0, 1e-6) << estimate;
    EXPECT_NEAR(summary["max_translation_direction_error_deg"].get<double>(), 0.0, 1e-6) << estimate;
    EXPECT_EQ(summary["success_1deg"], true);
  }
  // A dataset without the truth cannot score anything.
  WriteFile(dir / "export" / "notes.txt", "x");
  const CliResult bad = RunRigsim({"evaluate", (dir / "export").string(), (dir / "data" / "rig.json").string()},
                                  dir / "bad");
  EXPECT_EQ(bad.code, 1);
  EXPECT_NE(bad.err.find("rig.json"), std::string::npos) << bad.err;
}

}  // namespace
}  // namespace rigsim

namespace rigsim {
namespace {

// A user's rig of two small cameras, as make-rig writes it.
void WriteTinyRig(const fs::path& dir) {
  ASSERT_EQ(RunRigsim({"make-rig", "ring", "--cameras", "2", "--spacing", "50", "--width", "96", "--height", "64",
                       "--out", (dir / "my_rig").string()},
                      dir / "make-rig")
                .code,
            0);
}

TEST(SweepCli, TheMotionSuiteTriesTheUsersRigOnEveryPath) {
  const TempDir dir;
  WriteTinyRig(dir);
  const fs::path out = dir / "motion";
  const CliResult run = RunRigsim({"sweep", "--suite", "motion", "--rig", (dir / "my_rig" / "rig.json").string(),
                                   "--out", out.string()},
                                  dir / "run", std::chrono::seconds(600));
  ASSERT_EQ(run.code, 0) << run.err;
  // Small: 3 and 12 frames, every path, three seeds, rigsim without semantics.
  std::istringstream jsonl(ReadFile(out / "results.jsonl"));
  std::string line;
  std::set<std::pair<int, std::string>> points;
  int rows = 0;
  while (std::getline(jsonl, line)) {
    ++rows;
    const nlohmann::json row = nlohmann::json::parse(line);
    EXPECT_EQ(row["rig"], "file");
    EXPECT_EQ(row["cameras"], 2) << line;   // the file's cameras, not a preset's four
    EXPECT_EQ(row["width"], 640) << line;   // the sweep's default, which a file's rig does not take
    // Every path found a place in the street: a failure here would be the calibration's, not the placement's.
    EXPECT_EQ(row.value("failure_reason", "").find("no place"), std::string::npos) << line;
    points.insert({row["frames"].get<int>(), row["trajectory"].get<std::string>()});
  }
  EXPECT_EQ(points.size(), 2u * 5);
  EXPECT_EQ(rows, 2 * 5 * 3);
  EXPECT_TRUE(points.count({12, "figure-eight"}));
  // The answer, per frame count and path, in how many of the three seeds.
  for (const char* study : {"3 frames:\n", "12 frames:\n"}) EXPECT_NE(run.out.find(study), std::string::npos) << run.out;
  for (const char* path : {"straight", "circle", "loop", "figure-eight", "handheld"}) {
    const std::string said = std::string("\n  ") + path + ": placed every camera within 1° / 5° in ";
    const size_t first = run.out.find(said);
    ASSERT_NE(first, std::string::npos) << run.out;
    EXPECT_NE(run.out.find(said, first + 1), std::string::npos) << "one line per frame count: " << run.out;
    const std::string rest = run.out.substr(first + said.size(), run.out.find('\n', first + 1) - first - said.size());
    EXPECT_NE(rest.find(" of 3 seeds (cameras posed "), std::string::npos) << rest;
  }
  // The run-again line names the sensor, the rig and the folder (by their absolute paths) and
  // resumes the run.
  const std::string again = "rigsim sweep --suite motion --size small --sensor automotive --rig " +
                            fs::absolute(dir / "my_rig" / "rig.json").lexically_normal().string() + " --out " +
                            fs::absolute(out).lexically_normal().string();
  EXPECT_NE(ReadFile(out / "report.md").find("Run again (finished cells are kept): `" + again + "`"), std::string::npos);
  EXPECT_NE(run.out.find("run again (finished cells are kept): " + again + "\n"), std::string::npos) << run.out;
  std::vector<std::string> args;
  std::istringstream words(again.substr(std::string("rigsim ").size()));
  for (std::string w; words >> w;) args.push_back(w);
  const CliResult resumed = RunRigsim(args, dir / "again");
  ASSERT_EQ(resumed.code, 0) << resumed.err;
  EXPECT_NE(resumed.out.find("(0 run now, 30 from an earlier run)"), std::string::npos) << resumed.out;
  const std::string report = ReadFile(out / "report.md");
  EXPECT_NE(report.find("| trajectory=handheld | none |"), std::string::npos) << report;
  // The suite's images went through the automotive sensor, without the rig's car, and it says so.
  EXPECT_NE(report.find("Images: sensor preset `automotive` in every cell"), std::string::npos) << report;
  EXPECT_NE(report.find("The rig's own car (`ego_vehicle`, as `make-rig --ego-vehicle`): in no cell."), std::string::npos)
      << report;
  EXPECT_TRUE(fs::exists(out / "plots" / "3_frames_success.png"));
  EXPECT_TRUE(fs::exists(out / "plots" / "12_frames_rotation_error.png"));
  // Cameras this small may calibrate nowhere: a plot without a value is drawn empty, not failed.
  EXPECT_EQ(run.err.find("gnuplot failed"), std::string::npos) << run.err;
}

// The suites' cells render through the automotive sensor preset unless --sensor says otherwise;
// --ego-vehicle puts the rig's car around every cell's rig.
TEST(SweepCli, TheSuitesRenderThroughTheAutomotiveSensorUnlessAskedForIdeal) {
  const TempDir dir;
  const auto cells = [&](const std::vector<std::string>& extra, const std::string& name) {
    std::vector<std::string> args = {"sweep", "--suite", "thesis", "--dry-run", "--out", (dir / "out").string()};
    args.insert(args.end(), extra.begin(), extra.end());
    const CliResult run = RunRigsim(args, dir / name);
    EXPECT_EQ(run.code, 0) << run.err;
    std::vector<nlohmann::json> params;
    std::istringstream lines(run.out);
    for (std::string line; std::getline(lines, line);) {
      if (line.rfind("cell ", 0) == 0) params.push_back(nlohmann::json::parse(line.substr(line.find('{'))));
    }
    return params;
  };
  const std::vector<nlohmann::json> automotive = cells({}, "default");
  ASSERT_GE(automotive.size(), 10u);
  for (const nlohmann::json& p : automotive) {
    EXPECT_EQ(p.at("sensor"), "automotive") << p;
    EXPECT_FALSE(p.value("ego_vehicle", false)) << p;
  }
  const std::vector<nlohmann::json> ideal = cells({"--sensor", "ideal"}, "ideal");
  ASSERT_EQ(ideal.size(), automotive.size());
  for (const nlohmann::json& p : ideal) EXPECT_EQ(p.at("sensor"), "ideal") << p;
  for (const nlohmann::json& p : cells({"--ego-vehicle"}, "car")) EXPECT_EQ(p.at("ego_vehicle"), true) << p;
  EXPECT_FALSE(fs::exists(dir / "out"));
  // A preset rigsim does not have is refused; --sensor is the suites' (a config names its own).
  const CliResult typo = RunRigsim({"sweep", "--suite", "thesis", "--sensor", "automotve", "--dry-run"}, dir / "typo");
  EXPECT_EQ(typo.code, 1);
  EXPECT_NE(typo.err.find("automotve"), std::string::npos) << typo.err;
  WriteFile(dir / "c.yaml", "name: c\nbase: {rig: ring, cameras: 2}\n");
  const CliResult with_config = RunRigsim({"sweep", (dir / "c.yaml").string(), "--sensor", "ideal", "--dry-run"}, dir / "config");
  EXPECT_EQ(with_config.code, 1);
  EXPECT_NE(with_config.err.find("--sensor"), std::string::npos) << with_config.err;
  const CliResult help = RunRigsim({"sweep", "--help"}, dir / "help");
  EXPECT_NE(help.out.find("--sensor ideal: renders without a sensor model"), std::string::npos) << help.out;
}

TEST(SweepCli, ABadRigFileStopsTheMotionSuiteBeforeAnythingRenders) {
  const TempDir dir;
  WriteFile(dir / "rig.json", R"({"cameras": [{"name": "cam0", "model": "PINHOLE", "width": 64, "height": 48,
    "params": [50, 50, 31.5, 23.5]}]})");  // no cam_from_rig: where the camera sits is not known
  const CliResult run = RunRigsim({"sweep", "--suite", "motion", "--rig", (dir / "rig.json").string(), "--out",
                                   (dir / "out").string()},
                                  dir / "run");
  EXPECT_EQ(run.code, 1);
  EXPECT_NE(run.err.find((dir / "rig.json").string() + ": camera 'cam0' has no cam_from_rig"), std::string::npos)
      << run.err;
  EXPECT_FALSE(fs::exists(dir / "out"));
  // Without --rig the suite says what it needs.
  const CliResult none = RunRigsim({"sweep", "--suite", "motion", "--out", (dir / "out").string()}, dir / "none");
  EXPECT_EQ(none.code, 1);
  EXPECT_NE(none.err.find("--rig"), std::string::npos) << none.err;
}

}  // namespace
}  // namespace rigsim
