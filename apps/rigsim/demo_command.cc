#include <chrono>
#include <cstdio>

#include "apps/rigsim/calibrate_support.h"
#include "apps/rigsim/commands.h"
#include "apps/rigsim/render_support.h"
#include "apps/rigsim/report_support.h"
#include "apps/rigsim/version.h"
#include "common/data_dir.h"
#include "dataset/dataset.h"
#include "dataset/output_folder.h"
#include "rigs/rig_presets.h"
#include "rigs/trajectories.h"

namespace rigsim::cli {

void AddDemoCommand(CLI::App& app) {
  struct Args {
    std::string scene;  // empty: the built-in street (rigsim's data), looked up when the demo runs
    std::string out = "out/demo";
    bool force = false;
    int frames = 4;
    int width = RingRigOptions{}.width;
    int height = RingRigOptions{}.height;
    bool report = true;
    RenderSettings render;
    CalibrateSettings calibrate;
  };
  auto args = std::make_shared<Args>();
  CLI::App* cmd = app.add_subcommand(
      "demo",
      "Render the built-in street with the default rig (4 cameras in a ring, 20-40% overlap between\n"
      "neighbours, cam1 with barrel distortion, 1280x720), calibrate every camera pair with and\n"
      "without semantics, and print how close each came to the truth. Writes the dataset,\n"
      "calibration/ and evaluation.json to --out, and a teaching report, OUT/report/index.html\n"
      "(open it in a browser). --width 640 --height 360 runs in seconds on a laptop.");
  cmd->add_option("--scene", args->scene, "scene to render (default: the built-in street, assets/scenes/street.glb)")
      ->check(CLI::ExistingFile);
  cmd->add_option("--out", args->out, "dataset folder to write")->capture_default_str();
  cmd->add_flag("--force", args->force, "replace an existing output folder");
  cmd->add_option("--frames", args->frames, "frames rendered along the street (matches are pooled over them)")
      ->capture_default_str()
      ->check(CLI::Range(1, 1000));
  cmd->add_option("--width", args->width, "image width of every camera (the field of view stays)")
      ->capture_default_str()
      ->check(CLI::Range(64, 8192));
  cmd->add_option("--height", args->height, "image height of every camera")->capture_default_str()->check(CLI::Range(64, 8192));
  cmd->add_flag("--report,!--no-report", args->report, "write the teaching report OUT/report/ (default: on)");
  AddRenderSettingsOptions(*cmd, args->render);
  AddCalibrateSettingsOptions(*cmd, args->calibrate);
  cmd->callback([args] {
    const auto start = std::chrono::steady_clock::now();
    args->calibrate.options.rig.pairwise.num_threads = args->render.threads;  // one --threads for both stages
    // Fail on bad calibration options, or a report page missing, before spending time on rendering.
    args->calibrate.ToOptions();
    args->calibrate.Modes();
    if (args->report) ReportPageFiles(ReportOptions{});
    const OutputFolderRequest out{args->out, "--out", "rigsim demo", {}, args->force};
    CheckReplaceableOutput(out);

    const std::string scene_file = args->scene.empty() ? DataPath("assets/scenes/street.glb").string() : args->scene;
    const Scene scene = LoadSceneVerbose(scene_file);
    RenderJob job;
    job.scene = &scene;
    job.scene_name = std::filesystem::path(scene_file).filename().string();
    RingRigOptions ring;
    ring.width = args->width;
    ring.height = args->height;
    job.rig = MakeRingRig(ring);
    job.frames = MakeDemoTrajectory(args->frames);
    job.frames.tool_version = RIGSIM_VERSION_STRING;
    job.options = args->render.ToRenderOptions();
    RenderAndReport(job, args->out, args->force);

    const std::filesystem::path calibration = std::filesystem::path(args->out) / "calibration";
    CalibrateSettings calibrate = args->calibrate;
    calibrate.options.rig.keep_details = args->report;  // what the report shows of every stage
    const CalibrationRun run = CalibrateAndReport(args->out, calibrate, calibration, true);
    // The evaluation also beside the images, where the dataset's other ground truth is.
    std::filesystem::copy_file(calibration / "evaluation.json", DatasetLayout(args->out).EvaluationJson(),
                               std::filesystem::copy_options::overwrite_existing);
    if (args->report) {
      ReportOptions report;
      report.scene = scene_file;
      report.tool_version = RIGSIM_VERSION_STRING;
      report.command = "rigsim demo --out " + args->out;
      const std::filesystem::path index =
          WriteReportFolder(run, report, {std::filesystem::path(args->out) / "report", "", "rigsim", {}, true});
      std::printf("teaching report: %s (open it in a browser)\n", index.string().c_str());
    }
    WriteOutputMarker(args->out, out.written_by);  // the dataset, its calibration/, evaluation.json and report/
    const double seconds = std::chrono::duration<double>(std::chrono::steady_clock::now() - start).count();
    std::printf("demo finished in %.1f s\n", seconds);
    ThrowUnlessEveryCameraCalibrated(run.results);
  });
}

}  // namespace rigsim::cli
