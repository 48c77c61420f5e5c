// The matrix product of brute-force L2 matching in 8-bit integer arithmetic, for descriptors whose
// every value is a whole number in [0, 255] (OpenCV's SIFT stores them so). Every sum stays below
// 2^24, so the float product gives the same numbers exactly: the two are interchangeable bit for
// bit, and the integer one is faster (AVX-512 VNNI: 64 multiply-adds per instruction against 16
// in float).
#pragma once

#include <cstddef>
#include <cstdint>
#include <vector>

#include "calibrator/features.h"

namespace rigsim {

// Whether this build has the integer kernel (matching.cc and this file are built for the machine
// that runs them; a CPU without AVX-512 VNNI uses the float product).
bool ByteProductAvailable();

// Every descriptor value of the float set `f` at `rows` is a whole number in [0, 255].
bool DescriptorsAreBytes(const FeatureSet& f, const std::vector<int>& rows);

// The B side of the product: the descriptors `rows` of a float set, packed once for the kernel.
// Requires ByteProductAvailable() and DescriptorsAreBytes(b, rows).
class ByteProductColumns {
 public:
  ByteProductColumns(const FeatureSet& b, const std::vector<int>& rows);

  // out[r * out_stride + j] = -2 * (a_{ia[begin + r]} . b_{rows[j]}) for r < end - begin and
  // j < rows.size(), as float: the values `-2.f * (A * B^T)` gives for the same descriptors.
  // Requires DescriptorsAreBytes(a, ia) and a's descriptor size equal to b's.
  void MinusTwoDot(const FeatureSet& a, const std::vector<int>& ia, size_t begin, size_t end, float* out,
                   size_t out_stride) const;

 private:
  int num_columns_ = 0;
  int quads_ = 0;                // descriptor length in groups of 4 bytes (zero-padded)
  std::vector<uint8_t> packed_;  // [group of 16 columns][quad][column in group][4 bytes]
  std::vector<int32_t> sum128_;  // 128 * (sum of each column's bytes), padded to whole groups
};

}  // namespace rigsim
