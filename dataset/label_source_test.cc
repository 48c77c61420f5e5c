#include "dataset/label_source.h"


#include <gmock/gmock.h>
#include <gtest/gtest.h>

#include "dataset/image_io.h"
#include "dataset/label_image.h"
#include "testing/expect_error.h"
#include "testing/temp_dir.h"

namespace rigsim {
namespace {
namespace fs = std::filesystem;

class LabelSourceTest : public ::testing::Test {
 protected:
  void SetUp() override {
    truth_ = ImageU8(64, 48, 1, 23);
    for (int y = 20; y < 48; ++y) {
      for (int x = 0; x < 64; ++x) truth_.at(x, y) = x < 30 ? 11 : (y > 40 ? 7 : 26);
    }
    const DatasetLayout layout(dir_ / "dataset");
    fs::create_directories(layout.Label("cam0", "000000").parent_path());
    WriteImage(layout.Label("cam0", "000000"), truth_);
  }
  fs::path Write(const std::string& folder, const ImageU8& image) {
    const fs::path p = dir_ / folder / "cam0" / "000000.png";
    fs::create_directories(p.parent_path());
    WriteImage(p, image);
    return p;
  }
  // LoadLabels from `folder` fails with a message naming its file and saying `part`.
  void ExpectFolderFails(const std::string& folder, const std::string& part, int width = 64, int height = 48,
                         const char* file = __builtin_FILE(), int line = __builtin_LINE()) {
    const ::testing::ScopedTrace trace(file, line, folder);
    const fs::path label_file = dir_ / folder / "cam0" / "000000.png";
    auto load = [&] {
      LoadLabels(LabelSource::Folder(dir_ / folder), DatasetLayout(dir_ / "dataset"), "cam0", "000000", width, height);
    };
    EXPECT_THAT(load, ThrowsNaming<std::runtime_error>(label_file.string() + ": ", part));
  }
  const TempDir dir_;
  ImageU8 truth_;
};

TEST_F(LabelSourceTest, TruthIsTheRenderedLabels) {
  const DatasetLayout layout(dir_ / "dataset");
  EXPECT_EQ(LoadLabels(LabelSource::Truth(), layout, "cam0", "000000", 64, 48).data, truth_.data);
  EXPECT_EQ(LabelSource::Truth().KindName(), "truth");
}

TEST_F(LabelSourceTest, UserFolderInIdsAndInColoursGivesTheSameLabels) {
  Write("ids", truth_);
  Write("colors", ColorizeLabels(truth_));
  ImageU8 rgba(64, 48, 4, 255);  // RGBA: alpha is ignored
  const ImageU8 colors = ColorizeLabels(truth_);
  for (int y = 0; y < 48; ++y) {
    for (int x = 0; x < 64; ++x) {
      for (int c = 0; c < 3; ++c) rgba.at(x, y, c) = colors.at(x, y, c);
    }
  }
  Write("rgba", rgba);
  const DatasetLayout layout(dir_ / "dataset");
  for (const char* folder : {"ids", "colors", "rgba"}) {
    SCOPED_TRACE(folder);
    EXPECT_EQ(LoadLabels(LabelSource::Folder(dir_ / folder), layout, "cam0", "000000", 64, 48).data, truth_.data);
  }
  LabelImageFormat format;
  ReadLabelImageIdsOrColors(dir_ / "colors" / "cam0" / "000000.png", 64, 48, &format);
  EXPECT_EQ(format, LabelImageFormat::kColors);
  ReadLabelImageIdsOrColors(dir_ / "ids" / "cam0" / "000000.png", 64, 48, &format);
  EXPECT_EQ(format, LabelImageFormat::kIds);
}

TEST_F(LabelSourceTest, BadUserLabelImagesAreErrorsNamingTheFile) {
  Write("small", ImageU8(32, 48, 1, 11));
  ExpectFolderFails("small", "label image is 32x48, its image is 64x48");
  ImageU8 colors = ColorizeLabels(truth_);
  colors.at(5, 7, 0) = 1;  // (1, 130, 180): no Cityscapes colour
  Write("bad_color", colors);
  ExpectFolderFails("bad_color", "pixel (5, 7) has colour (1, 130, 180), which is no Cityscapes class colour");
  ImageU8 ids = truth_;
  ids.at(3, 2) = 77;
  Write("bad_id", ids);
  ExpectFolderFails("bad_id", "pixel (3, 2) has label id 77");
  Write("two_channels", ImageU8(64, 48, 2, 11));
  ExpectFolderFails("two_channels", "must have 1 channel (Cityscapes label ids) or 3");
  fs::create_directories(dir_ / "empty" / "cam0");
  ExpectFolderFails("empty", "label image missing");
  // No folder for the camera: the message names the folder, the nearest there is and what there is.
  fs::create_directories(dir_ / "misnamed" / "CAM0");
  fs::create_directories(dir_ / "misnamed" / "cam1");
  try {
    LoadLabels(LabelSource::Folder(dir_ / "misnamed"), DatasetLayout(dir_ / "dataset"), "cam0", "000000", 64, 48);
    ADD_FAILURE() << "no error for a missing camera folder";
  } catch (const std::runtime_error& e) {
    EXPECT_EQ(std::string(e.what()), (dir_ / "misnamed" / "cam0").string() +
                                         ": no such folder: the label images of camera 'cam0' of rig.json go in misnamed/cam0/ "
                                         "(did you mean 'CAM0'?); misnamed/ holds CAM0, cam1 (a folder per camera, named as in rig.json)");
  }
}

TEST_F(LabelSourceTest, MissingFolderIsNamedByCheck) {
  EXPECT_THAT([&] { LabelSource::Folder(dir_ / "nowhere").Check(); },
              ThrowsWith<std::runtime_error>((dir_ / "nowhere").string() + ": no such label folder"));
  SegmentationNoiseOptions bad;
  bad.confusion_rate = 2;
  EXPECT_THROW(LabelSource::Noisy(bad).Check(), std::invalid_argument);
}

TEST_F(LabelSourceTest, NoisyIsTheTruthThroughTheNoiseModel) {
  SegmentationNoiseOptions noise;
  noise.boundary_px = 3;
  noise.confusion_rate = 0.5;
  noise.blob_size_px = 8;
  noise.seed = 11;
  const DatasetLayout layout(dir_ / "dataset");
  const ImageU8 noisy = LoadLabels(LabelSource::Noisy(noise), layout, "cam0", "000000", 64, 48);
  EXPECT_EQ(noisy.data, ApplySegmentationNoise(truth_, noise, "cam0", "000000").data);
  EXPECT_NE(noisy.data, truth_.data);
  EXPECT_EQ(LabelSource::Noisy(noise).Describe(), "noisy truth (boundary 3 px, confusion 0.5, blobs 8 px, seed 11)");
  noise.boundary_px = 0;
  noise.confusion_rate = 0;
  EXPECT_EQ(LoadLabels(LabelSource::Noisy(noise), layout, "cam0", "000000", 64, 48).data, truth_.data);
}

}  // namespace
}  // namespace rigsim
