#include "pipeline/match_image.h"

#include <array>
#include <cstdlib>
#include <stdexcept>

#include <gtest/gtest.h>

namespace rigsim {
namespace {

ImageU8 Plain(int w, int h, uint8_t r, uint8_t g, uint8_t b) {
  ImageU8 image(w, h, 3);
  for (int y = 0; y < h; ++y) {
    for (int x = 0; x < w; ++x) {
      image.at(x, y, 0) = r, image.at(x, y, 1) = g, image.at(x, y, 2) = b;
    }
  }
  return image;
}

bool Is(const ImageU8& image, int x, int y, uint8_t r, uint8_t g, uint8_t b) {
  return image.at(x, y, 0) == r && image.at(x, y, 1) == g && image.at(x, y, 2) == b;
}

TEST(MatchImage, SideBySideWithALinePerMatch) {
  const ImageU8 red = Plain(100, 80, 255, 0, 0), blue = Plain(60, 70, 0, 0, 255);
  // One match from (10, 40) in the red image to (30, 40) in the blue one: a horizontal line.
  const ImageU8 out = DrawMatches(red, blue, {{Eigen::Vector2d(10, 40), Eigen::Vector2d(30, 40)}});
  ASSERT_EQ(out.width, 160);
  ASSERT_EQ(out.height, 80);
  EXPECT_TRUE(Is(out, 50, 10, 255, 0, 0)) << "the first image on the left";
  EXPECT_TRUE(Is(out, 150, 10, 0, 0, 255)) << "the second on the right";
  EXPECT_TRUE(Is(out, 150, 75, 0, 0, 0)) << "below the shorter image: black";
  EXPECT_FALSE(Is(out, 70, 40, 255, 0, 0)) << "the line crosses the first image at y = 40";
  EXPECT_FALSE(Is(out, 120, 40, 0, 0, 255)) << "and the second, up to x = 100 + 30";
  EXPECT_TRUE(Is(out, 145, 40, 0, 0, 255)) << "and stops there";
  EXPECT_TRUE(Is(out, 70, 20, 255, 0, 0)) << "nothing drawn elsewhere";
}

TEST(MatchImage, ScaledDownToTheWidthWithPixelCentresKept) {
  const ImageU8 a = Plain(2000, 1000, 255, 255, 255), b = Plain(2000, 1000, 255, 255, 255);
  MatchImageOptions options;
  options.max_width = 1600;  // scale 0.4
  // The centre of each image, (999.5, 499.5), is the centre of its scaled copy, (399.5, 199.5).
  const ImageU8 out = DrawMatches(a, b, {{Eigen::Vector2d(999.5, 499.5), Eigen::Vector2d(999.5, 499.5)}}, options);
  ASSERT_EQ(out.width, 1600);
  ASSERT_EQ(out.height, 400);
  EXPECT_FALSE(Is(out, 600, 200, 255, 255, 255)) << "the line between the two centres, at y = 200";
  EXPECT_TRUE(Is(out, 600, 190, 255, 255, 255));
  EXPECT_TRUE(Is(out, 600, 210, 255, 255, 255));
}

TEST(MatchImage, RightAndWrongMatchesInTheirColoursWithNamesAndLegend) {
  const ImageU8 grey = Plain(400, 300, 128, 128, 128);
  MatchAnnotation note{"camA", "camB", {1, 0}};
  // A right match along y = 100, a wrong one along y = 200.
  const ImageU8 out = DrawMatches(grey, grey,
                                  {{Eigen::Vector2d(50, 100), Eigen::Vector2d(350, 100)},
                                   {Eigen::Vector2d(50, 200), Eigen::Vector2d(350, 200)}},
                                  {}, note);
  // Along each line (anti-aliased: the strongest pixel of the column).
  auto strongest = [&](int x, int y0) {
    int best = y0;
    for (int y = y0 - 2; y <= y0 + 2; ++y) {
      if (std::abs(out.at(x, y, 1) - out.at(x, y, 0)) > std::abs(out.at(x, best, 1) - out.at(x, best, 0))) best = y;
    }
    return std::array<int, 3>{out.at(x, best, 0), out.at(x, best, 1), out.at(x, best, 2)};
  };
  const auto right = strongest(300, 100), wrong = strongest(300, 200);
  EXPECT_GT(right[1], right[0] + 60) << "right: green";
  EXPECT_GT(wrong[0], wrong[1] + 60) << "wrong: red";
  int changed_top_left = 0;  // the name "camA" written over the first photo
  for (int y = 0; y < 20; ++y) {
    for (int x = 0; x < 60; ++x) changed_top_left += !Is(out, x, y, 128, 128, 128);
  }
  EXPECT_GT(changed_top_left, 30);
  int changed_bottom = 0;  // the legend
  for (int y = 250; y < 300; ++y) {
    for (int x = 0; x < 200; ++x) changed_bottom += !Is(out, x, y, 128, 128, 128);
  }
  EXPECT_GT(changed_bottom, 100);
  EXPECT_THROW(DrawMatches(grey, grey, {{Eigen::Vector2d(1, 1), Eigen::Vector2d(2, 2)}}, {}, MatchAnnotation{"a", "b", {1, 0}}),
               std::invalid_argument);
}

TEST(MatchImage, RefusesImagesThatAreNotRgb) {
  EXPECT_THROW(DrawMatches(ImageU8(10, 10, 1), Plain(10, 10, 0, 0, 0), {}), std::invalid_argument);
  EXPECT_THROW(DrawMatches(Plain(10, 10, 0, 0, 0), ImageU8(), {}), std::invalid_argument);
}

}  // namespace
}  // namespace rigsim
