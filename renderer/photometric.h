// Photometric differences between the cameras of a rig, as real rigs have them: exposure, white
// balance, vignetting and sensor noise, applied to rendered RGB only (labels, instances and depth
// stay exact ground truth). Off unless asked for: default options change nothing.
//
// Model, in linear light (the 8-bit sRGB image is decoded, changed, and re-encoded with rounding):
//   out_c = gain * wb_c * V(r) * in_c  +  n,   n ~ Normal(0, a * I + b)   (per channel, clipped to [0, 1])
//   - gain = 2^exposure_stops, exposure_stops ~ Normal(0, exposure_stops_sigma) per camera;
//   - wb = (2^s_r, 1, 2^s_b), s_r, s_b ~ Normal(0, white_balance_stops_sigma) per camera (green is
//     the reference, as in a camera's white-balance gains);
//   - V(r) = 1 / (1 + k r^2)^2, the cos^4 law's shape, with r the distance from the principal point
//     divided by the distance to the farthest image corner and k chosen so that V(1) = 1 -
//     vignetting_strength (the fraction of light lost at that corner);
//   - I = the channel's noise-free value (the line above without n); a = shot_noise (variance per
//     unit intensity: the Poisson part, about 1 / full-well electrons when 1 = white), b =
//     read_noise_stddev^2: Poisson-Gaussian noise approximated by a Gaussian.
// Randomness only from the seed: per-camera parameters from (seed, camera index), noise from
// (seed, camera index, frame index, pixel, channel), so the bytes do not depend on thread count.
#pragma once

#include <cstdint>

#include <Eigen/Core>

#include "geometry/image.h"

namespace rigsim {

struct PhotometricOptions {
  double exposure_stops_sigma = 0.0;       // spread of per-camera exposure (stops); 0 = all equal
  double white_balance_stops_sigma = 0.0;  // spread of per-camera red and blue gains (stops)
  double vignetting_strength = 0.0;        // fraction of light lost at the farthest corner, [0, 1)
  double shot_noise = 0.0;                 // a: noise variance per unit linear intensity
  double read_noise_stddev = 0.0;          // sqrt(b): signal-independent noise (linear, 1 = white)
  uint64_t seed = 0;

  // Magnitudes `rigsim render --photometric` uses: visible but plausible differences.
  static PhotometricOptions Defaults();
  // False when every magnitude is 0: rendering then leaves the RGB bytes untouched.
  bool enabled() const;
  // Throws std::invalid_argument naming the field when a magnitude is negative, not finite or
  // out of its range (exposure <= 3 stops, white balance <= 1 stop, vignetting < 1, shot noise
  // <= 0.1, read noise <= 0.5).
  void Check() const;
};

// One camera's drawn parameters (what photometric.json records).
struct CameraPhotometry {
  double exposure_stops = 0.0;                                // gain = 2^exposure_stops
  Eigen::Vector3d white_balance = Eigen::Vector3d::Ones();    // R, G, B gains; G = 1
  double vignetting_strength = 0.0;
  double shot_noise = 0.0;
  double read_noise_stddev = 0.0;

  double gain() const;
  // Relative illumination at normalised radius r (0 at the principal point, 1 at the farthest corner).
  double Vignetting(double r) const;
};

// Deterministic in (options.seed, camera_index); identity parameters when options are off.
CameraPhotometry DrawCameraPhotometry(const PhotometricOptions& options, int camera_index);

// Which frame and camera an image is, for the noise: (seed, camera, frame) pick the noise field.
struct PhotometricNoiseKey {
  uint64_t seed = 0;
  int camera_index = 0;
  int frame_index = 0;
};

// Applies `params` to an sRGB-encoded 3-channel image in place. (cx, cy): the principal point in
// OpenCV pixels (vignetting centre). `invalid` (optional, 1 channel, same size): pixels marked
// non-zero are outside the lens's valid region and stay black. `num_threads`: 0 = all cores; the
// result does not depend on it. Throws std::invalid_argument on a size or channel mismatch.
void ApplyPhotometry(const CameraPhotometry& params, const PhotometricNoiseKey& key, double cx, double cy, ImageU8& rgb,
                     const ImageU8* invalid = nullptr, int num_threads = 0);

// ApplyPhotometry in two steps, for a stage between the optics and the noise (defocus,
// renderer/defocus.h): LinearBeforeNoise gives the noise-free linear values (3 floats per pixel:
// gain, white balance and vignetting applied; invalid pixels 0); AddNoiseAndEncode adds the same
// noise as ApplyPhotometry to them and writes the sRGB codes into `rgb` (invalid pixels left as
// they are). Together they give ApplyPhotometry's bytes up to the float rounding of the values.
ImageF LinearBeforeNoise(const CameraPhotometry& params, double cx, double cy, const ImageU8& rgb,
                         const ImageU8* invalid = nullptr, int num_threads = 0);
void AddNoiseAndEncode(const CameraPhotometry& params, const PhotometricNoiseKey& key, const ImageF& linear, ImageU8& rgb,
                       const ImageU8* invalid = nullptr, int num_threads = 0);

}  // namespace rigsim
