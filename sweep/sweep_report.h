// report.md of a sweep: what was run, the thesis's claims tested, per study its plots and a table
// per swept value and method, the failures, and what each column of results.csv means.
#pragma once

#include <string>
#include <vector>

#include "sweep/sweep_config.h"
#include "sweep/sweep_results.h"
#include "sweep/sweep_summary.h"

namespace rigsim {

struct SweepReportInput {
  const SweepConfig* config = nullptr;
  std::string sweep_hash;
  const std::vector<SweepCell>* cells = nullptr;
  const std::vector<CellRecord>* records = nullptr;  // one per cell, in cell order
  const std::vector<SummaryRow>* summary = nullptr;
  const std::vector<ClaimResult>* claims = nullptr;
  std::vector<std::string> plot_images;  // relative to the report
  std::string command;                   // how to run the sweep again
};

std::string SweepReportMarkdown(const SweepReportInput& input);

}  // namespace rigsim
