#include "calibrator/features/features.h"

#include <algorithm>
#include <cmath>
#include <cstdio>
#include <random>

#include <Eigen/Geometry>
#include <gmock/gmock.h>
#include <gtest/gtest.h>

#include "calibrator/features/matching.h"
#include "calibrator/features/semantics.h"
#include "labels/cityscapes.h"
#include "testing/expect_error.h"

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
  const LabelIdSet reliable = ReliableClasses().Ids();
  const FeatureSet all = DetectFeatures(img, &labels, options);
  const FeatureSet masked = DetectFeatures(img, &labels, options, &reliable);
  ASSERT_GT(masked.size(), 20);
  for (const Keypoint& k : masked.keypoints) {
    EXPECT_TRUE(reliable[k.class_id]);
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

// Without a mask, SIFT's budget goes to OpenCV, which then computes descriptors only for the
// keypoints it keeps: the result must be the strongest of the unlimited detection, bit for bit.
TEST(DetectFeatures, SiftBudgetIsTheHeadOfTheUnlimitedDetection) {
  const ImageU8 img = BlobImage(320, 240, 4);
  for (FeatureType type : {FeatureType::kSift, FeatureType::kRootSift}) {
    FeatureOptions options;
    options.type = type;
    options.max_features = 0;
    const FeatureSet all = DetectFeatures(img, nullptr, options);
    ASSERT_GT(all.size(), 300) << FeatureTypeName(type);
    for (int n : {1, 97, 250}) {
      options.max_features = n;
      const FeatureSet some = DetectFeatures(img, nullptr, options);
      const FeatureSet head = all.Head(n);
      ASSERT_EQ(some.size(), n) << FeatureTypeName(type);
      for (int i = 0; i < n; ++i) {
        EXPECT_EQ(some.keypoints[i].px, head.keypoints[i].px) << FeatureTypeName(type) << " " << n << " " << i;
        EXPECT_EQ(some.keypoints[i].size, head.keypoints[i].size);
        EXPECT_EQ(some.keypoints[i].angle, head.keypoints[i].angle);
      }
      EXPECT_EQ(some.descriptors, head.descriptors) << FeatureTypeName(type) << " " << n;
    }
  }
}

TEST(DetectFeatures, DeterministicAndRejectsBadInput) {
  const ImageU8 img = BlobImage(200, 150, 3);
  const FeatureSet a = DetectFeatures(img, nullptr, FeatureOptions());
  const FeatureSet b = DetectFeatures(img, nullptr, FeatureOptions());
  ASSERT_EQ(a.size(), b.size());
  EXPECT_EQ(a.descriptors, b.descriptors);
  const LabelIdSet reliable = ReliableClasses().Ids();
  EXPECT_THROW(DetectFeatures(img, nullptr, FeatureOptions(), &reliable), std::invalid_argument);
  const ImageU8 wrong(10, 10, 1);
  EXPECT_THROW(DetectFeatures(img, &wrong, FeatureOptions()), std::invalid_argument);
  FeatureOptions bad;
  bad.mask_erosion_px = -1;
  EXPECT_THROW(bad.Check(), std::invalid_argument);
}

TEST(FeatureType, NamesRoundTripAndUnknownNameIsRefused) {
  for (FeatureType t : kAllFeatureTypes) EXPECT_EQ(FeatureTypeFromName(FeatureTypeName(t)), t);
  EXPECT_EQ(FeatureTypeName(FeatureType::kRootSift), "rootsift");
  EXPECT_THAT([] { FeatureTypeFromName("surf"); }, ThrowsWith<std::invalid_argument>("'surf'", "akaze"));
  FeatureOptions bad;
  bad.akaze_threshold = 0;
  EXPECT_THROW(bad.Check(), std::invalid_argument);
}

// A similarity transform of the image plane: p_b = R (p_a - c) + c + t.
struct Similarity {
  double angle_rad = 0.0;
  Eigen::Vector2d centre = Eigen::Vector2d::Zero();
  Eigen::Vector2d shift = Eigen::Vector2d::Zero();
  Eigen::Vector2d operator()(const Eigen::Vector2d& p) const {
    return Eigen::Rotation2Dd(angle_rad) * (p - centre) + centre + shift;
  }
};

// Random grey discs and squares of many sizes (corners for ORB, blobs for SIFT and AKAZE), each
// primitive moved by `t` before painting, so that the second image is the first one seen through
// `t` without resampling. 3x3 supersampled: edges are anti-aliased in both images alike.
ImageU8 ShapesImage(int w, int h, const Similarity& t, unsigned seed) {
  constexpr int kSs = 3;
  const int sw = w * kSs, sh = h * kSs;
  std::vector<float> acc(size_t(sw) * sh, 128.f);
  std::mt19937 rng(seed);
  // Primitives cover a margin around the image so that the rotated copy is textured to its edges.
  std::uniform_real_distribution<double> ux(-0.25 * w, 1.25 * w), uy(-0.25 * h, 1.25 * h), ur(2.0, 14.0),
      uv(0.0, 255.0), ua(0.0, M_PI / 2), u01(0.0, 1.0);
  for (int k = 0; k < 2500; ++k) {
    const Eigen::Vector2d c = t(Eigen::Vector2d(ux(rng), uy(rng)));
    const double r = ur(rng), angle = ua(rng) + t.angle_rad;
    const float v = static_cast<float>(uv(rng));
    const bool square = u01(rng) < 0.5;
    const Eigen::Rotation2Dd inv(-angle);
    const int x0 = std::max(0, int((c.x() - 1.5 * r + 0.5) * kSs)), x1 = std::min(sw, int((c.x() + 1.5 * r + 0.5) * kSs) + 1);
    const int y0 = std::max(0, int((c.y() - 1.5 * r + 0.5) * kSs)), y1 = std::min(sh, int((c.y() + 1.5 * r + 0.5) * kSs) + 1);
    for (int y = y0; y < y1; ++y) {
      for (int x = x0; x < x1; ++x) {
        // Sample position in pixel coordinates (pixel centres at integers).
        const Eigen::Vector2d p((x + 0.5) / kSs - 0.5, (y + 0.5) / kSs - 0.5);
        const Eigen::Vector2d q = inv * (p - c);
        const bool inside = square ? (std::abs(q.x()) < r && std::abs(q.y()) < r) : q.squaredNorm() < r * r;
        if (inside) acc[size_t(y) * sw + x] = v;
      }
    }
  }
  ImageU8 img(w, h, 3);
  for (int y = 0; y < h; ++y) {
    for (int x = 0; x < w; ++x) {
      float sum = 0.f;
      for (int dy = 0; dy < kSs; ++dy)
        for (int dx = 0; dx < kSs; ++dx) sum += acc[size_t(y * kSs + dy) * sw + x * kSs + dx];
      const auto v = static_cast<uint8_t>(std::lround(sum / (kSs * kSs)));
      for (int c = 0; c < 3; ++c) img.at(x, y, c) = v;
    }
  }
  return img;
}

FeatureOptions OptionsFor(FeatureType type) {
  FeatureOptions o;
  o.type = type;
  o.max_features = 3000;
  return o;
}

// Every feature type finds features on a textured image and matches them in a rotated and shifted
// copy: the matches land where the known transform puts them.
class EveryFeatureType : public ::testing::TestWithParam<FeatureType> {};

TEST_P(EveryFeatureType, MatchesRotatedShiftedCopyAtTheTransformedPositions) {
  constexpr int kW = 480, kH = 360;
  const Similarity identity;
  Similarity t;
  t.angle_rad = 15.0 * M_PI / 180.0;
  t.centre = Eigen::Vector2d(kW / 2.0, kH / 2.0);
  t.shift = Eigen::Vector2d(11.3, -6.6);
  const ImageU8 img_a = ShapesImage(kW, kH, identity, 21);
  const ImageU8 img_b = ShapesImage(kW, kH, t, 21);
  const FeatureOptions options = OptionsFor(GetParam());
  const FeatureSet a = DetectFeatures(img_a, nullptr, options);
  const FeatureSet b = DetectFeatures(img_b, nullptr, options);
  const bool binary = GetParam() == FeatureType::kOrb || GetParam() == FeatureType::kAkaze;
  EXPECT_EQ(a.kind, binary ? DescriptorKind::kBinary : DescriptorKind::kFloat);
  EXPECT_EQ(a.descriptor_size, GetParam() == FeatureType::kOrb ? 32 : GetParam() == FeatureType::kAkaze ? 61 : 128);
  EXPECT_EQ((binary ? a.binary_descriptors.size() : a.descriptors.size()), size_t(a.size()) * a.descriptor_size);
  EXPECT_TRUE(binary ? a.descriptors.empty() : a.binary_descriptors.empty());
  ASSERT_GT(a.size(), 300);
  ASSERT_GT(b.size(), 300);
  EXPECT_LE(a.size(), options.max_features);

  const std::vector<Match> matches = MatchFeatures(a, b, MatchOptions());
  int correct = 0;
  for (const Match& m : matches) {
    // ORB does not interpolate: a keypoint of pyramid level L (size 31 * 1.2^L) sits on that
    // level's pixel grid, so its tolerance grows with the level (measured: 2-5 px errors all at
    // levels >= 1; mismatches are > 20 px away).
    const double level_scale = GetParam() == FeatureType::kOrb ? std::max(1.0, a.keypoints[m.a].size / 31.0) : 1.0;
    correct += (t(a.keypoints[m.a].px) - b.keypoints[m.b].px).norm() < 2.0 * level_scale;
  }
  const double precision = matches.empty() ? 0.0 : double(correct) / matches.size();
  std::printf("  %-8s keypoints %d / %d, matches %zu, correct %d (%.1f%%)\n",
              std::string(FeatureTypeName(GetParam())).c_str(), a.size(), b.size(), matches.size(), correct,
              100.0 * precision);
  EXPECT_GT(correct, 200);
  EXPECT_GT(precision, 0.9);
}

TEST_P(EveryFeatureType, DeterministicAndMaskRespectedWithClassLabels) {
  const ImageU8 img = ShapesImage(320, 240, Similarity(), 5);
  const ImageU8 labels = SplitLabels(320, 240, 192);
  FeatureOptions options = OptionsFor(GetParam());
  options.mask_erosion_px = 4;
  const FeatureSet a = DetectFeatures(img, &labels, options);
  const FeatureSet b = DetectFeatures(img, &labels, options);
  ASSERT_EQ(a.size(), b.size());
  EXPECT_EQ(a.descriptors, b.descriptors);
  EXPECT_EQ(a.binary_descriptors, b.binary_descriptors);
  int right = 0;
  for (const Keypoint& k : a.keypoints) {
    EXPECT_EQ(k.class_id, std::lround(k.px.x()) >= 192 ? 21 : 11);
    right += k.px.x() > 192;
  }
  ASSERT_GT(right, 20) << "without the mask the unreliable class has keypoints";

  const LabelIdSet reliable = ReliableClasses().Ids();
  const FeatureSet masked = DetectFeatures(img, &labels, options, &reliable);
  ASSERT_GT(masked.size(), 20);
  EXPECT_EQ(masked.kind, a.kind);
  for (const Keypoint& k : masked.keypoints) {
    EXPECT_EQ(k.class_id, 11);
    EXPECT_LT(k.px.x(), 192 - options.mask_erosion_px + 0.5) << "keypoint inside the eroded band";
  }
  // The budget: a small limit is kept, all of it on the reliable side.
  options.max_features = 40;
  const FeatureSet limited = DetectFeatures(img, &labels, options, &reliable);
  EXPECT_LE(limited.size(), 40);
  EXPECT_GT(limited.size(), 30);
  for (const Keypoint& k : limited.keypoints) EXPECT_EQ(k.class_id, 11);
}

// The rig's own mask (its vehicle) hides its pixels whether or not the reliable-class mask is used
// (the detection kinds of every semantic mode), for every feature type, and the budget goes to the
// rest of the image.
TEST_P(EveryFeatureType, RigMaskHidesItsPixelsWithAndWithoutTheClassMask) {
  const ImageU8 img = ShapesImage(320, 240, Similarity(), 7);
  const ImageU8 labels = SplitLabels(320, 240, 192);
  ImageU8 rig_mask(320, 240, 1, 255);
  for (int y = 150; y < 240; ++y) {
    for (int x = 0; x < 320; ++x) rig_mask.at(x, y) = 0;
  }
  const LabelIdSet reliable = ReliableClasses().Ids();
  const bool orb = GetParam() == FeatureType::kOrb;
  for (const LabelIdSet* only_on : {static_cast<const LabelIdSet*>(nullptr), &reliable}) {
    SCOPED_TRACE(only_on ? "reliable classes only" : "everywhere");
    FeatureOptions options = OptionsFor(GetParam());
    options.max_features = orb ? 3000 : 0;  // 0: all, so that kept + removed is the unmasked detection
    const FeatureSet plain = DetectFeatures(img, &labels, options, only_on);
    const FeatureSet masked = DetectFeatures(img, &labels, options, only_on, &rig_mask);
    int below = 0;
    for (const Keypoint& k : plain.keypoints) below += std::lround(k.px.y()) >= 150;
    ASSERT_GT(below, 20) << "without the rig mask the hidden rows have keypoints";
    ASSERT_GT(masked.size(), 20);
    for (const Keypoint& k : masked.keypoints) EXPECT_LT(std::lround(k.px.y()), 150) << "keypoint under the rig mask";
    if (orb) {
      EXPECT_EQ(masked.removed_by_mask, 0) << "ORB detects inside its mask only";
    } else {
      EXPECT_EQ(masked.removed_by_mask, below);
      EXPECT_EQ(masked.size() + masked.removed_by_mask, plain.size());
    }
    EXPECT_EQ(plain.removed_by_mask, 0);
    // The budget: a limit is filled above the hidden rows.
    options.max_features = 40;
    const FeatureSet limited = DetectFeatures(img, &labels, options, only_on, &rig_mask);
    EXPECT_GT(limited.size(), 30);
    EXPECT_LE(limited.size(), 40);
    for (const Keypoint& k : limited.keypoints) EXPECT_LT(std::lround(k.px.y()), 150);
  }
  const ImageU8 wrong(320, 200, 1, 255);
  EXPECT_THROW(DetectFeatures(img, &labels, OptionsFor(GetParam()), nullptr, &wrong), std::invalid_argument);
}

INSTANTIATE_TEST_SUITE_P(DetectFeatures, EveryFeatureType, ::testing::ValuesIn(kAllFeatureTypes),
                         [](const ::testing::TestParamInfo<FeatureType>& info) {
                           return std::string(FeatureTypeName(info.param));
                         });

TEST(DetectFeatures, RootSiftIsTheSquareRootOfTheL1NormalisedSift) {
  const ImageU8 img = ShapesImage(320, 240, Similarity(), 9);
  const FeatureSet sift = DetectFeatures(img, nullptr, OptionsFor(FeatureType::kSift));
  const FeatureSet root = DetectFeatures(img, nullptr, OptionsFor(FeatureType::kRootSift));
  ASSERT_GT(root.size(), 100);
  ASSERT_EQ(root.size(), sift.size());  // same keypoints, other descriptors
  ASSERT_EQ(root.descriptor_size, 128);
  for (int i = 0; i < root.size(); ++i) {
    ASSERT_EQ(root.keypoints[i].px, sift.keypoints[i].px);
    const Eigen::Map<const Eigen::VectorXf> r(root.descriptor(i), 128), s(sift.descriptor(i), 128);
    EXPECT_NEAR(r.norm(), 1.0f, 1e-5f) << i;
    EXPECT_GE(r.minCoeff(), 0.0f) << i;
    const Eigen::VectorXf expected = (s.cwiseAbs() / s.cwiseAbs().sum()).cwiseSqrt();
    EXPECT_LT((r - expected).cwiseAbs().maxCoeff(), 1e-6f) << i;
  }
  const FeatureSet head = root.Head(10);
  ASSERT_EQ(head.size(), 10);
  EXPECT_TRUE(std::equal(head.descriptors.begin(), head.descriptors.end(), root.descriptors.begin()));
  EXPECT_EQ(head.descriptors.size(), 1280u);
}

TEST(DetectFeatures, BinaryBudgetKeepsTheStrongest) {
  const ImageU8 img = ShapesImage(320, 240, Similarity(), 13);
  for (FeatureType type : {FeatureType::kOrb, FeatureType::kAkaze}) {
    FeatureOptions options = OptionsFor(type);
    options.max_features = 0;  // all
    const FeatureSet all = DetectFeatures(img, nullptr, options);
    ASSERT_GT(all.size(), 200) << FeatureTypeName(type);
    options.max_features = 100;
    const FeatureSet some = DetectFeatures(img, nullptr, options);
    EXPECT_LE(some.size(), 100) << FeatureTypeName(type);
    EXPECT_GE(some.size(), 90) << FeatureTypeName(type);
    // Head(n) keeps the first n keypoints with their own descriptors, whatever the kind.
    const FeatureSet head = all.Head(50);
    ASSERT_EQ(head.size(), 50);
    EXPECT_EQ(head.binary_descriptors.size(), 50u * all.descriptor_size);
    EXPECT_TRUE(std::equal(head.binary_descriptors.begin(), head.binary_descriptors.end(), all.binary_descriptors.begin()));
    EXPECT_EQ(all.Head(all.size() + 5).size(), all.size());
    if (type == FeatureType::kAkaze) {
      // AKAZE detects all and keeps the first 100 by response: a prefix of the full list.
      ASSERT_EQ(some.size(), 100);
      for (int i = 0; i < 100; ++i) EXPECT_EQ(some.keypoints[i].px, all.keypoints[i].px) << i;
      EXPECT_TRUE(std::equal(some.binary_descriptors.begin(), some.binary_descriptors.end(),
                             all.binary_descriptors.begin()));
    }
  }
}

}  // namespace
}  // namespace rigsim

namespace rigsim {
namespace {

// A 180-degree rotation maps pixel x to (width - 1 - x): a detector without positional bias finds
// the same features at mirrored positions. OpenCV 4.6's SIFT is 0.25 px off in x and y (without
// DetectFeatures' correction the median difference below is exactly 0.5 px).
TEST(DetectFeatures, KeypointsAreEquivariantUnderA180DegreeRotation) {
  constexpr int kW = 480, kH = 360;
  const ImageU8 img = BlobImage(kW, kH, 5);
  ImageU8 rotated(kW, kH, 3);
  for (int y = 0; y < kH; ++y) {
    for (int x = 0; x < kW; ++x) {
      for (int c = 0; c < 3; ++c) rotated.at(kW - 1 - x, kH - 1 - y, c) = img.at(x, y, c);
    }
  }
  // ORB is left out: it does not interpolate positions at all (whole pixels of its pyramid level).
  for (FeatureType type : {FeatureType::kSift, FeatureType::kRootSift, FeatureType::kAkaze}) {
    FeatureOptions options;
    options.type = type;
    const FeatureSet a = DetectFeatures(img, nullptr, options);
    const FeatureSet b = DetectFeatures(rotated, nullptr, options);
    std::vector<double> dx, dy;
    for (const Keypoint& ka : a.keypoints) {
      for (const Keypoint& kb : b.keypoints) {
        const Eigen::Vector2d mirrored(kW - 1 - kb.px.x(), kH - 1 - kb.px.y());
        if ((ka.px - mirrored).norm() < 1.0 && std::abs(ka.size - kb.size) < 0.1 * ka.size) {
          dx.push_back(ka.px.x() - mirrored.x());
          dy.push_back(ka.px.y() - mirrored.y());
          break;
        }
      }
    }
    const std::string name(FeatureTypeName(type));
    ASSERT_GT(dx.size(), 50u) << name;
    std::nth_element(dx.begin(), dx.begin() + dx.size() / 2, dx.end());
    std::nth_element(dy.begin(), dy.begin() + dy.size() / 2, dy.end());
    // The difference is twice the bias.
    EXPECT_NEAR(dx[dx.size() / 2] / 2, 0.0, 0.03) << name;
    EXPECT_NEAR(dy[dy.size() / 2] / 2, 0.0, 0.03) << name;
  }
}

}  // namespace
}  // namespace rigsim
