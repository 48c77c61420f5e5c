// A sweep's results on disk. Each finished cell is one file, written atomically, so a re-run
// resumes where it stopped, Ctrl-C loses only the cell in progress, and shards merge by copying:
//
//   OUT/sweep.json               the config as read, its hash, the cells' keys
//   OUT/cells/<key>.json         one finished cell: its parameters, what its render measured, and
//                                one row per method (status, failure reason, metrics)
//   OUT/results.csv              one row per (cell, method): every parameter and metric
//   OUT/results.jsonl            the same rows as JSON Lines
//
// The rows of results.csv and results.jsonl come in the config's cell order and method order,
// whatever order the cells finished in.
#pragma once

#include <filesystem>
#include <optional>
#include <string>
#include <vector>

#include <nlohmann/json.hpp>

#include "sweep/sweep_config.h"
#include "sweep/sweep_metrics.h"

namespace rigsim {

struct MethodRow {
  std::string method;
  // "ok": the method ran and its estimate was scored (possibly with cameras it could not place);
  // "failed": it produced no estimate (the reason says why).
  std::string status = "ok";
  std::string failure_reason;
  nlohmann::ordered_json metrics = nlohmann::ordered_json::object();  // names of SweepMetricSpecs; null = unknown
};

struct CellRecord {
  std::string key;
  nlohmann::ordered_json params;
  // What the cell's render measured, the same for every method (overlap achieved, render time).
  nlohmann::ordered_json cell_metrics = nlohmann::ordered_json::object();
  std::vector<MethodRow> rows;  // in the config's method order
};

nlohmann::ordered_json CellRecordToJson(const CellRecord& record);
CellRecord CellRecordFromJson(const nlohmann::ordered_json& j, const std::string& source);

// OUT/cells/<key>.json
std::filesystem::path CellRecordPath(const std::filesystem::path& out_dir, const std::string& key);
// Writes through a temporary file and a rename: the file is whole or absent.
void WriteCellRecord(const std::filesystem::path& out_dir, const CellRecord& record);
// The finished record of `cell` when it exists with the same parameters and a row for every
// method; nullopt otherwise (the cell runs again). A file that does not parse is treated as absent.
std::optional<CellRecord> ReadFinishedCell(const std::filesystem::path& out_dir, const SweepCell& cell,
                                           const std::vector<SweepMethod>& methods);

// One result row as JSON: cell index, key, studies, seed, every parameter, the cell's metrics,
// method, tool, semantics, features, status, failure_reason and every metric.
nlohmann::ordered_json ResultRow(const SweepCell& cell, const SweepMethod& method, const CellRecord& record,
                         const MethodRow& row);
// The CSV header and one line per row (RFC 4180 quoting; numbers with up to 6 significant digits,
// unknown values empty). A parameter a cell holds only where it is set (HeldWhenSet) is a column
// when some row sets it.
std::string ResultsCsv(const std::vector<nlohmann::ordered_json>& rows);
std::string ResultsJsonl(const std::vector<nlohmann::ordered_json>& rows);

}  // namespace rigsim
