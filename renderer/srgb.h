// The sRGB transfer function (IEC 61966-2-1) for 8-bit codes: the one place rigsim encodes linear
// light to image bytes and decodes them back (rendered RGB, textures, photometric variation).
#pragma once

#include <array>
#include <cstdint>

namespace rigsim {

// Linear value of an sRGB-encoded value, both in [0, 1].
double SrgbToLinear(double encoded);

// Tables for SrgbCodeFromLinear, built once. The encoder is inline because the renderer calls it
// three times per pixel, where a call into another file costs time (BENCHMARKS.md).
struct SrgbEncodeTables {
  static constexpr int kBuckets = 4096;
  // Code i + 1 starts at thresholds[i] (the smallest float at or above the midpoint between the
  // codes' linear values); thresholds[255] = +inf.
  std::array<float, 256> thresholds;
  // The code at linear value b / kBuckets. Every bucket holds at most one threshold (checked when
  // the table is built), so one comparison finishes the look-up.
  std::array<uint8_t, kBuckets + 1> bucket_start;

  static const SrgbEncodeTables& Get();
};

// The nearest 8-bit code of a linear value (clipped to [0, 1]; NaN -> 0), without a pow: exact
// against the code thresholds. SrgbCodeFromLinear(LinearFromSrgbCode(v)) == v for every code.
inline uint8_t SrgbCodeFromLinear(float linear, const SrgbEncodeTables& t = SrgbEncodeTables::Get()) {
  if (!(linear > 0.0f)) return 0;
  if (linear >= 1.0f) return 255;
  const int code = t.bucket_start[int(linear * float(SrgbEncodeTables::kBuckets))];
  return uint8_t(code + (linear >= t.thresholds[code]));
}

// Linear value of a code, and the whole table in float for per-texel decoding.
double LinearFromSrgbCode(uint8_t code);
const std::array<float, 256>& LinearFromSrgbCodeTable();

}  // namespace rigsim
