// rigsim: render labelled multi-camera datasets from glTF scenes and calibrate rigs from them.
#include <cstdio>
#include <exception>
#include <string>
#include <vector>

#include <CLI/CLI.hpp>

#include "apps/rigsim/commands.h"
#include "apps/rigsim/interrupt.h"
#include "apps/rigsim/parse_errors.h"
#include "apps/rigsim/version.h"
#include "pipeline/cpu_paths.h"

int main(int argc, char** argv) {
  CLI::App app{
      "rigsim " RIGSIM_VERSION_STRING
      ": a synthetic multi-camera rig simulator with targetless calibration built in.\n"
      "Renders glTF scenes through a rig of distorted cameras with exact ground truth (labels, instances,\n"
      "depth, poses), recovers the rig's extrinsics from the images alone, and measures the error.\n"
      "Start with `rigsim demo`."};
  app.require_subcommand(1);
  app.set_version_flag("--version", RIGSIM_VERSION_STRING);
  rigsim::cli::AddDemoCommand(app);
  rigsim::cli::AddMakeRigCommand(app);
  rigsim::cli::AddRenderCommand(app);
  rigsim::cli::AddRenderMergeCommand(app);
  rigsim::cli::AddCalibrateCommand(app);
  rigsim::cli::AddSegmentCommand(app);
  rigsim::cli::AddInspectCommand(app);
  rigsim::cli::AddGenerateSceneCommand(app);
  rigsim::cli::AddExportCommand(app);
  rigsim::cli::AddEvaluateCommand(app);
  rigsim::cli::AddSweepCommand(app);
  rigsim::cli::AddSweepMergeCommand(app);
  rigsim::cli::AddReportCommand(app);
  // Line by line: output and errors sent to one log file keep the order they were written in.
  std::setvbuf(stdout, nullptr, _IOLBF, 0);
  try {
    rigsim::SelectCpuPaths();  // before any command writes anything
    app.parse(argc, argv);
  } catch (const CLI::ParseError& e) {
    if (e.get_exit_code() == static_cast<int>(CLI::ExitCodes::Success)) return app.exit(e);  // --help, --version
    const std::vector<std::string> args(argv + 1, argv + argc);
    const CLI::App* sub = rigsim::cli::FailedSubcommand(app);
    std::fprintf(stderr, "rigsim: error: %s\n(`rigsim %s--help` explains every option)\n",
                 rigsim::cli::DescribeParseError(e, app, args).c_str(), sub ? (sub->get_name() + " ").c_str() : "");
    return 1;
  } catch (const rigsim::cli::Unfinished& e) {
    std::fprintf(stderr, "rigsim: %s\n", e.what());
    return e.code;
  } catch (const rigsim::cli::Interrupted& e) {
    std::fprintf(stderr, "rigsim: %s\n", e.what());
    return 128 + e.signal;
  } catch (const std::exception& e) {
    std::fprintf(stderr, "rigsim: error: %s\n", e.what());
    return 1;
  }
  return 0;
}
