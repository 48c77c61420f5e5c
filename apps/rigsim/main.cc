// rigsim: render labelled multi-camera datasets from glTF scenes and calibrate rigs from them.
#include <cstdio>
#include <exception>

#include <CLI/CLI.hpp>

#include "apps/rigsim/commands.h"
#include "apps/rigsim/interrupt.h"
#include "apps/rigsim/version.h"

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
  rigsim::cli::AddInspectCommand(app);
  rigsim::cli::AddGenerateSceneCommand(app);
  rigsim::cli::AddExportCommand(app);
  rigsim::cli::AddEvaluateCommand(app);
  rigsim::cli::AddSweepCommand(app);
  rigsim::cli::AddSweepMergeCommand(app);
  rigsim::cli::AddReportCommand(app);
  try {
    app.parse(argc, argv);
  } catch (const CLI::ParseError& e) {
    return app.exit(e);
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
