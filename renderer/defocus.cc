#include "renderer/defocus.h"

#include <algorithm>
#include <cmath>
#include <cstdint>
#include <stdexcept>
#include <string>
#include <vector>

#include <tbb/blocked_range.h>
#include <tbb/parallel_for.h>
#include <tbb/task_arena.h>

namespace rigsim {
namespace {

// Radii are quantised to 1/64 px so that each disc's area is an exact table entry: a flat image at
// one depth keeps its value exactly.
constexpr int kRadiusSteps = 64;

void Refuse(const std::string& name, double value, const std::string& range) {
  throw std::invalid_argument("defocus options: " + name + " = " + std::to_string(value) + " must be " + range);
}

// Coverage of the pixel at distance `dist` by a disc of radius `r`, its edge anti-aliased over a pixel.
inline float Coverage(float dist, float r) { return std::clamp(r + 0.5f - dist, 0.0f, 1.0f); }

}  // namespace

void DefocusOptions::Check() const {
  if (!std::isfinite(f_number) || f_number < 0.0 || (f_number > 0.0 && (f_number < 0.5 || f_number > 64.0))) {
    Refuse("f_number", f_number, "0 (a pinhole) or in [0.5, 64]");
  }
  if (enabled() && (!std::isfinite(focus_distance_m) || focus_distance_m <= 0.0)) {
    Refuse("focus_distance_m", focus_distance_m, "above 0 (metres)");
  }
  if (!std::isfinite(pixel_pitch_um) || pixel_pitch_um <= 0.0 || pixel_pitch_um > 100.0) {
    Refuse("pixel_pitch_um", pixel_pitch_um, "in (0, 100] (micrometres)");
  }
  if (!std::isfinite(max_radius_px) || max_radius_px < 1.0 || max_radius_px > 64.0) {
    Refuse("max_radius_px", max_radius_px, "in [1, 64] (pixels)");
  }
}

double BlurCircleDiameterPx(const DefocusOptions& o, double fx_px, double distance_m) {
  if (!o.enabled()) return 0.0;
  const double f = fx_px * o.pixel_pitch_um * 1e-6;
  const double s = o.focus_distance_m;
  if (!(s > f)) {
    throw std::invalid_argument("defocus: the focus distance " + std::to_string(s) + " m must be beyond the focal length " +
                                std::to_string(f) + " m (fx " + std::to_string(fx_px) + " px x pixel pitch " +
                                std::to_string(o.pixel_pitch_um) + " um)");
  }
  const double at_infinity = fx_px * (f / o.f_number) / (s - f);
  if (!(distance_m > 0.0) || !std::isfinite(distance_m)) return at_infinity;
  return at_infinity * std::abs(distance_m - s) / distance_m;
}

ImageF AxialDistance(const PixelCentreRays& rays, const ImageF& range) {
  if (range.channels != 1 || rays.width != range.width || rays.bearings.size() != range.data.size()) {
    throw std::invalid_argument("AxialDistance: the rays and the range image must be of one camera");
  }
  ImageF out = range;
  for (size_t i = 0; i < out.data.size(); ++i) {
    const float z = rays.bearings[i].z();
    if (rays.valid[i] && z > 0.0f) out.data[i] *= z;
  }
  return out;
}

void ApplyDefocus(const DefocusOptions& o, double fx_px, const ImageF& range, ImageF& linear, const ImageU8* invalid,
                  int num_threads) {
  o.Check();
  if (!o.enabled()) return;
  const int w = linear.width, h = linear.height;
  if (linear.channels != 3 || range.width != w || range.height != h || range.channels != 1) {
    throw std::invalid_argument("ApplyDefocus: the image must have 3 channels and the range image 1 of the same size");
  }
  if (invalid && (invalid->width != w || invalid->height != h || invalid->channels != 1)) {
    throw std::invalid_argument("ApplyDefocus: the invalid-pixel mask must be 1 channel of the image's size");
  }
  // Each pixel's quantised radius and its distance (no surface: infinitely far).
  const int max_step = int(std::lround(o.max_radius_px * kRadiusSteps));
  std::vector<uint16_t> radius(size_t(w) * h, 0);
  std::vector<float> distance(size_t(w) * h);
  int largest = 0;
  for (size_t i = 0; i < radius.size(); ++i) {
    const float d = range.data[i];
    distance[i] = d > 0.0f && std::isfinite(d) ? d : INFINITY;
    if (invalid && invalid->data[i] != 0) continue;
    const double r = BlurCircleDiameterPx(o, fx_px, d) / 2;
    radius[i] = uint16_t(std::min<long>(max_step, std::lround(r * kRadiusSteps)));
    largest = std::max<int>(largest, radius[i]);
  }
  // Blur circles under one pixel across (radius < 0.5) cover only their own pixel.
  if (largest < kRadiusSteps / 2) return;
  const int reach = int(std::ceil(float(largest) / kRadiusSteps + 0.5f));
  struct Offset {
    int dx, dy;
    float dist;
  };
  std::vector<Offset> offsets;
  for (int dy = -reach; dy <= reach; ++dy) {
    for (int dx = -reach; dx <= reach; ++dx) offsets.push_back({dx, dy, std::sqrt(float(dx * dx + dy * dy))});
  }
  // 1 / (a disc's area) = 1 / (sum of its coverage over the pixel grid), per quantised radius.
  std::vector<float> inverse_area(size_t(largest) + 1);
  for (int step = 0; step <= largest; ++step) {
    double area = 0.0;
    for (const Offset& off : offsets) area += Coverage(off.dist, float(step) / kRadiusSteps);
    inverse_area[step] = float(1.0 / area);
  }

  const ImageF source = linear;
  auto rows = [&](const tbb::blocked_range<int>& band) {
    for (int y = band.begin(); y < band.end(); ++y) {
      for (int x = 0; x < w; ++x) {
        const size_t p = size_t(y) * w + x;
        if (invalid && invalid->data[p] != 0) continue;
        const float distance_p = distance[p];
        const uint16_t radius_p = radius[p];
        double sum[3] = {0.0, 0.0, 0.0}, weight = 0.0;
        for (const Offset& off : offsets) {
          const int qx = x + off.dx, qy = y + off.dy;
          if (qx < 0 || qy < 0 || qx >= w || qy >= h) continue;
          const size_t q = size_t(qy) * w + qx;
          if (invalid && invalid->data[q] != 0) continue;
          // Behind p: spreads over p with at most p's radius (depth test).
          const uint16_t r = distance[q] > distance_p ? std::min(radius[q], radius_p) : radius[q];
          const float cover = Coverage(off.dist, float(r) / kRadiusSteps);
          if (cover <= 0.0f) continue;
          const double wq = double(cover) * inverse_area[r];
          const float* c = &source.data[q * 3];
          sum[0] += wq * c[0];
          sum[1] += wq * c[1];
          sum[2] += wq * c[2];
          weight += wq;
        }
        float* out = &linear.data[p * 3];
        for (int c = 0; c < 3; ++c) out[c] = float(sum[c] / weight);
      }
    }
  };
  tbb::task_arena arena(num_threads > 0 ? num_threads : tbb::task_arena::automatic);
  arena.execute([&] { tbb::parallel_for(tbb::blocked_range<int>(0, h, 8), rows); });
}

}  // namespace rigsim
