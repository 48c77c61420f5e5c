// Keeps freed memory in the process while feature detection runs.
//
// SIFT on a 3072x2048 photo builds its scale space from the doubled image: 11 buffers of 100 MB.
// glibc serves blocks that large with mmap and returns them to the system when freed, so every
// image page-faults and zeroes its 1.1 GB again: 30% of the detection time on Herz-Jesus-P8.
// While a KeepFreedMemory exists, large blocks come from the heap and freed ones stay there for
// the next image (detection of the 8 photos: 16.0 -> 13.5 s summed over threads); when the last
// one ends, the defaults come back and the unused memory is returned. A no-op outside glibc.
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
