#include "calibrator/features/semantics.h"

#include <stdexcept>

#include <gtest/gtest.h>

#include "labels/cityscapes.h"

namespace rigsim {
namespace {

TEST(SemanticMode, NamesRoundTrip) {
  for (SemanticMode m : kAllSemanticModes) EXPECT_EQ(SemanticModeFromName(SemanticModeName(m)), m);
  EXPECT_EQ(SemanticModeFromName("mask+gated"), SemanticMode::kMaskGated);
  EXPECT_THROW(SemanticModeFromName("masked"), std::invalid_argument);
  EXPECT_TRUE(UsesMask(SemanticMode::kMaskGated));
  EXPECT_FALSE(UsesMask(SemanticMode::kGated));
  EXPECT_TRUE(UsesGating(SemanticMode::kGated));
  EXPECT_FALSE(NeedsLabels(SemanticMode::kNone));
}

TEST(ReliableMask, ErodesClassBoundaryButNotImageBorder) {
  // Left half building (reliable), right half sky (unreliable).
  ImageU8 labels(40, 20, 1, 11);
  for (int y = 0; y < 20; ++y) {
    for (int x = 20; x < 40; ++x) labels.at(x, y) = kSkyId;
  }
  const ImageU8 mask = ReliableMask(labels, ReliableClasses().Ids(), 3);
  EXPECT_EQ(mask.at(0, 0), 255);    // image corner: not eroded
  EXPECT_EQ(mask.at(16, 10), 255);  // 4 px from the boundary
  EXPECT_EQ(mask.at(17, 10), 0);    // 3 px from the boundary
  EXPECT_EQ(mask.at(19, 10), 0);
  EXPECT_EQ(mask.at(25, 10), 0);  // sky
  const ImageU8 raw = ReliableMask(labels, ReliableClasses().Ids(), 0);
  EXPECT_EQ(raw.at(19, 10), 255);
  EXPECT_EQ(raw.at(20, 10), 0);
}

}  // namespace
}  // namespace rigsim
