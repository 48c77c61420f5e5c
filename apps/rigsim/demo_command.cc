#include <chrono>
#include <cstdio>

#include "apps/rigsim/calibrate_support.h"
#include "apps/rigsim/commands.h"
#include "apps/rigsim/render_support.h"
#include "apps/rigsim/version.h"
#include "dataset/dataset.h"
#include "dataset/output_folder.h"
#include "rigs/rig_presets.h"
#include "rigs/trajectories.h"

namespace rigsim::cli {

void AddDemoCommand(CLI::App& app) {
  struct Args {
    std::string scene = std::string(RIGSIM_ASSET_DIR) + "/scenes/street.glb";
    std::string out = "out/demo";
    bool force = false;
    int frames = 4;
    RenderSettings render;
    CalibrateSettings calibrate;
  };
  auto args = std::make_shared<Args>();
  CLI::App* cmd = app.add_subcommand(
      "demo",
      "Render the built-in street with the default rig (4 cameras in a ring, 20-40% overlap between\n"
      "neighbours, cam1 with barrel distortion, 1280x720), calibrate every camera pair with and\n"
      "without semantics, and print how close each came to the truth. Writes the dataset and\n"
      "evaluation.json to --out.");
  cmd->add_option("--scene", args->scene, "scene to render")->capture_default_str()->check(CLI::ExistingFile);
  cmd->add_option("--out", args->out, "dataset folder to write")->capture_default_str();
  cmd->add_flag("--force", args->force, "replace an existing output folder");
  cmd->add_option("--frames", args->frames, "frames rendered along the street (matches are pooled over them)")
      ->capture_default_str()
      ->check(CLI::Range(1, 1000));
  AddRenderSettingsOptions(*cmd, args->render);
  AddCalibrateSettingsOptions(*cmd, args->calibrate);
  cmd->callback([args] {
    const auto start = std::chrono::steady_clock::now();
    args->calibrate.options.pairwise.num_threads = args->render.threads;  // one --threads for both stages
    // Fail on bad calibration options before spending time on rendering.
    args->calibrate.ToOptions();
    args->calibrate.Modes();
    const OutputFolderRequest out{args->out, "--out", "rigsim demo", {}, args->force};
    CheckReplaceableOutput(out);

    const Scene scene = LoadSceneVerbose(args->scene);
    RenderJob job;
    job.scene = &scene;
    job.scene_name = std::filesystem::path(args->scene).filename().string();
    job.rig = MakeRingRig(RingRigOptions{});
    job.frames = MakeDemoTrajectory(args->frames);
    job.frames.tool_version = RIGSIM_VERSION_STRING;
    job.options = args->render.ToRenderOptions();
    RenderAndReport(job, args->out, args->force);

    const std::filesystem::path calibration = std::filesystem::path(args->out) / "calibration";
    const std::vector<RigCalibrationResult> results = CalibrateAndReport(args->out, args->calibrate, calibration, true);
    // The evaluation also beside the images, where the dataset's other ground truth is.
    std::filesystem::copy_file(calibration / "evaluation.json", DatasetLayout(args->out).EvaluationJson(),
                               std::filesystem::copy_options::overwrite_existing);
    WriteOutputMarker(args->out, out.written_by);  // the dataset, its calibration/ and evaluation.json
    const double seconds = std::chrono::duration<double>(std::chrono::steady_clock::now() - start).count();
    std::printf("demo finished in %.1f s\n", seconds);
    ThrowUnlessEveryCameraCalibrated(results);
  });
}

}  // namespace rigsim::cli
