#include "calibrator/features/keep_freed_memory.h"

#include <cstdlib>
#include <cstring>

#include <sys/resource.h>
#include <gtest/gtest.h>

namespace rigsim {
namespace {

long MinorFaults() {
  rusage usage{};
  getrusage(RUSAGE_SELF, &usage);
  return usage.ru_minflt;
}

// Page faults of allocating, writing and freeing a 64 MiB block, after one such block was freed.
long FaultsOfASecondLargeBlock() {
  constexpr size_t kBytes = size_t(64) << 20;
  // Through volatile pointers: the compiler may otherwise drop a malloc whose block is only freed.
  void* (*volatile allocate)(size_t) = std::malloc;
  void (*volatile release)(void*) = std::free;
  auto touch_and_free = [&] {
    char* p = static_cast<char*>(allocate(kBytes));
    std::memset(p, 1, kBytes);
    release(p);
  };
  touch_and_free();
  const long before = MinorFaults();
  touch_and_free();
  return MinorFaults() - before;
}

TEST(KeepFreedMemory, AFreedLargeBlockIsReusedWithoutPageFaults) {
#if !defined(__GLIBC__)
  GTEST_SKIP() << "glibc only";
#endif
  const long pages = (long(64) << 20) / 4096;
  // Without it, glibc maps the block afresh: every page faults again.
  EXPECT_GT(FaultsOfASecondLargeBlock(), pages / 2);
  {
    const KeepFreedMemory keep;
    EXPECT_LT(FaultsOfASecondLargeBlock(), pages / 20);
    { const KeepFreedMemory nested; }  // holders nest: the inner end does not restore the defaults
    EXPECT_LT(FaultsOfASecondLargeBlock(), pages / 20);
  }
  EXPECT_GT(FaultsOfASecondLargeBlock(), pages / 2);  // the defaults are back
}

}  // namespace
}  // namespace rigsim
