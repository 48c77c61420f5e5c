// `rigsim render --shard I/N` and `rigsim render-merge` through the built binary: three shards of
// the street merge into the bytes one render writes; bad shard requests are refused in the
// option's words; `--slurm --dry-run` writes the job array and the merge job that would do it.
#include <filesystem>
#include <map>
#include <string>
#include <vector>

#include <gtest/gtest.h>

#include "testing/temp_dir.h"
#include "tests/rigsim_cli.h"

namespace rigsim {
namespace {
namespace fs = std::filesystem;


std::vector<std::string> Render(const TempDir& dir, const std::string& out, std::vector<std::string> more = {}) {
  std::vector<std::string> args = {"render", "--scene", std::string(RIGSIM_SOURCE_DIR) + "/assets/scenes/street.glb",
                                   "--rig", (dir / "rig" / "rig.json").string(), "--frames",
                                   (dir / "rig" / "frames.json").string(), "--out", (dir / out).string(), "--spp", "2"};
  args.insert(args.end(), more.begin(), more.end());
  return args;
}

TEST(RenderShardsCli, ShardsMergeIntoTheOneMachineRender) {
  const TempDir dir;
  ASSERT_EQ(RunRigsim({"make-rig", "ring", "--cameras", "3", "--width", "160", "--height", "96", "--frames", "4",
                       "--out", (dir / "rig").string()},
                      dir / "make-rig")
                .code,
            0);
  ASSERT_EQ(RunRigsim(Render(dir, "whole", {"--coco"}), dir / "whole").code, 0);
  std::vector<std::string> merge = {"render-merge", (dir / "merged").string()};
  for (int i = 0; i < 3; ++i) {
    const std::string name = "shard" + std::to_string(i);
    const CliResult r = RunRigsim(Render(dir, name, {"--coco", "--shard", std::to_string(i) + "/3"}), dir / name);
    ASSERT_EQ(r.code, 0) << r.err;
    EXPECT_NE(r.out.find("shard " + std::to_string(i) + "/3: frames"), std::string::npos) << r.out;
    merge.push_back((dir / name).string());
  }
  const CliResult merged = RunRigsim(merge, dir / "merge");
  ASSERT_EQ(merged.code, 0) << merged.err;
  EXPECT_NE(merged.out.find("merged 3 shards (4 frames)"), std::string::npos) << merged.out;
  const auto expected = FilesUnder(dir / "whole"), got = FilesUnder(dir / "merged");
  ASSERT_EQ(got.size(), expected.size());
  for (const auto& [name, bytes] : expected) EXPECT_TRUE(got.count(name) && got.at(name) == bytes) << name;

  // Merging again into the same folder needs --force; a missing shard writes nothing.
  EXPECT_NE(RunRigsim(merge, dir / "again").code, 0);
  const CliResult gap = RunRigsim({"render-merge", (dir / "gap").string(), (dir / "shard0").string()}, dir / "gap");
  EXPECT_EQ(gap.code, 1);
  EXPECT_NE(gap.err.find("shards 1, 2 of 3 are missing"), std::string::npos) << gap.err;
  EXPECT_FALSE(fs::exists(dir / "gap"));
  EXPECT_TRUE(StagingFolders(dir / "gap").empty());

  // Shard requests the frames cannot meet.
  const CliResult bad = RunRigsim(Render(dir, "bad", {"--shard", "3/3"}), dir / "bad");
  EXPECT_EQ(bad.code, 1);
  EXPECT_NE(bad.err.find("--shard: give I/N with 0 <= I < N"), std::string::npos) << bad.err;
  const CliResult many = RunRigsim(Render(dir, "many", {"--shard", "0/5"}), dir / "many");
  EXPECT_EQ(many.code, 1);
  EXPECT_NE(many.err.find("has 4 frames; split it into at most 4 shards"), std::string::npos) << many.err;
  EXPECT_FALSE(fs::exists(dir / "bad"));
  EXPECT_FALSE(fs::exists(dir / "many"));

  // --slurm --dry-run: the scripts, with every path absolute; nothing rendered.
  const CliResult slurm = RunRigsim(Render(dir, "big", {"--slurm", "--dry-run", "--shards", "2", "--coco"}), dir / "slurm");
  ASSERT_EQ(slurm.code, 0) << slurm.err;
  const std::string array = ReadFile(dir / "big.shards" / "slurm" / "render.sbatch");
  EXPECT_NE(array.find("#SBATCH --array=0-1\n"), std::string::npos) << array;
  EXPECT_NE(array.find("'--coco' --shard \"$SLURM_ARRAY_TASK_ID/2\""), std::string::npos) << array;
  EXPECT_NE(array.find("'" + (dir / "rig" / "rig.json").string() + "'"), std::string::npos) << array;
  const std::string merge_script = ReadFile(dir / "big.shards" / "slurm" / "merge.sbatch");
  EXPECT_NE(merge_script.find("render-merge '" + (dir / "big").string() + "' '" + (dir / "big.shards" / "shards" / "0").string()),
            std::string::npos)
      << merge_script;
  EXPECT_FALSE(fs::exists(dir / "big"));
}

}  // namespace
}  // namespace rigsim
