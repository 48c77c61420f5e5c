#include "renderer/srgb.h"

#include <algorithm>
#include <cmath>
#include <limits>

namespace rigsim {
namespace {

// The code at the start of each of 4096 buckets over [0, 1], finished by the thresholds where the
// code changes (a step or two at most: near black, where the curve is steepest, a bucket spans
// under one code).
constexpr int kBuckets = 4096;

struct SrgbTables {
  std::array<double, 256> decode{};
  std::array<float, 256> decode_float{};
  std::array<double, 256> thresholds{};  // code i+1 starts at linear value thresholds[i]; [255] = +inf
  std::array<uint8_t, kBuckets + 1> bucket_start{};
};

const SrgbTables& Tables() {
  static const SrgbTables t = [] {
    SrgbTables out;
    for (int i = 0; i < 256; ++i) {
      out.decode[i] = SrgbToLinear(i / 255.0);
      out.decode_float[i] = static_cast<float>(out.decode[i]);
    }
    for (int i = 0; i < 255; ++i) out.thresholds[i] = SrgbToLinear((i + 0.5) / 255.0);
    out.thresholds[255] = std::numeric_limits<double>::infinity();
    for (int b = 0; b <= kBuckets; ++b) {
      const double v = double(b) / kBuckets;
      out.bucket_start[b] =
          uint8_t(std::upper_bound(out.thresholds.begin(), out.thresholds.begin() + 255, v) - out.thresholds.begin());
    }
    return out;
  }();
  return t;
}

}  // namespace

double SrgbToLinear(double c) { return c <= 0.04045 ? c / 12.92 : std::pow((c + 0.055) / 1.055, 2.4); }

uint8_t SrgbCodeFromLinear(double linear) {
  if (!(linear > 0.0)) return 0;
  if (linear >= 1.0) return 255;
  const SrgbTables& t = Tables();
  int code = t.bucket_start[int(linear * kBuckets)];
  while (linear >= t.thresholds[code]) ++code;
  return uint8_t(code);
}

double LinearFromSrgbCode(uint8_t code) { return Tables().decode[code]; }

const std::array<float, 256>& LinearFromSrgbCodeTable() { return Tables().decode_float; }

}  // namespace rigsim
