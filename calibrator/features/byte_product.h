// The matrix product of brute-force L2 matching in integer arithmetic, for descriptors whose
// every value is a whole number in [0, 255] (OpenCV's SIFT stores them so). Every sum stays below
// 2^24, so the float product gives the same numbers exactly: the two are interchangeable bit for
// bit, whichever CPU path (calibrator/cpu_path.h) computes them. The integer kernels (AVX2: 16
// multiply-adds per instruction; AVX-512 VNNI: 64, against 8 and 16 in float) are chosen at run
// time; the baseline path is the float product.
#pragma once

#include <cstddef>
#include <cstdint>
#include <vector>

#include "calibrator/features/cpu_path.h"
#include "calibrator/features/features.h"

namespace rigsim {

// Whether `path` has an integer kernel (every path but the baseline).
bool ByteProductAvailable(CpuPath path);

// Every descriptor value of the float set `f` at `rows` is a whole number in [0, 255].
bool DescriptorsAreBytes(const FeatureSet& f, const std::vector<int>& rows);

// The B side of the product: the descriptors `rows` of a float set, packed once for the kernel of
// `path`. Requires ByteProductAvailable(path), CpuSupports(path) and DescriptorsAreBytes(b, rows).
class ByteProductColumns {
 public:
  ByteProductColumns(const FeatureSet& b, const std::vector<int>& rows, CpuPath path);

  // out[r * out_stride + j] = -2 * (a_{ia[begin + r]} . b_{rows[j]}) for r < end - begin and
  // j < rows.size(), as float: the values `-2.f * (A * B^T)` gives for the same descriptors.
  // Requires DescriptorsAreBytes(a, ia) and a's descriptor size equal to b's.
  void MinusTwoDot(const FeatureSet& a, const std::vector<int>& ia, size_t begin, size_t end, float* out,
                   size_t out_stride) const;

 private:
  CpuPath path_;
  int num_columns_ = 0;
  int steps_ = 0;                  // descriptor length in the kernel's steps (zero-padded): VNNI 4 bytes, AVX2 2
  std::vector<uint8_t> packed_;    // VNNI: [group of 16 columns][step][column in group][4 bytes]
  std::vector<int16_t> packed16_;  // AVX2: [group of 8 columns][step][column in group][2 values]
  std::vector<int32_t> sum128_;    // VNNI: 128 * (sum of each column's bytes), padded to whole groups
};

}  // namespace rigsim
