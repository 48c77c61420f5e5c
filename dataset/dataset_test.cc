#include "dataset/dataset.h"

#include <fstream>

#include <gmock/gmock.h>
#include <gtest/gtest.h>

#include "testing/expect_error.h"
#include "testing/temp_dir.h"

namespace rigsim {
namespace {
namespace fs = std::filesystem;

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
    EXPECT_THAT([&] { FramesFromJsonText(text, "d/frames.json"); }, ThrowsWith<std::runtime_error>("d/frames.json")) << text;
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
  const TempDir dir;
  fs::create_directories(dir / "images" / "a");
  std::ofstream(dir / "images" / "a" / "b.jpg") << "x";
  std::ofstream(dir / "images" / "a" / "a.jpg") << "x";
  const FramesFile f = DatasetLayout(dir).ReadFramesOrScan("a");
  ASSERT_EQ(f.frames.size(), 2u);
  EXPECT_EQ(f.frames[0].name, "a");
  EXPECT_EQ(*DatasetLayout(dir).FindImage("a", "b"), dir / "images" / "a" / "b.jpg");
  EXPECT_THROW(DatasetLayout(dir).ReadFramesOrScan("missing"), std::runtime_error);
}

TEST(DatasetLayout, ScanningSkipsHiddenFilesAndFilesThatAreNoPhotos) {
  const TempDir dir;
  const fs::path cam = dir / "images" / "a";
  fs::create_directories(cam / "sub.jpg");  // a folder, whatever its name
  for (const char* name : {"0001.JPG", "0002.png", ".DS_Store", "._0001.JPG", "notes.txt", "0003.jpg.xmp", "Thumbs.db"}) {
    std::ofstream(cam / name) << "x";
  }
  const FramesFile f = DatasetLayout(dir).ReadFramesOrScan("a");
  ASSERT_EQ(f.frames.size(), 2u);
  EXPECT_EQ(f.frames[0].name, "0001");
  EXPECT_EQ(f.frames[1].name, "0002");
  for (const char* name : {"0001.JPG", "0002.png"}) fs::remove(cam / name);
  EXPECT_THAT([&] { DatasetLayout(dir).ReadFramesOrScan("a"); },
              ThrowsWith<std::runtime_error>(cam.string() + ": no images (.png .jpg"));
}

TEST(DatasetLayout, ImagesAreNamedWithTheExtensionTheyHave) {
  const TempDir dir;
  fs::create_directories(dir / "images" / "front");
  fs::create_directories(dir / "images" / "side");
  std::ofstream(dir / "images" / "front" / "0001.JPG") << "x";
  std::ofstream(dir / "images" / "side" / "0001.png") << "x";
  const DatasetLayout layout(dir);
  EXPECT_EQ(layout.ImageName("front", "0001"), "front/0001.JPG");
  EXPECT_EQ(layout.ImageName("side", "0001"), "side/0001.png");
  EXPECT_EQ(layout.ImageName("side", "0002"), "side/0002.png");  // none yet: what render writes
  EXPECT_EQ(layout.RequireImage("front", "0001"), dir / "images" / "front" / "0001.JPG");
  EXPECT_THAT([&] { layout.RequireImage("side", "0002"); },
              ThrowsNaming<std::runtime_error>((dir / "images" / "side" / "0002").string() +
                                                   ".*: image missing (camera 'side', frame '0002'",
                                               "tried .png .jpg .jpeg .JPG .JPEG .PNG .tif .tiff .exr"));
}

TEST(StagedOutput, NothingAppearsUntilCommitAndFailuresLeaveNothing) {
  const TempDir dir;
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
}

}  // namespace
}  // namespace rigsim
