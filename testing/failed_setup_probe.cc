// A suite whose set-up fails: its test must not pass as skipped (gtest_main.cc). Run by ctest
// through `sh -c '! probe'`: the probe must exit non-zero.
#include <gtest/gtest.h>

namespace {

class SetUpFails : public ::testing::Test {
 protected:
  static void SetUpTestSuite() { FAIL() << "the set-up fails on purpose"; }
};

TEST_F(SetUpFails, NeverRuns) { SUCCEED(); }

}  // namespace
