#include "apps/rigsim/shard_options.h"

#include <cstdio>
#include <stdexcept>

namespace rigsim::cli {

void AddShardOptions(CLI::App& cmd, ShardSettings& s, const std::string& what, const std::string& merge_command) {
  cmd.add_option("--shard", s.shard,
                 "I/N: run only share I of N of the " + what + " (0 <= I < N; every one is in exactly one share)\n"
                 "into --out; combine the shares' folders with `rigsim " + merge_command + "`");
  const std::string group = "Slurm (a job array of shards and a merge job; see docs/sweeps.md, \"Running on a cluster\")";
  cmd.add_flag("--slurm", s.slurm, "submit the work to Slurm with sbatch instead of running it here")->group(group);
  cmd.add_flag("--dry-run", s.dry_run, "with --slurm: write the job scripts, do not submit them")->group(group);
  cmd.add_option("--shards", s.job.num_shards, "--slurm: array tasks (default: one per " + what.substr(0, what.size() - 1) +
                                                   ", at most 64)")
      ->group(group)
      ->check(CLI::Range(1, 100000));
  cmd.add_option("--partition", s.job.partition, "--slurm: partition (default: the cluster's)")->group(group);
  cmd.add_option("--cpus-per-task", s.job.cpus_per_task, "--slurm: CPUs of each task")
      ->capture_default_str()
      ->group(group)
      ->check(CLI::Range(1, 4096));
  cmd.add_option("--time", s.job.time_limit, "--slurm: time limit of each task, e.g. 02:00:00")->group(group);
  cmd.add_option("--max-parallel", s.job.max_parallel, "--slurm: tasks running at once (0: no limit)")
      ->capture_default_str()
      ->group(group)
      ->check(CLI::NonNegativeNumber);
}

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

void SubmitOrWriteSlurm(const SlurmArrayJob& job, bool dry_run) {
  if (dry_run) {
    WriteSlurmScripts(job);
    std::printf("wrote %s and %s (not submitted: --dry-run)\n", SlurmArrayScriptPath(job).c_str(),
                SlurmMergeScriptPath(job).c_str());
    return;
  }
  std::printf("%s", SlurmFollowUp(job, SubmitSlurmJobs(job)).c_str());
}

}  // namespace rigsim::cli
