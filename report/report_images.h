// Images of a teaching report, scaled for a screen, and the compact encodings of the data the
// page draws over them (base64 of little-endian arrays, read by the page with atob into typed
// arrays).
#pragma once

#include <algorithm>
#include <cstdint>
#include <string>
#include <string_view>
#include <vector>

#include "common/base64.h"
#include "geometry/image.h"

namespace rigsim {

// Scale factor (<= 1) that fits `width` into `max_width`.
double DisplayScale(int width, int max_width);

// RGB scaled by `scale` (area averaging).
ImageU8 ScaleRgb(const ImageU8& rgb, double scale);
// Any image sampled at the nearest pixel of each output pixel's centre (labels, ids, ranges
// must not be averaged across surfaces).
template <typename T>
Image<T> SampleNearest(const Image<T>& image, int out_width, int out_height) {
  Image<T> out(out_width, out_height, image.channels);
  for (int y = 0; y < out_height; ++y) {
    const int sy = std::min(image.height - 1, int((y + 0.5) * image.height / out_height));
    for (int x = 0; x < out_width; ++x) {
      const int sx = std::min(image.width - 1, int((x + 0.5) * image.width / out_width));
      for (int c = 0; c < image.channels; ++c) out.at(x, y, c) = image.at(sx, sy, c);
    }
  }
  return out;
}

// Cityscapes label ids (1 channel) as RGBA: the class colour, transparent where unlabelled.
ImageU8 ColourLabels(const ImageU8& labels);
// Instance ids (1 channel) as RGBA: a colour per id, transparent where 0.
ImageU8 ColourInstances(const ImageU16& instances);
// Range (m, 1 channel) as RGB on a perceptual colour map over log range between `near_m` and
// `far_m` (near = bright yellow, far = dark blue); black where there is no surface.
ImageU8 ColourDepth(const ImageF& range, double near_m, double far_m);

// Ranges quantised to 16 bits on a log scale: 0 = no surface, else
// q = 1 + round((ln r - ln kRangeMin) / (ln kRangeMax - ln kRangeMin) * 65534), clamped.
inline constexpr double kRangeMin = 0.01, kRangeMax = 1.0e5;
std::vector<uint16_t> QuantiseRanges(const ImageF& range);
double DequantiseRange(uint16_t q);

template <typename T>
std::string Base64Of(const std::vector<T>& values) {
  return Base64Encode(std::string_view(reinterpret_cast<const char*>(values.data()), values.size() * sizeof(T)));
}

}  // namespace rigsim
