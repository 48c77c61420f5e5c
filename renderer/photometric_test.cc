#include "renderer/photometric.h"

#include <cmath>
#include <set>
#include <stdexcept>
#include <string>

#include <gmock/gmock.h>
#include <gtest/gtest.h>

#include "renderer/srgb.h"
#include "testing/expect_error.h"

namespace rigsim {
namespace {

// A flat image whose every channel has the sRGB code of `linear`.
ImageU8 Flat(int w, int h, double linear) { return ImageU8(w, h, 3, SrgbCodeFromLinear(linear)); }

// A varied image: every code appears.
ImageU8 Ramp(int w, int h) {
  ImageU8 img(w, h, 3);
  for (size_t i = 0; i < img.data.size(); ++i) img.data[i] = uint8_t((i * 7) % 256);
  return img;
}

TEST(Photometric, OffByDefaultAndIdentityLeavesBytesUnchanged) {
  const PhotometricOptions off;
  EXPECT_FALSE(off.enabled());
  EXPECT_TRUE(PhotometricOptions::Defaults().enabled());
  const CameraPhotometry p = DrawCameraPhotometry(off, 3);
  EXPECT_EQ(p.gain(), 1.0);
  EXPECT_EQ(p.white_balance, Eigen::Vector3d::Ones());
  EXPECT_EQ(p.Vignetting(1.0), 1.0);
  const ImageU8 before = Ramp(40, 30);
  ImageU8 img = before;
  ApplyPhotometry(p, {7, 3, 1}, 19.5, 14.5, img);
  EXPECT_EQ(img.data, before.data) << "identity parameters must not change a byte (decode/encode is exact)";
}

TEST(Photometric, SameSeedSameBytesWhateverTheThreadCountOtherSeedOtherBytes) {
  PhotometricOptions o = PhotometricOptions::Defaults();
  o.seed = 11;
  const ImageU8 source = Ramp(97, 61);
  auto run = [&](const PhotometricOptions& opt, int threads, int frame = 0) {
    ImageU8 img = source;
    ApplyPhotometry(DrawCameraPhotometry(opt, 2), {opt.seed, 2, frame}, 48, 30, img, nullptr, threads);
    return img.data;
  };
  const auto one = run(o, 1);
  EXPECT_EQ(one, run(o, 2));
  EXPECT_EQ(one, run(o, 0));
  EXPECT_NE(one, source.data);
  EXPECT_NE(one, run(o, 1, /*frame=*/1)) << "each frame gets its own noise";
  PhotometricOptions other = o;
  other.seed = 12;
  EXPECT_NE(one, run(other, 1));
}

TEST(Photometric, CamerasGetDifferentGainsFromTheSeed) {
  PhotometricOptions o;
  o.exposure_stops_sigma = 0.5;
  o.white_balance_stops_sigma = 0.2;
  o.seed = 5;
  std::set<double> gains, reds;
  double sum_sq = 0.0;
  const int n = 400;
  for (int c = 0; c < n; ++c) {
    const CameraPhotometry p = DrawCameraPhotometry(o, c);
    gains.insert(p.gain());
    reds.insert(p.white_balance.x());
    EXPECT_EQ(p.white_balance.y(), 1.0) << "green is the white-balance reference";
    EXPECT_NE(p.white_balance.x(), p.white_balance.z());
    sum_sq += p.exposure_stops * p.exposure_stops;
    // Deterministic in (seed, camera index).
    EXPECT_EQ(DrawCameraPhotometry(o, c).exposure_stops, p.exposure_stops);
  }
  EXPECT_EQ(gains.size(), size_t(n));
  EXPECT_EQ(reds.size(), size_t(n));
  // The draws have the requested spread (stops): 400 samples give the sigma within ~10%.
  EXPECT_NEAR(std::sqrt(sum_sq / n), 0.5, 0.06);

  // Applied: a flat grey camera image scales by gain * white balance per channel (no noise).
  const CameraPhotometry p = DrawCameraPhotometry(o, 1);
  ImageU8 img = Flat(8, 8, 0.2);
  ApplyPhotometry(p, {o.seed, 1, 0}, 3.5, 3.5, img);
  for (int c = 0; c < 3; ++c) {
    const double expected = std::min(1.0, LinearFromSrgbCode(SrgbCodeFromLinear(0.2)) * p.gain() * p.white_balance[c]);
    EXPECT_EQ(img.at(5, 2, c), SrgbCodeFromLinear(expected)) << c;
  }
}

TEST(Photometric, VignettingDarkensTheFarthestCornerByTheStrength) {
  CameraPhotometry p;
  p.vignetting_strength = 0.4;
  EXPECT_NEAR(p.Vignetting(0.0), 1.0, 1e-15);
  EXPECT_NEAR(p.Vignetting(1.0), 0.6, 1e-12);
  // cos^4 shape: V(r) = cos^4(atan(r * t)) with tan^2 of the corner angle t^2 = k.
  const double k = 1.0 / std::sqrt(0.6) - 1.0;
  EXPECT_NEAR(p.Vignetting(0.5), std::pow(std::cos(std::atan(0.5 * std::sqrt(k))), 4), 1e-12);

  // A flat image with the principal point at the centre of a 201 x 101 image: the centre pixel
  // keeps its value; the corner pixels (0.5 px inside the image corner) lose ~40%.
  const int w = 201, h = 101;
  const double cx = 100, cy = 50;
  ImageU8 img = Flat(w, h, 0.5);
  const double in = LinearFromSrgbCode(img.at(0, 0));
  ApplyPhotometry(p, {}, cx, cy, img);
  EXPECT_EQ(img.at(100, 50, 0), SrgbCodeFromLinear(in));
  const double corner_r = std::hypot(100.0, 50.0) / std::hypot(100.5, 50.5);
  for (auto [x, y] : {std::pair{0, 0}, {200, 0}, {0, 100}, {200, 100}}) {
    const double ratio = LinearFromSrgbCode(img.at(x, y, 1)) / LinearFromSrgbCode(img.at(100, 50, 1));
    EXPECT_NEAR(ratio, p.Vignetting(corner_r), 0.006) << x << "," << y;  // 8-bit quantisation near 0.3
    EXPECT_LT(ratio, 0.62);
  }
  // Off-centre principal point: the farthest corner is the opposite one.
  ImageU8 off = Flat(w, h, 0.5);
  ApplyPhotometry(p, {}, 0, 0, off);
  EXPECT_EQ(off.at(0, 0, 0), SrgbCodeFromLinear(in));
  EXPECT_NEAR(LinearFromSrgbCode(off.at(200, 100, 0)) / in, p.Vignetting(std::hypot(200, 100) / std::hypot(200.5, 100.5)), 0.006);
}

// Noise on a flat image: mean unchanged, standard deviation sqrt(a I + b) in linear light.
TEST(Photometric, NoiseHasTheRequestedStandardDeviation) {
  for (const auto& [shot, read] : {std::pair{0.0, 0.02}, {0.004, 0.0}, {0.002, 0.01}}) {
    CameraPhotometry p;
    p.shot_noise = shot;
    p.read_noise_stddev = read;
    ImageU8 img = Flat(400, 300, 0.25);
    const double level = LinearFromSrgbCode(img.at(0, 0));
    ApplyPhotometry(p, {3, 0, 0}, 199.5, 149.5, img);
    double sum = 0, sum_sq = 0;
    const size_t n = img.data.size();
    for (uint8_t v : img.data) {
      const double x = LinearFromSrgbCode(v);
      sum += x;
      sum_sq += x * x;
    }
    const double mean = sum / n, stddev = std::sqrt(sum_sq / n - mean * mean);
    const double expected = std::sqrt(shot * level + read * read);
    EXPECT_NEAR(mean, level, 0.002) << shot << " " << read;
    EXPECT_NEAR(stddev, expected, 0.03 * expected) << shot << " " << read;
  }
}

TEST(Photometric, InvalidPixelsStayBlackAndBadOptionsAreRefused) {
  CameraPhotometry p;
  p.read_noise_stddev = 0.05;
  ImageU8 img(10, 10, 3, 0);
  ImageU8 invalid(10, 10, 1, 0);
  for (int x = 0; x < 10; ++x) invalid.at(x, 0) = 1;
  ApplyPhotometry(p, {1, 0, 0}, 4.5, 4.5, img, &invalid);
  int lit = 0;
  for (int x = 0; x < 10; ++x) {
    EXPECT_EQ(img.at(x, 0, 0) + img.at(x, 0, 1) + img.at(x, 0, 2), 0);
    for (int y = 1; y < 10; ++y) lit += img.at(x, y, 0) > 0;
  }
  EXPECT_GT(lit, 20) << "noise lifts valid black pixels";

  for (auto set : std::vector<void (*)(PhotometricOptions&)>{
           [](PhotometricOptions& o) { o.exposure_stops_sigma = -0.1; },
           [](PhotometricOptions& o) { o.white_balance_stops_sigma = 2; },
           [](PhotometricOptions& o) { o.vignetting_strength = 1.0; },
           [](PhotometricOptions& o) { o.shot_noise = std::nan(""); },
           [](PhotometricOptions& o) { o.read_noise_stddev = 0.6; }}) {
    PhotometricOptions o;
    set(o);
    EXPECT_THROW(o.Check(), std::invalid_argument);
    EXPECT_THROW(DrawCameraPhotometry(o, 0), std::invalid_argument);
  }
  PhotometricOptions strong;
  strong.vignetting_strength = 1.5;
  EXPECT_THAT([&] { strong.Check(); }, ThrowsWith<std::invalid_argument>("vignetting_strength"));
  ImageU8 one_channel(4, 4, 1);
  EXPECT_THROW(ApplyPhotometry(p, {}, 1.5, 1.5, one_channel), std::invalid_argument);
}

}  // namespace
}  // namespace rigsim
