#include "dataset/previews.h"

#include <algorithm>
#include <array>
#include <cmath>
#include <cstdint>

namespace rigsim {
namespace {

// A turbo-like map from s in [0, 1] (0 = far, blue; 1 = near, red), piecewise linear through
// seven colours.
std::array<uint8_t, 3> Turbo(float s) {
  static constexpr std::array<std::array<float, 3>, 7> kStops = {{{48, 18, 59},
                                                                   {70, 134, 251},
                                                                   {27, 229, 181},
                                                                   {164, 252, 60},
                                                                   {251, 185, 56},
                                                                   {227, 68, 10},
                                                                   {122, 4, 3}}};
  const float f = std::clamp(s, 0.0f, 1.0f) * float(kStops.size() - 1);
  const int i = std::min(int(f), int(kStops.size()) - 2);
  const float a = f - float(i);
  std::array<uint8_t, 3> rgb;
  for (int c = 0; c < 3; ++c) rgb[c] = uint8_t(std::lround((1 - a) * kStops[i][c] + a * kStops[i + 1][c]));
  return rgb;
}

}  // namespace

ImageU8 ColorizeDepth(const ImageF& range) {
  constexpr float kNear = 1.0f, kFar = 200.0f;
  const float log_span = std::log(kFar / kNear);
  ImageU8 out(range.width, range.height, 3, 0);
  for (size_t i = 0; i < range.data.size(); ++i) {
    const float r = range.data[i];
    if (!(r > 0) || !std::isfinite(r)) continue;
    const std::array<uint8_t, 3> rgb = Turbo(1.0f - std::log(std::max(r, kNear) / kNear) / log_span);
    std::copy(rgb.begin(), rgb.end(), &out.data[3 * i]);
  }
  return out;
}

ImageU8 ColorizeInstances(const ImageU16& instances) {
  ImageU8 out(instances.width, instances.height, 3, 0);
  for (size_t i = 0; i < instances.data.size(); ++i) {
    const uint16_t id = instances.data[i];
    if (id == 0) continue;
    uint32_t h = uint32_t(id) * 0x9E3779B1u;  // Fibonacci hashing: neighbouring ids far apart
    h ^= h >> 15;
    h *= 0x85EBCA77u;
    h ^= h >> 13;
    // Bright enough to tell from the black background.
    for (int c = 0; c < 3; ++c) out.data[3 * i + c] = uint8_t(64 + ((h >> (8 * c)) & 0xFF) * 191 / 255);
  }
  return out;
}

}  // namespace rigsim
