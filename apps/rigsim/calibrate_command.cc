#include "apps/rigsim/calibrate_support.h"
#include "apps/rigsim/commands.h"
#include "common/param_spec.h"
#include "dataset/dataset.h"

namespace rigsim::cli {

void AddCalibrateCommand(CLI::App& app) {
  struct Args {
    std::string dataset, out;
    std::string features = "sift";
    bool force = false;
    CalibrateSettings settings;
  };
  auto args = std::make_shared<Args>();
  CLI::App* cmd = app.add_subcommand(
      "calibrate",
      "Calibrate the rig of DATASET from its images alone, once per semantic mode: features (SIFT\n"
      "unless --features says otherwise), matches per camera pair pooled over all frames, robust\n"
      "relative pose per pair, rotation averaging over the view graph, bundle adjustment. Gauge:\n"
      "the first camera is the rig frame.\n"
      "When rig.json holds the true poses (rendered data) every pair and camera is compared with\n"
      "the truth. Real photos: write rig.json with intrinsics only, photos in images/<cam>/.\n"
      "Writes OUT/evaluation.json and per mode OUT/<mode>/: rig.json, camchain.yaml (Kalibr),\n"
      "opencv.yaml, colmap/ (text model of every frame with a rig pose), pairs.json\n"
      "(per-pair statistics), rig_topdown.svg (the rig seen from above, over the truth when\n"
      "known) and matches/ (each solved pair's inliers drawn over its photos); the three exports\n"
      "hold only the cameras with a full pose.\n"
      "Exit code 0 when every camera got a full pose in every mode, 3 when some did not (the\n"
      "results are written all the same), 1 on bad input (nothing written).");
  cmd->add_option("DATASET", args->dataset, "dataset folder (rig.json, images/, optional labels/ and depth/)")
      ->required()
      ->check(CLI::ExistingDirectory);
  cmd->add_option("--out", args->out,
                  "output folder: evaluation.json and <mode>/ (default DATASET/calibration)");
  cmd->add_flag("--force", args->force, "replace an existing output folder");
  AddCalibrateSettingsOptions(*cmd, args->settings);
  AddLabelSourceOptions(*cmd, args->settings.labels);
  AddMaskOption(*cmd, args->settings);
  AddSegmenterOptions(*cmd, args->settings.segmenter, "--segmenter",
                      "labels for the semantic modes from a segmentation network (an .onnx file) run on the\n"
                      "photos first, as `rigsim segment` does; written to OUT/segmentation/ (labels/,\n"
                      "labels_color/, segmentation.json). In place of --labels");
  cmd->add_option("--features", args->features,
                  "keypoints and descriptors: sift (default), rootsift (SIFT descriptors L1-normalised\n"
                  "and square-rooted), orb or akaze (binary descriptors matched by Hamming distance,\n"
                  "several times faster to match). --max-features applies to all, --sift-contrast to\n"
                  "sift and rootsift only")
      ->capture_default_str()
      ->check(CLI::IsMember(NamesOf(kAllFeatureTypes, FeatureTypeName)));
  cmd->callback([args] {
    args->settings.options.features.type = FeatureTypeFromName(args->features);
    const std::filesystem::path out =
        args->out.empty() ? std::filesystem::path(args->dataset) / "calibration" : std::filesystem::path(args->out);
    ThrowUnlessEveryCameraCalibrated(CalibrateAndReport(args->dataset, args->settings, out, args->force).results);
  });
}

}  // namespace rigsim::cli
