// The sRGB transfer function (IEC 61966-2-1) for 8-bit codes: the one place rigsim encodes linear
// light to image bytes and decodes them back (rendered RGB, textures, photometric variation).
#pragma once

#include <array>
#include <cstdint>

namespace rigsim {

// Linear value of an sRGB-encoded value, both in [0, 1].
double SrgbToLinear(double encoded);

// The nearest 8-bit code of a linear value (clipped to [0, 1]; NaN -> 0), without a pow: exact
// against the code thresholds. SrgbCodeFromLinear(LinearFromSrgbCode(v)) == v for every code.
uint8_t SrgbCodeFromLinear(double linear);

// Linear value of a code, and the whole table in float for per-texel decoding.
double LinearFromSrgbCode(uint8_t code);
const std::array<float, 256>& LinearFromSrgbCodeTable();

}  // namespace rigsim
