// Keeps freed memory in the process while feature detection runs.
//
// SIFT on a large photo builds its scale space from the doubled image, in buffers of a hundred
// megabytes. glibc serves blocks that large with mmap and returns them to the system when freed,
// so every image page-faults and zeroes them again (BENCHMARKS.md, "Calibration on real
// photographs"). While a KeepFreedMemory exists, large blocks come from the heap and freed ones
// stay there for the next image; when the last one ends, the defaults come back and the unused
// memory is returned. A no-op outside glibc.
#pragma once

namespace rigsim {

class KeepFreedMemory {
 public:
  KeepFreedMemory();
  ~KeepFreedMemory();
  KeepFreedMemory(const KeepFreedMemory&) = delete;
  KeepFreedMemory& operator=(const KeepFreedMemory&) = delete;
};

}  // namespace rigsim
