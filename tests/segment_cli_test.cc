// `rigsim segment` and `calibrate --segmenter` through the built binary, with networks written by
// the test (testing/onnx_builder.h): the labels a network gives land where calibrate reads them and
// change what the mask mode calibrates with; a model or class table that does not fit stops the
// command before it writes anything.
#include <array>
#include <filesystem>
#include <string>
#include <vector>

#include <gtest/gtest.h>

#include "dataset/dataset.h"
#include "dataset/image_io.h"
#include "dataset/label_image.h"
#include "geometry/rig.h"
#include "labels/cityscapes.h"
#include "testing/onnx_builder.h"
#include "testing/rendered_yard.h"
#include "testing/temp_dir.h"
#include "tests/rigsim_cli.h"

namespace rigsim {
namespace {
namespace fs = std::filesystem;

constexpr std::array<double, 3> kMean = {0.485, 0.456, 0.406};  // the defaults: ImageNet's
constexpr std::array<double, 3> kStd = {0.229, 0.224, 0.225};

// The yard's photos as a real-photo user has them: rig.json, frames.json, images/; no labels.
void WriteYardPhotos(const fs::path& dir) {
  const RenderedYard& yard = TwoCameraYard();
  FramesFile frames;
  for (size_t f = 0; f < yard.rig_from_world.size(); ++f) frames.frames.push_back({"00000" + std::to_string(f), {}, 0.0});
  fs::create_directories(dir);
  WriteRig(yard.rig, dir / "rig.json");
  WriteFrames(frames, dir / "frames.json");
  const DatasetLayout layout(dir);
  for (size_t c = 0; c < yard.rig.cameras.size(); ++c) {
    for (size_t f = 0; f < frames.frames.size(); ++f) {
      const fs::path p = layout.Image(yard.rig.cameras[c].name, frames.frames[f].name);
      fs::create_directories(p.parent_path());
      WriteImage(p, yard.rgb[c][f]);
    }
  }
}

// A Cityscapes network (19 channels) that gives every pixel the class of train id `train_id`.
std::string EverywhereModel(int train_id) {
  OnnxConvModel m;
  m.weights.assign(19, {0, 0, 0});
  m.bias.assign(19, 0.f);
  m.bias[train_id] = 1.f;
  return OnnxModelBytes(m);
}

// The 19 training classes' colours, channel k = train id k: a nearest-colour network.
std::string PaletteModel() {
  std::vector<std::array<uint8_t, 3>> colours(19);
  for (const LabelClass& c : CityscapesClasses()) {
    if (c.train_id < 19) colours[c.train_id] = c.color;
  }
  return OnnxModelBytes(NearestColourModel(colours, kMean, kStd));
}

class SegmentCli : public testing::Test {
 protected:
  static void SetUpTestSuite() {
    scratch_ = new TempDir();
    WriteYardPhotos(*scratch_ / "yard");
  }
  static void TearDownTestSuite() { delete scratch_; }
  static fs::path Yard() { return *scratch_ / "yard"; }
  static TempDir* scratch_;
};
TempDir* SegmentCli::scratch_ = nullptr;

// One command from photos to a calibration with the network's labels: with every pixel building
// (reliable) the mask mode calibrates as the baseline does; with every pixel sky (unreliable) it
// has no feature left and calibrates no camera (exit 3), while the baseline still does.
TEST_F(SegmentCli, CalibrateWithTheNetworksLabels) {
  TempDir dir;
  WriteFile(dir / "building.onnx", EverywhereModel(2));
  WriteFile(dir / "sky.onnx", EverywhereModel(10));
  const fs::path out = dir / "cal";
  const CliResult r = RunRigsim({"calibrate", Yard().string(), "--semantics", "none,mask", "--segmenter",
                                 (dir / "building.onnx").string(), "--out", out.string()},
                                dir / "building");
  ASSERT_EQ(r.code, 0) << r.err;
  for (const char* cam : {"cam0", "cam1"}) {
    for (const char* frame : {"000000", "000001"}) {
      const ImageU8 labels = ReadLabelImage(out / "segmentation" / "labels" / cam / (std::string(frame) + ".png"), 320, 240);
      EXPECT_EQ(std::count(labels.data.begin(), labels.data.end(), 11), 320 * 240) << cam << " " << frame;
      EXPECT_TRUE(fs::exists(out / "segmentation" / "labels_color" / cam / (std::string(frame) + ".png")));
    }
  }
  EXPECT_TRUE(fs::exists(out / "segmentation" / "segmentation.json"));
  EXPECT_TRUE(fs::exists(out / "mask" / "rig.json"));
  EXPECT_TRUE(StagingFolders(out).empty());

  const CliResult sky = RunRigsim({"calibrate", Yard().string(), "--semantics", "none,mask", "--segmenter",
                                   (dir / "sky.onnx").string(), "--out", (dir / "sky").string()},
                                  dir / "sky");
  EXPECT_EQ(sky.code, 3) << sky.err;
  const ImageU8 labels = ReadLabelImage(dir / "sky" / "segmentation" / "labels" / "cam1" / "000001.png", 320, 240);
  EXPECT_EQ(std::count(labels.data.begin(), labels.data.end(), kSkyId), 320 * 240);
}

// `segment` writes label ids and previews in the layout --labels reads; each colour of the photo
// becomes its class. It replaces its own output only with --force.
TEST_F(SegmentCli, SegmentWritesLabelsPerPhoto) {
  TempDir dir;
  WriteFile(dir / "palette.onnx", PaletteModel());
  const fs::path photos = dir / "photos";
  ImageU8 photo(64, 48, 3);
  const std::array<uint8_t, 4> stripes = {7, 11, 21, 23};  // road, building, vegetation, sky
  for (int y = 0; y < 48; ++y) {
    for (int x = 0; x < 64; ++x) {
      for (int c = 0; c < 3; ++c) photo.at(x, y, c) = FindClassById(stripes[x / 16])->color[c];
    }
  }
  for (const char* cam : {"front", "back"}) {
    fs::create_directories(photos / "images" / cam);
    WriteImage(photos / "images" / cam / "f1.png", photo);
  }
  const std::vector<std::string> args = {"segment", photos.string(), "--model", (dir / "palette.onnx").string(),
                                         "--input-size", "32x24"};
  const CliResult r = RunRigsim(args, dir / "segment");
  ASSERT_EQ(r.code, 0) << r.err;
  for (const char* cam : {"front", "back"}) {
    const ImageU8 labels = ReadLabelImage(photos / "segmentation" / "labels" / cam / "f1.png", 64, 48);
    for (int x : {0, 5, 13, 18, 29, 34, 45, 50, 63}) EXPECT_EQ(labels.at(x, 20), stripes[x / 16]) << cam << " x " << x;
    const ImageU8 preview = ReadImageU8(photos / "segmentation" / "labels_color" / cam / "f1.png", 3);
    EXPECT_EQ(preview.at(40, 20, 1), FindClassById(21)->color[1]);
  }
  EXPECT_NE(RunRigsim(args, dir / "again").code, 0);  // its output exists
  std::vector<std::string> force = args;
  force.push_back("--force");
  EXPECT_EQ(RunRigsim(force, dir / "force").code, 0);
}

// A network that does not fit stops the command before it writes: the wrong number of classes, a
// file that is no model, a missing class table; and --segmenter does not combine with --labels.
TEST_F(SegmentCli, BadModelsWriteNothing) {
  TempDir dir;
  OnnxConvModel five;
  five.weights.assign(5, {1, 0, 0});
  five.bias.assign(5, 0.f);
  WriteFile(dir / "five.onnx", OnnxModelBytes(five));
  WriteFile(dir / "corrupt.onnx", PaletteModel().substr(0, 300));
  WriteFile(dir / "palette.onnx", PaletteModel());
  struct Case {
    std::vector<std::string> args;
    std::string named;  // the file the message must start from
  };
  const fs::path out = dir / "out";
  const std::vector<Case> cases = {
      {{"segment", Yard().string(), "--model", (dir / "five.onnx").string()}, (dir / "five.onnx").string()},
      {{"segment", Yard().string(), "--model", (dir / "corrupt.onnx").string()}, (dir / "corrupt.onnx").string()},
      {{"segment", Yard().string(), "--model", (dir / "palette.onnx").string(), "--classes", (dir / "none.txt").string()},
       (dir / "none.txt").string()},
      {{"calibrate", Yard().string(), "--semantics", "none,mask", "--segmenter", (dir / "five.onnx").string()},
       (dir / "five.onnx").string()},
      {{"calibrate", Yard().string(), "--semantics", "mask", "--segmenter", (dir / "palette.onnx").string(), "--labels",
        "noisy"},
       "--segmenter"},
      {{"calibrate", Yard().string(), "--semantics", "mask", "--classes", "ade20k"}, "--classes"},
  };
  for (const Case& c : cases) {
    std::vector<std::string> args = c.args;
    args.insert(args.end(), {"--out", out.string()});
    const CliResult r = RunRigsim(args, dir / "run");
    EXPECT_EQ(r.code, 1) << args[0] << " " << c.named << "\n" << r.err;
    EXPECT_NE(r.err.find(c.named), std::string::npos) << r.err;
    EXPECT_FALSE(fs::exists(out)) << c.named;
    EXPECT_TRUE(StagingFolders(out).empty());
  }
  EXPECT_FALSE(fs::exists(Yard() / "segmentation"));
  EXPECT_FALSE(fs::exists(Yard() / "calibration"));
}

}  // namespace
}  // namespace rigsim
