// A plain in-memory image: row-major, channels interleaved. Pixel (x, y) is the pixel whose
// centre has coordinates (x, y) in the OpenCV convention (top-left pixel centre = (0, 0)), the
// camera models' (camera_models.h); it sits beside them so that the calibration core, which
// takes images in memory, needs nothing above geometry/. Reading and writing: dataset/image_io.h.
#pragma once

#include <cassert>
#include <cstddef>
#include <cstdint>
#include <vector>

namespace rigsim {

template <typename T>
struct Image {
  int width = 0;
  int height = 0;
  int channels = 1;
  std::vector<T> data;

  Image() = default;
  Image(int w, int h, int c, T fill = T()) : width(w), height(h), channels(c), data(size_t(w) * h * c, fill) {}

  bool empty() const { return data.empty(); }
  T& at(int x, int y, int c = 0) {
    assert(x >= 0 && y >= 0 && x < width && y < height && c >= 0 && c < channels);
    return data[(size_t(y) * width + x) * channels + c];
  }
  const T& at(int x, int y, int c = 0) const {
    assert(x >= 0 && y >= 0 && x < width && y < height && c >= 0 && c < channels);
    return data[(size_t(y) * width + x) * channels + c];
  }
  bool SameSize(int w, int h) const { return width == w && height == h; }
};

using ImageU8 = Image<uint8_t>;    // RGB (3 channels) or labels (1 channel)
using ImageU16 = Image<uint16_t>;  // instance ids
using ImageF = Image<float>;       // depth (range, metres)

}  // namespace rigsim
