#include "slurm/slurm_jobs.h"

#include <string>

#include <gtest/gtest.h>

namespace rigsim {
namespace {

SlurmArrayJob RenderJob() {
  SlurmArrayJob job;
  job.binary = "/opt/rig sim/rigsim";
  job.command = "render";
  job.args = {"--scene", "/data/it's.glb", "--spp", "4"};
  job.merge_command = "render-merge";
  job.out = "/data/out";
  job.work = "/data/out.shards";
  job.name = "out";
  job.num_shards = 3;
  job.max_parallel = 2;
  job.time_limit = "01:00:00";
  return job;
}

TEST(SlurmJobs, TheArrayRunsShardIOfNIntoItsOwnFolder) {
  const std::string script = SlurmArrayScript(RenderJob());
  EXPECT_EQ(script.rfind("#!/bin/bash\n", 0), 0u);
  EXPECT_NE(script.find("#SBATCH --array=0-2%2\n"), std::string::npos) << script;
  EXPECT_NE(script.find("#SBATCH --time=01:00:00\n"), std::string::npos);
  EXPECT_EQ(script.find("--partition"), std::string::npos) << "the cluster's default partition";
  EXPECT_NE(script.find("#SBATCH --output=/data/out.shards/slurm/logs/shard-%a.log\n"), std::string::npos);
  // Paths quoted for bash, the shard from the task id.
  EXPECT_NE(script.find("exec '/opt/rig sim/rigsim' render '--scene' '/data/it'\\''s.glb' '--spp' '4' --shard "
                        "\"$SLURM_ARRAY_TASK_ID/3\" --out '/data/out.shards/shards'/\"$SLURM_ARRAY_TASK_ID\""),
            std::string::npos)
      << script;
}

TEST(SlurmJobs, TheMergeReadsEveryShardInOrder) {
  const SlurmArrayJob job = RenderJob();
  const std::string script = SlurmMergeScript(job);
  EXPECT_NE(script.find("exec '/opt/rig sim/rigsim' render-merge '/data/out' '/data/out.shards/shards/0' "
                        "'/data/out.shards/shards/1' '/data/out.shards/shards/2'\n"),
            std::string::npos)
      << script;
  EXPECT_EQ(SlurmShardDirs(job).size(), 3u);
  EXPECT_EQ(SlurmArrayScriptPath(job), "/data/out.shards/slurm/render.sbatch");
  const std::string follow = SlurmFollowUp(job, {"17", "18"});
  EXPECT_NE(follow.find("--dependency=afterok:<its job id> --kill-on-invalid-dep=yes /data/out.shards/slurm/merge.sbatch"),
            std::string::npos);
  EXPECT_NE(follow.find("squeue -j 17,18"), std::string::npos);
}

}  // namespace
}  // namespace rigsim
