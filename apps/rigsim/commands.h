// Subcommands of the rigsim command-line tool. Each Add*Command registers its options and a
// callback on `app`; errors are thrown as exceptions and reported by main().
#pragma once

#include <stdexcept>
#include <string>

#include <CLI/CLI.hpp>

namespace rigsim::cli {

// Thrown when a command finished and wrote its output but did not fully succeed: main() prints
// the message and exits with `code` (calibrate and demo: 3 when a camera got no full pose).
struct Unfinished : std::runtime_error {
  Unfinished(int exit_code, const std::string& message) : std::runtime_error(message), code(exit_code) {}
  int code;
};

void AddDemoCommand(CLI::App& app);
void AddMakeRigCommand(CLI::App& app);
void AddRenderCommand(CLI::App& app);
void AddCalibrateCommand(CLI::App& app);
void AddInspectCommand(CLI::App& app);
void AddGenerateSceneCommand(CLI::App& app);
void AddExportCommand(CLI::App& app);
void AddEvaluateCommand(CLI::App& app);
void AddSweepCommand(CLI::App& app);
void AddSweepMergeCommand(CLI::App& app);
void AddRenderMergeCommand(CLI::App& app);
void AddReportCommand(CLI::App& app);
void AddSegmentCommand(CLI::App& app);

}  // namespace rigsim::cli
