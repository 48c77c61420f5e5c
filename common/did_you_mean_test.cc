#include "common/did_you_mean.h"

#include <gtest/gtest.h>

namespace rigsim {
namespace {

TEST(EditDistance, CountsInsertionsDeletionsSubstitutionsAndSwaps) {
  EXPECT_EQ(EditDistance("building", "building"), 0);
  EXPECT_EQ(EditDistance("buildng", "building"), 1);     // deletion
  EXPECT_EQ(EditDistance("buildings", "building"), 1);   // insertion
  EXPECT_EQ(EditDistance("bulding", "building"), 1);
  EXPECT_EQ(EditDistance("biulding", "building"), 1);    // two neighbours swapped
  EXPECT_EQ(EditDistance("Building", "building"), 0);    // letter case ignored
  EXPECT_EQ(EditDistance("", "abc"), 3);
  EXPECT_EQ(EditDistance("sky", "road"), 4);
}

TEST(DidYouMean, SuggestsTheClosestLikelyTypoOnly) {
  const std::vector<std::string> classes = {"road", "sidewalk", "building", "wall", "vegetation"};
  EXPECT_EQ(DidYouMean("biulding", classes), " (did you mean 'building'?)");
  EXPECT_EQ(DidYouMean("vegetaton", classes), " (did you mean 'vegetation'?)");
  EXPECT_EQ(DidYouMean("wal", classes), " (did you mean 'wall'?)");
  EXPECT_EQ(DidYouMean("person", classes), "");  // nothing close: no guess
  EXPECT_EQ(ClosestName("xyz", {}), std::nullopt);
}

}  // namespace
}  // namespace rigsim
