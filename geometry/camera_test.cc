#include "geometry/camera.h"
#include "geometry/rigid3.h"

#include <random>

#include <gtest/gtest.h>

namespace rigsim {
namespace {

// One representative camera per model, with the distortion of real lenses.
Camera ExampleCamera(CameraModelId id) {
  switch (id) {
    case CameraModelId::kPinhole: return Camera(id, 640, 480, {500, 510, 319.5, 239.5});
    case CameraModelId::kOpenCV: return Camera(id, 640, 480, {400, 405, 322, 236, -0.28, 0.07, 0.001, -0.0008});
    case CameraModelId::kFullOpenCV:
      return Camera(id, 640, 480, {400, 405, 322, 236, -0.3, 0.09, 0.0005, 0.0007, -0.01, 0.05, 0.01, 0.002});
    case CameraModelId::kOpenCVFisheye:
      // About 200 degrees across the image diagonal.
      return Camera(id, 640, 480, {150, 150, 319.5, 239.5, 0.02, -0.01, 0.003, -0.0005});
  }
  throw std::logic_error("model");
}

class AllModels : public testing::TestWithParam<CameraModelId> {};

TEST_P(AllModels, PixelRoundTripIsExactAcrossTheValidImage) {
  const Camera cam = ExampleCamera(GetParam());
  int valid = 0;
  double worst = 0.0;
  for (double y = -0.5; y < cam.height(); y += 7.3) {
    for (double x = -0.5; x < cam.width(); x += 7.1) {
      const Eigen::Vector2d px(x, y);
      const auto ray = cam.CamFromImg(px);
      if (!ray) continue;
      ++valid;
      EXPECT_NEAR(ray->norm(), 1.0, 1e-12);
      const auto back = cam.ImgFromCam(*ray * 7.0);
      ASSERT_TRUE(back.has_value()) << "pixel " << x << "," << y;
      worst = std::max(worst, (*back - px).norm());
    }
  }
  EXPECT_LT(worst, 1e-9);
  // Most of the sensor is imaged (the fisheye's corners lie outside its image circle).
  EXPECT_GT(valid, 0.7 * (cam.width() / 7.1) * (cam.height() / 7.3));
}

TEST_P(AllModels, PointRoundTripRecoversTheBearing) {
  const Camera cam = ExampleCamera(GetParam());
  std::mt19937 rng(42);
  std::uniform_real_distribution<double> angle(-1.0, 1.0);
  int tested = 0;
  for (int i = 0; i < 2000; ++i) {
    const Eigen::Vector3d x(angle(rng), angle(rng), 1.0);
    const auto px = cam.ImgFromCam(x);
    if (!px || !cam.IsInImage(*px)) continue;
    ++tested;
    const auto ray = cam.CamFromImg(*px);
    ASSERT_TRUE(ray.has_value());
    EXPECT_LT((*ray - x.normalized()).norm(), 1e-10);
  }
  EXPECT_GT(tested, 100);
}

INSTANTIATE_TEST_SUITE_P(Camera, AllModels, testing::ValuesIn(kAllCameraModels),
                         [](const auto& info) { return std::string(CameraModelName(info.param)); });

TEST(Camera, PixelCentreConventionIsOpenCVs) {
  // The optical axis hits (cx, cy); with cx = (w-1)/2 that is the centre of the image, halfway
  // between the two middle pixels of an even-sized image.
  const Camera cam = Camera::PinholeFromHorizontalFov(640, 480, 90.0);
  EXPECT_DOUBLE_EQ(cam.cx(), 319.5);
  EXPECT_DOUBLE_EQ(cam.cy(), 239.5);
  const Eigen::Vector2d axis = *cam.ImgFromCam(Eigen::Vector3d(0, 0, 3));
  EXPECT_DOUBLE_EQ(axis.x(), 319.5);
  EXPECT_DOUBLE_EQ(axis.y(), 239.5);
  // A 90 degree horizontal field of view spans the image's outer edges, -0.5 and w - 0.5.
  EXPECT_NEAR(cam.ImgFromCam(Eigen::Vector3d(-1, 0, 1))->x(), -0.5, 1e-12);
  EXPECT_NEAR(cam.ImgFromCam(Eigen::Vector3d(1, 0, 1))->x(), 639.5, 1e-12);
  EXPECT_TRUE(cam.IsInImage(Eigen::Vector2d(-0.5, -0.5)));
  EXPECT_FALSE(cam.IsInImage(Eigen::Vector2d(639.5, 10)));
}

TEST(Camera, AxesPointRightAndDown) {
  const Camera cam = ExampleCamera(CameraModelId::kPinhole);
  const Eigen::Vector2d right = *cam.ImgFromCam(Eigen::Vector3d(1, 0, 5));
  const Eigen::Vector2d down = *cam.ImgFromCam(Eigen::Vector3d(0, 1, 5));
  EXPECT_GT(right.x(), cam.cx());
  EXPECT_NEAR(right.y(), cam.cy(), 1e-12);
  EXPECT_GT(down.y(), cam.cy());
  EXPECT_NEAR(down.x(), cam.cx(), 1e-12);
  EXPECT_NEAR(right.x(), 500 * 0.2 + 319.5, 1e-12);
  EXPECT_NEAR(down.y(), 510 * 0.2 + 239.5, 1e-12);
}

TEST(Camera, NegativeK1IsBarrelDistortion) {
  // Barrel distortion pulls off-axis points towards the centre.
  const Camera barrel(CameraModelId::kOpenCV, 640, 480, {400, 400, 319.5, 239.5, -0.2, 0, 0, 0});
  const Camera pinhole(CameraModelId::kPinhole, 640, 480, {400, 400, 319.5, 239.5});
  const Eigen::Vector3d x(0.5, 0.0, 1.0);
  const double r_barrel = barrel.ImgFromCam(x)->x() - 319.5;
  const double r_pinhole = pinhole.ImgFromCam(x)->x() - 319.5;
  EXPECT_LT(r_barrel, r_pinhole);
  EXPECT_NEAR(r_barrel, 400 * 0.5 * (1 - 0.2 * 0.25), 1e-12);
}

TEST(Camera, TangentialTermsFollowOpenCVsOrder) {
  // OpenCV: x' = x(1 + k1 r^2 ...) + 2 p1 x y + p2 (r^2 + 2 x^2); y' = ... + p1 (r^2 + 2 y^2) + 2 p2 x y.
  const Camera cam(CameraModelId::kOpenCV, 640, 480, {100, 100, 0, 0, 0, 0, 0.01, 0.0});
  const Eigen::Vector2d px = *cam.ImgFromCam(Eigen::Vector3d(0.0, 0.5, 1.0));
  EXPECT_NEAR(px.x(), 0.0, 1e-12);                          // 2 p1 x y = 0
  EXPECT_NEAR(px.y(), 100 * (0.5 + 0.01 * 0.75), 1e-12);   // p1 (r^2 + 2 y^2)
}

TEST(Camera, FisheyeSeesBeyondNinetyDegrees) {
  const Camera cam = ExampleCamera(CameraModelId::kOpenCVFisheye);
  EXPECT_GT(cam.max_valid_angle(), DegToRad(100.0));
  // A point slightly behind the camera, 95 degrees off the axis.
  const double theta = DegToRad(95.0);
  const Eigen::Vector3d x(std::sin(theta), 0.0, std::cos(theta));
  const auto px = cam.ImgFromCam(x);
  ASSERT_TRUE(px.has_value());
  // Equidistant-like: radius ~ f * theta_d.
  const double theta_d = theta * (1 + 0.02 * theta * theta - 0.01 * std::pow(theta, 4) + 0.003 * std::pow(theta, 6) -
                                  0.0005 * std::pow(theta, 8));
  EXPECT_NEAR(px->x() - 319.5, 150 * theta_d, 1e-9);
  const auto ray = cam.CamFromImg(*px);
  ASSERT_TRUE(ray.has_value());
  EXPECT_LT((*ray - x).norm(), 1e-10);
  EXPECT_LT(ray->z(), 0.0);
}

TEST(Camera, PerspectiveRejectsPointsBehind) {
  const Camera cam = ExampleCamera(CameraModelId::kOpenCV);
  EXPECT_FALSE(cam.ImgFromCam(Eigen::Vector3d(0.1, 0.1, -1.0)).has_value());
  EXPECT_FALSE(cam.ImgFromCam(Eigen::Vector3d(0.1, 0.1, 0.0)).has_value());
}

TEST(Camera, DistortionBeyondItsFoldIsInvalid) {
  // r (1 + k1 r^2) with k1 = -0.5 peaks at r = sqrt(2/3): beyond it the lens folds back.
  const Camera cam(CameraModelId::kOpenCV, 640, 480, {300, 300, 319.5, 239.5, -0.5, 0, 0, 0});
  EXPECT_NEAR(std::tan(cam.max_valid_angle()), std::sqrt(2.0 / 3.0), 2e-3);
  EXPECT_FALSE(cam.ImgFromCam(Eigen::Vector3d(1.0, 0.0, 1.0)).has_value());
  // Image corners lie beyond the largest distorted radius: no ray.
  EXPECT_FALSE(cam.CamFromImg(Eigen::Vector2d(639.5, 479.5)).has_value());
  EXPECT_TRUE(cam.CamFromImg(Eigen::Vector2d(319.5, 239.5)).has_value());
}

TEST(Camera, ImpossibleIntrinsicsAreRejected) {
  EXPECT_THROW(Camera(CameraModelId::kPinhole, 640, 480, {-500, 500, 320, 240}), std::invalid_argument);
  EXPECT_THROW(Camera(CameraModelId::kPinhole, 640, 480, {500, 500, 320}), std::invalid_argument);
  EXPECT_THROW(Camera(CameraModelId::kPinhole, 0, 480, {500, 500, 320, 240}), std::invalid_argument);
  EXPECT_THROW(Camera(CameraModelId::kOpenCV, 640, 480, {500, 500, 320, 240, NAN, 0, 0, 0}), std::invalid_argument);
  EXPECT_THROW(CameraModelFromName("SIMPLE_RADIAL_FANCY"), std::invalid_argument);
}

TEST(CameraModels, NamesAndParameterCountsAreColmaps) {
  EXPECT_EQ(CameraModelFromName("OPENCV"), CameraModelId::kOpenCV);
  EXPECT_EQ(CameraModelNumParams(CameraModelId::kPinhole), 4);
  EXPECT_EQ(CameraModelNumParams(CameraModelId::kOpenCV), 8);
  EXPECT_EQ(CameraModelNumParams(CameraModelId::kFullOpenCV), 12);
  EXPECT_EQ(CameraModelNumParams(CameraModelId::kOpenCVFisheye), 8);
}

}  // namespace
}  // namespace rigsim
