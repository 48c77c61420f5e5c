#include "sweep/sweep_results.h"

#include <algorithm>
#include <cmath>
#include <cstdio>
#include <fstream>
#include <sstream>
#include <stdexcept>
#include <unistd.h>

namespace rigsim {

namespace fs = std::filesystem;
using Json = nlohmann::ordered_json;

Json CellRecordToJson(const CellRecord& r) {
  Json rows = Json::array();
  for (const MethodRow& m : r.rows) {
    rows.push_back({{"method", m.method}, {"status", m.status}, {"failure_reason", m.failure_reason}, {"metrics", m.metrics}});
  }
  return {{"key", r.key}, {"params", r.params}, {"cell_metrics", r.cell_metrics}, {"rows", rows}};
}

CellRecord CellRecordFromJson(const Json& j, const std::string& source) {
  try {
    CellRecord r;
    r.key = j.at("key").get<std::string>();
    r.params = j.at("params");
    r.cell_metrics = j.at("cell_metrics");
    for (const Json& m : j.at("rows")) {
      r.rows.push_back({m.at("method").get<std::string>(), m.at("status").get<std::string>(),
                        m.at("failure_reason").get<std::string>(), m.at("metrics")});
    }
    return r;
  } catch (const Json::exception& e) {
    throw std::runtime_error(source + ": not a sweep cell record (" + e.what() + ")");
  }
}

fs::path CellRecordPath(const fs::path& out_dir, const std::string& key) { return out_dir / "cells" / (key + ".json"); }

void WriteCellRecord(const fs::path& out_dir, const CellRecord& record) {
  const fs::path path = CellRecordPath(out_dir, record.key);
  fs::create_directories(path.parent_path());
  const fs::path tmp = path.string() + ".tmp" + std::to_string(::getpid());
  {
    std::ofstream out(tmp, std::ios::binary | std::ios::trunc);
    out << CellRecordToJson(record).dump(1) << "\n";
    out.flush();
    if (!out) {
      fs::remove(tmp);
      throw std::runtime_error(path.string() + ": cannot write the cell's results");
    }
  }
  fs::rename(tmp, path);
}

std::optional<CellRecord> ReadFinishedCell(const fs::path& out_dir, const SweepCell& cell,
                                           const std::vector<SweepMethod>& methods) {
  const fs::path path = CellRecordPath(out_dir, cell.key);
  std::ifstream in(path, std::ios::binary);
  if (!in) return std::nullopt;
  std::stringstream text;
  text << in.rdbuf();
  const Json j = Json::parse(text.str(), nullptr, false);
  if (j.is_discarded()) return std::nullopt;
  CellRecord r;
  try {
    r = CellRecordFromJson(j, path.string());
  } catch (const std::runtime_error&) {
    return std::nullopt;
  }
  if (r.params != cell.params) return std::nullopt;
  for (const SweepMethod& m : methods) {
    bool found = false;
    for (const MethodRow& row : r.rows) found = found || row.method == m.name;
    if (!found) return std::nullopt;
  }
  return r;
}

Json ResultRow(const SweepCell& cell, const SweepMethod& method, const CellRecord& record, const MethodRow& row) {
  std::string studies;
  for (const std::string& s : cell.studies) studies += (studies.empty() ? "" : ";") + s;
  Json j = Json::object();  // the writers below put the columns in order
  j["cell"] = cell.index;
  j["key"] = cell.key;
  j["studies"] = studies;
  j["seed"] = cell.params.at("seed");
  for (const ParamSpec& p : CellParamSpecs()) j[p.name] = CellParam(cell.params, p.name);
  for (const MetricSpec& m : CellMetricSpecs()) j[m.name] = record.cell_metrics.value(m.name, Json(nullptr));
  j["method"] = method.name;
  j["tool"] = method.tool;
  j["semantics"] = method.semantics;
  j["features"] = method.features;
  j["time"] = method.time;
  j["status"] = row.status;
  j["failure_reason"] = row.failure_reason;
  for (const MetricSpec& m : SweepMetricSpecs()) j[m.name] = row.metrics.value(m.name, Json(nullptr));
  return j;
}

namespace {

// The column names in order, the same for every row: a parameter held only where it is set
// (HeldWhenSet) is a column when some row sets it, so that results without it stay as they were.
std::vector<std::string> Columns(const std::vector<Json>& rows) {
  std::vector<std::string> c = {"cell", "key", "studies", "seed"};
  for (const ParamSpec& p : CellParamSpecs()) {
    const auto set = [&](const Json& r) { return r.contains(p.name) && r.at(p.name) != p.default_value; };
    if (!HeldWhenSet(p) || std::any_of(rows.begin(), rows.end(), set)) c.push_back(p.name);
  }
  for (const MetricSpec& m : CellMetricSpecs()) c.push_back(m.name);
  for (const char* n : {"method", "tool", "semantics", "features", "time", "status", "failure_reason"}) c.push_back(n);
  for (const MetricSpec& m : SweepMetricSpecs()) c.push_back(m.name);
  return c;
}

std::string CsvField(const Json& v) {
  if (v.is_null()) return "";
  if (v.is_boolean()) return v.get<bool>() ? "true" : "false";
  if (v.is_number_integer()) return v.dump();
  if (v.is_number()) {
    char buf[32];
    std::snprintf(buf, sizeof buf, "%.6g", v.get<double>());
    return buf;
  }
  const std::string s = v.is_string() ? v.get<std::string>() : v.dump();
  if (s.find_first_of(",\"\n\r") == std::string::npos) return s;
  std::string q = "\"";
  for (char c : s) q += c == '"' ? std::string("\"\"") : std::string(1, c);
  return q + "\"";
}

}  // namespace

std::string ResultsCsv(const std::vector<Json>& rows) {
  const std::vector<std::string> columns = Columns(rows);
  std::string out;
  for (size_t i = 0; i < columns.size(); ++i) {
    if (i) out += ',';
    out += columns[i];
  }
  out += "\n";
  for (const Json& r : rows) {
    for (size_t i = 0; i < columns.size(); ++i) {
      if (i) out += ',';
      out += CsvField(r.value(columns[i], Json(nullptr)));
    }
    out += "\n";
  }
  return out;
}

std::string ResultsJsonl(const std::vector<Json>& rows) {
  const std::vector<std::string> columns = Columns(rows);
  std::string out;
  for (const Json& r : rows) {
    nlohmann::ordered_json o;
    for (const std::string& c : columns) o[c] = r.value(c, Json(nullptr));
    out += o.dump() + "\n";
  }
  return out;
}

}  // namespace rigsim
