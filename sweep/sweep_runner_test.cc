#include "sweep/sweep_runner.h"

#include <algorithm>
#include <filesystem>
#include <map>
#include <fstream>
#include <sstream>
#include <thread>

#include <gmock/gmock.h>
#include <gtest/gtest.h>

#include "common/run_program.h"
#include "dataset/output_folder.h"
#include "testing/expect_error.h"
#include "testing/temp_dir.h"

namespace rigsim {
namespace {

namespace fs = std::filesystem;
using Json = nlohmann::ordered_json;

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
  const TempDir scratch;
  const fs::path out = scratch / "out";
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
  const std::string csv = ReadFile(out / "results.csv");
  EXPECT_EQ(std::count(csv.begin(), csv.end(), '\n'), 13);
  EXPECT_TRUE(fs::exists(out / "results.jsonl"));
  EXPECT_TRUE(fs::exists(out / "summary.csv"));
  EXPECT_TRUE(fs::exists(out / "sweep.json"));
  EXPECT_FALSE(fs::exists(out / "work"));
  EXPECT_FALSE(fs::exists(out / "datasets"));
  const std::string report = ReadFile(out / "report.md");
  EXPECT_NE(report.find("# Sweep: fake"), std::string::npos);
  EXPECT_NE(report.find("| frames=2 | none | 2 | 0 | -, - | 0 of 2 | 0 of 2 | 0 of 2 |"), std::string::npos) << report;
  EXPECT_NE(report.find("| frames=3 | mask | 2 | 0 | -, - | 0 of 2 | 2 of 2 | 0 of 2 |"), std::string::npos);
  // The summary comes back for the command's own lines.
  ASSERT_EQ(outcome.summary.size(), 3u * 2);
  EXPECT_EQ(outcome.summary[2].point, "frames=3");
  EXPECT_EQ(outcome.summary[2].Count("success_2deg"), 2);
  if (!FindProgram("gnuplot").empty()) {
    EXPECT_TRUE(fs::file_size(out / "plots" / "fake_success.png") > 1000);
    EXPECT_TRUE(fs::exists(out / "plots" / "fake_rotation_error.svg"));
    EXPECT_NE(report.find("![plots/fake_success.png](plots/fake_success.png)"), std::string::npos);
  }
  // A second run finds every cell finished and writes the same results.
  const std::string jsonl = ReadFile(out / "results.jsonl");
  FakeRunner again;
  EXPECT_EQ(RunSweep(Config(), options, again.Get()).resumed, 6);
  EXPECT_EQ(again.calls, 0);
  EXPECT_EQ(ReadFile(out / "results.jsonl"), jsonl);
}

TEST(SweepRunner, AnInterruptedCellLeavesNothingAndTheNextRunResumesThere) {
  const TempDir scratch;
  const fs::path out = scratch / "out";
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
}

TEST(SweepRunner, NeverWritesIntoAFolderOfOtherFiles) {
  const TempDir scratch;
  const fs::path out = scratch / "out";
  fs::create_directories(out);
  WriteFile(out / "thesis.tex", "mine");
  FakeRunner fake;
  SweepRunOptions options;
  options.out_dir = out;
  options.restart = true;
  EXPECT_THAT([&] { RunSweep(Config(), options, fake.Get()); },
              ThrowsWith<std::runtime_error>("holds files that rigsim did not write"));
  EXPECT_EQ(fake.calls, 0);
  EXPECT_EQ(ReadFile(out / "thesis.tex"), "mine");
  EXPECT_EQ(std::distance(fs::directory_iterator(out), fs::directory_iterator()), 1);
}

TEST(SweepRunner, ResumesOrRestartsOnlyInAFolderASweepWrote) {
  const TempDir scratch;
  const fs::path out = scratch / "out";
  FakeRunner fake;
  SweepRunOptions options;
  options.out_dir = out;
  options.keep_datasets = true;
  RunSweep(Config(), options, fake.Get());
  EXPECT_EQ(ReadFile(out / "datasets" / ExpandCells(Config())[0].key / "image.png"), "pixels");
  // A file of the user's in it: neither resumed nor restarted, and the file kept.
  WriteFile(out / "notes.txt", "mine");
  for (const bool restart : {false, true}) {
    options.restart = restart;
    FakeRunner refused;
    EXPECT_THAT([&] { RunSweep(Config(), options, refused.Get()); },
                ThrowsWith<std::runtime_error>("holds notes.txt, which rigsim did not write there"));
    EXPECT_EQ(refused.calls, 0);
    EXPECT_EQ(ReadFile(out / "notes.txt"), "mine");
  }
  fs::remove(out / "notes.txt");
  options.restart = true;
  options.keep_datasets = false;
  FakeRunner again;
  RunSweep(Config(), options, again.Get());
  EXPECT_EQ(again.calls, 6);  // started over
  EXPECT_FALSE(fs::exists(out / "datasets"));
  // A folder another command wrote is not a sweep's.
  const fs::path dataset = scratch / "dataset";
  fs::create_directories(dataset);
  WriteOutputMarker(dataset, "rigsim render", {"rig.json"});
  WriteFile(dataset / "rig.json", "{}");
  options.out_dir = dataset;
  FakeRunner other;
  EXPECT_THROW(RunSweep(Config(), options, other.Get()), std::runtime_error);
  EXPECT_EQ(other.calls, 0);
}

// Every file of a sweep folder's results, by relative path (cells/ and sweep.json aside).
std::map<std::string, std::string> ResultFiles(const fs::path& out) {
  std::map<std::string, std::string> files = FilesUnder(out);
  std::erase_if(files, [](const auto& f) { return f.first.rfind("cells", 0) == 0 || f.first == "sweep.json"; });
  return files;
}

TEST(SweepRunner, TheTimeLeftComesFromTheCellsRunSoFar) {
  // Two paths over three seeds: the cost model weighs them alike.
  const SweepConfig config = ParseSweepConfig(
      Json::parse(R"({"seeds": 3, "grid": {"trajectory": ["straight", "handheld"]}})"), "t.json");
  const std::vector<SweepCell> cells = ExpandCells(config);
  ASSERT_EQ(cells.size(), 6u);
  ASSERT_DOUBLE_EQ(CellCost(cells[0], config.methods), CellCost(cells[3], config.methods));
  std::vector<std::optional<double>> seconds(6);
  EXPECT_LT(EstimateTimeLeft(cells, config.methods, seconds, {0, 1, 2, 3, 4, 5}), 0);  // nothing measured yet
  // One straight cell took 10 s: the rest at 10 s each.
  seconds[0] = 10;
  EXPECT_DOUBLE_EQ(EstimateTimeLeft(cells, config.methods, seconds, {1, 2, 3, 4, 5}), 50);
  // The first handheld cell took 40 s: its other seeds take as long, not the 17.5 s the cells'
  // mean would give.
  seconds[1] = seconds[2] = 10;
  seconds[3] = 40;
  EXPECT_DOUBLE_EQ(EstimateTimeLeft(cells, config.methods, seconds, {4, 5}), 80);
  // 15 s into cell 4.
  EXPECT_DOUBLE_EQ(EstimateTimeLeft(cells, config.methods, seconds, {4, 5}, 15), 65);
  // A cell of another size is scaled by its cost.
  SweepCell bigger = cells[0];
  bigger.params["frames"] = 4 * cells[0].params["frames"].get<int>();
  std::vector<SweepCell> with = cells;
  with.push_back(bigger);
  seconds.push_back(std::nullopt);
  const double per_cost = 70.0 / (4 * CellCost(cells[0], config.methods));  // 70 s over four cells
  EXPECT_NEAR(EstimateTimeLeft(with, config.methods, seconds, {6}), per_cost * CellCost(bigger, config.methods), 1e-9);
  EXPECT_GT(CellCost(bigger, config.methods), 3 * CellCost(cells[0], config.methods));
}

TEST(SweepRunner, OneOffWorkIsLeftOutOfTheTimeLeft) {
  // The first cell generates a scene for every later one (0.8 s); the cells themselves take
  // milliseconds: five of them do not take 5 x 0.8 s.
  FakeRunner fake;
  const CellRunner inner = fake.Get();
  const CellRunner runner = [&](const SweepCell& cell, const fs::path& dataset,
                                const std::function<void(const std::string&)>& status) {
    if (cell.index == 0) {
      status(kOneOffStage);
      std::this_thread::sleep_for(std::chrono::milliseconds(800));
    }
    return inner(cell, dataset, status);
  };
  const TempDir scratch;
  SweepRunOptions options;
  options.out_dir = scratch / "out";
  std::vector<SweepProgress> seen;
  options.progress = [&](const SweepProgress& p) { seen.push_back(p); };
  RunSweep(Config(), options, runner);
  const auto after_first = std::find_if(seen.begin(), seen.end(), [](const SweepProgress& p) { return p.done == 1; });
  ASSERT_NE(after_first, seen.end());
  EXPECT_GE(after_first->eta_s, 0.0);
  EXPECT_LT(after_first->eta_s, 1.5) << "the scene's time counted as every cell's";
}

TEST(SweepRunner, TheRunAgainLineKeepsEveryArgumentAndTheFolder) {
  const std::string command =
      SweepCommandLine({"--suite", "motion", "--size", "small", "--rig", "/data/my rigs/rig's.json", "--threads", "2"});
  EXPECT_EQ(command, "rigsim sweep --suite motion --size small --rig '/data/my rigs/rig'\\''s.json' --threads 2");
  EXPECT_EQ(RunAgainCommand(command, "/tmp/sweeps/./motion"), command + " --out /tmp/sweeps/motion");
  // A relative folder is made absolute: the line works from any folder.
  EXPECT_EQ(RunAgainCommand("rigsim sweep /c.yaml", "out/x"),
            "rigsim sweep /c.yaml --out " + (fs::current_path() / "out" / "x").string());
}

TEST(SweepShards, MergedShardsWriteWhatASingleRunWrites) {
  const TempDir base;
  FakeRunner single;
  SweepRunOptions options;
  options.command = "rigsim sweep fake.json";
  options.out_dir = base / "single";
  RunSweep(Config(), options, single.Get());
  std::vector<fs::path> shards;
  int calls = 0;
  for (int i = 0; i < 3; ++i) {
    FakeRunner part;
    options.out_dir = base / ("shard" + std::to_string(i));
    options.shard_index = i;
    options.num_shards = 3;
    const SweepOutcome o = RunSweep(Config(), options, part.Get());
    EXPECT_FALSE(fs::exists(options.out_dir / "results.csv"));  // a shard writes its cells only
    calls += part.calls;
    shards.push_back(options.out_dir);
  }
  EXPECT_EQ(calls, 6);  // every cell in exactly one shard
  const MergeOutcome merged = MergeSweepShards(base / "merged", shards);
  EXPECT_EQ(merged.merged, 6);
  EXPECT_TRUE(merged.missing.empty());
  const auto a = ResultFiles(base / "single"), b = ResultFiles(base / "merged");
  EXPECT_GE(a.size(), 5u);
  ASSERT_EQ(a.size(), b.size());
  // The report's line that runs the sweep again names the folder it is in; all else is the same.
  const std::string single_out = fs::absolute(base / "single").lexically_normal().string();
  const std::string merged_out = fs::absolute(base / "merged").lexically_normal().string();
  EXPECT_NE(a.at("report.md").find("Run again (finished cells are kept): `rigsim sweep fake.json --out " + single_out + "`"),
            std::string::npos)
      << a.at("report.md");
  std::string report = b.at("report.md");
  ASSERT_NE(report.find("--out " + merged_out + "`"), std::string::npos) << report;
  report.replace(report.find(merged_out), merged_out.size(), single_out);
  EXPECT_EQ(report, a.at("report.md"));
  for (const auto& [name, bytes] : a) {
    if (name == "report.md") continue;
    EXPECT_TRUE(b.count(name) && b.at(name) == bytes) << name << " differs";
  }

  // A shard missing: its cells are named. A shard of another sweep is refused.
  const MergeOutcome partial = MergeSweepShards(base / "partial", {shards[0], shards[2]});
  EXPECT_EQ(partial.merged + static_cast<int>(partial.missing.size()), 6);
  EXPECT_FALSE(partial.missing.empty());
  EXPECT_EQ(partial.missing[0].rfind("cell ", 0), 0u);
  SweepConfig other = Config();
  other.seeds = {7};
  SweepRunOptions other_options;
  other_options.out_dir = base / "other";
  FakeRunner third;
  RunSweep(other, other_options, third.Get());
  try {
    MergeSweepShards(base / "mixed", {shards[0], base / "other"});
    FAIL() << "merged shards of two sweeps";
  } catch (const std::runtime_error& e) {
    EXPECT_NE(std::string(e.what()).find("a shard of another sweep"), std::string::npos) << e.what();
  }
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
