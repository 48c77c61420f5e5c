// The running test's name, for what a test names after itself (its temporary folder, its seed).
#pragma once

#include <string>

namespace rigsim {

struct RunningTest {
  std::string name;          // "Suite.Name", or "Suite" in SetUpTestSuite and TearDownTestSuite
  bool whole_suite = false;  // no test is running: the suite is being set up or torn down
};

// Throws std::logic_error outside a test and outside a suite's set-up and tear-down.
RunningTest CurrentTest();

}  // namespace rigsim
