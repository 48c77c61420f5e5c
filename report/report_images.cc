#include "report/report_images.h"

#include <algorithm>
#include <array>
#include <cmath>

#include <opencv2/imgproc.hpp>

#include "labels/cityscapes.h"

namespace rigsim {

double DisplayScale(int width, int max_width) {
  return width > max_width && max_width > 0 ? double(max_width) / width : 1.0;
}

ImageU8 ScaleRgb(const ImageU8& rgb, double scale) {
  const int w = std::max(1, int(std::lround(rgb.width * scale))), h = std::max(1, int(std::lround(rgb.height * scale)));
  if (w == rgb.width && h == rgb.height) return rgb;
  const int type = CV_8UC(rgb.channels);
  const cv::Mat in(rgb.height, rgb.width, type, const_cast<uint8_t*>(rgb.data.data()));
  ImageU8 out(w, h, rgb.channels);
  cv::Mat dst(h, w, type, out.data.data());
  cv::resize(in, dst, dst.size(), 0, 0, cv::INTER_AREA);
  return out;
}

ImageU8 ColourLabels(const ImageU8& labels) {
  ImageU8 out(labels.width, labels.height, 4);
  for (int y = 0; y < labels.height; ++y) {
    for (int x = 0; x < labels.width; ++x) {
      const LabelClass* c = FindClassById(labels.at(x, y));
      if (!c || c->id == kUnlabeledId) continue;
      for (int k = 0; k < 3; ++k) out.at(x, y, k) = c->color[k];
      out.at(x, y, 3) = 255;
    }
  }
  return out;
}

ImageU8 ColourInstances(const ImageU16& instances) {
  ImageU8 out(instances.width, instances.height, 4);
  for (int y = 0; y < instances.height; ++y) {
    for (int x = 0; x < instances.width; ++x) {
      const uint32_t id = instances.at(x, y);
      if (id == 0) continue;
      // A well-spread hue per id (golden-ratio steps), full saturation.
      const double hue = std::fmod(id * 0.6180339887, 1.0) * 6.0;
      const double f = hue - std::floor(hue);
      const double v = 0.55 + 0.45 * ((id * 7919u) % 3) / 2.0;
      const std::array<double, 6 * 3> wheel = {1, f, 0, 1 - f, 1, 0, 0, 1, f, 0, 1 - f, 1, f, 0, 1, 1, 0, 1 - f};
      const int s = int(hue) % 6;
      for (int k = 0; k < 3; ++k) out.at(x, y, k) = uint8_t(std::lround(255 * v * wheel[s * 3 + k]));
      out.at(x, y, 3) = 255;
    }
  }
  return out;
}

namespace {

// Matplotlib's viridis at 9 stops, reversed (near = bright).
constexpr std::array<std::array<double, 3>, 9> kViridis = {{{253, 231, 37},
                                                            {170, 220, 50},
                                                            {94, 201, 98},
                                                            {39, 173, 129},
                                                            {33, 145, 140},
                                                            {44, 114, 142},
                                                            {59, 82, 139},
                                                            {72, 40, 120},
                                                            {68, 1, 84}}};

}  // namespace

ImageU8 ColourDepth(const ImageF& range, double near_m, double far_m) {
  ImageU8 out(range.width, range.height, 3);
  const double l0 = std::log(near_m), l1 = std::log(far_m);
  for (int y = 0; y < range.height; ++y) {
    for (int x = 0; x < range.width; ++x) {
      const double r = range.at(x, y);
      if (!(r > 0) || !std::isfinite(r)) continue;
      const double t = std::clamp((std::log(r) - l0) / (l1 - l0), 0.0, 1.0) * (kViridis.size() - 1);
      const int i = std::min(int(t), int(kViridis.size()) - 2);
      const double f = t - i;
      for (int k = 0; k < 3; ++k) out.at(x, y, k) = uint8_t(std::lround((1 - f) * kViridis[i][k] + f * kViridis[i + 1][k]));
    }
  }
  return out;
}

std::vector<uint16_t> QuantiseRanges(const ImageF& range) {
  std::vector<uint16_t> q(size_t(range.width) * range.height, 0);
  const double l0 = std::log(kRangeMin), span = std::log(kRangeMax) - l0;
  for (int y = 0; y < range.height; ++y) {
    for (int x = 0; x < range.width; ++x) {
      const double r = range.at(x, y);
      if (!(r > 0) || !std::isfinite(r)) continue;
      const double t = std::clamp((std::log(r) - l0) / span, 0.0, 1.0);
      q[size_t(y) * range.width + x] = uint16_t(1 + std::lround(t * 65534));
    }
  }
  return q;
}

double DequantiseRange(uint16_t q) {
  if (q == 0) return 0.0;
  const double l0 = std::log(kRangeMin), span = std::log(kRangeMax) - l0;
  return std::exp(l0 + (q - 1) / 65534.0 * span);
}

}  // namespace rigsim
