#include "renderer/sensor_model.h"

#include <algorithm>
#include <cmath>
#include <stdexcept>
#include <string>
#include <tuple>
#include <utility>
#include <vector>

#include <gmock/gmock.h>
#include <gtest/gtest.h>

#include "renderer/srgb.h"
#include "testing/expect_error.h"

namespace rigsim {
namespace {

double NormalCdf(double z) { return 0.5 * std::erfc(-z / std::sqrt(2.0)); }

// The model's prediction of the decoded (linear) mean and variance of a flat image at linear level
// `level`: Normal(level, a level + b) rounded to the nearest sRGB code (SrgbEncodeTables' thresholds)
// and clipped to [0, 1], summed code by code.
std::pair<double, double> PredictedMeanAndVariance(double level, double a, double read_stddev) {
  const double sigma = std::sqrt(a * level + read_stddev * read_stddev);
  const SrgbEncodeTables& t = SrgbEncodeTables::Get();
  double mean = 0, second = 0, below = 0.0;
  for (int code = 0; code < 256; ++code) {
    const double upper = code == 255 ? 1.0 : NormalCdf((double(t.thresholds[code]) - level) / sigma);
    const double p = upper - below;
    below = upper;
    const double v = LinearFromSrgbCode(uint8_t(code));
    mean += p * v;
    second += p * v * v;
  }
  return {mean, second - mean * mean};
}

// A varied RGB image: smooth shading, an edge and fine texture, like a rendered street.
ImageU8 StreetLike(int w, int h) {
  ImageU8 img(w, h, 3);
  for (int y = 0; y < h; ++y) {
    for (int x = 0; x < w; ++x) {
      for (int c = 0; c < 3; ++c) {
        const double v = 110 + 60 * std::sin(x / (6.0 + c)) * std::cos(y / 9.0) + (x > w / 2 ? 45 : -20) +
                         3 * ((x * 7 + y * 13 + c * 5) % 5 - 2);
        img.at(x, y, c) = uint8_t(std::clamp(v, 0.0, 255.0));
      }
    }
  }
  return img;
}

double Psnr(const ImageU8& a, const ImageU8& b) {
  double sum = 0;
  for (size_t i = 0; i < a.data.size(); ++i) sum += (double(a.data[i]) - b.data[i]) * (double(a.data[i]) - b.data[i]);
  return 10 * std::log10(255.0 * 255.0 / (sum / a.data.size()));
}

TEST(SensorModel, PresetsAreNamedIdealIsNothingAndNoiseComesFromTheDatasheet) {
  EXPECT_EQ(SensorPresetNames(), (std::vector<std::string>{"ideal", "machine-vision", "automotive", "phone"}));
  const SensorPreset& ideal = FindSensorPreset("ideal");
  EXPECT_FALSE(ideal.photometric.enabled());
  EXPECT_FALSE(ideal.defocus.enabled());
  EXPECT_EQ(ideal.jpeg_quality, 0);
  for (const SensorPreset& p : SensorPresets()) {
    EXPECT_NO_THROW(p.photometric.Check()) << p.name;
    EXPECT_NO_THROW(p.defocus.Check()) << p.name;
    EXPECT_FALSE(p.summary.empty());
    if (p.name == "ideal") continue;
    EXPECT_TRUE(p.photometric.enabled() && p.defocus.enabled()) << p.name;
    // a = g / full well, read = g * read electrons / full well.
    EXPECT_DOUBLE_EQ(p.photometric.shot_noise, p.analog_gain / p.full_well_electrons) << p.name;
    EXPECT_DOUBLE_EQ(p.photometric.read_noise_stddev, p.analog_gain * p.read_noise_electrons / p.full_well_electrons);
  }
  // The datasheet figures that are not estimates.
  const SensorPreset& mv = FindSensorPreset("machine-vision");
  EXPECT_EQ(mv.full_well_electrons, 32691);
  EXPECT_EQ(mv.read_noise_electrons, 6.83);
  EXPECT_EQ(mv.jpeg_quality, 0);
  EXPECT_EQ(FindSensorPreset("automotive").jpeg_quality, 75);  // the DDAD photos' quantisation tables
}

TEST(SensorModel, UnknownPresetNamesThePresets) {
  EXPECT_THAT([] { FindSensorPreset("automotve"); },
              ThrowsWith<std::invalid_argument>("unknown sensor preset 'automotve' (did you mean 'automotive'?); the "
                                                "presets are: ideal, machine-vision, automotive, phone"));
  EXPECT_THROW(FindSensorPreset(""), std::invalid_argument);
}

// The noise model's statistics pinned: flat grey images at several levels through each noisy
// preset's noise have the mean and variance the model predicts (Gaussian of variance a I + b,
// rounded to sRGB codes), within 5 standard errors of 360,000 samples. machine-vision's noise is
// below a code step at these levels: its variance is mostly the rounding's.
TEST(SensorModel, NoiseMeanAndVariancePerLevelMatchTheModel) {
  for (const std::string name : {"machine-vision", "automotive", "phone"}) {
    const SensorPreset& preset = FindSensorPreset(name);
    CameraPhotometry p;  // gain 1, no vignetting: the noise alone
    p.shot_noise = preset.photometric.shot_noise;
    p.read_noise_stddev = preset.photometric.read_noise_stddev;
    for (int code : {40, 100, 160, 220}) {
      ImageU8 img(400, 300, 3, uint8_t(code));
      const double level = LinearFromSrgbCode(uint8_t(code));
      ApplyPhotometry(p, {11, 1, int(code)}, 199.5, 149.5, img);
      double sum = 0, sum_sq = 0;
      const double n = double(img.data.size());
      for (uint8_t v : img.data) {
        const double x = LinearFromSrgbCode(v);
        sum += x;
        sum_sq += x * x;
      }
      const double mean = sum / n, variance = sum_sq / n - mean * mean;
      const auto [expected_mean, expected_variance] =
          PredictedMeanAndVariance(level, p.shot_noise, p.read_noise_stddev);
      const double model_variance = p.shot_noise * level + p.read_noise_stddev * p.read_noise_stddev;
      EXPECT_NEAR(mean, expected_mean, 5 * std::sqrt(expected_variance / n)) << name << " code " << code;
      EXPECT_NEAR(variance, expected_variance, 5 * expected_variance * std::sqrt(2 / n)) << name << " code " << code;
      // Rounding to codes adds little to the model's variance at these levels.
      if (name != "machine-vision") EXPECT_NEAR(expected_variance / model_variance, 1.0, 0.15) << name << " code " << code;
    }
  }
}

// JPEG at quality q: other bytes, the same on every run, and a PSNR within 2 dB of what libjpeg-turbo
// gives this image (31.9, 34.9 and 41.0 dB at 30, 75 and 95).
TEST(SensorModel, JpegChangesBytesDeterministicallyWithinAPsnrBand) {
  const ImageU8 source = StreetLike(160, 96);
  double previous_psnr = 0;
  for (const auto& [quality, min_psnr, max_psnr] : {std::tuple{30, 30.0, 34.0}, {75, 33.0, 37.0}, {95, 39.0, 43.0}}) {
    ImageU8 once = source, twice = source;
    JpegRoundTrip(once, quality);
    JpegRoundTrip(twice, quality);
    EXPECT_EQ(once.data, twice.data) << "same bytes in, same bytes out";
    EXPECT_NE(once.data, source.data);
    const double psnr = Psnr(source, once);
    EXPECT_GT(psnr, min_psnr) << quality;
    EXPECT_LT(psnr, max_psnr) << quality;
    EXPECT_GT(psnr, previous_psnr) << "higher quality, closer to the source";
    previous_psnr = psnr;
  }
  // Pixels outside the lens stay black.
  ImageU8 img = source;
  ImageU8 invalid(160, 96, 1, 0);
  for (int x = 0; x < 160; ++x) invalid.at(x, 5) = 1;
  for (int x = 0; x < 160; ++x) img.at(x, 5, 0) = img.at(x, 5, 1) = img.at(x, 5, 2) = 0;
  JpegRoundTrip(img, 50, &invalid);
  for (int x = 0; x < 160; ++x) EXPECT_EQ(img.at(x, 5, 0) + img.at(x, 5, 1) + img.at(x, 5, 2), 0);
  EXPECT_THROW(JpegRoundTrip(img, 0), std::invalid_argument);
  EXPECT_THROW(JpegRoundTrip(img, 101), std::invalid_argument);
}

// Everything off leaves the bytes; the photometric stage alone is ApplyPhotometry's bytes; with
// defocus, photometry -> defocus -> noise -> JPEG in that order.
TEST(SensorModel, StagesRunInOrderAndOffChangesNothing) {
  const ImageU8 source = StreetLike(64, 48);
  const ImageF range(64, 48, 1, 4.0f);
  ImageU8 img = source;
  ApplySensorStages({}, 50, 31.5, 23.5, range, img);
  EXPECT_EQ(img.data, source.data);

  const SensorPreset& preset = FindSensorPreset("automotive");
  PhotometricOptions o = preset.photometric;
  o.seed = 5;
  SensorStages stages;
  stages.photometric = true;
  stages.photometry = DrawCameraPhotometry(o, 1);
  stages.noise_key = {5, 1, 0};
  ImageU8 staged = source, direct = source;
  ApplySensorStages(stages, 50, 31.5, 23.5, range, staged);
  ApplyPhotometry(stages.photometry, stages.noise_key, 31.5, 23.5, direct);
  EXPECT_EQ(staged.data, direct.data);

  stages.defocus = preset.defocus;
  stages.defocus.pixel_pitch_um = 100;  // f = 5 mm on this small camera: 3.4 px blur circles at 4 m
  stages.defocus.focus_distance_m = 0.05;
  stages.jpeg_quality = preset.jpeg_quality;
  staged = source;
  ApplySensorStages(stages, 50, 31.5, 23.5, range, staged, nullptr, 1);
  ImageF linear = LinearBeforeNoise(stages.photometry, 31.5, 23.5, source);
  ApplyDefocus(stages.defocus, 50, range, linear);
  direct = source;
  AddNoiseAndEncode(stages.photometry, stages.noise_key, linear, direct);
  JpegRoundTrip(direct, stages.jpeg_quality);
  EXPECT_EQ(staged.data, direct.data);
}

}  // namespace
}  // namespace rigsim
