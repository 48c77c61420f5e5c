#include "exports/opencv_yaml.h"

#include <filesystem>

#include <gtest/gtest.h>
#include <opencv2/core.hpp>

#include "exports/test_rig.h"
#include "testing/temp_dir.h"

namespace rigsim {
namespace {

TEST(OpenCvYaml, ReadsBackWithFileStorage) {
  const Rig rig = test::MixedRig();
  const TempDir dir;
  const auto path = dir / "rig.yaml";
  WriteOpenCvRigYaml(rig, path);
  cv::FileStorage fs(path.string(), cv::FileStorage::READ);
  ASSERT_TRUE(fs.isOpened());
  EXPECT_EQ(int(fs["num_cameras"]), 3);
  cv::FileNode cams = fs["cameras"];
  ASSERT_EQ(cams.size(), 3u);
  for (int i = 0; i < 3; ++i) {
    const RigCamera& rc = rig.cameras[i];
    cv::FileNode n = cams[i];
    EXPECT_EQ(std::string(n["name"]), rc.name);
    EXPECT_EQ(std::string(n["model"]), std::string(CameraModelName(rc.camera.model())));
    EXPECT_EQ(int(n["image_width"]), rc.camera.width());
    cv::Mat k, d, r, t;
    n["camera_matrix"] >> k;
    n["distortion_coefficients"] >> d;
    n["R"] >> r;
    n["T"] >> t;
    ASSERT_EQ(k.rows, 3);
    // OpenCV pixel convention: exactly our cx, cy.
    EXPECT_EQ(k.at<double>(0, 0), rc.camera.fx());
    EXPECT_EQ(k.at<double>(1, 1), rc.camera.fy());
    EXPECT_EQ(k.at<double>(0, 2), rc.camera.cx());
    EXPECT_EQ(k.at<double>(1, 2), rc.camera.cy());
    EXPECT_EQ(k.at<double>(2, 2), 1.0);
    const Eigen::Matrix3d rr = rc.cam_from_rig->RotationMatrix();
    for (int a = 0; a < 3; ++a) {
      EXPECT_DOUBLE_EQ(t.at<double>(a), rc.cam_from_rig->translation[a]);
      for (int b = 0; b < 3; ++b) EXPECT_DOUBLE_EQ(r.at<double>(a, b), rr(a, b));
    }
    // Distortion in OpenCV's order: (k1 k2 p1 p2) or fisheye (k1 k2 k3 k4) = our params after cx, cy.
    ASSERT_EQ(d.total(), 4u);
    for (int j = 0; j < 4; ++j) {
      const double expected = rc.camera.model() == CameraModelId::kPinhole ? 0.0 : rc.camera.params()[4 + j];
      EXPECT_EQ(d.at<double>(j), expected) << rc.name << " coefficient " << j;
    }
    EXPECT_EQ(int(n["fisheye"]), rc.camera.model() == CameraModelId::kOpenCVFisheye ? 1 : 0);
  }
  std::filesystem::remove(path);
}

TEST(OpenCvYaml, FullOpenCvKeepsRationalOrderAndPoselessCamerasHaveNoRT) {
  Rig rig;
  rig.cameras.push_back({"a b", Camera(CameraModelId::kFullOpenCV, 320, 240, {300, 300, 160, 120, 0.1, 0.02, 0.001, 0.002, 0.003, 0.04, 0.005, 0.006}),
                         std::nullopt, 0.0});
  cv::FileStorage fs(OpenCvRigYaml(rig), cv::FileStorage::READ | cv::FileStorage::MEMORY);
  cv::FileNode n = fs["cameras"][0];
  EXPECT_EQ(std::string(n["name"]), "a b");
  cv::Mat d;
  n["distortion_coefficients"] >> d;
  ASSERT_EQ(d.total(), 8u);
  const double expected[] = {0.1, 0.02, 0.001, 0.002, 0.003, 0.04, 0.005, 0.006};  // k1 k2 p1 p2 k3 k4 k5 k6
  for (int j = 0; j < 8; ++j) EXPECT_EQ(d.at<double>(j), expected[j]);
  EXPECT_TRUE(n["R"].empty());
  EXPECT_TRUE(n["T"].empty());
}

}  // namespace
}  // namespace rigsim
