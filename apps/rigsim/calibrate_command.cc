#include "apps/rigsim/calibrate_support.h"
#include "apps/rigsim/commands.h"
#include "dataset/dataset.h"

namespace rigsim::cli {

void AddCalibrateCommand(CLI::App& app) {
  struct Args {
    std::string dataset, out;
    CalibrateSettings settings;
  };
  auto args = std::make_shared<Args>();
  CLI::App* cmd = app.add_subcommand(
      "calibrate",
      "Estimate the relative pose of every camera pair of DATASET from its images alone (SIFT,\n"
      "ratio test, robust essential matrix on undistorted bearings), once per semantic mode.\n"
      "When rig.json holds the true poses (rendered data) every pair is compared with the truth.\n"
      "Real photos: write rig.json with intrinsics only and put the photos in images/<cam>/.");
  cmd->add_option("DATASET", args->dataset, "dataset folder (rig.json, images/, optional labels/ and depth/)")
      ->required()
      ->check(CLI::ExistingDirectory);
  cmd->add_option("--out", args->out, "where to write the per-pair results (default DATASET/evaluation.json)");
  AddCalibrateSettingsOptions(*cmd, args->settings);
  cmd->callback([args] {
    const std::filesystem::path out =
        args->out.empty() ? DatasetLayout(args->dataset).EvaluationJson() : std::filesystem::path(args->out);
    CalibrateAndReport(args->dataset, args->settings, out);
  });
}

}  // namespace rigsim::cli
