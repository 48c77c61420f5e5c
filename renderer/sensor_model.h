// The camera's sensor and lens as a named model: what happens to rendered RGB between the radiance
// and the image file, in the order a camera does it (labels, instances and depth stay exact):
//
//   exposure, white balance -> vignetting -> defocus -> shot + read noise -> 8-bit sRGB -> JPEG
//   (renderer/photometric.h)    (photometric.h) (defocus.h) (photometric.h)
//
// JPEG is a compress-decompress round trip at the preset's quality (libjpeg-turbo through
// dataset/image_codecs.h: baseline, 4:2:0, integer DCT): the dataset stays PNG, and what the
// calibrator sees are the JPEG's blocks and ringing. Pixels outside the lens's valid region stay black.
//
// A preset is a set of these values from a real camera class's datasheets (EMVA 1288 figures where
// published): docs/scenes-and-rigs.md ("Sensor presets") has the table, the sources and which
// values are estimates. The noise comes from the datasheet: a signal of I (linear, 1 = full well) holds I * full_well
// electrons, so at an analog gain g (white = full_well / g electrons)
//   shot_noise a = g / full_well,   read_noise_stddev = g * read_noise_electrons / full_well.
#pragma once

#include <string>
#include <vector>

#include "geometry/image.h"
#include "renderer/defocus.h"
#include "renderer/photometric.h"

namespace rigsim {

struct SensorPreset {
  std::string name;
  std::string summary;  // one line: the camera class it stands for
  // Datasheet figures the noise is derived from (0 for the ideal sensor).
  double full_well_electrons = 0.0;
  double read_noise_electrons = 0.0;
  double analog_gain = 1.0;
  PhotometricOptions photometric;  // seed 0: the caller sets the render's
  DefocusOptions defocus;
  int jpeg_quality = 0;  // 0: no JPEG

  // The shot and read noise of the datasheet figures (the formula above).
  static double ShotNoise(double full_well_electrons, double analog_gain);
  static double ReadNoise(double read_noise_electrons, double full_well_electrons, double analog_gain);
};

// ideal (the default: today's renders, nothing applied), machine-vision, automotive, phone.
const std::vector<SensorPreset>& SensorPresets();
std::vector<std::string> SensorPresetNames();
// Throws std::invalid_argument "unknown sensor preset 'x' (did you mean 'y'?); the presets are: ...".
const SensorPreset& FindSensorPreset(const std::string& name);

// A JPEG compress-decompress round trip of an RGB image at `quality` (1..100) in place; pixels
// marked in `invalid` (optional, 1 channel) are set back to black afterwards. Deterministic: the
// same bytes in, the same bytes out, whatever SIMD path libjpeg-turbo picks.
void JpegRoundTrip(ImageU8& rgb, int quality, const ImageU8* invalid = nullptr);

// Every sensor stage on one rendered view, in place: photometry (when `photometric`), defocus (when
// `defocus.enabled()`; `fx_px`, `cx`, `cy` the camera's, `range` its AxialDistance), noise, JPEG (when
// `jpeg_quality` > 0). With everything off the bytes are untouched; without defocus the photometry
// is ApplyPhotometry's, byte for byte.
struct SensorStages {
  bool photometric = false;
  CameraPhotometry photometry;
  PhotometricNoiseKey noise_key;
  DefocusOptions defocus;
  int jpeg_quality = 0;
};
void ApplySensorStages(const SensorStages& stages, double fx_px, double cx, double cy, const ImageF& range, ImageU8& rgb,
                       const ImageU8* invalid = nullptr, int num_threads = 0);

}  // namespace rigsim
