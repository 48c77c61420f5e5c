#include "geometry/camera_validation.h"

#include <cmath>
#include <stdexcept>
#include <string>

#include <gtest/gtest.h>

namespace rigsim {
namespace {

// Expects CheckCameraCoversImage to throw a message naming the source, the camera and `part`.
void ExpectRejected(const Camera& camera, const std::string& part) {
  try {
    CheckCameraCoversImage(camera, "cam7", "rig.json");
    ADD_FAILURE() << "accepted; expected an error containing '" << part << "'";
  } catch (const std::runtime_error& e) {
    const std::string msg = e.what();
    EXPECT_EQ(msg.rfind("rig.json: camera 'cam7': ", 0), 0u) << msg;
    EXPECT_NE(msg.find(part), std::string::npos) << msg;
  }
}

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
  ExpectRejected(Camera(CameraModelId::kOpenCV, 1280, 720, {400, 400, 639.5, 359.5, -0.5, 0, 0, 0}),
                 "distortion cannot be inverted over the 1280x720 image");
  ExpectRejected(Camera(CameraModelId::kFullOpenCV, 640, 480, {300, 300, 319.5, 239.5, -0.6, 0, 0, 0, 0, 0, 0, 0}),
                 "FULL_OPENCV");
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
  ExpectRejected(Camera(CameraModelId::kOpenCVFisheye, 1280, 720, {300, 300, 5000, 359.5, -0.2, 0, 0, 0}),
                 "no ray at the image centre");
}

TEST(CameraValidation, AbsurdImageSizeIsRejected) {
  ExpectRejected(Camera(CameraModelId::kPinhole, 100000, 100000, {5e4, 5e4, 5e4, 5e4}), "exceeds the limit");
}

TEST(CameraValidation, RigCheckNamesTheCamera) {
  Rig rig;
  rig.cameras.push_back({"good", Camera::PinholeFromHorizontalFov(64, 48, 90), std::nullopt, 0.0});
  rig.cameras.push_back({"bad", Camera(CameraModelId::kOpenCV, 640, 480, {200, 200, 319.5, 239.5, -0.5, 0, 0, 0}),
                         std::nullopt, 0.0});
  try {
    CheckRigCoversImages(rig, "/data/rig.json");
    ADD_FAILURE() << "accepted";
  } catch (const std::runtime_error& e) {
    EXPECT_EQ(std::string(e.what()).rfind("/data/rig.json: camera 'bad': ", 0), 0u) << e.what();
  }
}

}  // namespace
}  // namespace rigsim
