// The tests' main: GoogleTest's, with one change. Where a suite's SetUpTestSuite fails an
// assertion, GoogleTest marks the suite's tests skipped and exits 0, and ctest counts a skipped
// test as not failed: a broken set-up would hide its tests. Aborting there makes ctest fail them.
#include <cstdio>
#include <cstdlib>

#include <gtest/gtest.h>

namespace {

class FailedSetUpAborts : public ::testing::EmptyTestEventListener {
  void OnTestSuiteEnd(const ::testing::TestSuite& suite) override {
    if (!suite.ad_hoc_test_result().Failed()) return;
    std::fprintf(stderr, "%s: the suite's set-up or tear-down failed (above), so its tests did not run\n", suite.name());
    std::fflush(stderr);
    std::abort();
  }
};

}  // namespace

int main(int argc, char** argv) {
  ::testing::InitGoogleTest(&argc, argv);
  ::testing::UnitTest::GetInstance()->listeners().Append(new FailedSetUpAborts);
  return RUN_ALL_TESTS();
}
