#include "dataset/segmentation_noise.h"

#include <algorithm>
#include <cmath>
#include <cstdio>
#include <set>
#include <string>

#include <gtest/gtest.h>

#include "labels/cityscapes.h"

namespace rigsim {
namespace {

// A street-like label map: sky on top, buildings with a wall, a thin pole, vegetation, a car,
// road and sidewalk below, and an unlabeled (void) patch.
ImageU8 StreetLabels(int w = 320, int h = 240) {
  ImageU8 l(w, h, 1, 23);  // sky
  for (int y = 0; y < h; ++y) {
    for (int x = 0; x < w; ++x) {
      uint8_t c = 23;
      if (y > h / 5 + (x * 7) % 13) c = x < w / 2 ? 11 : 12;  // building | wall, ragged roofline
      if (y > 2 * h / 3) c = 8;                                 // sidewalk
      if (y > 3 * h / 4 + x / 16) c = 7;                        // road, slanted kerb
      if ((x - 240) * (x - 240) + (y - 100) * (y - 100) < 900) c = 21;  // a tree crown
      if (x >= 100 && x < 103 && y > 60 && y <= 2 * h / 3) c = 17;       // pole, 3 px wide
      if (x >= 150 && x < 230 && y >= 150 && y < 190) c = 26;            // car
      if (x < 20 && y < 20) c = 0;                                        // unlabeled corner
      l.at(x, y) = c;
    }
  }
  return l;
}

int CountDifferent(const ImageU8& a, const ImageU8& b) {
  int n = 0;
  for (size_t i = 0; i < a.data.size(); ++i) n += a.data[i] != b.data[i];
  return n;
}

TEST(SegmentationNoise, ZeroNoiseIsTheIdentity) {
  const ImageU8 truth = StreetLabels();
  for (uint64_t seed : {0ull, 1ull, 12345ull}) {
    SegmentationNoiseOptions o;
    o.seed = seed;
    EXPECT_TRUE(o.IsIdentity());
    EXPECT_EQ(ApplySegmentationNoise(truth, o, "cam0", "000000").data, truth.data);
  }
}

TEST(SegmentationNoise, DeterministicForASeedCameraAndFrame) {
  const ImageU8 truth = StreetLabels();
  SegmentationNoiseOptions o;
  o.boundary_px = 4;
  o.confusion_rate = 0.3;
  o.seed = 7;
  const ImageU8 a = ApplySegmentationNoise(truth, o, "cam0", "000001");
  EXPECT_EQ(ApplySegmentationNoise(truth, o, "cam0", "000001").data, a.data);
  EXPECT_GT(CountDifferent(a, truth), 500);
  // Another camera, frame or seed draws other errors.
  EXPECT_GT(CountDifferent(ApplySegmentationNoise(truth, o, "cam1", "000001"), a), 100);
  EXPECT_GT(CountDifferent(ApplySegmentationNoise(truth, o, "cam0", "000002"), a), 100);
  SegmentationNoiseOptions other = o;
  other.seed = 8;
  EXPECT_GT(CountDifferent(ApplySegmentationNoise(truth, other, "cam0", "000001"), a), 100);
  EXPECT_NE(SegmentationNoiseImageSeed(7, "cam0", "000001"), SegmentationNoiseImageSeed(7, "cam00", "00001"));
}

TEST(SegmentationNoise, BoundaryShiftChangesOnlyPixelsWithinNPixelsOfAnotherClass) {
  const ImageU8 truth = StreetLabels();
  for (int n : {1, 3, 6}) {
    SCOPED_TRACE(n);
    SegmentationNoiseOptions o;
    o.boundary_px = n;
    const ImageU8 noisy = ApplySegmentationNoise(truth, o, "cam0", "000000");
    int changed = 0;
    for (int y = 0; y < truth.height; ++y) {
      for (int x = 0; x < truth.width; ++x) {
        const uint8_t now = noisy.at(x, y);
        if (now == truth.at(x, y)) continue;
        ++changed;
        // The new class must be one that lies within n px of this pixel in the truth.
        bool near = false;
        for (int dy = -n; dy <= n && !near; ++dy) {
          for (int dx = -n; dx <= n && !near; ++dx) {
            const int qx = x + dx, qy = y + dy;
            near = dx * dx + dy * dy <= n * n && qx >= 0 && qy >= 0 && qx < truth.width && qy < truth.height &&
                   truth.at(qx, qy) == now;
          }
        }
        ASSERT_TRUE(near) << "pixel (" << x << ", " << y << ") became class " << int(now) << ", not within " << n
                          << " px in the truth";
      }
    }
    // Boundaries really move: of the order of the boundary length times the shift.
    EXPECT_GT(changed, 100 * n);
  }
}

TEST(SegmentationNoise, BoundaryBetweenTwoClassesMovesByAtMostNBothWays) {
  // Road left of x = 80, building right of it: per row, the boundary stays a single step that
  // moves by at most n; over many images both directions occur.
  ImageU8 truth(160, 120, 1, 11);
  for (int y = 0; y < 120; ++y) {
    for (int x = 0; x < 80; ++x) truth.at(x, y) = 7;
  }
  SegmentationNoiseOptions o;
  o.boundary_px = 5;
  int grew = 0, shrank = 0;
  for (int frame = 0; frame < 20; ++frame) {
    const ImageU8 noisy = ApplySegmentationNoise(truth, o, "cam0", std::to_string(frame));
    for (int y = 0; y < 120; ++y) {
      int boundary = 0;
      while (boundary < 160 && noisy.at(boundary, y) == 7) ++boundary;
      for (int x = boundary; x < 160; ++x) ASSERT_EQ(noisy.at(x, y), 11) << "row " << y << " is not one step";
      EXPECT_LE(std::abs(boundary - 80), 5);
      grew += boundary > 80;
      shrank += boundary < 80;
    }
  }
  EXPECT_GT(grew, 100);
  EXPECT_GT(shrank, 100);
}

TEST(SegmentationNoise, ConfusionRateOverManyBlobsIsNearP) {
  // Large regions of confusable classes cut into many superpixel blobs.
  ImageU8 truth(960, 720, 1, 11);
  for (int y = 360; y < 720; ++y) {
    for (int x = 0; x < 960; ++x) truth.at(x, y) = x < 480 ? 7 : 21;
  }
  for (int y = 0; y < 100; ++y) {
    for (int x = 0; x < 100; ++x) truth.at(x, y) = 0;  // void: never confused
  }
  for (double p : {0.05, 0.2, 0.5, 1.0}) {
    SCOPED_TRACE(p);
    SegmentationNoiseOptions o;
    o.confusion_rate = p;
    o.blob_size_px = 16;
    o.seed = 3;
    const uint64_t image_seed = SegmentationNoiseImageSeed(o.seed, "cam2", "000004");
    const LabelBlobs blobs = FindLabelBlobs(truth, o.blob_size_px, image_seed);
    const ImageU8 noisy = ApplySegmentationNoise(truth, o, image_seed);
    std::vector<std::set<uint8_t>> classes_of_blob(blobs.count());
    for (size_t i = 0; i < truth.data.size(); ++i) classes_of_blob[blobs.blob_of_pixel[i]].insert(noisy.data[i]);
    int confusable = 0, relabelled = 0;
    for (int b = 0; b < blobs.count(); ++b) {
      ASSERT_EQ(classes_of_blob[b].size(), 1u) << "blob " << b << " was split";  // blob-wise, not pixel-wise
      const uint8_t now = *classes_of_blob[b].begin(), was = blobs.blob_class[b];
      const auto allowed = ConfusableClasses(was);
      if (allowed.empty()) {
        EXPECT_EQ(now, was) << "void blob changed";
        continue;
      }
      ++confusable;
      if (now != was) {
        ++relabelled;
        EXPECT_NE(std::find(allowed.begin(), allowed.end(), now), allowed.end())
            << int(was) << " became " << int(now) << ", not a confusable class";
      }
    }
    ASSERT_GT(confusable, 2500);
    const double rate = double(relabelled) / confusable;
    std::printf("p = %.2f: %d of %d blobs relabelled (%.4f)\n", p, relabelled, confusable, rate);
    EXPECT_NEAR(rate, p, 0.025);
  }
}

TEST(SegmentationNoise, BlobsAreConnectedSingleClassRegionsOfAboutTheCellSize) {
  const ImageU8 truth = StreetLabels();
  const LabelBlobs blobs = FindLabelBlobs(truth, 32, 99);
  ASSERT_EQ(blobs.blob_of_pixel.size(), truth.data.size());
  for (size_t i = 0; i < truth.data.size(); ++i) ASSERT_EQ(blobs.blob_class[blobs.blob_of_pixel[i]], truth.data[i]);
  // 320x240 in ~32 px cells is ~75 cells; class boundaries split some of them.
  EXPECT_GT(blobs.count(), 75);
  EXPECT_LT(blobs.count(), 400);
  EXPECT_EQ(blobs.blob_of_pixel[0], 0);  // raster order
}

TEST(SegmentationNoise, RejectsBadOptions) {
  const ImageU8 truth = StreetLabels(40, 30);
  SegmentationNoiseOptions o;
  o.boundary_px = -1;
  EXPECT_THROW(ApplySegmentationNoise(truth, o, "c", "f"), std::invalid_argument);
  o.boundary_px = 2;
  o.confusion_rate = 1.5;
  EXPECT_THROW(ApplySegmentationNoise(truth, o, "c", "f"), std::invalid_argument);
  o.confusion_rate = std::nan("");
  EXPECT_THROW(o.Check(), std::invalid_argument);
  o.confusion_rate = 0.1;
  o.blob_size_px = 2;
  EXPECT_THROW(o.Check(), std::invalid_argument);
  o.blob_size_px = 48;
  EXPECT_THROW(ApplySegmentationNoise(ImageU8(4, 4, 3), o, "c", "f"), std::invalid_argument);
}

}  // namespace
}  // namespace rigsim
