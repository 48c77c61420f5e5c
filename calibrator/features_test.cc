#include "calibrator/features.h"

#include <cmath>
#include <random>

#include <gtest/gtest.h>

#include "calibrator/semantics.h"

namespace rigsim {
namespace {

// Random dark and bright blobs on grey: plenty of SIFT keypoints everywhere.
ImageU8 BlobImage(int w, int h, unsigned seed) {
  std::mt19937 rng(seed);
  std::uniform_real_distribution<double> ux(0, w), uy(0, h), ur(2.0, 6.0), uv(-100, 100);
  std::vector<double> acc(size_t(w) * h, 128.0);
  for (int k = 0; k < 400; ++k) {
    const double cx = ux(rng), cy = uy(rng), r = ur(rng), v = uv(rng);
    for (int y = std::max(0, int(cy - 3 * r)); y < std::min(h, int(cy + 3 * r) + 1); ++y) {
      for (int x = std::max(0, int(cx - 3 * r)); x < std::min(w, int(cx + 3 * r) + 1); ++x) {
        acc[size_t(y) * w + x] += v * std::exp(-((x - cx) * (x - cx) + (y - cy) * (y - cy)) / (2 * r * r));
      }
    }
  }
  ImageU8 img(w, h, 3);
  for (int y = 0; y < h; ++y) {
    for (int x = 0; x < w; ++x) {
      const auto v = static_cast<uint8_t>(std::clamp(acc[size_t(y) * w + x], 0.0, 255.0));
      for (int c = 0; c < 3; ++c) img.at(x, y, c) = v;
    }
  }
  return img;
}

// Left 60% building (reliable), the rest vegetation (unreliable).
ImageU8 SplitLabels(int w, int h, int boundary_x) {
  ImageU8 labels(w, h, 1, 11);
  for (int y = 0; y < h; ++y) {
    for (int x = boundary_x; x < w; ++x) labels.at(x, y) = 21;
  }
  return labels;
}

TEST(DetectFeatures, ClassFromLabelsAndDescriptorLayout) {
  const ImageU8 img = BlobImage(320, 240, 1);
  const ImageU8 labels = SplitLabels(320, 240, 192);
  const FeatureSet fs = DetectFeatures(img, &labels, FeatureOptions());
  ASSERT_GT(fs.size(), 100);
  EXPECT_EQ(fs.descriptor_size, 128);
  EXPECT_EQ(fs.descriptors.size(), size_t(fs.size()) * 128);
  int left = 0, right = 0;
  for (const Keypoint& k : fs.keypoints) {
    const int x = static_cast<int>(std::lround(k.px.x()));
    EXPECT_EQ(k.class_id, x >= 192 ? 21 : 11);
    (x >= 192 ? right : left)++;
  }
  EXPECT_GT(left, 20);
  EXPECT_GT(right, 20);  // the unmasked baseline does detect on the unreliable class
  // Without labels every keypoint is unlabeled.
  const FeatureSet no_labels = DetectFeatures(img, nullptr, FeatureOptions());
  for (const Keypoint& k : no_labels.keypoints) EXPECT_EQ(k.class_id, kUnlabeledId);
}

TEST(DetectFeatures, MaskKeepsKeypointsOffUnreliableClassesAndSpendsBudgetThere) {
  const ImageU8 img = BlobImage(320, 240, 2);
  const ImageU8 labels = SplitLabels(320, 240, 192);
  FeatureOptions options;
  options.mask_erosion_px = 4;
  const ReliableClasses reliable;
  const FeatureSet all = DetectFeatures(img, &labels, options);
  const FeatureSet masked = DetectFeatures(img, &labels, options, &reliable);
  ASSERT_GT(masked.size(), 20);
  for (const Keypoint& k : masked.keypoints) {
    EXPECT_TRUE(reliable.IsReliable(k.class_id));
    EXPECT_LT(k.px.x(), 192 - options.mask_erosion_px + 0.5) << "keypoint inside the eroded band";
  }
  int left_unmasked = 0;
  for (const Keypoint& k : all.keypoints) left_unmasked += k.px.x() < 187;
  // Budget: with a small limit the masked detector still fills it, all on reliable pixels;
  // masking after the limit (what OpenCV's own mask does) would leave fewer.
  options.max_features = left_unmasked / 2;
  const FeatureSet limited = DetectFeatures(img, &labels, options, &reliable);
  EXPECT_EQ(limited.size(), options.max_features);
  for (const Keypoint& k : limited.keypoints) EXPECT_EQ(k.class_id, 11);
}

TEST(DetectFeatures, DeterministicAndRejectsBadInput) {
  const ImageU8 img = BlobImage(200, 150, 3);
  const FeatureSet a = DetectFeatures(img, nullptr, FeatureOptions());
  const FeatureSet b = DetectFeatures(img, nullptr, FeatureOptions());
  ASSERT_EQ(a.size(), b.size());
  EXPECT_EQ(a.descriptors, b.descriptors);
  const ReliableClasses reliable;
  EXPECT_THROW(DetectFeatures(img, nullptr, FeatureOptions(), &reliable), std::invalid_argument);
  const ImageU8 wrong(10, 10, 1);
  EXPECT_THROW(DetectFeatures(img, &wrong, FeatureOptions()), std::invalid_argument);
  FeatureOptions bad;
  bad.mask_erosion_px = -1;
  EXPECT_THROW(bad.Check(), std::invalid_argument);
}

}  // namespace
}  // namespace rigsim
