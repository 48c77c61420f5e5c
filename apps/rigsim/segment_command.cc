#include <cstdio>
#include <filesystem>
#include <functional>
#include <string>

#include "apps/rigsim/commands.h"
#include "apps/rigsim/segment_support.h"
#include "dataset/output_folder.h"

namespace rigsim::cli {

void AddSegmentCommand(CLI::App& app) {
  struct Args {
    std::string dataset, out;
    bool force = false;
    SegmenterSettings segmenter;
  };
  auto args = std::make_shared<Args>();
  CLI::App* cmd = app.add_subcommand(
      "segment",
      "Label the photos of DATASET (images/<cam>/<frame>.*) with a semantic segmentation network\n"
      "exported to ONNX, run by OpenCV on the CPU: each photo resized to the network's input,\n"
      "normalised, its class scores resized back to the photo, and the network's classes mapped to\n"
      "Cityscapes' through --classes. Writes OUT/labels/<cam>/<frame>.png (Cityscapes label ids, what\n"
      "calibrate --labels OUT/labels reads), OUT/labels_color/ (colour previews) and\n"
      "OUT/segmentation.json (the model, its settings, seconds per photo, share of each class).\n"
      "rigsim ships no weights; README, 'Labels from a network', says how to export one.");
  cmd->add_option("DATASET", args->dataset, "dataset folder (images/<cam>/, rig.json or not)")
      ->required()
      ->check(CLI::ExistingDirectory);
  cmd->add_option("--out", args->out, "output folder (default DATASET/segmentation)");
  cmd->add_flag("--force", args->force, "replace an output folder rigsim wrote");
  AddSegmenterOptions(*cmd, args->segmenter, "--model", "the network: an .onnx file (required)");
  cmd->callback([args] {
    const std::filesystem::path dataset = args->dataset;
    const std::filesystem::path out = args->out.empty() ? dataset / "segmentation" : std::filesystem::path(args->out);
    // Everything is checked before anything is written: the model, the class table, the photos.
    const SegmenterOptions options = args->segmenter.ToOptions();
    const Segmenter segmenter(options);
    const std::vector<SegmentedPhoto> photos = PhotosToSegment(dataset);
    OutputFolderRequest request{out, args->out.empty() ? "" : "--out", "rigsim segment", {}, args->force};
    request.inputs = {{dataset / "images", "the dataset's images/"}};
    for (const CommandInput& input : SegmenterInputs(options, "--model")) request.inputs.push_back(input);
    StagedOutput staged(request);
    SegmentWithProgress(segmenter, [&](const std::function<void(int, int)>& progress) {
      return SegmentPhotos(photos, segmenter, staged.staging_dir(), progress);
    });
    staged.Commit();
    std::printf("labels in %s (previews in labels_color/); calibrate with them:\n  rigsim calibrate %s --semantics "
                "none,mask --labels %s\n",
                (out / "labels").string().c_str(), dataset.string().c_str(), (out / "labels").string().c_str());
  });
}

}  // namespace rigsim::cli
