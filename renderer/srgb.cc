#include "renderer/srgb.h"

#include <algorithm>
#include <cmath>
#include <limits>
#include <stdexcept>

namespace rigsim {
namespace {

struct SrgbDecodeTables {
  std::array<double, 256> decode{};
  std::array<float, 256> decode_float{};
};

const SrgbDecodeTables& DecodeTables() {
  static const SrgbDecodeTables t = [] {
    SrgbDecodeTables out;
    for (int i = 0; i < 256; ++i) {
      out.decode[i] = SrgbToLinear(i / 255.0);
      out.decode_float[i] = static_cast<float>(out.decode[i]);
    }
    return out;
  }();
  return t;
}

SrgbEncodeTables BuildEncodeTables() {
  SrgbEncodeTables out;
  constexpr int kBuckets = SrgbEncodeTables::kBuckets;
  for (int i = 0; i < 255; ++i) {
    const double midpoint = SrgbToLinear((i + 0.5) / 255.0);
    float f = static_cast<float>(midpoint);
    if (double(f) < midpoint) f = std::nextafter(f, std::numeric_limits<float>::infinity());
    out.thresholds[i] = f;  // for a float x: x >= f exactly when x >= midpoint
  }
  out.thresholds[255] = std::numeric_limits<float>::infinity();
  for (int b = 0; b <= kBuckets; ++b) {
    const float v = float(b) / kBuckets;
    out.bucket_start[b] =
        uint8_t(std::upper_bound(out.thresholds.begin(), out.thresholds.begin() + 255, v) - out.thresholds.begin());
  }
  for (int b = 0; b < kBuckets; ++b) {
    if (out.bucket_start[b + 1] - out.bucket_start[b] > 1) {
      throw std::logic_error("sRGB encoder: a bucket holds more than one code threshold");
    }
  }
  return out;
}

}  // namespace

const SrgbEncodeTables& SrgbEncodeTables::Get() {
  static const SrgbEncodeTables t = BuildEncodeTables();
  return t;
}

double SrgbToLinear(double c) { return c <= 0.04045 ? c / 12.92 : std::pow((c + 0.055) / 1.055, 2.4); }

double LinearFromSrgbCode(uint8_t code) { return DecodeTables().decode[code]; }

const std::array<float, 256>& LinearFromSrgbCodeTable() { return DecodeTables().decode_float; }

}  // namespace rigsim
