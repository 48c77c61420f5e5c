#include "exports/nerfstudio.h"

#include <gtest/gtest.h>
#include <nlohmann/json.hpp>

#include "exports/test_rig.h"

namespace rigsim {
namespace {

Eigen::Matrix4d ToMatrix(const nlohmann::json& j) {
  Eigen::Matrix4d m;
  for (int r = 0; r < 4; ++r) {
    for (int c = 0; c < 4; ++c) m(r, c) = j[r][c].get<double>();
  }
  return m;
}

TEST(Nerfstudio, OpenGlAxes) {
  // A camera looking down world -Z (OpenCV frame: x = world +X, y = world -Y, z = world -Z).
  Rig rig;
  rig.cameras.push_back({"front", Camera::PinholeFromHorizontalFov(640, 480, 90), Rigid3d(), 0.0});
  FramesFile frames;
  const Eigen::Vector3d centre(1, 2, 3);
  const Eigen::Matrix3d world_from_cam = Eigen::Vector3d(1, -1, -1).asDiagonal();
  frames.frames.push_back({"000000", Rigid3d(world_from_cam, centre).Inverse(), 0.0});
  const auto files = NerfstudioTransforms(rig, frames);
  ASSERT_EQ(files.size(), 1u);
  EXPECT_EQ(files[0].filename, "transforms.json");
  const auto j = nlohmann::json::parse(files[0].text);
  EXPECT_EQ(j["camera_model"], "OPENCV");
  const Eigen::Matrix4d t = ToMatrix(j["frames"][0]["transform_matrix"]);
  // OpenGL: x right, y up, z back. Looking down -Z means the camera's +z (back) is world +Z.
  EXPECT_LT((t.col(0).head<3>() - Eigen::Vector3d::UnitX()).norm(), 1e-12);
  EXPECT_LT((t.col(1).head<3>() - Eigen::Vector3d::UnitY()).norm(), 1e-12);
  EXPECT_LT((t.col(2).head<3>() - Eigen::Vector3d::UnitZ()).norm(), 1e-12);
  EXPECT_LT((t.col(3).head<3>() - centre).norm(), 1e-12);
  EXPECT_EQ(t(3, 3), 1.0);
  EXPECT_EQ(j["frames"][0]["file_path"], "images/front/000000.png");
}

TEST(Nerfstudio, ProjectionMatchesRigsimAndMixedRigsSplit) {
  const Rig rig = test::MixedRig();
  const FramesFile frames = test::TwoFrames();
  const auto files = NerfstudioTransforms(rig, frames);
  ASSERT_EQ(files.size(), 2u);
  EXPECT_EQ(files[0].filename, "transforms_perspective.json");
  EXPECT_EQ(files[1].filename, "transforms_fisheye.json");
  const auto persp = nlohmann::json::parse(files[0].text);
  const auto fish = nlohmann::json::parse(files[1].text);
  EXPECT_EQ(persp["camera_model"], "OPENCV");
  EXPECT_EQ(fish["camera_model"], "OPENCV_FISHEYE");
  ASSERT_EQ(persp["frames"].size(), 4u);  // 2 frames x (cam0, cam1)
  ASSERT_EQ(fish["frames"].size(), 2u);
  // Fisheye coefficients k1..k4 in order.
  const auto& f0 = fish["frames"][0];
  const char* keys[] = {"k1", "k2", "k3", "k4"};
  for (int k = 0; k < 4; ++k) EXPECT_EQ(f0[keys[k]].get<double>(), rig.cameras[2].camera.params()[4 + k]);
  // OPENCV: k1 k2 p1 p2 by name.
  const auto& e = persp["frames"][0];  // frame 0, cam0
  const std::vector<double>& p = rig.cameras[0].camera.params();
  EXPECT_EQ(e["k1"].get<double>(), p[4]);
  EXPECT_EQ(e["k2"].get<double>(), p[5]);
  EXPECT_EQ(e["p1"].get<double>(), p[6]);
  EXPECT_EQ(e["p2"].get<double>(), p[7]);
  EXPECT_EQ(e["file_path"], "images/cam0/000000.png");
  NerfstudioExportOptions named;
  named.image_name = [](const std::string& cam, const std::string& frame) { return cam + "/" + frame + ".jpeg"; };
  EXPECT_EQ(nlohmann::json::parse(NerfstudioTransforms(rig, frames, named)[1].text)["frames"][1]["file_path"],
            "images/cam2/000001.jpeg");
  // Project a point the nerfstudio way (GL camera, pixel centres at +0.5) through cam1 (pinhole).
  const auto& e1 = persp["frames"][1];  // frame 0, cam1
  const Eigen::Matrix4d world_from_gl = ToMatrix(e1["transform_matrix"]);
  const Eigen::Vector3d x_world(0.3, -1.2, -2.0);
  const Eigen::Vector3d x_gl = (world_from_gl.inverse() * x_world.homogeneous()).head<3>();
  ASSERT_LT(x_gl.z(), 0.0);  // in front = negative z in OpenGL
  const Eigen::Vector2d ns_px(e1["fl_x"].get<double>() * x_gl.x() / -x_gl.z() + e1["cx"].get<double>(),
                              e1["fl_y"].get<double>() * -x_gl.y() / -x_gl.z() + e1["cy"].get<double>());
  const Rigid3d cam_from_world = *rig.cameras[1].cam_from_rig * *frames.frames[0].rig_from_world;
  const auto ours = rig.cameras[1].camera.ImgFromCam(cam_from_world * x_world);
  ASSERT_TRUE(ours.has_value());
  EXPECT_LT((ns_px - (*ours + Eigen::Vector2d(0.5, 0.5))).norm(), 1e-9);
}

}  // namespace
}  // namespace rigsim
