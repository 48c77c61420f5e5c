#include "slurm/slurm_jobs.h"

#include <fstream>
#include <sstream>
#include <stdexcept>

#include "common/run_program.h"
#include "geometry/json_io.h"

namespace rigsim {

namespace fs = std::filesystem;

namespace {

// A word for bash: single-quoted, so nothing in it is expanded.
std::string Quote(const std::string& s) {
  std::string q = "'";
  for (char c : s) q += c == '\'' ? std::string("'\\''") : std::string(1, c);
  return q + "'";
}

std::string JobName(const SlurmArrayJob& s, const std::string& what) {
  std::string name = "rigsim-" + what + "-";
  for (char c : s.name) name += std::isalnum(static_cast<unsigned char>(c)) || c == '-' || c == '_' ? c : '_';
  return name;
}

std::string Header(const SlurmArrayJob& s, const std::string& job_name, int cpus, const std::string& log) {
  std::string h = "#!/bin/bash\n";
  h += "#SBATCH --job-name=" + job_name + "\n";
  h += "#SBATCH --cpus-per-task=" + std::to_string(cpus) + "\n";
  h += "#SBATCH --output=" + (s.work / "slurm" / "logs" / log).string() + "\n";
  if (!s.partition.empty()) h += "#SBATCH --partition=" + s.partition + "\n";
  if (!s.time_limit.empty()) h += "#SBATCH --time=" + s.time_limit + "\n";
  return h;
}

std::string Args(const SlurmArrayJob& s) {
  std::string args;
  for (const std::string& a : s.args) {
    args += ' ';
    args += Quote(a);
  }
  return args;
}

// sbatch --parsable prints "JOBID" or "JOBID;CLUSTER".
std::string Submit(const std::vector<std::string>& args, const fs::path& log) {
  fs::remove(log);
  const ProgramRun run = RunProgram(args, log);
  const std::string output = json_io::ReadText(log);
  if (run.exit_code != 0) {
    throw std::runtime_error("sbatch failed" + (run.error.empty() ? "" : " (" + run.error + ")") + ": " + output);
  }
  std::string id = output.substr(0, output.find_first_of(";\n"));
  if (id.empty() || id.find_first_not_of("0123456789") != std::string::npos) {
    throw std::runtime_error("sbatch printed no job id: " + output);
  }
  return id;
}

}  // namespace

std::vector<fs::path> SlurmShardDirs(const SlurmArrayJob& s) {
  std::vector<fs::path> dirs;
  for (int i = 0; i < s.num_shards; ++i) dirs.push_back(s.work / "shards" / std::to_string(i));
  return dirs;
}

fs::path SlurmArrayScriptPath(const SlurmArrayJob& s) { return s.work / "slurm" / (s.command + ".sbatch"); }
fs::path SlurmMergeScriptPath(const SlurmArrayJob& s) { return s.work / "slurm" / "merge.sbatch"; }

std::string SlurmArrayScript(const SlurmArrayJob& s) {
  std::string h = Header(s, JobName(s, s.command), s.cpus_per_task, "shard-%a.log");
  h += "#SBATCH --array=0-" + std::to_string(s.num_shards - 1);
  if (s.max_parallel > 0) h += '%' + std::to_string(s.max_parallel);
  h += '\n';
  h += "# Task I runs shard I of " + std::to_string(s.num_shards) + " into " + (s.work / "shards").string() +
       "/I.\n"
       "# The binary, the inputs and the output folders must be on a file system every node sees.\n"
       "# A failed task can be run again alone: sbatch --array=I " + SlurmArrayScriptPath(s).string() +
       "\nset -euo pipefail\n";
  h += "exec ";
  h += Quote(s.binary.string()) + " " + s.command + Args(s) + " --shard \"$SLURM_ARRAY_TASK_ID/" +
       std::to_string(s.num_shards) + "\" --out " + Quote((s.work / "shards").string()) +
       "/\"$SLURM_ARRAY_TASK_ID\" --threads \"${SLURM_CPUS_PER_TASK:-" + std::to_string(s.cpus_per_task) + "}\"\n";
  return h;
}

std::string SlurmMergeScript(const SlurmArrayJob& s) {
  std::string h = Header(s, JobName(s, "merge"), 1, "merge.log");
  h += "# Combines the shards into " + s.out.string() + ".\nset -euo pipefail\n";
  h += "exec ";
  h += Quote(s.binary.string()) + " " + s.merge_command + " " + Quote(s.out.string());
  for (const fs::path& d : SlurmShardDirs(s)) {
    h += ' ';
    h += Quote(d.string());
  }
  return h + "\n";
}

void WriteSlurmScripts(const SlurmArrayJob& s) {
  fs::create_directories(s.work / "slurm" / "logs");
  json_io::WriteTextAtomic(SlurmArrayScriptPath(s), SlurmArrayScript(s));
  json_io::WriteTextAtomic(SlurmMergeScriptPath(s), SlurmMergeScript(s));
}

SlurmSubmission SubmitSlurmJobs(const SlurmArrayJob& s) {
  WriteSlurmScripts(s);
  SlurmSubmission job;
  const fs::path log = s.work / "slurm" / "logs" / "sbatch.log";
  job.array_job_id = Submit({"sbatch", "--parsable", SlurmArrayScriptPath(s).string()}, log);
  job.merge_job_id = Submit({"sbatch", "--parsable", "--dependency=afterok:" + job.array_job_id, "--kill-on-invalid-dep=yes",
                             SlurmMergeScriptPath(s).string()},
                            log);
  return job;
}

std::string SlurmFollowUp(const SlurmArrayJob& s, const SlurmSubmission& submitted) {
  const std::string& a = submitted.array_job_id;
  const std::string& m = submitted.merge_job_id;
  return "submitted job array " + a + " (" + std::to_string(s.num_shards) + " tasks) and the merge as job " + m +
         " (runs when every task has\nsucceeded; a failed task cancels it)\n" +
         "follow:   squeue -j " + a + "," + m + "    scontrol show job " + a + "    sacct -j " + a + "," + m + "\n" +
         "logs:     " + (s.work / "slurm" / "logs").string() + "\n" +
         "a task I failed? run it again, and the merge after it:\n"
         "          sbatch --parsable --array=I " + SlurmArrayScriptPath(s).string() + "\n" +
         "          sbatch --dependency=afterok:<its job id> --kill-on-invalid-dep=yes " + SlurmMergeScriptPath(s).string() +
         "\n" + "result:   " + s.out.string() + " once the merge has run\n";
}

}  // namespace rigsim
