#include "dataset/label_image.h"

#include <gmock/gmock.h>
#include <gtest/gtest.h>

#include "testing/expect_error.h"

namespace rigsim {
namespace {

TEST(LabelImage, ColourRoundTrip) {
  ImageU8 labels(3, 1, 1);
  labels.at(0, 0) = 7;   // road
  labels.at(1, 0) = 23;  // sky
  labels.at(2, 0) = 26;  // car
  const ImageU8 colors = ColorizeLabels(labels);
  EXPECT_EQ(colors.at(0, 0, 0), 128);
  EXPECT_EQ(colors.at(0, 0, 1), 64);
  EXPECT_EQ(colors.at(2, 0, 2), 142);
  EXPECT_EQ(LabelsFromColors(colors, "x.png").data, labels.data);
}

TEST(LabelImage, UnknownIdsAndColoursAreErrorsNamingTheFile) {
  ImageU8 labels(2, 2, 1, 11);
  labels.at(1, 1) = 99;
  EXPECT_THAT([&] { CheckLabelIds(labels, "labels/cam0/000000.png"); },
              ThrowsWith<std::runtime_error>("labels/cam0/000000.png", "99"));
  ImageU8 colors(1, 1, 3, 1);
  EXPECT_THROW(LabelsFromColors(colors, "c.png"), std::runtime_error);
}

}  // namespace
}  // namespace rigsim
