// A sweep as Slurm jobs: a job array whose task I runs shard I of N (`rigsim sweep ... --shard I/N
// --out OUT/shards/I`), and a merge job that waits for every task to succeed
// (--dependency=afterok, --kill-on-invalid-dep=yes: a failed task cancels it instead of leaving it
// pending forever) and runs `rigsim sweep-merge OUT OUT/shards/0 ...`.
//
//   OUT/slurm/sweep.sbatch   the array job      OUT/slurm/merge.sbatch   the merge job
//   OUT/slurm/logs/          one log per task (shard-<I>.log) and merge.log
//   OUT/shards/<I>/          each task's sweep folder (its cells resume when the task is run again)
//
// Every path in the scripts is absolute: the binary, the config and OUT must be on a file system
// every node sees.
#pragma once

#include <filesystem>
#include <string>
#include <vector>

namespace rigsim {

struct SlurmSweep {
  std::filesystem::path binary;           // rigsim, absolute
  std::vector<std::string> sweep_args;    // what selects the sweep: {CONFIG} (absolute) or {--suite, thesis, --size, small}
  std::filesystem::path out;              // absolute
  std::string name;                       // the sweep's name, for the job names
  int num_shards = 1;
  std::string partition;                  // empty: the cluster's default
  int cpus_per_task = 2;
  std::string time_limit;                 // e.g. "02:00:00"; empty: the partition's default
  int max_parallel = 0;                   // tasks running at once (the array's %K); 0: no limit
  bool keep_datasets = false;
};

// The array job's script.
std::string SlurmArrayScript(const SlurmSweep& sweep);
// The merge job's script.
std::string SlurmMergeScript(const SlurmSweep& sweep);
// The shard folders the merge reads, in order.
std::vector<std::filesystem::path> SlurmShardDirs(const SlurmSweep& sweep);

struct SlurmSubmission {
  std::string array_job_id, merge_job_id;
};

// Writes both scripts into OUT/slurm/ and submits them with sbatch (the merge depending on the
// array). Throws std::runtime_error with sbatch's message when a submission fails.
SlurmSubmission SubmitSlurmSweep(const SlurmSweep& sweep);

// Writes the scripts only (--dry-run).
void WriteSlurmScripts(const SlurmSweep& sweep);

}  // namespace rigsim
