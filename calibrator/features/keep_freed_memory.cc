#include "calibrator/features/keep_freed_memory.h"

#include <mutex>

#if defined(__GLIBC__)
#include <malloc.h>
#endif

namespace rigsim {
namespace {

std::mutex g_mutex;
int g_holders = 0;  // KeepFreedMemory objects alive (calibrations can run side by side)

#if defined(__GLIBC__)
// glibc's defaults (mallopt(3)): at most 65536 mmap'ed blocks, trim the heap top above 128 KiB.
constexpr int kDefaultMmapMax = 65536;
constexpr int kDefaultTrimThreshold = 128 * 1024;
#endif

}  // namespace

KeepFreedMemory::KeepFreedMemory() {
  const std::lock_guard<std::mutex> lock(g_mutex);
  if (g_holders++ > 0) return;
#if defined(__GLIBC__)
  mallopt(M_MMAP_MAX, 0);  // every block from the heap (a thread's arena, or the main one when larger)
  mallopt(M_TRIM_THRESHOLD, 1 << 30);
#endif
}

KeepFreedMemory::~KeepFreedMemory() {
  const std::lock_guard<std::mutex> lock(g_mutex);
  if (--g_holders > 0) return;
#if defined(__GLIBC__)
  mallopt(M_MMAP_MAX, kDefaultMmapMax);
  mallopt(M_TRIM_THRESHOLD, kDefaultTrimThreshold);
  malloc_trim(0);
#endif
}

}  // namespace rigsim
