// Work that splits into shards as Slurm jobs: a job array whose task I runs shard I of N
// (`rigsim COMMAND ARGS... --shard I/N --out WORK/shards/I`), and a merge job that waits for every
// task to succeed (--dependency=afterok, --kill-on-invalid-dep=yes: a failed task cancels it
// instead of leaving it pending forever) and runs `rigsim MERGE_COMMAND OUT WORK/shards/0 ...`.
// A sweep (COMMAND sweep, WORK = OUT) and a long render (COMMAND render, WORK = OUT.shards) use it.
//
//   WORK/slurm/<command>.sbatch  the array job      WORK/slurm/merge.sbatch   the merge job
//   WORK/slurm/logs/             one log per task (shard-<I>.log) and merge.log
//   WORK/shards/<I>/             each task's output folder
//
// Every path in the scripts is absolute: the binary, the inputs, OUT and WORK must be on a file
// system every node sees.
#pragma once

#include <filesystem>
#include <string>
#include <vector>

namespace rigsim {

struct SlurmArrayJob {
  std::filesystem::path binary;     // rigsim, absolute
  std::string command;              // what each task runs with --shard I/N: "sweep" or "render"
  std::vector<std::string> args;    // the command's arguments every task shares (paths absolute)
  std::string merge_command;        // "sweep-merge" or "render-merge"
  std::filesystem::path out;        // what the merge writes, absolute
  std::filesystem::path work;       // where slurm/ and shards/ go, absolute
  std::string name;                 // for the job names
  int num_shards = 0;               // array tasks; 0 until the command chooses
  std::string partition;            // empty: the cluster's default
  int cpus_per_task = 2;
  std::string time_limit;           // e.g. "02:00:00"; empty: the partition's default
  int max_parallel = 0;             // tasks running at once (the array's %K); 0: no limit
};

// The array job's script.
std::string SlurmArrayScript(const SlurmArrayJob& job);
// The merge job's script.
std::string SlurmMergeScript(const SlurmArrayJob& job);
// The shard folders the merge reads, in order.
std::vector<std::filesystem::path> SlurmShardDirs(const SlurmArrayJob& job);
std::filesystem::path SlurmArrayScriptPath(const SlurmArrayJob& job);
std::filesystem::path SlurmMergeScriptPath(const SlurmArrayJob& job);

struct SlurmSubmission {
  std::string array_job_id, merge_job_id;
};

// Writes both scripts into WORK/slurm/ and submits them with sbatch (the merge depending on the
// array). Throws std::runtime_error with sbatch's message when a submission fails.
SlurmSubmission SubmitSlurmJobs(const SlurmArrayJob& job);

// Writes the scripts only (--dry-run).
void WriteSlurmScripts(const SlurmArrayJob& job);

// What the CLI prints after submitting: the job ids, how to follow them and to rerun a task.
std::string SlurmFollowUp(const SlurmArrayJob& job, const SlurmSubmission& submitted);

}  // namespace rigsim
