#include "sweep/sweep_runner.h"

#include <algorithm>
#include <chrono>
#include <fstream>
#include <map>
#include <numeric>
#include <sstream>
#include <stdexcept>

#include "dataset/output_folder.h"
#include "geometry/json_io.h"
#include "sweep/sweep_plots.h"
#include "sweep/sweep_report.h"
#include "sweep/sweep_summary.h"

namespace rigsim {

namespace fs = std::filesystem;
using Json = nlohmann::ordered_json;

double CellCost(const SweepCell& cell, const std::vector<SweepMethod>& methods) {
  const Json& p = cell.params;
  const std::string rig = p.at("rig").get<std::string>();
  const double cameras = rig == "ring" ? p.at("cameras").get<double>() : rig == "surround" ? 4.0 : 2.0;
  const double views = cameras * p.at("frames").get<double>();
  const double megapixels = p.at("width").get<double>() * p.at("height").get<double>() / 1e6;
  // Rough relative weights, enough to estimate the time left and balance shards: a view's render
  // costs a tenth of its calibration by one method per sample, COLMAP three times rigsim.
  double cost = views * megapixels * 0.1 * p.at("spp").get<double>();
  for (const SweepMethod& m : methods) cost += views * megapixels * (m.tool == "colmap" ? 3.0 : 1.0);
  return cost;
}

double EstimateTimeLeft(const std::vector<SweepCell>& cells, const std::vector<SweepMethod>& methods,
                        const std::vector<std::optional<double>>& seconds, const std::vector<size_t>& left,
                        double in_progress_s) {
  // The cost model alone misjudges cells that differ in what it does not weigh (a handheld path
  // calibrates several times slower than a straight one), so a point's measured seeds come first.
  const auto point = [&](size_t i) {
    nlohmann::ordered_json p = cells[i].params;
    p.erase("seed");
    return p.dump();
  };
  std::map<std::string, std::pair<double, int>> by_point;
  double spent_s = 0.0, spent_cost = 0.0;
  for (size_t i = 0; i < cells.size(); ++i) {
    if (!seconds[i]) continue;
    auto& [sum, n] = by_point[point(i)];
    sum += *seconds[i];
    ++n;
    spent_s += *seconds[i];
    spent_cost += CellCost(cells[i], methods);
  }
  if (spent_cost <= 0) return -1.0;
  double total = 0.0;
  for (size_t k = 0; k < left.size(); ++k) {
    const auto it = by_point.find(point(left[k]));
    double s = it != by_point.end() ? it->second.first / it->second.second
                                    : CellCost(cells[left[k]], methods) * spent_s / spent_cost;
    if (k == 0) s = std::max(0.0, s - in_progress_s);
    total += s;
  }
  return total;
}

namespace {

using Clock = std::chrono::steady_clock;

// What a sweep writes into its folder, and nothing else: --force removes only these.
const std::vector<std::string>& SweepEntries() {
  static const std::vector<std::string> entries = {"cells",        "work",        "datasets",      "scenes",
                                                   "shards",       "slurm",       "plots",         "results.csv",
                                                   "results.jsonl", "summary.csv", "summary.json", "report.md",
                                                   "sweep.json"};
  return entries;
}

constexpr const char* kWrittenBy = "rigsim sweep";

// The output folder's rules (dataset/output_folder.h), and a sweep's own: it resumes in a folder
// only an earlier sweep wrote.
void CheckSweepFolder(const fs::path& out) {
  OutputFolderRequest request;
  request.dir = out;
  request.written_by = kWrittenBy;
  const OutputFolderState state = CheckOutputFolder(request);
  if (state.kind == OutputFolderState::kWrittenByRigsim && state.written_by != kWrittenBy) {
    throw std::runtime_error("--out " + out.string() + ": holds what " + state.written_by +
                             " wrote, not a sweep's results; choose another --out");
  }
}

void RemoveSweepOutputs(const fs::path& out) {
  for (const std::string& name : SweepEntries()) fs::remove_all(out / name);
}

Json SweepJson(const SweepConfig& config, const std::vector<SweepCell>& cells, const SweepRunOptions& options) {
  Json keys = Json::array();
  for (const SweepCell& c : cells) keys.push_back(c.key);
  return {{"config", SweepConfigToJson(config)},
          {"sweep_hash", SweepHash(config)},
          {"command", options.command},
          {"shard", {{"index", options.shard_index}, {"count", options.num_shards}}},
          {"cells", keys}};
}

std::string Describe(const SweepCell& cell, const std::vector<SweepStudy>& studies) {
  std::string what = "cell " + std::to_string(cell.index) + " (";
  bool first = true;
  for (const SweepStudy& s : studies) {
    if (std::find(cell.studies.begin(), cell.studies.end(), s.name) == cell.studies.end()) continue;
    for (const std::string& p : s.VariedParams()) {
      const Json v = CellParam(cell.params, p);
      what += (first ? "" : ", ") + p + "=" + FormatParamValue(v);
      first = false;
    }
    break;
  }
  return what + (first ? "" : ", ") + "seed=" + cell.params.at("seed").dump() + ")";
}

}  // namespace

std::vector<int> AssignShards(const std::vector<SweepCell>& cells, const std::vector<SweepMethod>& methods,
                              int num_shards) {
  // Longest processing time first: the costliest cell goes to the shard with the least work so
  // far (ties: the lower shard, then the earlier cell), which keeps the shards' totals close.
  std::vector<size_t> order(cells.size());
  std::iota(order.begin(), order.end(), size_t(0));
  std::vector<double> cost(cells.size());
  for (size_t i = 0; i < cells.size(); ++i) cost[i] = CellCost(cells[i], methods);
  std::stable_sort(order.begin(), order.end(), [&](size_t a, size_t b) { return cost[a] > cost[b]; });
  std::vector<double> load(num_shards, 0.0);
  std::vector<int> shard(cells.size(), 0);
  for (size_t i : order) {
    const int s = static_cast<int>(std::min_element(load.begin(), load.end()) - load.begin());
    shard[i] = s;
    load[s] += cost[i];
  }
  return shard;
}

void PrepareSweepFolder(const SweepConfig& config, const SweepRunOptions& options) {
  const fs::path& out = options.out_dir;
  if (options.num_shards < 1 || options.shard_index < 0 || options.shard_index >= options.num_shards) {
    throw std::invalid_argument("shard " + std::to_string(options.shard_index) + "/" +
                                std::to_string(options.num_shards) + " does not exist");
  }
  CheckSweepFolder(out);
  // Another config's results are replaced only with --force, as any output is; the same config
  // resumes.
  if (!options.restart && fs::exists(out / "sweep.json")) {
    const SweepFolder earlier = ReadSweepFolder(out);
    if (earlier.sweep_hash != SweepHash(config)) {
      throw std::runtime_error("--out " + out.string() + ": holds the results of another sweep (" + earlier.config.name +
                               ", another config: its sweep.json); --force starts over there (removing only what a "
                               "sweep writes), or choose another --out");
    }
  }
  if (options.restart) RemoveSweepOutputs(out);
  fs::create_directories(out / "cells");
  WriteOutputMarker(out, kWrittenBy, SweepEntries());
  fs::remove_all(out / "work");  // a cell interrupted by a kill: its half-made dataset
  json_io::WriteTextAtomic(out / "sweep.json", SweepJson(config, ExpandCells(config), options).dump(1) + "\n");
}

SweepOutcome RunSweep(const SweepConfig& config, const SweepRunOptions& options, const CellRunner& run_cell) {
  const fs::path& out = options.out_dir;
  PrepareSweepFolder(config, options);
  const std::vector<SweepCell> all_cells = ExpandCells(config);
  const std::vector<int> shard = AssignShards(all_cells, config.methods, options.num_shards);
  std::vector<SweepCell> cells;
  for (size_t i = 0; i < all_cells.size(); ++i) {
    if (shard[i] == options.shard_index) cells.push_back(all_cells[i]);
  }

  SweepOutcome outcome;
  outcome.cells = static_cast<int>(cells.size());
  SweepProgress progress;
  progress.total = outcome.cells;
  std::vector<char> finished(cells.size(), 0);
  for (size_t i = 0; i < cells.size(); ++i) {
    if (const auto r = ReadFinishedCell(out, cells[i], config.methods)) {
      finished[i] = 1;
      ++outcome.resumed;
      for (const MethodRow& row : r->rows) progress.failed_rows += row.status != "ok";
    }
  }
  progress.resumed = outcome.resumed;
  progress.done = outcome.resumed;
  // The time left: the cells not finished yet, at the times the cells run so far took.
  std::vector<std::optional<double>> seconds(cells.size());
  std::vector<size_t> left;
  for (size_t i = 0; i < cells.size(); ++i) {
    if (!finished[i]) left.push_back(i);
  }
  const auto start = Clock::now();
  auto cell_start = start;
  double one_off_s = 0.0;  // of the cell running: the time of its kOneOffStage
  std::optional<Clock::time_point> one_off_since;
  // Estimated once per cell (the cell running, the rest after it); the progress line counts down.
  double eta_cell = -1.0, eta_rest = -1.0;
  const auto estimate = [&] {
    eta_cell = left.empty() ? -1.0 : EstimateTimeLeft(cells, config.methods, seconds, {left[0]});
    eta_rest = EstimateTimeLeft(cells, config.methods, seconds, std::vector<size_t>(left.begin() + !left.empty(), left.end()));
  };
  auto report = [&](const std::string& current) {
    const auto now = Clock::now();
    progress.elapsed_s = std::chrono::duration<double>(now - start).count();
    const double in_cell_s = std::chrono::duration<double>(now - cell_start).count() - one_off_s;
    progress.eta_s = eta_rest < 0 ? -1.0 : eta_rest + std::max(0.0, eta_cell - in_cell_s);
    progress.current = current;
    if (options.progress) options.progress(progress);
  };
  for (size_t i = 0; i < cells.size(); ++i) {
    if (finished[i]) continue;
    if (options.check_interrupt) options.check_interrupt();
    cell_start = Clock::now();
    estimate();
    one_off_s = 0.0;
    one_off_since.reset();
    const SweepCell& cell = cells[i];
    const std::string what = Describe(cell, config.studies);
    const fs::path work = out / "work" / cell.key;
    fs::remove_all(work);
    fs::create_directories(work);
    CellRecord record;
    try {
      record = run_cell(cell, work, [&](const std::string& stage) {
        if (options.check_interrupt) options.check_interrupt();
        const auto now = Clock::now();
        if (one_off_since) one_off_s += std::chrono::duration<double>(now - *one_off_since).count();
        one_off_since.reset();
        if (stage == kOneOffStage) one_off_since = now;
        report(what + ": " + stage);
      });
    } catch (...) {
      fs::remove_all(out / "work");
      throw;
    }
    record.key = cell.key;
    record.params = cell.params;
    WriteCellRecord(out, record);
    if (options.keep_datasets) {
      fs::remove_all(out / "datasets" / cell.key);
      fs::create_directories(out / "datasets");
      fs::rename(work, out / "datasets" / cell.key);
    } else {
      fs::remove_all(work);
    }
    ++outcome.ran;
    for (const MethodRow& row : record.rows) progress.failed_rows += row.status != "ok";
    seconds[i] = std::chrono::duration<double>(Clock::now() - cell_start).count() - one_off_s;
    left.erase(left.begin());
    cell_start = Clock::now();
    estimate();
    ++progress.done;
    report(what + ": done");
  }
  fs::remove_all(out / "work");
  outcome.failed_rows = progress.failed_rows;
  if (options.num_shards == 1) outcome.warnings = WriteSweepResults(config, out, options.command, &outcome.summary);
  return outcome;
}

SweepFolder ReadSweepFolder(const fs::path& dir) {
  const fs::path path = dir / "sweep.json";
  if (!fs::exists(path)) throw std::runtime_error(dir.string() + ": not a sweep's output folder (no sweep.json)");
  Json j;
  try {
    j = Json::parse(json_io::ReadText(path));
    SweepFolder f;
    f.dir = dir;
    f.config = ParseSweepConfig(j.at("config"), path.string());
    f.sweep_hash = j.at("sweep_hash").get<std::string>();
    f.command = j.value("command", "");
    f.shard_index = j.at("shard").at("index").get<int>();
    f.num_shards = j.at("shard").at("count").get<int>();
    return f;
  } catch (const Json::exception& e) {
    throw std::runtime_error(path.string() + ": not a sweep's record (" + e.what() + ")");
  }
}

MergeOutcome MergeSweepShards(const fs::path& out, const std::vector<fs::path>& shard_dirs) {
  if (shard_dirs.empty()) throw std::invalid_argument("no shard folder to merge");
  std::vector<SweepFolder> shards;
  for (const fs::path& d : shard_dirs) shards.push_back(ReadSweepFolder(d));
  for (const SweepFolder& s : shards) {
    if (s.sweep_hash != shards[0].sweep_hash) {
      throw std::runtime_error(s.dir.string() + ": a shard of another sweep (hash " + s.sweep_hash + ", " +
                               shards[0].dir.string() + " has " + shards[0].sweep_hash + "): merge shards of one config");
    }
  }
  const SweepConfig& config = shards[0].config;
  CheckSweepFolder(out);
  if (fs::exists(out / "sweep.json") && ReadSweepFolder(out).sweep_hash != shards[0].sweep_hash) {
    throw std::runtime_error(out.string() + ": holds the results of another sweep; merge into a new folder");
  }
  fs::create_directories(out / "cells");
  WriteOutputMarker(out, kWrittenBy, SweepEntries());
  SweepRunOptions record;
  record.command = shards[0].command;
  const std::vector<SweepCell> cells = ExpandCells(config);
  json_io::WriteTextAtomic(out / "sweep.json", SweepJson(config, cells, record).dump(1) + "\n");
  MergeOutcome outcome;
  outcome.cells = static_cast<int>(cells.size());
  for (const SweepCell& cell : cells) {
    bool found = ReadFinishedCell(out, cell, config.methods).has_value();
    for (const SweepFolder& s : shards) {
      if (found) break;
      if (const auto r = ReadFinishedCell(s.dir, cell, config.methods)) {
        WriteCellRecord(out, *r);
        found = true;
      }
    }
    if (found) {
      ++outcome.merged;
    } else {
      outcome.missing.push_back("cell " + std::to_string(cell.index) + " (" + cell.key + ")");
    }
  }
  outcome.warnings = WriteSweepResults(config, out, shards[0].command);
  return outcome;
}

namespace {

// An argument as a POSIX shell reads it back: as it is when it holds nothing the shell treats
// specially, else in single quotes.
std::string ShellWord(const std::string& a) {
  const bool plain = !a.empty() && a.find_first_not_of("ABCDEFGHIJKLMNOPQRSTUVWXYZabcdefghijklmnopqrstuvwxyz"
                                                       "0123456789_-+=/.,:@%") == std::string::npos;
  if (plain) return a;
  std::string q = "'";
  for (char c : a) q += c == '\'' ? std::string("'\\''") : std::string(1, c);
  return q + "'";
}

}  // namespace

std::string SweepCommandLine(const std::vector<std::string>& args) {
  std::string line = "rigsim sweep";
  for (const std::string& a : args) {
    line += ' ';
    line += ShellWord(a);
  }
  return line;
}

std::string RunAgainCommand(const std::string& command, const fs::path& out_dir) {
  return command + " --out " + ShellWord(fs::absolute(out_dir).lexically_normal().string());
}

std::vector<std::string> WriteSweepResults(const SweepConfig& config, const fs::path& out, const std::string& command,
                                           std::vector<SummaryRow>* summary_out) {
  std::vector<std::string> warnings;
  const std::vector<SweepCell> all = ExpandCells(config);
  std::vector<SweepCell> cells;
  std::vector<CellRecord> records;
  int missing = 0;
  for (const SweepCell& c : all) {
    if (auto r = ReadFinishedCell(out, c, config.methods)) {
      cells.push_back(c);
      records.push_back(std::move(*r));
    } else {
      ++missing;
    }
  }
  if (missing > 0) {
    warnings.push_back(std::to_string(missing) + " of " + std::to_string(all.size()) +
                       " cells have no results yet: the tables and plots leave them out");
  }
  std::vector<Json> rows;
  for (size_t c = 0; c < cells.size(); ++c) {
    for (const SweepMethod& m : config.methods) {
      for (const MethodRow& row : records[c].rows) {
        if (row.method == m.name) rows.push_back(ResultRow(cells[c], m, records[c], row));
      }
    }
  }
  json_io::WriteTextAtomic(out / "results.csv", ResultsCsv(rows));
  json_io::WriteTextAtomic(out / "results.jsonl", ResultsJsonl(rows));
  const std::vector<SummaryRow> summary = Summarise(config, cells, records);
  const std::vector<ClaimResult> claims = TestClaims(config, cells, records);
  json_io::WriteTextAtomic(out / "summary.csv", SummaryCsv(summary));
  json_io::WriteTextAtomic(out / "summary.json",
                           Json{{"groups", SummaryToJson(summary)}, {"claims", ClaimsToJson(claims)}}.dump(1) + "\n");
  const SweepPlots plots = WriteSweepPlots(config, summary, out);
  warnings.insert(warnings.end(), plots.warnings.begin(), plots.warnings.end());
  SweepReportInput input;
  input.config = &config;
  input.sweep_hash = SweepHash(config);
  input.cells = &cells;
  input.records = &records;
  input.summary = &summary;
  input.claims = &claims;
  input.plot_images = plots.images;
  input.command = command.empty() ? "" : RunAgainCommand(command, out);
  json_io::WriteTextAtomic(out / "report.md", SweepReportMarkdown(input));
  if (summary_out) *summary_out = summary;
  return warnings;
}

}  // namespace rigsim
