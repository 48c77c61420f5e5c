// rigsim sweep CONFIG | --suite NAME: renders and calibrates every cell of a sweep and summarises
// where calibration works and where it breaks.
#include <cstdio>
#include <filesystem>
#include <string>
#include <tuple>
#include <vector>

#include "apps/rigsim/commands.h"
#include "apps/rigsim/interrupt.h"
#include "apps/rigsim/parse_errors.h"
#include "apps/rigsim/progress.h"
#include "apps/rigsim/shard_options.h"
#include "common/format.h"
#include "pipeline/calibration_run.h"
#include "procedural/presets.h"
#include "renderer/sensor_model.h"
#include "sweep/cell_runner.h"
#include "sweep/suites.h"
#include "sweep/sweep_config.h"
#include "sweep/sweep_runner.h"

namespace rigsim::cli {

namespace {

namespace fs = std::filesystem;

// The sweep's line (progress.h LiveLine), with the cell running on a terminal; in a log a line per
// finished cell.
class SweepProgressLine {
 public:
  void operator()(const SweepProgress& p) {
    std::string text = "sweep: " + std::to_string(p.done) + "/" + Count(p.total, "cell");
    if (p.resumed > 0) text += " (" + std::to_string(p.resumed) + " from an earlier run)";
    if (p.failed_rows > 0) text += ", " + Count(p.failed_rows, "failed run");
    if (p.eta_s >= 1 && p.done < p.total) text += ", about " + DurationInWords(p.eta_s) + " left";
    if (line_.OnTerminal()) {
      text += "  [" + p.current + "]";
      if (text.size() > 150) text = text.substr(0, 147) + "...";
    }
    line_.Show(text, p.done != last_done_);
    last_done_ = p.done;
  }
  ~SweepProgressLine() { line_.Finish(true); }

 private:
  LiveLine line_;
  int last_done_ = -1;
};

void ListParams() {
  std::printf("Cell parameters (a config's base, set, grid and zip):\n\n");
  for (const ParamSpec& p : CellParamSpecs()) {
    std::string def = p.default_value.is_null() ? "unset" : FormatParamValue(p.default_value);
    std::string help = p.help;
    if (p.kind == ParamSpec::Kind::kChoice) help += " {" + JoinNames(p.choices) + "}";
    std::printf("  %-16s default %-8s %s\n", p.name.c_str(), def.c_str(), help.c_str());
  }
  std::printf("\nMethods: semantics %s; features %s; time %s; peers %s\n",
              JoinNames(NamesOf(kAllSemanticModes, SemanticModeName)).c_str(),
              JoinNames(NamesOf(kAllFeatureTypes, FeatureTypeName)).c_str(), JoinNames(SweepTimeNames()).c_str(),
              JoinNames(SweepPeerNames()).c_str());
}

bool IsScenePresetName(const std::string& name) {
  for (ScenePreset p : AllScenePresets()) {
    if (ScenePresetName(p) == name) return true;
  }
  return false;
}

// The config of a built-in suite, and how to start it again (for its report and Slurm's tasks):
// `sweep_args` gets the suite's options, paths absolute.
SweepConfig SuiteSweep(const std::string& suite, const std::string& size, const std::string& rig,
                       const std::string& scene, const std::string& sensor, bool ego_vehicle,
                       std::vector<std::string>* sweep_args) {
  SuiteInputs inputs;
  inputs.sensor = sensor;
  inputs.ego_vehicle = ego_vehicle;
  if (!rig.empty()) inputs.rig_file = fs::absolute(rig).lexically_normal().string();
  inputs.scene = scene;
  if (!scene.empty() && !IsScenePresetName(scene)) {
    if (!fs::is_regular_file(scene)) {
      throw CLI::ValidationError("--scene", "'" + scene + "' is neither a scene preset (" +
                                                JoinNames(NamesOf(AllScenePresets(), ScenePresetName)) +
                                                ") nor a scene file");
    }
    inputs.scene = fs::absolute(scene).lexically_normal().string();
  }
  SweepConfig sweep = ParseSweepConfig(SuiteConfig(suite, size, inputs), "--suite " + suite);
  // The sensor is named even when it is the default, so that the line runs the same cells should
  // the default change.
  *sweep_args = {"--suite", suite, "--size", size, "--sensor", sensor};
  if (ego_vehicle) sweep_args->push_back("--ego-vehicle");
  if (!rig.empty()) sweep_args->insert(sweep_args->end(), {"--rig", inputs.rig_file});
  if (!scene.empty()) sweep_args->insert(sweep_args->end(), {"--scene", inputs.scene});
  return sweep;
}

}  // namespace

void AddSweepCommand(CLI::App& app) {
  struct Args {
    std::string config, suite, size = "small", out, rig, scene, sensor = kSuiteDefaultSensor;
    bool keep_datasets = false, force = false, list_params = false, ego_vehicle = false;
    int threads = 0;
    ShardSettings shards;
  };
  auto args = std::make_shared<Args>();
  CLI::App* cmd = app.add_subcommand(
      "sweep",
      "Map where calibration works: vary what makes it hard (overlap, baseline, lens, label noise, scene,\n"
      "...) over seeds, render every cell once, calibrate it by every method (rigsim's semantic modes and\n"
      "feature types, COLMAP) and score each against the truth.\n"
      "CONFIG is a .json or .yaml file (see docs/sweeps.md; --list-params lists the parameters), or\n"
      "--suite thesis runs the built-in test of the thesis's four claims (--size small: 13 cells, about 15\n"
      "minutes on 2 cores; full: every study at every level over 3 seeds, many hours: shard it with Slurm);\n"
      "--suite motion --rig RIG.json [--scene S] tries your own rig along every path (straight, circle, loop,\n"
      "figure-eight, handheld) at 3 and 12 frames (--size full: and 30) over 3 seeds: which path calibrates it,\n"
      "and how well; it ends with a line per path: in how many seeds every camera was placed within 1° / 5°.\n"
      "The suites render through the automotive sensor preset (--sensor ideal: renders without a sensor model).\n"
      "Writes OUT/results.csv and results.jsonl (a row per cell and method), summary.csv, plots/ (PNG\n"
      "and SVG, by gnuplot) and report.md. Finished cells are kept in OUT/cells/: running the same\n"
      "command again resumes, and Ctrl-C loses only the cell in progress. Exit code 0 when the sweep\n"
      "ran (whatever the calibrations gave), 1 on bad input, 130 when interrupted.");
  CLI::Option* config = cmd->add_option("CONFIG", args->config, "sweep config (.json, .yaml)")->check(CLI::ExistingFile);
  CLI::Option* suite =
      cmd->add_option("--suite", args->suite, "a built-in sweep instead of CONFIG: thesis, motion")->excludes(config);
  cmd->add_option("--rig", args->rig,
                  "with --suite motion: your rig, a rig.json as make-rig writes it (every camera's intrinsics and "
                  "cam_from_rig) or a calibration file that make-rig --type file reads (Kalibr, COLMAP, DGP, nuScenes)")
      ->check(CLI::ExistingFile)
      ->excludes(config);
  cmd->add_option("--scene", args->scene,
                  "with --suite motion: where to drive it, a scene preset (street, plaza, parking) or a .glb/.gltf file "
                  "(default street)")
      ->excludes(config);
  cmd->add_option("--sensor", args->sensor,
                  "with --suite: the cameras' sensor and lens, as render --sensor: automotive (the default: an automotive "
                  "camera's noise, defocus and JPEG, the preset measured against a real car rig's photos in VALIDATION.md), "
                  "ideal (renders without a sensor model, noise-free, sharp and lossless: easier than real photos), or "
                  "another preset")
      ->capture_default_str()
      ->check(CLI::IsMember(SensorPresetNames()))
      ->excludes(config);
  cmd->add_flag("--ego-vehicle", args->ego_vehicle,
                "with --suite: the rig's own car around every cell's rig, as make-rig --ego-vehicle (off by default: "
                "the thesis's rigs, a ring, a wide-baseline pair up to 5 m apart and handheld paths, are not a car's; "
                "give it for a motion rig that is one)")
      ->excludes(config);
  cmd->add_option("--size", args->size, "with --suite: small (thesis: 1 seed, two values per study; motion: 3 and 12 frames, rigsim "
                  "without semantics, 3 seeds) or full")
      ->capture_default_str()
      ->check(CLI::IsMember({"small", "full"}));
  cmd->add_option("--out", args->out, "output folder (default out/sweep/<config name>)");
  cmd->add_flag("--keep-datasets", args->keep_datasets,
                "keep every cell's rendered dataset in OUT/datasets/<key> (they are deleted after their cell "
                "otherwise, so that a large sweep does not fill the disk)");
  cmd->add_flag("--force", args->force, "start over: remove OUT's earlier sweep results (only what a sweep writes)");
  cmd->add_option("--threads", args->threads, "worker threads, 0 = all cores")->capture_default_str()->check(NonNegative());
  cmd->add_flag("--list-params", args->list_params, "list the cell parameters and methods, and exit");
  AddShardOptions(*cmd, args->shards, "cells", "sweep-merge");
  cmd->get_option("--dry-run")->description("list the cells and exit; with --slurm: write the job scripts, do not submit");
  cmd->callback([args, config, suite] {
    if (args->list_params) {
      ListParams();
      return;
    }
    if (config->count() == 0 && suite->count() == 0) {
      throw CLI::ValidationError("sweep", "give CONFIG, --suite thesis or --suite motion --rig RIG.json");
    }
    SweepConfig sweep;
    fs::path config_dir = fs::current_path();
    // How the sweep is started, the same for every shard (for Slurm's tasks and the report's line
    // that runs it again: every option given but --out and the shards', paths absolute).
    std::vector<std::string> sweep_args;
    if (!args->suite.empty()) {
      sweep = SuiteSweep(args->suite, args->size, args->rig, args->scene, args->sensor, args->ego_vehicle, &sweep_args);
    } else {
      sweep = ReadSweepConfig(args->config);
      config_dir = fs::absolute(args->config).parent_path();
      sweep_args = {fs::absolute(args->config).lexically_normal().string()};
    }
    std::vector<std::string> run_args = sweep_args;
    if (args->keep_datasets) run_args.push_back("--keep-datasets");
    if (args->threads > 0) run_args.insert(run_args.end(), {"--threads", std::to_string(args->threads)});
    const fs::path out = args->out.empty() ? fs::path("out") / "sweep" / sweep.name : fs::path(args->out);
    const std::vector<SweepCell> cells = ExpandCells(sweep);
    CheckCellRigFiles(cells, config_dir);  // a bad rig.json stops the sweep before anything renders
    SweepRunOptions options;
    options.out_dir = out;
    options.keep_datasets = args->keep_datasets;
    options.restart = args->force;
    options.command = SweepCommandLine(run_args);
    if (!args->shards.shard.empty()) std::tie(options.shard_index, options.num_shards) = ParseShard(args->shards.shard);
    std::fprintf(stderr, "sweep %s: %s x %s into %s\n", sweep.name.c_str(), Count(cells.size(), "cell").c_str(),
                 Count(sweep.methods.size(), "method").c_str(), out.string().c_str());
    if (args->shards.slurm) {
      if (!args->shards.shard.empty()) throw std::invalid_argument("--slurm makes the shards itself: leave out --shard");
      SlurmArrayJob job = args->shards.job;
      job.binary = fs::read_symlink("/proc/self/exe");
      job.command = "sweep";
      job.args = sweep_args;
      if (args->keep_datasets) job.args.push_back("--keep-datasets");
      job.merge_command = "sweep-merge";
      job.out = job.work = fs::absolute(out).lexically_normal();
      job.name = sweep.name;
      if (job.num_shards <= 0) job.num_shards = std::max(1, std::min<int>(64, static_cast<int>(cells.size())));
      options.num_shards = job.num_shards;
      PrepareSweepFolder(sweep, options);
      SubmitOrWriteSlurm(job, args->shards.dry_run);
      if (!args->shards.dry_run) std::printf("the report: %s once the merge has run\n", (job.out / "report.md").c_str());
      return;
    }
    if (args->shards.dry_run) {
      for (const SweepCell& c : cells) std::printf("cell %d %s %s\n", c.index, c.key.c_str(), c.params.dump().c_str());
      return;
    }
    CellRunnerOptions runner;
    runner.config_dir = config_dir;
    runner.scene_dir = out / "scenes";
    runner.num_threads = args->threads;
    InterruptScope interrupt;
    options.check_interrupt = [] { InterruptScope::ThrowIfRequested(); };
    SweepProgressLine progress;
    options.progress = [&progress](const SweepProgress& p) { progress(p); };
    const SweepOutcome outcome = RunSweep(sweep, options, MakeCellRunner(sweep, runner));
    for (const std::string& w : outcome.warnings) std::fprintf(stderr, "warning: %s\n", w.c_str());
    std::printf("sweep %s: %s (%d run now, %d from an earlier run), %s\n", sweep.name.c_str(),
                Count(outcome.cells, "cell").c_str(), outcome.ran, outcome.resumed, Count(outcome.failed_rows, "failed run").c_str());
    if (options.num_shards > 1) {
      std::printf("shard %d/%d in %s; combine the shards with: rigsim sweep-merge OUT SHARD_DIR...\n", options.shard_index,
                  options.num_shards, out.string().c_str());
      return;
    }
    std::printf("%s\n", ConfidenceLine(outcome.summary).c_str());
    // The motion suite's answer: which path placed the rig, in how many of the seeds.
    if (args->suite == "motion") {
      for (const std::string& line : PlacementLines(outcome.summary)) std::printf("%s\n", line.c_str());
    }
    std::printf("results in %s: report.md, results.csv, results.jsonl, summary.csv, plots/\n", out.string().c_str());
    std::printf("run again (finished cells are kept): %s\n", RunAgainCommand(options.command, out).c_str());
  });
}

void AddSweepMergeCommand(CLI::App& app) {
  struct Args {
    std::string out;
    std::vector<std::string> shards;
  };
  auto args = std::make_shared<Args>();
  CLI::App* cmd = app.add_subcommand(
      "sweep-merge",
      "Combine the folders of a sweep's shards (rigsim sweep --shard I/N) into OUT: the same results.csv,\n"
      "summary, plots and report.md a single run of the sweep writes. Refuses shards of different sweeps.\n"
      "Exit code 0 when every cell was found, 3 when some are missing (they are named; the results of the\n"
      "others are written), 1 on bad input.");
  cmd->add_option("OUT", args->out, "output folder (created, or a folder of the same sweep)")->required();
  cmd->add_option("SHARD_DIR", args->shards, "the shards' output folders")->required()->check(CLI::ExistingDirectory);
  cmd->callback([args] {
    std::vector<fs::path> shards(args->shards.begin(), args->shards.end());
    const MergeOutcome outcome = MergeSweepShards(args->out, shards);
    for (const std::string& w : outcome.warnings) std::fprintf(stderr, "warning: %s\n", w.c_str());
    std::printf("merged %d of %s from %s into %s\n", outcome.merged, Count(outcome.cells, "cell").c_str(),
                Count(shards.size(), "shard folder").c_str(), args->out.c_str());
    if (!outcome.missing.empty()) {
      std::string list;
      for (size_t i = 0; i < outcome.missing.size() && i < 20; ++i) list += (i ? ", " : "") + outcome.missing[i];
      if (outcome.missing.size() > 20) list += ", ... (" + std::to_string(outcome.missing.size()) + " in all)";
      throw Unfinished(3, Count(outcome.missing.size(), "cell") + (outcome.missing.size() == 1 ? " is" : " are") + " in no shard folder: " + list +
                              "; run their shards again (rigsim sweep ... --shard I/N) and merge again");
    }
  });
}

}  // namespace rigsim::cli
