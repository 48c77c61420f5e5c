#include "renderer/sensor_model.h"

#include <stdexcept>
#include <string>
#include <vector>

#include "common/did_you_mean.h"
#include "dataset/image_codecs.h"

namespace rigsim {
namespace {

// A preset from its datasheet figures; the sources and which values are estimates are in
// docs/scenes-and-rigs.md ("Sensor presets").
SensorPreset Make(std::string name, std::string summary, double full_well_e, double read_noise_e, double gain,
                  double exposure_sigma, double white_balance_sigma, double vignetting, double f_number,
                  double focus_distance_m, double pixel_pitch_um, int jpeg_quality) {
  SensorPreset p;
  p.name = std::move(name);
  p.summary = std::move(summary);
  p.full_well_electrons = full_well_e;
  p.read_noise_electrons = read_noise_e;
  p.analog_gain = gain;
  p.photometric.exposure_stops_sigma = exposure_sigma;
  p.photometric.white_balance_stops_sigma = white_balance_sigma;
  p.photometric.vignetting_strength = vignetting;
  p.photometric.shot_noise = SensorPreset::ShotNoise(full_well_e, gain);
  p.photometric.read_noise_stddev = SensorPreset::ReadNoise(read_noise_e, full_well_e, gain);
  p.defocus.f_number = f_number;
  p.defocus.focus_distance_m = focus_distance_m;
  p.defocus.pixel_pitch_um = pixel_pitch_um;
  p.jpeg_quality = jpeg_quality;
  return p;
}

std::vector<SensorPreset> MakePresets() {
  SensorPreset ideal;
  ideal.name = "ideal";
  ideal.summary = "no sensor: the rendered radiance as 8-bit sRGB, nothing added (the default)";
  return {
      ideal,
      // Sony IMX174 (5.86 um global shutter), EMVA 1288 at 0 dB: 32,691 e- saturation, 6.83 e- dark
      // noise. Raw 8-bit frames, no JPEG; a C-mount lens at f/4 focused at 2 m.
      Make("machine-vision", "global-shutter machine-vision camera, Sony IMX174 class (5.86 um pixels), raw frames",
           32691, 6.83, 1.0, 0.1, 0.05, 0.2, 4.0, 2.0, 5.86, 0),
      // 3.0 um automotive HDR sensors (onsemi AR0231AT, Sony IMX390 class): full well per linear
      // exposure and read noise estimated; gain 2 for the short exposures of a moving car; a fast
      // fixed-focus lens at f/1.6 near its hyperfocal distance; JPEG quality 75 as the DDAD photos.
      Make("automotive", "automotive surround camera, onsemi AR0231 / Sony IMX390 class (3.0 um), JPEG 75 as DDAD",
           10000, 3.0, 2.0, 0.3, 0.1, 0.35, 1.6, 1.5, 3.0, 75),
      // Sony IMX586 (0.8 um quad Bayer, 1.6 um binned in its 12 MP mode): full well and read noise
      // estimated; the lens-shading correction leaves about a quarter of the corner loss; f/1.8
      // focused at 2 m; JPEG 90.
      Make("phone", "phone main camera, Sony IMX586 class (0.8 um, 1.6 um binned), JPEG 90", 2400, 2.0, 1.0, 0.2, 0.1,
           0.25, 1.8, 2.0, 1.6, 90),
  };
}

}  // namespace

double SensorPreset::ShotNoise(double full_well_electrons, double analog_gain) {
  return full_well_electrons > 0 ? analog_gain / full_well_electrons : 0.0;
}

double SensorPreset::ReadNoise(double read_noise_electrons, double full_well_electrons, double analog_gain) {
  return full_well_electrons > 0 ? analog_gain * read_noise_electrons / full_well_electrons : 0.0;
}

const std::vector<SensorPreset>& SensorPresets() {
  static const std::vector<SensorPreset> presets = MakePresets();
  return presets;
}

std::vector<std::string> SensorPresetNames() {
  std::vector<std::string> names;
  for (const SensorPreset& p : SensorPresets()) names.push_back(p.name);
  return names;
}

const SensorPreset& FindSensorPreset(const std::string& name) {
  for (const SensorPreset& p : SensorPresets()) {
    if (p.name == name) return p;
  }
  std::string list;
  for (const std::string& n : SensorPresetNames()) list += (list.empty() ? "" : ", ") + n;
  throw std::invalid_argument("unknown sensor preset '" + name + "'" + DidYouMean(name, SensorPresetNames()) +
                              "; the presets are: " + list);
}

void JpegRoundTrip(ImageU8& rgb, int quality, const ImageU8* invalid) {
  if (quality < 1 || quality > 100) {
    throw std::invalid_argument("JPEG quality " + std::to_string(quality) + " must be in 1..100");
  }
  if (rgb.channels != 3 || rgb.data.size() != size_t(rgb.width) * rgb.height * 3) {
    throw std::invalid_argument("JpegRoundTrip: the image must have 3 channels");
  }
  if (invalid && (invalid->width != rgb.width || invalid->height != rgb.height || invalid->channels != 1)) {
    throw std::invalid_argument("JpegRoundTrip: the invalid-pixel mask must be 1 channel of the image's size");
  }
  JpegSettings settings;
  settings.quality = quality;
  const std::vector<uint8_t> bytes = EncodeJpeg(rgb.data.data(), rgb.width, rgb.height, 3, settings, "JPEG round trip");
  DecodedPixels decoded = DecodeImageBytes(bytes.data(), bytes.size(), "JPEG round trip", {});
  if (decoded.width != rgb.width || decoded.height != rgb.height || decoded.channels != 3 ||
      decoded.type != DecodedPixels::Type::kU8) {
    throw std::runtime_error("JPEG round trip: the decoded image is not the encoded one's size");
  }
  rgb.data = std::move(decoded.u8);
  if (invalid) {
    for (size_t i = 0; i < invalid->data.size(); ++i) {
      if (invalid->data[i] != 0) rgb.data[3 * i] = rgb.data[3 * i + 1] = rgb.data[3 * i + 2] = 0;
    }
  }
}

void ApplySensorStages(const SensorStages& s, double fx_px, double cx, double cy, const ImageF& range, ImageU8& rgb,
                       const ImageU8* invalid, int num_threads) {
  if (s.defocus.enabled()) {
    ImageF linear = LinearBeforeNoise(s.photometry, cx, cy, rgb, invalid, num_threads);
    ApplyDefocus(s.defocus, fx_px, range, linear, invalid, num_threads);
    AddNoiseAndEncode(s.photometry, s.noise_key, linear, rgb, invalid, num_threads);
  } else if (s.photometric) {
    ApplyPhotometry(s.photometry, s.noise_key, cx, cy, rgb, invalid, num_threads);
  }
  if (s.jpeg_quality > 0) JpegRoundTrip(rgb, s.jpeg_quality, invalid);
}

}  // namespace rigsim
