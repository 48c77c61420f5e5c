// Subcommands of the rigsim command-line tool. Each Add*Command registers its options and a
// callback on `app`; errors are thrown as exceptions and reported by main().
#pragma once

#include <CLI/CLI.hpp>

namespace rigsim::cli {

void AddDemoCommand(CLI::App& app);
void AddMakeRigCommand(CLI::App& app);
void AddRenderCommand(CLI::App& app);
void AddCalibrateCommand(CLI::App& app);
void AddInspectCommand(CLI::App& app);
void AddGenerateSceneCommand(CLI::App& app);
void AddExportCommand(CLI::App& app);

}  // namespace rigsim::cli
