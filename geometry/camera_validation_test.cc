#include "geometry/camera_validation.h"

#include <cmath>
#include <stdexcept>
#include <string>

#include <gmock/gmock.h>
#include <gtest/gtest.h>

#include "testing/expect_error.h"

namespace rigsim {
namespace {

// A call that checks `camera` as camera 'cam7' of rig.json; a rejection names both first.
auto Checking(const Camera& camera) {
  return [camera] { CheckCameraCoversImage(camera, "cam7", "rig.json"); };
}
const std::string kCam7 = "rig.json: camera 'cam7': ";

TEST(CameraValidation, OrdinaryPerspectiveCamerasPass) {
  EXPECT_TRUE(CheckCameraCoversImage(Camera::PinholeFromHorizontalFov(1280, 720, 95), "c", "s").empty());
  // The ring rig's distorted camera: OPENCV barrel k1 = -0.25, k2 = 0.06 at 95 deg.
  const double f = 0.5 * 1280 / std::tan(0.5 * 95 * 3.141592653589793 / 180);
  EXPECT_TRUE(
      CheckCameraCoversImage(Camera(CameraModelId::kOpenCV, 1280, 720, {f, f, 639.5, 359.5, -0.25, 0.06, 0, 0}), "c", "s")
          .empty());
}

TEST(CameraValidation, PerspectiveLensThatFoldsInsideTheImageIsRejected) {
  // k1 = -0.5 alone folds back at r = 1/sqrt(3*0.5) = 0.816 (distorted radius 0.544); with f = 400
  // that is 218 px from the centre, well inside a 1280x720 image.
  EXPECT_THAT(Checking(Camera(CameraModelId::kOpenCV, 1280, 720, {400, 400, 639.5, 359.5, -0.5, 0, 0, 0})),
              ThrowsNaming<std::runtime_error>(kCam7, "distortion cannot be inverted over the 1280x720 image"));
  EXPECT_THAT(Checking(Camera(CameraModelId::kFullOpenCV, 640, 480, {300, 300, 319.5, 239.5, -0.6, 0, 0, 0, 0, 0, 0, 0})),
              ThrowsNaming<std::runtime_error>(kCam7, "FULL_OPENCV"));
  // A sane lens with a principal point far outside the image still inverts: accepted.
  EXPECT_NO_THROW(CheckCameraCoversImage(Camera(CameraModelId::kPinhole, 64, 48, {50, 50, 500, -300}), "c", "s"));
}

TEST(CameraValidation, FisheyeWithImageCircleInsideTheSensorWarns) {
  // theta_d = theta - 0.2 theta^3 stops increasing at theta = 1.29 rad (theta_d 0.86): with f = 300
  // the image circle has a radius of 258 px, inside a 1280x720 sensor's corners.
  const Camera circle(CameraModelId::kOpenCVFisheye, 1280, 720, {300, 300, 639.5, 359.5, -0.2, 0, 0, 0});
  const CameraCoverage cov = MeasureCameraCoverage(circle);
  EXPECT_TRUE(cov.centre_valid);
  EXPECT_GT(cov.invalid_samples, 0);
  EXPECT_LT(cov.invalid_samples, cov.samples);
  const auto warnings = CheckCameraCoversImage(circle, "fish", "rig.json");
  ASSERT_EQ(warnings.size(), 1u);
  EXPECT_NE(warnings[0].find("rig.json: camera 'fish': "), std::string::npos) << warnings[0];
  EXPECT_NE(warnings[0].find("outside the fisheye's valid image circle"), std::string::npos) << warnings[0];
  // A fisheye whose principal point lies far outside its own image circle has no centre ray.
  EXPECT_THAT(Checking(Camera(CameraModelId::kOpenCVFisheye, 1280, 720, {300, 300, 5000, 359.5, -0.2, 0, 0, 0})),
              ThrowsNaming<std::runtime_error>(kCam7, "no ray at the image centre"));
}

TEST(CameraValidation, AbsurdImageSizeIsRejected) {
  EXPECT_THAT(Checking(Camera(CameraModelId::kPinhole, 100000, 100000, {5e4, 5e4, 5e4, 5e4})),
              ThrowsNaming<std::runtime_error>(kCam7, "exceeds the limit"));
}

TEST(CameraValidation, RigCheckNamesTheCamera) {
  Rig rig;
  rig.cameras.push_back({"good", Camera::PinholeFromHorizontalFov(64, 48, 90), std::nullopt, 0.0});
  rig.cameras.push_back({"bad", Camera(CameraModelId::kOpenCV, 640, 480, {200, 200, 319.5, 239.5, -0.5, 0, 0, 0}),
                         std::nullopt, 0.0});
  EXPECT_THAT([&] { CheckRigCoversImages(rig, "/data/rig.json"); },
              ThrowsNaming<std::runtime_error>("/data/rig.json: camera 'bad': ", ""));
}

TEST(CameraValidation, ARenderLensThatFoldsInsideTheImageIsRejectedNamingIt) {
  Rig rig;
  rig.cameras.push_back({"cam3", Camera(CameraModelId::kPinhole, 1280, 720, {400, 400, 639.5, 359.5}), Rigid3d(), 0.0});
  EXPECT_TRUE(CheckRigCoversImages(rig, "rig.json").empty());
  rig.cameras[0].render_lens = Camera(CameraModelId::kOpenCV, 1280, 720, {400, 400, 639.5, 359.5, -0.5, 0, 0, 0});
  EXPECT_THAT([&] { CheckRigCoversImages(rig, "rig.json"); },
              ThrowsNaming<std::runtime_error>("rig.json: camera 'cam3 (render_lens)'", "cannot be inverted"));
}

}  // namespace
}  // namespace rigsim
