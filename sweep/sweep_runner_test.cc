#include "sweep/sweep_runner.h"

#include <algorithm>
#include <filesystem>
#include <fstream>
#include <sstream>

#include <gtest/gtest.h>
#include <unistd.h>

#include "common/run_program.h"
#include "dataset/output_folder.h"

namespace rigsim {
namespace {

namespace fs = std::filesystem;
using Json = nlohmann::ordered_json;

fs::path TempDir(const std::string& name) {
  const fs::path dir = fs::temp_directory_path() / ("rigsim_" + name + "_" + std::to_string(::getpid()));
  fs::remove_all(dir);
  return dir;
}

std::string Read(const fs::path& p) {
  std::ifstream in(p, std::ios::binary);
  std::stringstream s;
  s << in.rdbuf();
  return s.str();
}

SweepConfig Config() {
  return ParseSweepConfig(Json::parse(R"({"name": "fake", "seeds": [1, 2], "grid": {"frames": [2, 3, 4]}})"),
                          "fake.json");
}

// A runner that makes up metrics from the parameters and counts its calls; it writes a file into
// the dataset folder as a render would.
struct FakeRunner {
  int calls = 0;
  int throw_at_call = -1;
  CellRunner Get() {
    return [this](const SweepCell& cell, const fs::path& dataset, const std::function<void(const std::string&)>& status) {
      ++calls;
      status("rendering");
      std::ofstream(dataset / "image.png") << "pixels";
      if (calls == throw_at_call) throw std::runtime_error("interrupted");
      CellRecord r;
      r.cell_metrics = {{"overlap_pct", 30.0}};
      const double frames = cell.params["frames"].get<double>();
      for (const char* m : {"none", "mask"}) {
        r.rows.push_back({m, "ok", "",
                          {{"success_2deg", frames > 2 ? 1 : 0},
                           {"median_rotation_error_deg", 1.0 / frames},
                           {"match_precision", 0.5}}});
      }
      return r;
    };
  }
};

TEST(SweepRunner, RunsEveryCellOnceAndWritesTheResults) {
  const fs::path out = TempDir("sweep_run");
  FakeRunner fake;
  SweepRunOptions options;
  options.out_dir = out;
  std::vector<SweepProgress> seen;
  options.progress = [&](const SweepProgress& p) { seen.push_back(p); };
  const SweepOutcome outcome = RunSweep(Config(), options, fake.Get());
  EXPECT_EQ(fake.calls, 6);
  EXPECT_EQ(outcome.ran, 6);
  EXPECT_EQ(outcome.resumed, 0);
  ASSERT_FALSE(seen.empty());
  EXPECT_EQ(seen.back().done, 6);
  EXPECT_EQ(seen.back().total, 6);
  EXPECT_NE(seen.front().current.find("cell 0 (frames=2, seed=1): rendering"), std::string::npos) << seen.front().current;
  // 1 header + 6 cells x 2 methods.
  const std::string csv = Read(out / "results.csv");
  EXPECT_EQ(std::count(csv.begin(), csv.end(), '\n'), 13);
  EXPECT_TRUE(fs::exists(out / "results.jsonl"));
  EXPECT_TRUE(fs::exists(out / "summary.csv"));
  EXPECT_TRUE(fs::exists(out / "sweep.json"));
  EXPECT_FALSE(fs::exists(out / "work"));
  EXPECT_FALSE(fs::exists(out / "datasets"));
  const std::string report = Read(out / "report.md");
  EXPECT_NE(report.find("# Sweep: fake"), std::string::npos);
  EXPECT_NE(report.find("| frames=2 | none | 2 | 0 | 0% | 0% |"), std::string::npos) << report;
  EXPECT_NE(report.find("| frames=3 | mask | 2 | 0 | 0% | 100% |"), std::string::npos);
  if (!FindProgram("gnuplot").empty()) {
    EXPECT_TRUE(fs::file_size(out / "plots" / "fake_success.png") > 1000);
    EXPECT_TRUE(fs::exists(out / "plots" / "fake_rotation_error.svg"));
    EXPECT_NE(report.find("![plots/fake_success.png](plots/fake_success.png)"), std::string::npos);
  }
  // A second run finds every cell finished and writes the same results.
  const std::string jsonl = Read(out / "results.jsonl");
  FakeRunner again;
  EXPECT_EQ(RunSweep(Config(), options, again.Get()).resumed, 6);
  EXPECT_EQ(again.calls, 0);
  EXPECT_EQ(Read(out / "results.jsonl"), jsonl);
  fs::remove_all(out);
}

TEST(SweepRunner, AnInterruptedCellLeavesNothingAndTheNextRunResumesThere) {
  const fs::path out = TempDir("sweep_interrupt");
  FakeRunner fake;
  fake.throw_at_call = 3;
  SweepRunOptions options;
  options.out_dir = out;
  EXPECT_THROW(RunSweep(Config(), options, fake.Get()), std::runtime_error);
  int files = 0;
  for (const auto& e : fs::directory_iterator(out / "cells")) {
    EXPECT_EQ(e.path().extension(), ".json") << e.path();  // no half-written record
    ++files;
  }
  EXPECT_EQ(files, 2);
  EXPECT_FALSE(fs::exists(out / "work"));  // the interrupted cell's dataset is gone
  FakeRunner rest;
  const SweepOutcome outcome = RunSweep(Config(), options, rest.Get());
  EXPECT_EQ(outcome.resumed, 2);
  EXPECT_EQ(rest.calls, 4);
  fs::remove_all(out);
}

TEST(SweepRunner, NeverWritesIntoAFolderOfOtherFiles) {
  const fs::path out = TempDir("sweep_foreign");
  fs::create_directories(out);
  std::ofstream(out / "thesis.tex") << "mine";
  FakeRunner fake;
  SweepRunOptions options;
  options.out_dir = out;
  options.restart = true;
  try {
    RunSweep(Config(), options, fake.Get());
    FAIL() << "wrote into a folder of other files";
  } catch (const std::runtime_error& e) {
    EXPECT_NE(std::string(e.what()).find("holds files that rigsim did not write"), std::string::npos) << e.what();
  }
  EXPECT_EQ(fake.calls, 0);
  EXPECT_EQ(Read(out / "thesis.tex"), "mine");
  EXPECT_EQ(std::distance(fs::directory_iterator(out), fs::directory_iterator()), 1);
  fs::remove_all(out);
}

TEST(SweepRunner, ResumesOrRestartsOnlyInAFolderASweepWrote) {
  const fs::path out = TempDir("sweep_restart");
  FakeRunner fake;
  SweepRunOptions options;
  options.out_dir = out;
  options.keep_datasets = true;
  RunSweep(Config(), options, fake.Get());
  EXPECT_EQ(Read(out / "datasets" / ExpandCells(Config())[0].key / "image.png"), "pixels");
  // A file of the user's in it: neither resumed nor restarted, and the file kept.
  std::ofstream(out / "notes.txt") << "mine";
  for (const bool restart : {false, true}) {
    options.restart = restart;
    FakeRunner refused;
    try {
      RunSweep(Config(), options, refused.Get());
      ADD_FAILURE() << "ran beside a file of the user's";
    } catch (const std::runtime_error& e) {
      EXPECT_NE(std::string(e.what()).find("holds notes.txt, which rigsim did not write there"), std::string::npos) << e.what();
    }
    EXPECT_EQ(refused.calls, 0);
    EXPECT_EQ(Read(out / "notes.txt"), "mine");
  }
  fs::remove(out / "notes.txt");
  options.restart = true;
  options.keep_datasets = false;
  FakeRunner again;
  RunSweep(Config(), options, again.Get());
  EXPECT_EQ(again.calls, 6);  // started over
  EXPECT_FALSE(fs::exists(out / "datasets"));
  // A folder another command wrote is not a sweep's.
  const fs::path dataset = TempDir("sweep_in_a_dataset");
  fs::create_directories(dataset);
  WriteOutputMarker(dataset, "rigsim render", {"rig.json"});
  std::ofstream(dataset / "rig.json") << "{}";
  options.out_dir = dataset;
  FakeRunner other;
  EXPECT_THROW(RunSweep(Config(), options, other.Get()), std::runtime_error);
  EXPECT_EQ(other.calls, 0);
  fs::remove_all(dataset);
  fs::remove_all(out);
}

TEST(SweepShards, EveryCellInExactlyOneShardAndTheShardsBalanced) {
  const SweepConfig config = ParseSweepConfig(
      Json::parse(R"({"seeds": 3, "grid": {"width": [320, 640, 1280], "frames": [2, 3]}})"), "t.json");
  const std::vector<SweepCell> cells = ExpandCells(config);
  for (int n : {1, 2, 4, 7}) {
    const std::vector<int> shard = AssignShards(cells, config.methods, n);
    ASSERT_EQ(shard.size(), cells.size());
    std::vector<double> load(n, 0.0);
    for (size_t i = 0; i < cells.size(); ++i) {
      ASSERT_GE(shard[i], 0);
      ASSERT_LT(shard[i], n);
      load[shard[i]] += CellCost(cells[i], config.methods);
    }
    const double most = *std::max_element(load.begin(), load.end());
    const double least = *std::min_element(load.begin(), load.end());
    double biggest_cell = 0.0;
    for (const SweepCell& c : cells) biggest_cell = std::max(biggest_cell, CellCost(c, config.methods));
    // Greedy largest-first: no shard exceeds another by more than one cell's cost.
    EXPECT_LE(most - least, biggest_cell + 1e-9) << n << " shards";
    EXPECT_EQ(AssignShards(cells, config.methods, n), shard);  // deterministic
  }
}

}  // namespace
}  // namespace rigsim
