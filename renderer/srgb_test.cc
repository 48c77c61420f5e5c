#include "renderer/srgb.h"

#include <cmath>

#include <gtest/gtest.h>

namespace rigsim {
namespace {

TEST(Srgb, CodesRoundTripAndRoundToNearest) {
  for (int v = 0; v < 256; ++v) EXPECT_EQ(SrgbCodeFromLinear(LinearFromSrgbCode(uint8_t(v))), v);
  EXPECT_EQ(SrgbCodeFromLinear(-1.0), 0);
  EXPECT_EQ(SrgbCodeFromLinear(std::nan("")), 0);
  EXPECT_EQ(SrgbCodeFromLinear(2.0), 255);
  // Nearest code: just below and above the midpoint between codes 100 and 101.
  EXPECT_EQ(SrgbCodeFromLinear(SrgbToLinear(100.49 / 255)), 100);
  EXPECT_EQ(SrgbCodeFromLinear(SrgbToLinear(100.51 / 255)), 101);
  // The transfer function itself, at its linear segment and at a point of the power segment.
  EXPECT_DOUBLE_EQ(SrgbToLinear(0.04), 0.04 / 12.92);
  EXPECT_NEAR(SrgbToLinear(0.5), 0.214041, 1e-6);
}

// The table look-up against the definition (the nearest code in encoded space: code c covers
// linear values from the midpoint below it to the midpoint above it) at every threshold's
// neighbouring floats and across [0, 1].
TEST(Srgb, EncoderMatchesTheThresholdsAtEveryCodeBoundary) {
  auto reference = [](float linear) {
    int code = 0;
    while (code < 255 && double(linear) >= SrgbToLinear((code + 0.5) / 255.0)) ++code;
    return code;
  };
  for (int code = 0; code < 255; ++code) {
    const float midpoint = float(SrgbToLinear((code + 0.5) / 255.0));
    float x = midpoint;
    for (int i = 0; i < 3; ++i) x = std::nextafter(x, 0.0f);
    for (int i = 0; i < 7; ++i, x = std::nextafter(x, 1.0f)) ASSERT_EQ(SrgbCodeFromLinear(x), reference(x)) << x;
  }
  for (int i = 0; i <= 100000; ++i) {
    const float x = float(i) / 100000;
    ASSERT_EQ(SrgbCodeFromLinear(x), reference(x)) << x;
  }
}

TEST(Srgb, FloatTableEqualsTheDecodedCodes) {
  for (int v = 0; v < 256; ++v) EXPECT_FLOAT_EQ(LinearFromSrgbCodeTable()[v], float(LinearFromSrgbCode(uint8_t(v))));
  EXPECT_EQ(LinearFromSrgbCode(0), 0.0);
  EXPECT_DOUBLE_EQ(LinearFromSrgbCode(255), 1.0);
}

}  // namespace
}  // namespace rigsim
