#include "apps/rigsim/calibrate_support.h"
#include "apps/rigsim/commands.h"
#include "dataset/dataset.h"

namespace rigsim::cli {

void AddCalibrateCommand(CLI::App& app) {
  struct Args {
    std::string dataset, out;
    bool force = false;
    CalibrateSettings settings;
  };
  auto args = std::make_shared<Args>();
  CLI::App* cmd = app.add_subcommand(
      "calibrate",
      "Calibrate the rig of DATASET from its images alone, once per semantic mode: SIFT features,\n"
      "matches per camera pair pooled over all frames, robust relative pose per pair, rotation\n"
      "averaging over the view graph, bundle adjustment. Gauge: the first camera is the rig frame.\n"
      "When rig.json holds the true poses (rendered data) every pair and camera is compared with\n"
      "the truth. Real photos: write rig.json with intrinsics only, photos in images/<cam>/.");
  cmd->add_option("DATASET", args->dataset, "dataset folder (rig.json, images/, optional labels/ and depth/)")
      ->required()
      ->check(CLI::ExistingDirectory);
  cmd->add_option("--out", args->out,
                  "output folder: evaluation.json and <mode>/rig.json (default DATASET/calibration)");
  cmd->add_flag("--force", args->force, "replace an existing output folder");
  AddCalibrateSettingsOptions(*cmd, args->settings);
  cmd->callback([args] {
    const std::filesystem::path out =
        args->out.empty() ? std::filesystem::path(args->dataset) / "calibration" : std::filesystem::path(args->out);
    CalibrateAndReport(args->dataset, args->settings, out, args->force);
  });
}

}  // namespace rigsim::cli
