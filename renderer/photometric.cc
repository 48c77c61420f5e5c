#include "renderer/photometric.h"

#include <algorithm>
#include <array>
#include <cmath>
#include <limits>
#include <numbers>
#include <stdexcept>
#include <string>
#include <tuple>
#include <utility>

#include <tbb/blocked_range.h>
#include <tbb/parallel_for.h>
#include <tbb/task_arena.h>

#include "common/splitmix64.h"
#include "renderer/srgb.h"

namespace rigsim {
namespace {

// Streams keep the per-camera draws and the noise independent of each other.
enum Stream : uint64_t { kExposure = 1, kWhiteRed = 2, kWhiteBlue = 3, kNoise = 4 };

// Two independent standard normal variates from 64 hashed bits (Box-Muller on two 32-bit uniforms).
std::pair<double, double> GaussianPair(uint64_t bits) {
  const double u1 = (double(bits >> 32) + 0.5) / 4294967296.0;    // (0, 1): log is finite
  const double u2 = double(bits & 0xFFFFFFFFull) / 4294967296.0;  // [0, 1)
  const double radius = std::sqrt(-2.0 * std::log(u1)), angle = 2.0 * std::numbers::pi * u2;
  return {radius * std::cos(angle), radius * std::sin(angle)};
}

double Gaussian(uint64_t bits) { return GaussianPair(bits).first; }

uint64_t CameraKey(uint64_t seed, int camera_index, uint64_t stream) {
  return SplitMix64(SplitMix64(SplitMix64(seed) ^ uint64_t(uint32_t(camera_index))) ^ stream);
}


void CheckRange(double value, double max, bool max_inclusive, const std::string& name, const std::string& unit) {
  if (!std::isfinite(value) || value < 0.0 || (max_inclusive ? value > max : value >= max)) {
    throw std::invalid_argument("photometric options: " + name + " = " + std::to_string(value) + " must be in [0, " +
                                std::to_string(max) + (max_inclusive ? "]" : ")") + unit);
  }
}

}  // namespace

PhotometricOptions PhotometricOptions::Defaults() {
  PhotometricOptions o;
  o.exposure_stops_sigma = 0.3;
  o.white_balance_stops_sigma = 0.1;
  o.vignetting_strength = 0.3;
  o.shot_noise = 1e-4;         // ~10^4 electrons at white
  o.read_noise_stddev = 0.002;
  return o;
}

bool PhotometricOptions::enabled() const {
  return exposure_stops_sigma != 0.0 || white_balance_stops_sigma != 0.0 || vignetting_strength != 0.0 ||
         shot_noise != 0.0 || read_noise_stddev != 0.0;
}

void PhotometricOptions::Check() const {
  CheckRange(exposure_stops_sigma, 3.0, true, "exposure_stops_sigma", " stops");
  CheckRange(white_balance_stops_sigma, 1.0, true, "white_balance_stops_sigma", " stops");
  CheckRange(vignetting_strength, 1.0, false, "vignetting_strength", " (fraction of light lost at the farthest corner)");
  CheckRange(shot_noise, 0.1, true, "shot_noise", " (variance per unit linear intensity)");
  CheckRange(read_noise_stddev, 0.5, true, "read_noise_stddev", " (linear, 1 = white)");
}

double CameraPhotometry::gain() const { return std::exp2(exposure_stops); }

double CameraPhotometry::Vignetting(double r) const {
  if (vignetting_strength <= 0.0) return 1.0;
  const double k = 1.0 / std::sqrt(1.0 - vignetting_strength) - 1.0;  // V(1) = 1 - strength
  const double d = 1.0 + k * r * r;
  return 1.0 / (d * d);
}

CameraPhotometry DrawCameraPhotometry(const PhotometricOptions& o, int camera_index) {
  o.Check();
  CameraPhotometry p;
  p.exposure_stops = o.exposure_stops_sigma * Gaussian(CameraKey(o.seed, camera_index, kExposure));
  p.white_balance = Eigen::Vector3d(std::exp2(o.white_balance_stops_sigma * Gaussian(CameraKey(o.seed, camera_index, kWhiteRed))), 1.0,
                                    std::exp2(o.white_balance_stops_sigma * Gaussian(CameraKey(o.seed, camera_index, kWhiteBlue))));
  p.vignetting_strength = o.vignetting_strength;
  p.shot_noise = o.shot_noise;
  p.read_noise_stddev = o.read_noise_stddev;
  return p;
}

namespace {

void CheckSizes(const char* what, const ImageU8& rgb, const ImageU8* invalid) {
  if (rgb.channels != 3 || rgb.data.size() != size_t(rgb.width) * rgb.height * 3) {
    throw std::invalid_argument(std::string(what) + ": the image must have 3 channels");
  }
  if (invalid && (invalid->width != rgb.width || invalid->height != rgb.height || invalid->channels != 1)) {
    throw std::invalid_argument(std::string(what) + ": the invalid-pixel mask must be 1 channel of the image's size");
  }
}

// The vignetting at every pixel, V(r) = 1 / (1 + k r^2)^2 (CameraPhotometry::Vignetting), evaluated
// from r^2 directly, r normalised by the farthest image corner from the principal point.
class VignettingField {
 public:
  VignettingField(const CameraPhotometry& p, int width, int height, double cx, double cy) : cx_(cx), cy_(cy) {
    double max_r2 = 0.0;
    for (double x : {-0.5, width - 0.5}) {
      for (double y : {-0.5, height - 0.5}) max_r2 = std::max(max_r2, (x - cx) * (x - cx) + (y - cy) * (y - cy));
    }
    inv_max_r2_ = max_r2 > 0 ? 1.0 / max_r2 : 0.0;
    k_ = p.vignetting_strength > 0 ? 1.0 / std::sqrt(1.0 - p.vignetting_strength) - 1.0 : 0.0;
  }
  double operator()(int x, int y) const {
    const double d = 1.0 + k_ * ((x - cx_) * (x - cx_) + (y - cy_) * (y - cy_)) * inv_max_r2_;
    return 1.0 / (d * d);
  }

 private:
  double cx_, cy_, inv_max_r2_ = 0.0, k_ = 0.0;
};

// Adds the noise to the noise-free linear value `linear(x, y, c)` of every valid pixel and writes
// its sRGB code into `rgb`, in parallel over rows (the noise is keyed by pixel, not by thread).
template <class Linear>
void NoiseAndEncode(const CameraPhotometry& p, const PhotometricNoiseKey& key, ImageU8& rgb, const ImageU8* invalid,
                    int num_threads, const Linear& linear) {
  const bool noisy = p.shot_noise > 0.0 || p.read_noise_stddev > 0.0;
  const double read_var = p.read_noise_stddev * p.read_noise_stddev;
  const uint64_t frame_key = SplitMix64(SplitMix64(SplitMix64(SplitMix64(key.seed) ^ uint64_t(uint32_t(key.camera_index))) ^ uint64_t(uint32_t(key.frame_index))) ^ kNoise);
  auto rows = [&](const tbb::blocked_range<int>& range) {
    for (int y = range.begin(); y < range.end(); ++y) {
      for (int x = 0; x < rgb.width; ++x) {
        if (invalid && invalid->at(x, y) != 0) continue;
        // Three normals per pixel: both of one Box-Muller pair and one of a second.
        double z[3] = {0.0, 0.0, 0.0};
        if (noisy) {
          const uint64_t pixel = uint64_t(y) * rgb.width + x;
          std::tie(z[0], z[1]) = GaussianPair(SplitMix64(frame_key ^ (2 * pixel)));
          z[2] = Gaussian(SplitMix64(frame_key ^ (2 * pixel + 1)));
        }
        uint8_t* px = &rgb.at(x, y, 0);
        const Eigen::Vector3d values = linear(x, y, px);
        for (int c = 0; c < 3; ++c) {
          double value = values[c];
          if (noisy) value += std::sqrt(p.shot_noise * std::max(value, 0.0) + read_var) * z[c];
          px[c] = SrgbCodeFromLinear(value);
        }
      }
    }
  };
  tbb::task_arena arena(num_threads > 0 ? num_threads : tbb::task_arena::automatic);
  arena.execute([&] { tbb::parallel_for(tbb::blocked_range<int>(0, rgb.height, 8), rows); });
}

}  // namespace

void ApplyPhotometry(const CameraPhotometry& p, const PhotometricNoiseKey& key, double cx, double cy, ImageU8& rgb,
                     const ImageU8* invalid, int num_threads) {
  CheckSizes("ApplyPhotometry", rgb, invalid);
  const VignettingField vignetting(p, rgb.width, rgb.height, cx, cy);
  const Eigen::Vector3d channel_gain = p.gain() * p.white_balance;
  const std::array<float, 256>& decode = LinearFromSrgbCodeTable();
  NoiseAndEncode(p, key, rgb, invalid, num_threads, [&](int x, int y, const uint8_t* px) {
    const double v = vignetting(x, y);
    return Eigen::Vector3d(decode[px[0]] * channel_gain[0] * v, decode[px[1]] * channel_gain[1] * v,
                           decode[px[2]] * channel_gain[2] * v);
  });
}

ImageF LinearBeforeNoise(const CameraPhotometry& p, double cx, double cy, const ImageU8& rgb, const ImageU8* invalid,
                         int num_threads) {
  CheckSizes("LinearBeforeNoise", rgb, invalid);
  const VignettingField vignetting(p, rgb.width, rgb.height, cx, cy);
  const Eigen::Vector3d channel_gain = p.gain() * p.white_balance;
  const std::array<float, 256>& decode = LinearFromSrgbCodeTable();
  ImageF linear(rgb.width, rgb.height, 3, 0.0f);
  auto rows = [&](const tbb::blocked_range<int>& range) {
    for (int y = range.begin(); y < range.end(); ++y) {
      for (int x = 0; x < rgb.width; ++x) {
        if (invalid && invalid->at(x, y) != 0) continue;
        const double v = vignetting(x, y);
        for (int c = 0; c < 3; ++c) linear.at(x, y, c) = float(decode[rgb.at(x, y, c)] * channel_gain[c] * v);
      }
    }
  };
  tbb::task_arena arena(num_threads > 0 ? num_threads : tbb::task_arena::automatic);
  arena.execute([&] { tbb::parallel_for(tbb::blocked_range<int>(0, rgb.height, 8), rows); });
  return linear;
}

void AddNoiseAndEncode(const CameraPhotometry& p, const PhotometricNoiseKey& key, const ImageF& linear, ImageU8& rgb,
                       const ImageU8* invalid, int num_threads) {
  CheckSizes("AddNoiseAndEncode", rgb, invalid);
  if (linear.width != rgb.width || linear.height != rgb.height || linear.channels != 3) {
    throw std::invalid_argument("AddNoiseAndEncode: the linear image must have 3 channels of the image's size");
  }
  NoiseAndEncode(p, key, rgb, invalid, num_threads,
                 [&](int x, int y, const uint8_t*) {
                   return Eigen::Vector3d(linear.at(x, y, 0), linear.at(x, y, 1), linear.at(x, y, 2));
                 });
}

}  // namespace rigsim
