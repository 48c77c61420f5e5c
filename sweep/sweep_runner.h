// Runs a sweep's cells into an output folder, skipping the cells already finished there, and
// writes the results, summary, plots and report from every finished cell.
//
//   OUT/sweep.json      the config (normalised), its hash, the cells' keys in order
//   OUT/cells/          one file per finished cell (sweep_results.h)
//   OUT/work/<key>/     the cell being run (its dataset); removed when the cell ends
//   OUT/datasets/<key>/ the cell's dataset, with --keep-datasets
//   OUT/results.csv, results.jsonl, summary.csv, summary.json, plots/, report.md
//
// A cell is run by a CellRunner (sweep/cell_runner.h renders and calibrates; tests pass their own).
// An exception from the runner, or from `check_interrupt`, stops the sweep: the cell in progress
// leaves nothing behind and the finished ones stay.
#pragma once

#include <filesystem>
#include <functional>
#include <optional>
#include <string>
#include <vector>

#include "sweep/sweep_config.h"
#include "sweep/sweep_results.h"
#include "sweep/sweep_summary.h"

namespace rigsim {

// The stage a CellRunner reports while it does work for later cells too (a preset scene generated
// once per seed): the time to the next stage is left out of the cell's time, from which the time
// left is estimated.
inline constexpr const char* kOneOffStage = "generating the scene";

// Runs one cell: renders into `dataset_dir` (an empty folder that exists), calibrates by every
// method and scores. `status` reports what it is doing, for the progress line.
using CellRunner = std::function<CellRecord(const SweepCell& cell, const std::filesystem::path& dataset_dir,
                                            const std::function<void(const std::string&)>& status)>;

struct SweepProgress {
  int done = 0;          // cells finished, resumed ones included
  int total = 0;
  int resumed = 0;       // found finished at the start
  int failed_rows = 0;   // (cell, method) rows with status "failed" so far
  double elapsed_s = 0;  // since the start of this run
  double eta_s = -1;     // estimated time left (EstimateTimeLeft); < 0 until a cell has finished in this run
  std::string current;   // the cell being run and its stage
};

struct SweepRunOptions {
  std::filesystem::path out_dir;
  bool keep_datasets = false;
  // Start over: remove the folder's earlier sweep results first (only what a sweep writes).
  bool restart = false;
  // Run only the cells of shard `shard_index` of `num_shards` (AssignShards); all when 1.
  int shard_index = 0;
  int num_shards = 1;
  std::function<void(const SweepProgress&)> progress;
  std::function<void()> check_interrupt;  // throws to stop the sweep
  // How the sweep was started (SweepCommandLine), for report.md's line that runs it again: the
  // same for every shard of one sweep (no --out, --shard); the report adds the folder it is in.
  std::string command;
};

struct SweepOutcome {
  int cells = 0;       // in this run's share
  int resumed = 0;
  int ran = 0;
  int failed_rows = 0;
  std::vector<std::string> warnings;  // plots not drawn, ...
  std::vector<SummaryRow> summary;    // of every finished cell (empty for one shard of several)
};

// `rigsim sweep` and its arguments, each quoted for a POSIX shell where it needs it.
std::string SweepCommandLine(const std::vector<std::string>& args);
// The command that runs the sweep again into `out_dir`, keeping its finished cells: `command`
// (SweepCommandLine of every option but --out, paths absolute) with --out.
std::string RunAgainCommand(const std::string& command, const std::filesystem::path& out_dir);

// Relative cost of a cell (render and calibration work), for the time estimate and for
// balancing shards.
double CellCost(const SweepCell& cell, const std::vector<SweepMethod>& methods);

// The time (s) the cells `left` will take, from the wall times `seconds` of the cells run so far
// (one per cell; nullopt for those not run in this run): a cell whose study point (its parameters
// but the seed) has cells run takes their mean time; another its CellCost at the mean time per
// cost of every cell run. `in_progress_s` is the time already spent on left[0], the cell running.
// -1 until a cell has run.
double EstimateTimeLeft(const std::vector<SweepCell>& cells, const std::vector<SweepMethod>& methods,
                        const std::vector<std::optional<double>>& seconds, const std::vector<size_t>& left,
                        double in_progress_s = 0.0);

// The shard of every cell: each cell in exactly one of `num_shards`, the shards' summed CellCost
// as even as a greedy assignment makes them (costliest cell first, to the least loaded shard).
// Deterministic: depends only on the cells and methods.
std::vector<int> AssignShards(const std::vector<SweepCell>& cells, const std::vector<SweepMethod>& methods,
                              int num_shards);

// Makes `options.out_dir` a sweep folder for `config` (sweep.json; with `restart`, its earlier
// sweep results removed first). Throws std::runtime_error when it exists and is not a sweep's
// output folder: a folder of other files is never written into or removed.
void PrepareSweepFolder(const SweepConfig& config, const SweepRunOptions& options);

// Runs the cells of the options' shard that are not finished yet (PrepareSweepFolder first).
SweepOutcome RunSweep(const SweepConfig& config, const SweepRunOptions& options, const CellRunner& run_cell);

// What a sweep folder's sweep.json says: the sweep it belongs to and which shard it holds.
struct SweepFolder {
  std::filesystem::path dir;
  SweepConfig config;
  std::string sweep_hash;
  std::string command;  // how the sweep was started (without --out), for the report
  int shard_index = 0, num_shards = 1;
};
// Throws std::runtime_error naming the folder when it holds no sweep (no or a broken sweep.json).
SweepFolder ReadSweepFolder(const std::filesystem::path& dir);

struct MergeOutcome {
  int cells = 0;                     // in the sweep
  int merged = 0;                    // found finished in a shard (or already in the output)
  std::vector<std::string> missing;  // "cell N (key)" of the cells no shard finished
  std::vector<std::string> warnings;
};

// Combines the finished cells of shard folders (RunSweep with num_shards > 1) into `out` and writes
// the results there: the same files a single run of the sweep writes. Refuses shards of different
// sweeps (their hashes differ) and an `out` that is not a sweep folder; cells no shard finished are
// listed in `missing` and left out of the results.
MergeOutcome MergeSweepShards(const std::filesystem::path& out, const std::vector<std::filesystem::path>& shard_dirs);

// Writes results.csv, results.jsonl, summary.csv, summary.json, plots/ and report.md from the
// finished cells of `config` found in `out_dir`. Returns warnings (cells missing, plots not drawn).
// `summary`, when given, gets the summary of the finished cells.
std::vector<std::string> WriteSweepResults(const SweepConfig& config, const std::filesystem::path& out_dir,
                                           const std::string& command, std::vector<SummaryRow>* summary = nullptr);

}  // namespace rigsim
