#include "report/report_images.h"

#include <cmath>

#include <gtest/gtest.h>

namespace rigsim {
namespace {

TEST(QuantiseRanges, KeepsNoSurfaceAndRoundTripsWithinAFewParts) {
  ImageF range(3, 1, 1);
  range.at(0, 0) = 0.0f;
  range.at(1, 0) = 1.7f;
  range.at(2, 0) = 350.0f;
  const std::vector<uint16_t> q = QuantiseRanges(range);
  EXPECT_EQ(q[0], 0);
  EXPECT_EQ(DequantiseRange(q[0]), 0.0);
  for (int i = 1; i < 3; ++i) EXPECT_NEAR(DequantiseRange(q[i]) / range.at(i, 0), 1.0, 2e-4);
}

TEST(SampleNearest, TakesThePixelUnderEachOutputCentre) {
  ImageU8 labels(4, 2, 1);
  for (int x = 0; x < 4; ++x) labels.at(x, 0) = labels.at(x, 1) = uint8_t(10 * x);
  const ImageU8 half = SampleNearest(labels, 2, 1);
  EXPECT_EQ(half.at(0, 0), 10);  // output centre 0.5 -> input 1
  EXPECT_EQ(half.at(1, 0), 30);
}

TEST(ColourLabels, UnlabelledIsTransparent) {
  ImageU8 labels(2, 1, 1);
  labels.at(0, 0) = 0;
  labels.at(1, 0) = 11;  // building
  const ImageU8 rgba = ColourLabels(labels);
  EXPECT_EQ(rgba.at(0, 0, 3), 0);
  EXPECT_EQ(rgba.at(1, 0, 3), 255);
  EXPECT_EQ(rgba.at(1, 0, 0), 70);  // Cityscapes' building grey (70, 70, 70)
}

TEST(ScaleRgb, FitsTheWidth) {
  const ImageU8 rgb(100, 50, 3, 128);
  EXPECT_DOUBLE_EQ(DisplayScale(100, 40), 0.4);
  EXPECT_DOUBLE_EQ(DisplayScale(100, 400), 1.0);
  const ImageU8 small = ScaleRgb(rgb, 0.4);
  EXPECT_EQ(small.width, 40);
  EXPECT_EQ(small.height, 20);
  EXPECT_EQ(small.at(5, 5, 1), 128);
}

}  // namespace
}  // namespace rigsim
