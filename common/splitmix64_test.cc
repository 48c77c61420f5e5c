#include "common/splitmix64.h"

#include <gtest/gtest.h>

namespace rigsim {
namespace {

// The reference generator's first outputs from state 0 (Vigna's splitmix64.c): the same numbers
// every seeded generator of rigsim is built on.
TEST(SplitMix64, MatchesTheReferenceSequence) {
  EXPECT_EQ(SplitMix64(0), 0xE220A8397B1DCDAFull);
  EXPECT_EQ(SplitMix64(kSplitMix64Increment), 0x6E789E6AA1B965F4ull);
  static_assert(SplitMix64(0) == 0xE220A8397B1DCDAFull, "usable at compile time");
}

}  // namespace
}  // namespace rigsim
