#include "renderer/defocus.h"

#include <cmath>
#include <numbers>
#include <stdexcept>
#include <vector>

#include <gmock/gmock.h>
#include <gtest/gtest.h>

#include "common/splitmix64.h"
#include "geometry/camera.h"
#include "testing/expect_error.h"

namespace rigsim {
namespace {

// fx 2000 px with 10 um pixels: f = 20 mm; at f/1.4 focused at 1 m the blur circle of a point at
// infinity is 2000 * (0.02 / 1.4) / 0.98 = 29.15 px across.
DefocusOptions Lens() {
  DefocusOptions o;
  o.f_number = 1.4;
  o.focus_distance_m = 1.0;
  o.pixel_pitch_um = 10.0;
  o.max_radius_px = 32;
  return o;
}
constexpr double kFx = 2000.0;

// The distance at which the lens's blur circle is `diameter_px` across (behind the focus distance).
double DistanceForDiameter(const DefocusOptions& o, double diameter_px) {
  const double at_infinity = BlurCircleDiameterPx(o, kFx, 0.0);
  return o.focus_distance_m / (1.0 - diameter_px / at_infinity);
}

// A textured linear image: every pixel its own value.
ImageF Texture(int w, int h, uint64_t seed) {
  ImageF img(w, h, 3);
  for (size_t i = 0; i < img.data.size(); ++i) img.data[i] = float(SplitMix64(seed ^ i) % 1000) / 1000.0f;
  return img;
}

// A vertical step edge between columns w/2 - 1 and w/2: `left` on the left, `right` on the right.
ImageF Step(int w, int h, float left, float right) {
  ImageF img(w, h, 3);
  for (int y = 0; y < h; ++y) {
    for (int x = 0; x < w; ++x) {
      for (int c = 0; c < 3; ++c) img.at(x, y, c) = x < w / 2 ? left : right;
    }
  }
  return img;
}

// Share of a disc of radius 1 left of the vertical line at t in [-1, 1].
double DiscShareLeftOf(double t) { return (std::acos(-t) + t * std::sqrt(1 - t * t)) / std::numbers::pi; }

// Where a rising profile first crosses `level` (linear interpolation between columns).
double Crossing(const ImageF& img, int y, float level) {
  for (int x = 1; x < img.width; ++x) {
    const float a = img.at(x - 1, y), b = img.at(x, y);
    if (a < level && b >= level) return x - 1 + (level - a) / (b - a);
  }
  return -1;
}

// A thin lens focuses on a plane: a wall facing the camera 3 m away, whose range grows off axis as
// 1/cos, is one axial distance everywhere, the range at the principal point; sky stays 0.
TEST(Defocus, AxialDistanceOfAFrontoParallelPlaneIsItsDistance) {
  const Camera camera(CameraModelId::kOpenCV, 64, 48, {40, 40, 31.5, 23.5, -0.2, 0.05, 0, 0});
  const PixelCentreRays rays = *PixelCentreRayCache().For(camera);
  ImageF range(64, 48, 1, 0.0f);
  for (int y = 0; y < 48; ++y) {
    for (int x = 0; x < 63; ++x) {  // the last column is sky
      const Eigen::Vector3d ray = camera.CamFromImg(Eigen::Vector2d(x, y))->normalized();
      range.data[size_t(y) * 64 + x] = float(3.0 / ray.z());
    }
  }
  EXPECT_GT(range.data[0], 4.0f) << "the corner is far off axis";
  const ImageF axial = AxialDistance(rays, range);
  for (int y = 0; y < 48; ++y) {
    for (int x = 0; x < 63; ++x) EXPECT_NEAR(axial.data[size_t(y) * 64 + x], 3.0f, 1e-5) << x << ", " << y;
    EXPECT_EQ(axial.data[size_t(y) * 64 + 63], 0.0f) << y;
  }
}

TEST(Defocus, BlurCircleFollowsTheThinLens) {
  const DefocusOptions o = Lens();
  const double f = 0.02, N = 1.4, s = 1.0;
  EXPECT_NEAR(BlurCircleDiameterPx(o, kFx, 0.0), kFx * (f / N) / (s - f), 1e-9);
  EXPECT_NEAR(BlurCircleDiameterPx(o, kFx, INFINITY), kFx * (f / N) / (s - f), 1e-9);
  EXPECT_EQ(BlurCircleDiameterPx(o, kFx, 1.0), 0.0) << "in focus";
  // The brief's form: c = f^2 / (N (s - f)) |d - s| / d, in pixels of 10 um.
  for (double d : {0.3, 0.7, 2.0, 10.0}) {
    EXPECT_NEAR(BlurCircleDiameterPx(o, kFx, d), f * f / (N * (s - f)) * std::abs(d - s) / d / 10e-6, 1e-9) << d;
  }
  DefocusOptions pinhole = o;
  pinhole.f_number = 0;
  EXPECT_EQ(BlurCircleDiameterPx(pinhole, kFx, 3.0), 0.0);
  DefocusOptions too_close = o;
  too_close.focus_distance_m = 0.01;  // inside the 20 mm focal length
  EXPECT_THAT([&] { BlurCircleDiameterPx(too_close, kFx, 3.0); }, ThrowsWith<std::invalid_argument>("focal length"));
}

// A plane at the focus distance, or any plane seen through a pinhole, keeps every value.
TEST(Defocus, PlaneInFocusOrAPinholeLeavesTheImageUnchanged) {
  const ImageF texture = Texture(64, 48, 3);
  ImageF img = texture;
  ApplyDefocus(Lens(), kFx, ImageF(64, 48, 1, 1.0f), img);
  EXPECT_EQ(img.data, texture.data);
  DefocusOptions pinhole = Lens();
  pinhole.f_number = 0;
  ApplyDefocus(pinhole, kFx, ImageF(64, 48, 1, 3.0f), img);
  EXPECT_EQ(img.data, texture.data);
  // Off focus, the same texture blurs.
  ApplyDefocus(Lens(), kFx, ImageF(64, 48, 1, 3.0f), img);
  EXPECT_NE(img.data, texture.data);
}

// A step edge on a plane off focus spreads over the blur circle: its 10-90% width is that of a
// uniform disc of the predicted radius (the disc's share left of a line through it).
TEST(Defocus, OffFocusEdgeWidensByThePredictedRadius) {
  for (double diameter : {6.0, 12.0, 20.0}) {
    const DefocusOptions o = Lens();
    const double d = DistanceForDiameter(o, diameter);
    ASSERT_NEAR(BlurCircleDiameterPx(o, kFx, d), diameter, 1e-9);
    ImageF img = Step(160, 60, 0.05f, 0.85f);
    ApplyDefocus(o, kFx, ImageF(160, 60, 1, float(d)), img, nullptr, 2);
    // The disc's share is 10% at t = -t90 and 90% at t90: width 2 t90 R.
    double lo = 0, hi = 1;
    for (int i = 0; i < 60; ++i) ((DiscShareLeftOf((lo + hi) / 2) < 0.9) ? lo : hi) = (lo + hi) / 2;
    const double predicted = 2 * lo * diameter / 2;
    const int y = 30;
    const double x10 = Crossing(img, y, 0.05f + 0.1f * 0.8f), x90 = Crossing(img, y, 0.05f + 0.9f * 0.8f);
    EXPECT_NEAR(x90 - x10, predicted, 0.35) << "diameter " << diameter;
    EXPECT_NEAR((x10 + x90) / 2, 79.5, 0.2) << "centred on the edge";
    // Far from the edge, the plane keeps its values.
    EXPECT_FLOAT_EQ(img.at(5, y), 0.05f);
    EXPECT_FLOAT_EQ(img.at(150, y), 0.85f);
  }
}

// Depth test: a background far behind a sharp foreground does not spread over it, while a blurred
// foreground spreads over the sharp background behind it.
TEST(Defocus, SharpForegroundKeepsItsEdgeBlurredForegroundSpreads) {
  const DefocusOptions o = Lens();
  const int w = 80, h = 20;
  // Left: foreground at the focus distance (bright); right: background at 5 m (dark, blurred).
  ImageF range(w, h, 1);
  for (int y = 0; y < h; ++y) {
    for (int x = 0; x < w; ++x) range.at(x, y) = x < w / 2 ? 1.0f : 5.0f;
  }
  ImageF img = Step(w, h, 0.9f, 0.1f);
  ApplyDefocus(o, kFx, range, img);
  for (int x = 0; x < w / 2; ++x) EXPECT_FLOAT_EQ(img.at(x, 10), 0.9f) << "sharp foreground, column " << x;
  // Right: the background (at the focus distance now) behind a blurred foreground at 0.5 m.
  for (int y = 0; y < h; ++y) {
    for (int x = 0; x < w; ++x) range.at(x, y) = x < w / 2 ? 0.5f : 1.0f;
  }
  img = Step(w, h, 0.9f, 0.1f);
  ApplyDefocus(o, kFx, range, img);
  EXPECT_GT(img.at(w / 2, 10), 0.3f) << "the blurred foreground's rim covers the background beside it";
  EXPECT_FLOAT_EQ(img.at(w - 1, 10), 0.1f);
}

TEST(Defocus, SameResultWhateverTheThreadCountInvalidPixelsAndBadOptions) {
  ImageF range(50, 40, 1);
  for (size_t i = 0; i < range.data.size(); ++i) range.data[i] = i % 7 == 0 ? 0.0f : 0.5f + float(i % 13);
  ImageU8 invalid(50, 40, 1, 0);
  for (int x = 0; x < 50; ++x) invalid.at(x, 0) = 1;
  ImageF one = Texture(50, 40, 9), two = one;
  for (int x = 0; x < 50; ++x) one.at(x, 0, 1) = two.at(x, 0, 1) = 7.0f;  // would show if it leaked
  ApplyDefocus(Lens(), kFx, range, one, &invalid, 1);
  ApplyDefocus(Lens(), kFx, range, two, &invalid, 2);
  EXPECT_EQ(one.data, two.data);
  for (int y = 1; y < 40; ++y) {
    for (int x = 0; x < 50; ++x) EXPECT_LT(one.at(x, y, 1), 1.0f) << x << "," << y;
  }
  EXPECT_EQ(one.at(3, 0, 1), 7.0f) << "invalid pixels are left as they are";

  for (auto set : std::vector<void (*)(DefocusOptions&)>{
           [](DefocusOptions& o) { o.f_number = -1; }, [](DefocusOptions& o) { o.f_number = 0.1; },
           [](DefocusOptions& o) { o.focus_distance_m = 0; }, [](DefocusOptions& o) { o.pixel_pitch_um = 0; },
           [](DefocusOptions& o) { o.max_radius_px = 100; }}) {
    DefocusOptions o = Lens();
    set(o);
    EXPECT_THROW(o.Check(), std::invalid_argument);
  }
  ImageF wrong(10, 10, 3);
  EXPECT_THROW(ApplyDefocus(Lens(), kFx, ImageF(9, 10, 1, 1.0f), wrong), std::invalid_argument);
}

}  // namespace
}  // namespace rigsim
