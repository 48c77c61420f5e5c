#include "testing/test_name.h"

#include <stdexcept>

#include <gtest/gtest.h>

namespace rigsim {

RunningTest CurrentTest() {
  const ::testing::UnitTest& unit = *::testing::UnitTest::GetInstance();
  if (const ::testing::TestInfo* test = unit.current_test_info()) {
    return {std::string(test->test_suite_name()) + "." + test->name(), false};
  }
  if (const ::testing::TestSuite* suite = unit.current_test_suite()) return {suite->name(), true};
  throw std::logic_error("called outside a test and outside a test suite's set-up and tear-down");
}

}  // namespace rigsim
