#include "dataset/dataset.h"

#include <fstream>

#include <gtest/gtest.h>

namespace rigsim {
namespace {
namespace fs = std::filesystem;

fs::path FreshDir(const std::string& name) {
  const fs::path dir = fs::temp_directory_path() / ("rigsim_" + name);
  fs::remove_all(dir);
  fs::create_directories(dir);
  return dir;
}

TEST(Frames, JsonRoundTrip) {
  FramesFile f;
  f.scene = "street.glb";
  f.seed = 7;
  f.tool_version = "0.1.0";
  f.frames.push_back({"000000", Rigid3d(Eigen::Quaterniond(0, 1, 0, 0), Eigen::Vector3d(1, 2, 3)), 0.5});
  f.frames.push_back({"000001", std::nullopt, 1.0});
  EXPECT_EQ(FramesToJsonText(f).find("label_rules"), std::string::npos);  // only when rules were used
  f.label_rules = "rules.json";
  const FramesFile back = FramesFromJsonText(FramesToJsonText(f), "frames.json");
  ASSERT_EQ(back.frames.size(), 2u);
  EXPECT_EQ(back.scene, "street.glb");
  EXPECT_EQ(back.label_rules, "rules.json");
  EXPECT_EQ(back.seed, 7u);
  EXPECT_TRUE(back.frames[0].rig_from_world.has_value());
  EXPECT_FALSE(back.frames[1].rig_from_world.has_value());
  EXPECT_DOUBLE_EQ(back.frames[1].timestamp_s, 1.0);
  EXPECT_LT((back.frames[0].rig_from_world->translation - Eigen::Vector3d(1, 2, 3)).norm(), 1e-12);
}

TEST(Frames, BadInputNamesTheFile) {
  for (const char* text : {"[1,2", "{}", R"({"frames":[]})", R"({"frames":[{"name":"a/b"}]})",
                           R"({"frames":[{"name":"a"},{"name":"a"}]})"}) {
    try {
      FramesFromJsonText(text, "d/frames.json");
      FAIL() << text;
    } catch (const std::runtime_error& e) {
      EXPECT_NE(std::string(e.what()).find("d/frames.json"), std::string::npos);
    }
  }
}

TEST(DatasetLayout, PathsFollowTheDocumentedLayout) {
  const DatasetLayout d("/data/set");
  EXPECT_EQ(d.Image("cam1", "000003"), fs::path("/data/set/images/cam1/000003.png"));
  EXPECT_EQ(d.Label("cam1", "000003"), fs::path("/data/set/labels/cam1/000003.png"));
  EXPECT_EQ(d.Depth("cam1", "000003"), fs::path("/data/set/depth/cam1/000003.exr"));
  EXPECT_EQ(d.Instance("cam1", "000003"), fs::path("/data/set/instances/cam1/000003.png"));
}

TEST(DatasetLayout, FramesAreScannedWhenThereIsNoFramesJson) {
  const fs::path dir = FreshDir("scan");
  fs::create_directories(dir / "images" / "a");
  std::ofstream(dir / "images" / "a" / "b.jpg") << "x";
  std::ofstream(dir / "images" / "a" / "a.jpg") << "x";
  const FramesFile f = DatasetLayout(dir).ReadFramesOrScan("a");
  ASSERT_EQ(f.frames.size(), 2u);
  EXPECT_EQ(f.frames[0].name, "a");
  EXPECT_EQ(*DatasetLayout(dir).FindImage("a", "b"), dir / "images" / "a" / "b.jpg");
  EXPECT_THROW(DatasetLayout(dir).ReadFramesOrScan("missing"), std::runtime_error);
  fs::remove_all(dir);
}

TEST(StagedOutput, NothingAppearsUntilCommitAndFailuresLeaveNothing) {
  const fs::path dir = FreshDir("staged");
  const fs::path out = dir / "out";
  {
    StagedOutput staged(out, false);
    std::ofstream(staged.staging_dir() / "file") << "x";
    EXPECT_FALSE(fs::exists(out));
  }  // not committed: as if interrupted
  EXPECT_FALSE(fs::exists(out));
  EXPECT_TRUE(fs::is_empty(dir));
  {
    StagedOutput staged(out, false);
    std::ofstream(staged.staging_dir() / "file") << "new";
    staged.Commit();
  }
  EXPECT_TRUE(fs::exists(out / "file"));
  EXPECT_THROW(StagedOutput(out, false), std::runtime_error);  // no overwrite without force
  {
    StagedOutput staged(out, true);
    std::ofstream(staged.staging_dir() / "other") << "x";
    EXPECT_TRUE(fs::exists(out / "file"));  // old output intact until commit
    staged.Commit();
  }
  EXPECT_FALSE(fs::exists(out / "file"));
  EXPECT_TRUE(fs::exists(out / "other"));
  fs::remove_all(dir);
}

}  // namespace
}  // namespace rigsim
