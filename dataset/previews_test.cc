#include "dataset/previews.h"

#include <gtest/gtest.h>

namespace rigsim {
namespace {

TEST(Previews, DepthIsRedNearBlueFarBlackWithoutSurface) {
  ImageF range(3, 1, 1, 0.0f);
  range.at(0, 0) = 1.0f;
  range.at(1, 0) = 500.0f;
  const ImageU8 rgb = ColorizeDepth(range);
  EXPECT_GT(rgb.at(0, 0, 0), rgb.at(0, 0, 2));  // near: red
  EXPECT_LT(rgb.at(1, 0, 0), rgb.at(1, 0, 2));  // far: blue
  EXPECT_EQ(rgb.at(2, 0, 0) + rgb.at(2, 0, 1) + rgb.at(2, 0, 2), 0);
}

TEST(Previews, InstancesGetTheirOwnColourAndNoneIsBlack) {
  ImageU16 ids(4, 1, 1, 0);
  ids.at(1, 0) = 5;
  ids.at(2, 0) = 6;
  ids.at(3, 0) = 5;
  const ImageU8 rgb = ColorizeInstances(ids);
  EXPECT_EQ(rgb.at(0, 0, 0) + rgb.at(0, 0, 1) + rgb.at(0, 0, 2), 0);
  for (int c = 0; c < 3; ++c) EXPECT_EQ(rgb.at(1, 0, c), rgb.at(3, 0, c));
  EXPECT_NE(std::make_tuple(rgb.at(1, 0, 0), rgb.at(1, 0, 1), rgb.at(1, 0, 2)),
            std::make_tuple(rgb.at(2, 0, 0), rgb.at(2, 0, 1), rgb.at(2, 0, 2)));
}

}  // namespace
}  // namespace rigsim
