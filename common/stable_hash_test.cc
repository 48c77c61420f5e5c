#include "common/stable_hash.h"

#include <gtest/gtest.h>

namespace rigsim {
namespace {

TEST(StableHash, IsFnv1a64InHex) {
  EXPECT_EQ(StableHash(""), "cbf29ce484222325");  // FNV-1a 64 offset basis
  EXPECT_EQ(StableHash("a"), "af63dc4c8601ec8c");
  EXPECT_NE(StableHash("ab"), StableHash("ba"));
}

}  // namespace
}  // namespace rigsim
