#include "dataset/label_image.h"

#include <gtest/gtest.h>

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
  try {
    CheckLabelIds(labels, "labels/cam0/000000.png");
    FAIL();
  } catch (const std::runtime_error& e) {
    EXPECT_NE(std::string(e.what()).find("labels/cam0/000000.png"), std::string::npos);
    EXPECT_NE(std::string(e.what()).find("99"), std::string::npos);
  }
  ImageU8 colors(1, 1, 3, 1);
  EXPECT_THROW(LabelsFromColors(colors, "c.png"), std::runtime_error);
}

}  // namespace
}  // namespace rigsim
