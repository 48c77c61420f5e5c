// rigsim sweep CONFIG | --suite NAME: renders and calibrates every cell of a sweep and summarises
// where calibration works and where it breaks.
#include <cstdio>
#include <filesystem>
#include <string>
#include <tuple>

#include <unistd.h>

#include "apps/rigsim/commands.h"
#include "apps/rigsim/interrupt.h"
#include "sweep/cell_runner.h"
#include "sweep/slurm.h"
#include "sweep/suites.h"
#include "sweep/sweep_config.h"
#include "sweep/sweep_runner.h"

namespace rigsim::cli {

namespace {

namespace fs = std::filesystem;

std::string Duration(double s) {
  char buf[32];
  if (s < 90) {
    std::snprintf(buf, sizeof buf, "%.0f s", s);
  } else if (s < 5400) {
    std::snprintf(buf, sizeof buf, "%.0f min", s / 60);
  } else {
    std::snprintf(buf, sizeof buf, "%.1f h", s / 3600);
  }
  return buf;
}

// One line on stderr, rewritten in place on a terminal; a line per finished cell otherwise.
class SweepProgressLine {
 public:
  SweepProgressLine() : tty_(::isatty(2)) {}
  void operator()(const SweepProgress& p) {
    std::string line = "sweep: " + std::to_string(p.done) + "/" + std::to_string(p.total) + " cells";
    if (p.resumed > 0) line += " (" + std::to_string(p.resumed) + " from an earlier run)";
    if (p.failed_rows > 0) line += ", " + std::to_string(p.failed_rows) + " failed runs";
    line += p.eta_s >= 0 ? ", about " + Duration(p.eta_s) + " left" : "";
    if (tty_) {
      std::string full = line + "  [" + p.current + "]";
      if (full.size() > 150) full = full.substr(0, 147) + "...";
      std::fprintf(stderr, "\r\033[K%s", full.c_str());
    } else if (p.done != last_done_) {
      std::fprintf(stderr, "%s\n", line.c_str());
    }
    last_done_ = p.done;
    std::fflush(stderr);
  }
  ~SweepProgressLine() {
    if (tty_) std::fprintf(stderr, "\n");
  }

 private:
  bool tty_;
  int last_done_ = -1;
};

// "I/N" of --shard.
std::pair<int, int> ParseShard(const std::string& text) {
  const size_t slash = text.find('/');
  try {
    size_t used_i = 0, used_n = 0;
    const int i = std::stoi(text.substr(0, slash), &used_i);
    const int n = std::stoi(text.substr(slash + 1), &used_n);
    if (slash == std::string::npos || used_i != slash || used_n != text.size() - slash - 1 || n < 1 || i < 0 || i >= n) {
      throw std::invalid_argument("");
    }
    return {i, n};
  } catch (const std::exception&) {
    throw std::invalid_argument("--shard: give I/N with 0 <= I < N, e.g. 0/4 (got '" + text + "')");
  }
}

void ListParams() {
  std::printf("Cell parameters (a config's base, set, grid and zip):\n\n");
  for (const ParamSpec& p : CellParamSpecs()) {
    std::string def = p.default_value.is_null() ? "unset" : FormatParamValue(p.default_value);
    std::printf("  %-16s default %-8s %s\n", p.name.c_str(), def.c_str(), p.help.c_str());
  }
  std::printf("\nMethods: semantics none, mask, gated, mask+gated; features sift, rootsift, orb, akaze; peers colmap\n");
}

}  // namespace

void AddSweepCommand(CLI::App& app) {
  struct Args {
    std::string config, suite, size = "small", out, shard;
    bool keep_datasets = false, force = false, list_params = false, dry_run = false;
    int threads = 0;
    bool slurm = false;
    SlurmSweep slurm_job;
  };
  auto args = std::make_shared<Args>();
  CLI::App* cmd = app.add_subcommand(
      "sweep",
      "Map where calibration works: vary what makes it hard (overlap, baseline, lens, label noise, scene,\n"
      "...) over seeds, render every cell once, calibrate it by every method (rigsim's semantic modes and\n"
      "feature types, COLMAP) and score each against the truth.\n"
      "CONFIG is a .json or .yaml file (see README, \"Sweeps\"; --list-params lists the parameters), or\n"
      "--suite thesis runs the built-in test of the thesis's four claims (--size small: minutes; full).\n"
      "Writes OUT/results.csv and results.jsonl (a row per cell and method), summary.csv, plots/ (PNG\n"
      "and SVG, by gnuplot) and report.md. Finished cells are kept in OUT/cells/: running the same\n"
      "command again resumes, and Ctrl-C loses only the cell in progress. Exit code 0 when the sweep\n"
      "ran (whatever the calibrations gave), 1 on bad input, 130 when interrupted.");
  CLI::Option* config = cmd->add_option("CONFIG", args->config, "sweep config (.json, .yaml)")->check(CLI::ExistingFile);
  CLI::Option* suite = cmd->add_option("--suite", args->suite, "a built-in sweep instead of CONFIG: thesis")->excludes(config);
  cmd->add_option("--size", args->size, "with --suite: small (1 seed, two values per study) or full")
      ->capture_default_str()
      ->check(CLI::IsMember({"small", "full"}));
  cmd->add_option("--out", args->out, "output folder (default out/sweep/<config name>)");
  cmd->add_flag("--keep-datasets", args->keep_datasets,
                "keep every cell's rendered dataset in OUT/datasets/<key> (they are deleted after their cell "
                "otherwise, so that a large sweep does not fill the disk)");
  cmd->add_flag("--force", args->force, "start over: remove OUT's earlier sweep results (only what a sweep writes)");
  cmd->add_option("--threads", args->threads, "worker threads, 0 = all cores")->capture_default_str()->check(CLI::NonNegativeNumber);
  cmd->add_flag("--list-params", args->list_params, "list the cell parameters and methods, and exit");
  cmd->add_flag("--dry-run", args->dry_run, "list the cells and exit; with --slurm: write the job scripts, do not submit");
  cmd->add_option("--shard", args->shard,
                  "I/N: run only shard I of N (0 <= I < N; every cell is in one shard, the shards balanced by\n"
                  "their render and calibration cost); combine the shards' folders with `rigsim sweep-merge`");
  const std::string slurm_group = "Slurm (a job array of shards and a merge job; see README, \"Sweeps on a cluster\")";
  cmd->add_flag("--slurm", args->slurm, "submit the sweep to Slurm with sbatch instead of running it here")->group(slurm_group);
  cmd->add_option("--shards", args->slurm_job.num_shards, "--slurm: array tasks (default: one per cell, at most 64)")
      ->group(slurm_group)
      ->check(CLI::Range(1, 100000));
  cmd->add_option("--partition", args->slurm_job.partition, "--slurm: partition (default: the cluster's)")->group(slurm_group);
  cmd->add_option("--cpus-per-task", args->slurm_job.cpus_per_task, "--slurm: CPUs of each task")
      ->capture_default_str()
      ->group(slurm_group)
      ->check(CLI::Range(1, 4096));
  cmd->add_option("--time", args->slurm_job.time_limit, "--slurm: time limit of each task, e.g. 02:00:00")->group(slurm_group);
  cmd->add_option("--max-parallel", args->slurm_job.max_parallel, "--slurm: tasks running at once (0: no limit)")
      ->capture_default_str()
      ->group(slurm_group)
      ->check(CLI::NonNegativeNumber);
  cmd->callback([args, config, suite] {
    if (args->list_params) {
      ListParams();
      return;
    }
    if (config->count() == 0 && suite->count() == 0) throw CLI::ValidationError("sweep", "give CONFIG or --suite thesis");
    SweepConfig sweep;
    fs::path config_dir = fs::current_path();
    // How the sweep is started, the same for every shard and run (for its report).
    std::string command = "rigsim sweep ";
    std::vector<std::string> sweep_args;
    if (!args->suite.empty()) {
      sweep = ParseSweepConfig(SuiteConfig(args->suite, args->size), "--suite " + args->suite);
      command += "--suite " + args->suite + " --size " + args->size;
      sweep_args = {"--suite", args->suite, "--size", args->size};
    } else {
      sweep = ReadSweepConfig(args->config);
      config_dir = fs::absolute(args->config).parent_path();
      command += fs::path(args->config).filename().string();
      sweep_args = {fs::absolute(args->config).lexically_normal().string()};
    }
    const fs::path out = args->out.empty() ? fs::path("out") / "sweep" / sweep.name : fs::path(args->out);
    const std::vector<SweepCell> cells = ExpandCells(sweep);
    SweepRunOptions options;
    options.out_dir = out;
    options.keep_datasets = args->keep_datasets;
    options.restart = args->force;
    options.command = command;
    if (!args->shard.empty()) std::tie(options.shard_index, options.num_shards) = ParseShard(args->shard);
    std::fprintf(stderr, "sweep %s: %zu cells x %zu methods into %s\n", sweep.name.c_str(), cells.size(),
                 sweep.methods.size(), out.string().c_str());
    if (args->slurm) {
      if (!args->shard.empty()) throw std::invalid_argument("--slurm makes the shards itself: leave out --shard");
      SlurmSweep job = args->slurm_job;
      job.binary = fs::read_symlink("/proc/self/exe");
      job.sweep_args = sweep_args;
      job.out = fs::absolute(out).lexically_normal();
      job.name = sweep.name;
      job.keep_datasets = args->keep_datasets;
      if (job.num_shards <= 0) job.num_shards = std::max(1, std::min<int>(64, static_cast<int>(cells.size())));
      options.num_shards = job.num_shards;
      PrepareSweepFolder(sweep, options);
      if (args->dry_run) {
        WriteSlurmScripts(job);
        std::printf("wrote %s and %s (not submitted: --dry-run)\n", (job.out / "slurm" / "sweep.sbatch").c_str(),
                    (job.out / "slurm" / "merge.sbatch").c_str());
        return;
      }
      const SlurmSubmission submitted = SubmitSlurmSweep(job);
      std::printf("submitted the sweep as job array %s (%d tasks) and its merge as job %s (runs when every task has\n"
                  "succeeded; a failed task cancels it)\n",
                  submitted.array_job_id.c_str(), job.num_shards, submitted.merge_job_id.c_str());
      std::printf("follow:   squeue -j %s,%s    scontrol show job %s    sacct -j %s,%s\n", submitted.array_job_id.c_str(),
                  submitted.merge_job_id.c_str(), submitted.array_job_id.c_str(), submitted.array_job_id.c_str(),
                  submitted.merge_job_id.c_str());
      std::printf("logs:     %s\n", (job.out / "slurm" / "logs").c_str());
      std::printf("a task I failed? run it again, and the merge after it:\n"
                  "          sbatch --parsable --array=I %s\n"
                  "          sbatch --dependency=afterok:<its job id> --kill-on-invalid-dep=yes %s\n",
                  (job.out / "slurm" / "sweep.sbatch").c_str(), (job.out / "slurm" / "merge.sbatch").c_str());
      std::printf("results:  %s (report.md, results.csv) once the merge has run\n", job.out.c_str());
      return;
    }
    if (args->dry_run) {
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
    std::printf("sweep %s: %d cells (%d run now, %d from an earlier run), %d failed runs\n", sweep.name.c_str(),
                outcome.cells, outcome.ran, outcome.resumed, outcome.failed_rows);
    if (options.num_shards > 1) {
      std::printf("shard %d/%d in %s; combine the shards with: rigsim sweep-merge OUT SHARD_DIR...\n", options.shard_index,
                  options.num_shards, out.string().c_str());
    } else {
      std::printf("results in %s: report.md, results.csv, results.jsonl, summary.csv, plots/\n", out.string().c_str());
    }
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
    std::printf("merged %d of %d cells from %zu shard folders into %s\n", outcome.merged, outcome.cells, shards.size(),
                args->out.c_str());
    if (!outcome.missing.empty()) {
      std::string list;
      for (size_t i = 0; i < outcome.missing.size() && i < 20; ++i) list += (i ? ", " : "") + outcome.missing[i];
      if (outcome.missing.size() > 20) list += ", ... (" + std::to_string(outcome.missing.size()) + " in all)";
      throw Unfinished(3, std::to_string(outcome.missing.size()) + " cells are in no shard folder: " + list +
                              "; run their shards again (rigsim sweep ... --shard I/N) and merge again");
    }
  });
}

}  // namespace rigsim::cli
