// The options of commands whose work splits into shards (sweep, render): --shard I/N to run one
// share here, --slurm to run every share as a Slurm job array with a merge job after it.
#pragma once

#include <string>
#include <utility>

#include <CLI/CLI.hpp>

#include "slurm/slurm_jobs.h"

namespace rigsim::cli {

struct ShardSettings {
  std::string shard;  // "I/N"
  bool slurm = false;
  bool dry_run = false;
  SlurmArrayJob job;  // --shards, --partition, --cpus-per-task, --time, --max-parallel
};

// --shard, --slurm and its options; `what` names the command's shares ("cells", "frames") in the help.
void AddShardOptions(CLI::App& cmd, ShardSettings& s, const std::string& what, const std::string& merge_command);

// "I/N" of --shard as (I, N); std::invalid_argument in the option's words.
std::pair<int, int> ParseShard(const std::string& text);

// Writes the scripts (--dry-run) or submits them, and prints what happened and how to follow it.
void SubmitOrWriteSlurm(const SlurmArrayJob& job, bool dry_run);

}  // namespace rigsim::cli
