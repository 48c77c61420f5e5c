#include "pipeline/intrinsics_error.h"

#include <cmath>
#include <limits>
#include <vector>

#include <gmock/gmock.h>
#include <gtest/gtest.h>

#include "testing/expect_error.h"

namespace rigsim {
namespace {

// OPENCV: fx fy cx cy k1 k2 p1 p2.
Camera Lens() { return Camera(CameraModelId::kOpenCV, 640, 360, {400, 402, 319.5, 179.5, -0.2, 0.05, 0.001, -0.002}); }

// Sample standard deviation about a known mean of 0.
double RootMeanSquare(const std::vector<double>& v) {
  double s = 0;
  for (double x : v) s += x * x;
  return std::sqrt(s / v.size());
}

TEST(IntrinsicsError, ZeroGivesTheCameraBackBitForBit) {
  const Camera lens = Lens();
  EXPECT_EQ(WithIntrinsicsError(lens, {0.0, 7}, 3).params(), lens.params());
  Rig rig;
  rig.cameras.push_back({"a", lens, std::nullopt, 0.0});
  EXPECT_EQ(WithIntrinsicsError(rig, {0.0, 7}).cameras[0].camera.params(), lens.params());
}

TEST(IntrinsicsError, TheSameSeedAndCameraGiveTheSameIntrinsics) {
  const Camera lens = Lens();
  const std::vector<double> a = WithIntrinsicsError(lens, {0.02, 5}, 1).params();
  EXPECT_EQ(WithIntrinsicsError(lens, {0.02, 5}, 1).params(), a);
  EXPECT_NE(WithIntrinsicsError(lens, {0.02, 6}, 1).params(), a) << "another seed";
  EXPECT_NE(WithIntrinsicsError(lens, {0.02, 5}, 2).params(), a) << "another camera";
  // A rig's camera c gets camera index c's draw.
  Rig rig;
  rig.cameras.push_back({"a", lens, std::nullopt, 0.0});
  rig.cameras.push_back({"b", lens, std::nullopt, 0.0});
  EXPECT_EQ(WithIntrinsicsError(rig, {0.02, 5}).cameras[1].camera.params(), a);
}

TEST(IntrinsicsError, EachParameterMovesAsDocumented) {
  const Camera lens = Lens();
  const IntrinsicsErrorOptions o{0.03, 11};
  const std::vector<double> p = WithIntrinsicsError(lens, o, 4).params(), t = lens.params();
  const auto z = [&](int k) { return IntrinsicsErrorDraw(o.seed, 4, k); };
  EXPECT_DOUBLE_EQ(p[0], t[0] * std::exp(0.03 * z(0)));
  EXPECT_DOUBLE_EQ(p[1] / p[0], t[1] / t[0]) << "the aspect is kept";
  EXPECT_DOUBLE_EQ(p[2], t[2] + 0.03 * 320 * z(2));
  EXPECT_DOUBLE_EQ(p[3], t[3] + 0.03 * 180 * z(3));
  for (int k = 4; k < 8; ++k) EXPECT_DOUBLE_EQ(p[k], t[k] * (1 + 0.03 * z(k))) << k;
}

// Over many cameras the spread of each error is E: focal lengths relative, principal points in
// units of half the image, distortion relative.
TEST(IntrinsicsError, TheSpreadIsTheStatedError) {
  const Camera lens = Lens();
  for (const double e : {0.005, 0.02, 0.1}) {
    std::vector<double> focal, cx, cy, k1;
    for (uint64_t seed = 1; seed <= 4; ++seed) {
      for (int c = 0; c < 50; ++c) {
        const std::vector<double> p = WithIntrinsicsError(lens, {e, seed}, c).params();
        focal.push_back(p[0] / lens.fx() - 1);
        cx.push_back((p[2] - lens.cx()) / 320);
        cy.push_back((p[3] - lens.cy()) / 180);
        k1.push_back(p[4] / lens.params()[4] - 1);
      }
    }
    ASSERT_EQ(focal.size(), 200u);
    for (const auto* v : {&focal, &cx, &cy, &k1}) EXPECT_NEAR(RootMeanSquare(*v), e, 0.2 * e) << e;
  }
}

TEST(IntrinsicsError, ValuesThatAreNoCalibrationAreRefused) {
  const Camera lens = Lens();
  for (const double bad : {-0.01, 0.51, std::numeric_limits<double>::quiet_NaN(), std::numeric_limits<double>::infinity()}) {
    EXPECT_THAT([&] { WithIntrinsicsError(lens, {bad, 1}, 0); }, ThrowsWith<std::invalid_argument>("intrinsics_error: must be 0 to 0.5"))
        << bad;
    const IntrinsicsErrorOptions options{bad, 1};
    EXPECT_THAT([&] { options.Check("--intrinsics-error"); },
                ThrowsWith<std::invalid_argument>("--intrinsics-error: must be 0 to 0.5"));
  }
  EXPECT_NO_THROW(WithIntrinsicsError(lens, {0.5, 1}, 0));
}

}  // namespace
}  // namespace rigsim
