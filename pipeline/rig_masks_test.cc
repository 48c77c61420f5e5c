#include "pipeline/rig_masks.h"

#include <cmath>
#include <filesystem>
#include <random>
#include <string>
#include <vector>

#include <gmock/gmock.h>
#include <gtest/gtest.h>

#include "dataset/dataset.h"
#include "dataset/image_io.h"
#include "labels/cityscapes.h"
#include "pipeline/calibration_plan.h"
#include "pipeline/feature_cache.h"
#include "testing/expect_error.h"
#include "testing/temp_dir.h"

namespace rigsim {
namespace {

namespace fs = std::filesystem;

constexpr int kMaskW = 160, kMaskH = 120;

Rig TwoCameras() {
  Rig rig;
  rig.cameras.push_back({"front", Camera::PinholeFromHorizontalFov(kMaskW, kMaskH, 90), Rigid3d(), 0.0});
  rig.cameras.push_back({"left", Camera::PinholeFromHorizontalFov(kMaskW, kMaskH, 90), Rigid3d(), 0.0});
  return rig;
}

// A mask of the cameras' size hiding the rows from `hidden_from_row` down (a hood), in `channels`
// channels; the kept part is `value` in every channel, the hidden part 0.
ImageU8 HoodMask(int hidden_from_row, int channels, uint8_t value = 255, int w = kMaskW, int h = kMaskH) {
  ImageU8 m(w, h, channels, value);
  for (int y = hidden_from_row; y < h; ++y) {
    for (int x = 0; x < w; ++x) {
      for (int c = 0; c < channels; ++c) m.at(x, y, c) = 0;
    }
  }
  return m;
}

struct MaskWarnings {
  std::vector<std::string> seen;
  std::function<void(const std::string&)> Sink() {
    return [this](const std::string& w) { seen.push_back(w); };
  }
};

TEST(ReadRigMasks, BlackHidesAnythingElseKeepsInGreyAndInColour) {
  const TempDir tmp;
  const fs::path dir = tmp / "masks";
  fs::create_directories(dir);
  WriteImage(dir / "front.png", HoodMask(90, 1, 1));  // any value but 0 keeps
  ImageU8 rgba = HoodMask(60, 4);
  // Colour keeps even where two channels are 0; alpha says nothing.
  rgba.at(3, 100, 0) = 9;
  rgba.at(4, 10, 3) = 0;
  WriteImage(dir / "left.png", rgba);
  MaskWarnings warnings;
  const RigMasks masks = ReadRigMasks(dir, TwoCameras(), tmp / "rig.json", warnings.Sink());
  EXPECT_TRUE(warnings.seen.empty());
  ASSERT_EQ(masks.masks.size(), 2u);
  EXPECT_TRUE(masks.cameras_without.empty());
  const CameraMask* front = masks.Of("front");
  ASSERT_NE(front, nullptr);
  EXPECT_EQ(front->file, dir / "front.png");
  EXPECT_EQ(front->keep.channels, 1);
  EXPECT_EQ(front->keep.at(5, 89), 255);
  EXPECT_EQ(front->keep.at(5, 90), 0);
  EXPECT_DOUBLE_EQ(front->hidden_fraction, 30.0 / kMaskH);
  const CameraMask* left = masks.Of("left");
  ASSERT_NE(left, nullptr);
  EXPECT_EQ(left->keep.at(3, 100), 255);
  EXPECT_EQ(left->keep.at(4, 100), 0);
  EXPECT_EQ(left->keep.at(4, 10), 255);
  EXPECT_DOUBLE_EQ(left->hidden_fraction, (60.0 * kMaskW - 1) / (kMaskW * kMaskH));
  EXPECT_EQ(masks.Of("rear"), nullptr);
  EXPECT_EQ(DescribeRigMasks(masks, 2), dir.string() + " (2 cameras)");
}

TEST(ReadRigMasks, ACameraWithoutAMaskIsNotMaskedAndSaidSo) {
  const TempDir tmp;
  const fs::path dir = tmp / "masks";
  fs::create_directories(dir);
  WriteImage(dir / "left.png", HoodMask(60, 1));
  // A drawing's source beside its PNG is not read.
  WriteFile(dir / "left.xcf", "not an image");
  WriteFile(dir / "README.txt", "the hood of our van");
  MaskWarnings warnings;
  const RigMasks masks = ReadRigMasks(dir, TwoCameras(), tmp / "rig.json", warnings.Sink());
  ASSERT_EQ(masks.masks.size(), 1u);
  EXPECT_EQ(masks.masks[0].camera, "left");
  EXPECT_EQ(masks.cameras_without, std::vector<std::string>{"front"});
  EXPECT_THAT(warnings.seen, testing::ElementsAre("--mask " + dir.string() + " has no mask for front: its features are not masked"));
  EXPECT_EQ(DescribeRigMasks(masks, 2), dir.string() + " (1 of 2 cameras; front has none)");
}

TEST(ReadRigMasks, BadMasksAreRefusedNamingTheFile) {
  const TempDir tmp;
  const fs::path rig_json = tmp / "data" / "rig.json";
  const Rig rig = TwoCameras();
  MaskWarnings warnings;
  const auto read = [&](const fs::path& dir) { return ReadRigMasks(dir, rig, rig_json, warnings.Sink()); };
  EXPECT_THAT([&] { read(tmp / "nowhere"); },
              ThrowsExactly<std::runtime_error>("--mask " + (tmp / "nowhere").string() + ": no such folder"));
  WriteFile(tmp / "file", "x");
  EXPECT_THAT([&] { read(tmp / "file"); }, ThrowsWith<std::runtime_error>((tmp / "file").string() + ": not a folder"));

  // Each folder holds one good mask and one bad file.
  int n = 0;
  const auto folder = [&](const std::string& name, const std::function<void(const fs::path&)>& bad) {
    const fs::path dir = tmp / ("m" + std::to_string(n++));
    fs::create_directories(dir);
    WriteImage(dir / "front.png", HoodMask(90, 1));
    bad(dir);
    return dir / name;
  };
  fs::path f = folder("lefft.png", [](const fs::path& d) { WriteImage(d / "lefft.png", HoodMask(90, 1)); });
  EXPECT_THAT([&] { read(f.parent_path()); },
              ThrowsExactly<std::runtime_error>(f.string() + ": no camera 'lefft' in " + rig_json.string() +
                                                " (did you mean 'left'?); its cameras are front, left (a mask is <camera>.png)"));
  f = folder("left.png", [](const fs::path& d) { WriteImage(d / "left.png", HoodMask(45, 1, 255, 80, 60)); });
  EXPECT_THAT([&] { read(f.parent_path()); },
              ThrowsExactly<std::runtime_error>(f.string() + ": the mask is 80x60 but camera left's images are 160x120 (" +
                                                rig_json.string() + "); a mask has its camera's image size"));
  f = folder("left.png", [](const fs::path& d) { WriteFile(d / "left.png", "not a png at all"); });
  EXPECT_THAT([&] { read(f.parent_path()); }, ThrowsNaming<std::runtime_error>(f, ""));
  f = folder("left.png", [](const fs::path& d) { WriteImage(d / "left.png", HoodMask(0, 1)); });
  EXPECT_THAT([&] { read(f.parent_path()); }, ThrowsWith<std::runtime_error>(f.string() + ": the mask is black everywhere"));
  f = folder("left.jpg", [](const fs::path& d) { WriteImage(d / "left.jpg", HoodMask(60, 1)); });
  EXPECT_THAT([&] { read(f.parent_path()); },
              ThrowsExactly<std::runtime_error>(f.string() + ": masks are PNG files (lossless, black = no features): write " +
                                                (f.parent_path() / "left.png").string()));
  fs::create_directories(tmp / "empty");
  EXPECT_THAT([&] { read(tmp / "empty"); },
              ThrowsExactly<std::runtime_error>("--mask " + (tmp / "empty").string() + ": no mask for any camera of " +
                                                rig_json.string() + "; name them <camera>.png: front, left"));
}

// Random dark and bright blobs on grey: keypoints everywhere.
ImageU8 BlobImage(unsigned seed) {
  std::mt19937 rng(seed);
  std::uniform_real_distribution<double> ux(0, kMaskW), uy(0, kMaskH), ur(1.5, 4.0), uv(-100, 100);
  std::vector<double> acc(size_t(kMaskW) * kMaskH, 128.0);
  for (int k = 0; k < 250; ++k) {
    const double cx = ux(rng), cy = uy(rng), r = ur(rng), v = uv(rng);
    for (int y = std::max(0, int(cy - 3 * r)); y < std::min(kMaskH, int(cy + 3 * r) + 1); ++y) {
      for (int x = std::max(0, int(cx - 3 * r)); x < std::min(kMaskW, int(cx + 3 * r) + 1); ++x) {
        acc[size_t(y) * kMaskW + x] += v * std::exp(-((x - cx) * (x - cx) + (y - cy) * (y - cy)) / (2 * r * r));
      }
    }
  }
  ImageU8 img(kMaskW, kMaskH, 3);
  for (int y = 0; y < kMaskH; ++y) {
    for (int x = 0; x < kMaskW; ++x) {
      for (int c = 0; c < 3; ++c) img.at(x, y, c) = static_cast<uint8_t>(std::clamp(acc[size_t(y) * kMaskW + x], 0.0, 255.0));
    }
  }
  return img;
}

// Two cameras, two frames of blob photos, labels all building (reliable) but a vegetation strip on
// the right: every mode detects in the lower half unless a mask hides it.
struct BlobDataset {
  fs::path root;
  Rig rig = TwoCameras();
  FramesFile frames;
  std::vector<fs::path> photos;  // camera-major
  explicit BlobDataset(const fs::path& dir) : root(dir) {
    frames.frames = {{"000000", std::nullopt, 0.0}, {"000001", std::nullopt, 0.1}};
    const DatasetLayout layout(root);
    unsigned seed = 1;
    for (const RigCamera& rc : rig.cameras) {
      for (const Frame& f : frames.frames) {
        const fs::path image = layout.Image(rc.name, f.name), label = layout.Label(rc.name, f.name);
        fs::create_directories(image.parent_path());
        fs::create_directories(label.parent_path());
        WriteImage(image, BlobImage(seed++));
        ImageU8 labels(kMaskW, kMaskH, 1, 11);
        for (int y = 0; y < kMaskH; ++y) {
          for (int x = 130; x < kMaskW; ++x) labels.at(x, y) = 21;
        }
        WriteImage(label, labels);
        photos.push_back(image);
      }
    }
  }
};

// The mask is applied where features are detected, once for every mode: in none, mask, gated and
// mask+gated the masked camera has no keypoint under its mask and the same ones as without it
// elsewhere; the camera without a mask is untouched; what the mask removed is counted.
TEST(FeatureCache, TheRigMaskHidesItsPixelsInEverySemanticMode) {
  const TempDir tmp;
  const BlobDataset data(tmp / "data");
  const std::vector<SemanticMode> modes(std::begin(kAllSemanticModes), std::end(kAllSemanticModes));
  FeatureOptions options;
  options.max_features = 0;  // all: with a mask, kept + removed is the unmasked detection
  const LabelIdSet reliable = ReliableClasses().Ids();
  RigMasks masks;
  masks.folder = tmp / "masks";
  masks.masks.push_back({"front", masks.folder / "front.png", HoodMask(80, 1), 40.0 / kMaskH});
  masks.cameras_without = {"left"};
  const DatasetLayout layout(data.root);
  const FeatureCache plain(layout, data.rig, data.frames, data.photos, modes, options, reliable, LabelSource::Truth(), 1);
  const FeatureCache masked(layout, data.rig, data.frames, data.photos, modes, options, reliable, LabelSource::Truth(), 1,
                            &masks);
  for (SemanticMode m : modes) {
    SCOPED_TRACE(SemanticModeName(m));
    const std::vector<int> removed = masked.RemovedByMask(m);
    ASSERT_EQ(removed.size(), 2u);
    EXPECT_EQ(removed[1], 0) << "left has no mask";
    EXPECT_EQ(plain.RemovedByMask(m), std::vector<int>({0, 0}));
    int hidden_total = 0;
    for (int v = 0; v < 4; ++v) {
      const FeatureSet& p = plain.Of(m)[v];
      const FeatureSet& k = masked.Of(m)[v];
      if (v >= 2) {  // left: as without masks
        EXPECT_EQ(k.descriptors, p.descriptors);
        continue;
      }
      // front: exactly the unmasked keypoints above the hood, in the same order.
      std::vector<Eigen::Vector2d> above;
      int hidden = 0;
      for (const Keypoint& kp : p.keypoints) {
        if (std::lround(kp.px.y()) < 80) {
          above.push_back(kp.px);
        } else {
          ++hidden;
        }
      }
      ASSERT_GT(hidden, 10) << "without the mask there are keypoints under it";
      ASSERT_GT(above.size(), 10u);
      ASSERT_EQ(k.keypoints.size(), above.size());
      for (size_t i = 0; i < above.size(); ++i) EXPECT_EQ(k.keypoints[i].px, above[i]);
      EXPECT_EQ(k.removed_by_mask, hidden);
      hidden_total += hidden;
    }
    EXPECT_EQ(removed[0], hidden_total);
  }
}

TEST(PlanCalibration, ReadsTheMasksAndRefusesBadOnesBeforeAnythingIsWritten) {
  const TempDir tmp;
  const BlobDataset data(tmp / "data");
  WriteRig(data.rig, data.root / "rig.json");
  WriteFrames(data.frames, data.root / "frames.json");
  CalibrationRequest request;
  request.dataset = data.root;
  request.modes = {SemanticMode::kNone, SemanticMode::kMask};
  request.out = {tmp / "out", "--out", "rigsim calibrate", {}, false};
  request.mask_dir = tmp / "masks";
  fs::create_directories(request.mask_dir);
  WriteImage(request.mask_dir / "fron.png", HoodMask(80, 1));
  MaskWarnings warnings;
  EXPECT_THAT([&] { PlanCalibration(request, warnings.Sink()); },
              ThrowsWith<std::runtime_error>((request.mask_dir / "fron.png").string() + ": no camera 'fron' in " +
                                             (data.root / "rig.json").string() + " (did you mean 'front'?)"));
  EXPECT_FALSE(fs::exists(tmp / "out"));
  fs::rename(request.mask_dir / "fron.png", request.mask_dir / "front.png");
  const CalibrationPlan plan = PlanCalibration(request, warnings.Sink());
  ASSERT_NE(plan.options.masks, nullptr);
  ASSERT_NE(plan.options.masks->Of("front"), nullptr);
  EXPECT_EQ(plan.options.masks->cameras_without, std::vector<std::string>{"left"});
  EXPECT_FALSE(fs::exists(tmp / "out")) << "planning writes nothing";
  request.mask_dir.clear();
  EXPECT_EQ(PlanCalibration(request, warnings.Sink()).options.masks, nullptr);
}

}  // namespace
}  // namespace rigsim
