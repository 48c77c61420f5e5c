#include "segmentation/segmenter.h"

#include <gtest/gtest.h>

#include "dataset/dataset.h"
#include "dataset/image_io.h"
#include "dataset/label_source.h"
#include "labels/cityscapes.h"
#include "segmentation/segment_dataset.h"
#include "testing/onnx_builder.h"
#include "testing/temp_dir.h"

namespace rigsim {
namespace {

constexpr std::array<double, 3> kImageNetMean = {0.485, 0.456, 0.406};
constexpr std::array<double, 3> kImageNetStd = {0.229, 0.224, 0.225};

// The preview colours of Cityscapes' 19 training classes, channel k = train id k.
std::vector<std::array<uint8_t, 3>> TrainColours() {
  std::vector<std::array<uint8_t, 3>> colours;
  for (uint8_t id : LoadClassTable("cityscapes").label_ids) colours.push_back(FindClassById(id)->color);
  return colours;
}

// A 64 x 48 photo of four vertical stripes, 16 px each, painted in the colours of `stripe_ids`.
ImageU8 StripePhoto(const std::array<uint8_t, 4>& stripe_ids) {
  ImageU8 photo(64, 48, 3);
  for (int y = 0; y < photo.height; ++y) {
    for (int x = 0; x < photo.width; ++x) {
      for (int c = 0; c < 3; ++c) photo.at(x, y, c) = FindClassById(stripe_ids[x / 16])->color[c];
    }
  }
  return photo;
}

constexpr std::array<uint8_t, 4> kStripes = {7, 11, 21, 23};  // road, building, vegetation, sky

// Pixels at least `margin` px from a stripe boundary carry their stripe's class. (Nearer, the
// interpolated scores of two classes may favour a third: the blend of vegetation's and sky's
// colours is nearest to wall's.)
void ExpectStripes(const ImageU8& labels, int margin) {
  ASSERT_EQ(labels.width, 64);
  ASSERT_EQ(labels.height, 48);
  int wrong = 0;
  for (int y = 0; y < labels.height; ++y) {
    for (int x = 0; x < labels.width; ++x) {
      const int offset = x % 16;
      if ((offset >= margin || x < 16) && (offset < 16 - margin || x >= 48)) wrong += labels.at(x, y) != kStripes[x / 16];
    }
  }
  EXPECT_EQ(wrong, 0);
}

std::filesystem::path WriteModel(const TempDir& dir, const OnnxConvModel& m, const std::string& name = "net.onnx") {
  WriteFile(dir / name, OnnxModelBytes(m));
  return dir / name;
}

SegmenterOptions Options(const std::filesystem::path& model) {
  SegmenterOptions o;
  o.model = model;
  return o;
}

SegmenterErrorKind KindOf(const std::function<void()>& call) {
  try {
    call();
  } catch (const SegmenterError& e) {
    return e.kind;
  }
  ADD_FAILURE() << "no SegmenterError";
  return SegmenterErrorKind::kBadOptions;
}

// Pre-processing (downsizing, scaling, ImageNet normalisation, RGB), the network, the scores
// resized back to the photo and the class table: each colour becomes its class.
TEST(Segmenter, KnownColoursBecomeTheirClasses) {
  TempDir dir;
  SegmenterOptions o = Options(WriteModel(dir, NearestColourModel(TrainColours(), kImageNetMean, kImageNetStd)));
  o.input_width = 32;
  o.input_height = 24;
  const Segmenter segmenter(o);
  EXPECT_EQ((segmenter.InputSize(64, 48)), (std::array<int, 2>{32, 24}));
  ExpectStripes(segmenter.Segment(StripePhoto(kStripes)), 2);
}

// The network's own input size when it declares one, else 520 px on the shorter side (a multiple of 8).
TEST(Segmenter, InputSizeFollowsTheModel) {
  TempDir dir;
  OnnxConvModel m = NearestColourModel(TrainColours(), kImageNetMean, kImageNetStd);
  const Segmenter open(Options(WriteModel(dir, m, "open.onnx")));
  EXPECT_EQ((open.InputSize(3072, 2048)), (std::array<int, 2>{784, 520}));
  m.width = 16;
  m.height = 12;
  const Segmenter fixed(Options(WriteModel(dir, m, "fixed.onnx")));
  EXPECT_EQ((fixed.InputSize(64, 48)), (std::array<int, 2>{16, 12}));
  ExpectStripes(fixed.Segment(StripePhoto(kStripes)), 3);
  SegmenterOptions other = Options(dir / "fixed.onnx");
  other.input_width = 32;
  other.input_height = 24;
  EXPECT_EQ(KindOf([&] { Segmenter s(other); }), SegmenterErrorKind::kInputSizeMismatch);
}

// A network built for BGR input gives the right classes only when told so.
TEST(Segmenter, ChannelOrder) {
  TempDir dir;
  std::vector<std::array<uint8_t, 3>> bgr = TrainColours();
  for (auto& c : bgr) std::swap(c[0], c[2]);
  const std::array<double, 3> mean = {kImageNetMean[2], kImageNetMean[1], kImageNetMean[0]};
  const std::array<double, 3> std = {kImageNetStd[2], kImageNetStd[1], kImageNetStd[0]};
  SegmenterOptions o = Options(WriteModel(dir, NearestColourModel(bgr, mean, std)));
  o.mean = mean;
  o.std = std;
  o.channel_order = ChannelOrder::kBgr;
  ExpectStripes(Segmenter(o).Segment(StripePhoto(kStripes)), 1);
  o.channel_order = ChannelOrder::kRgb;
  const ImageU8 swapped = Segmenter(o).Segment(StripePhoto(kStripes));
  EXPECT_NE(swapped.at(40, 24), 21) << "vegetation's green-yellow read as RGB should not stay vegetation";
}

// A network ending in an ArgMax gives class indices; they are mapped the same way.
TEST(Segmenter, ClassIndexOutput) {
  TempDir dir;
  OnnxConvModel m = NearestColourModel(TrainColours(), kImageNetMean, kImageNetStd);
  m.argmax = true;
  SegmenterOptions o = Options(WriteModel(dir, m));
  o.input_width = 32;
  o.input_height = 24;
  ExpectStripes(Segmenter(o).Segment(StripePhoto(kStripes)), 2);
}

TEST(Segmenter, ClassTableFileMapsChannels) {
  TempDir dir;
  // Two channels: reddish -> car, everything greenish -> terrain.
  const OnnxConvModel m = NearestColourModel({{200, 0, 0}, {0, 200, 0}}, kImageNetMean, kImageNetStd);
  WriteFile(dir / "two.txt", "0 car\n1 terrain\n");
  SegmenterOptions o = Options(WriteModel(dir, m));
  o.classes = (dir / "two.txt").string();
  ImageU8 photo(20, 10, 3, 0);
  for (int y = 0; y < 10; ++y) {
    for (int x = 0; x < 20; ++x) photo.at(x, y, x < 10 ? 0 : 1) = 190;
  }
  const ImageU8 labels = Segmenter(o).Segment(photo);
  EXPECT_EQ(labels.at(2, 5), FindClassByName("car")->id);
  EXPECT_EQ(labels.at(17, 5), FindClassByName("terrain")->id);
}

TEST(Segmenter, WrongNumberOfClasses) {
  TempDir dir;
  const OnnxConvModel five = NearestColourModel({{0, 0, 0}, {255, 0, 0}, {0, 255, 0}, {0, 0, 255}, {9, 9, 9}},
                                                kImageNetMean, kImageNetStd);
  const Segmenter s(Options(WriteModel(dir, five)));
  EXPECT_EQ(KindOf([&] { s.Segment(StripePhoto(kStripes)); }), SegmenterErrorKind::kClassCountMismatch);
  OnnxConvModel indices = five;
  indices.argmax = true;  // indices up to 4; a two-class table
  WriteFile(dir / "two.txt", "0 car\n1 terrain\n");
  SegmenterOptions o = Options(WriteModel(dir, indices, "argmax.onnx"));
  o.classes = (dir / "two.txt").string();
  const Segmenter si(o);
  EXPECT_EQ(KindOf([&] { si.Segment(StripePhoto(kStripes)); }), SegmenterErrorKind::kClassCountMismatch);
}

TEST(Segmenter, UnreadableModels) {
  TempDir dir;
  EXPECT_EQ(KindOf([&] { Segmenter s(Options(dir / "missing.onnx")); }), SegmenterErrorKind::kUnreadableModel);
  WriteFile(dir / "text.onnx", "not a network\n");
  EXPECT_EQ(KindOf([&] { Segmenter s(Options(dir / "text.onnx")); }), SegmenterErrorKind::kUnreadableModel);
  const std::string bytes = OnnxModelBytes(NearestColourModel(TrainColours(), kImageNetMean, kImageNetStd));
  WriteFile(dir / "truncated.onnx", bytes.substr(0, bytes.size() - 40));
  EXPECT_EQ(KindOf([&] { Segmenter s(Options(dir / "truncated.onnx")); }), SegmenterErrorKind::kUnreadableModel);
  std::filesystem::create_directory(dir / "folder.onnx");
  EXPECT_EQ(KindOf([&] { Segmenter s(Options(dir / "folder.onnx")); }), SegmenterErrorKind::kUnreadableModel);
}

TEST(Segmenter, MissingClassTable) {
  TempDir dir;
  SegmenterOptions o = Options(WriteModel(dir, NearestColourModel(TrainColours(), kImageNetMean, kImageNetStd)));
  o.classes = (dir / "classes.txt").string();
  EXPECT_EQ(KindOf([&] { Segmenter s(o); }), SegmenterErrorKind::kClassTableFile);
}

TEST(Segmenter, BadOptions) {
  SegmenterOptions o;
  o.std[1] = 0;
  EXPECT_EQ(KindOf([&] { o.Check(); }), SegmenterErrorKind::kBadOptions);
  o = {};
  o.input_width = 100;
  EXPECT_EQ(KindOf([&] { o.Check(); }), SegmenterErrorKind::kBadOptions);
}

// Bilinear resizing with pixel centres aligned: two score pixels, class 0 then class 1, stretched
// to 8 pixels switch class in the middle.
TEST(Segmenter, ScoresAreResizedWithCentresAligned) {
  const float scores[] = {1, 0,   // channel 0
                          0, 1};  // channel 1
  const Image<uint16_t> out = ArgmaxOfResizedScores(scores, 2, 2, 1, 8, 3);
  for (int y = 0; y < 3; ++y) {
    for (int x = 0; x < 8; ++x) EXPECT_EQ(out.at(x, y), x < 4 ? 0 : 1) << x;
  }
  // Three channels where the interpolation, not the nearest pixel, decides: channel 2 is second
  // everywhere but wins between the two.
  const float three[] = {1.0f, 0.0f, 0.0f, 1.0f, 0.8f, 0.8f};
  const Image<uint16_t> mid = ArgmaxOfResizedScores(three, 3, 2, 1, 8, 1);
  EXPECT_EQ(mid.at(0, 0), 0);
  EXPECT_EQ(mid.at(3, 0), 2);
  EXPECT_EQ(mid.at(4, 0), 2);
  EXPECT_EQ(mid.at(7, 0), 1);
}

// A dataset's photos segmented into the folder layout calibrate's --labels DIR reads.
TEST(SegmentDataset, WritesLabelsCalibrateReads) {
  TempDir dir;
  const DatasetLayout layout(dir / "photos");
  for (const char* cam : {"left", "right"}) {
    for (const char* frame : {"a", "b"}) {
      std::filesystem::create_directories(layout.Image(cam, frame).parent_path());
      WriteImage(layout.Image(cam, frame), StripePhoto(kStripes));
    }
  }
  const std::vector<SegmentedPhoto> photos = PhotosToSegment(layout.root());
  ASSERT_EQ(photos.size(), 4u);
  EXPECT_EQ(photos[1].camera, "left");
  EXPECT_EQ(photos[1].frame, "b");
  SegmenterOptions o = Options(WriteModel(dir, NearestColourModel(TrainColours(), kImageNetMean, kImageNetStd)));
  o.input_width = 32;
  o.input_height = 24;
  const Segmenter segmenter(o);
  int calls = 0;
  const SegmentDatasetSummary summary =
      SegmentPhotos(photos, segmenter, dir / "out", [&](int done, int total) {
        EXPECT_EQ(++calls, done);
        EXPECT_EQ(total, 4);
      });
  EXPECT_EQ(summary.photos, 4);
  EXPECT_EQ(calls, 4);
  EXPECT_EQ(summary.pixels_per_class.size(), 4u);
  const LabelSource source = LabelSource::Folder(dir / "out" / "labels");
  ExpectStripes(LoadLabels(source, layout, "right", "a", 64, 48), 2);
  const LabelSource colours = LabelSource::Folder(dir / "out" / "labels_color");
  ExpectStripes(LoadLabels(colours, layout, "left", "b", 64, 48), 2);
  EXPECT_TRUE(std::filesystem::exists(dir / "out" / "segmentation.json"));
  EXPECT_EQ(summary.photos_with_truth, 0);
}

// On rendered data the labels are compared with the truth: here the truth says road everywhere,
// so road's IoU is the network's share of road, and the reliable mask's the share of road and
// building (both reliable; vegetation and sky are not).
TEST(SegmentDataset, ComparesWithTheTruth) {
  TempDir dir;
  const DatasetLayout layout(dir / "rendered");
  std::filesystem::create_directories(layout.Image("cam", "0").parent_path());
  std::filesystem::create_directories(layout.Label("cam", "0").parent_path());
  WriteImage(layout.Image("cam", "0"), StripePhoto(kStripes));
  WriteImage(layout.Label("cam", "0"), ImageU8(64, 48, 1, 7));
  const std::vector<SegmentedPhoto> photos = PhotosToSegment(layout.root());
  ASSERT_EQ(photos.size(), 1u);
  EXPECT_EQ(photos[0].truth, layout.Label("cam", "0"));
  const Segmenter segmenter(Options(WriteModel(dir, NearestColourModel(TrainColours(), kImageNetMean, kImageNetStd))));
  const SegmentDatasetSummary s = SegmentPhotos(photos, segmenter, dir / "out");
  const ImageU8 net = ReadImageU8(dir / "out" / "labels" / "cam" / "0.png");
  const auto count = [&](auto pred) { return std::count_if(net.data.begin(), net.data.end(), pred); };
  const double total = 64 * 48;
  EXPECT_EQ(s.photos_with_truth, 1);
  EXPECT_EQ(s.pixels_compared, 64 * 48);
  EXPECT_DOUBLE_EQ(s.per_class.at(7).IoU(), count([](uint8_t v) { return v == 7; }) / total);
  EXPECT_DOUBLE_EQ(s.per_class.at(23).IoU(), 0.0);
  EXPECT_DOUBLE_EQ(s.reliable.IoU(), count([](uint8_t v) { return v == 7 || v == 11; }) / total);
  EXPECT_NEAR(s.reliable.IoU(), 0.5, 0.05);
}

}  // namespace
}  // namespace rigsim
