#include "exports/colmap.h"

#include <sstream>
#include <string>
#include <vector>

#include <gtest/gtest.h>

#include "exports/test_rig.h"

namespace rigsim {
namespace {

std::vector<std::vector<std::string>> DataLines(const std::string& text) {
  std::vector<std::vector<std::string>> rows;
  std::istringstream in(text);
  for (std::string line; std::getline(in, line);) {
    if (line.empty() || line[0] == '#') continue;
    std::istringstream ls(line);
    std::vector<std::string> tokens;
    for (std::string t; ls >> t;) tokens.push_back(t);
    rows.push_back(tokens);
  }
  return rows;
}

TEST(Colmap, PrincipalPointGetsHalfAPixel) {
  const Rig rig = test::MixedRig();
  const ColmapModelText m = ColmapModel(rig, test::TwoFrames());
  const auto cams = DataLines(m.cameras);
  ASSERT_EQ(cams.size(), 3u);
  const char* names[] = {"OPENCV", "PINHOLE", "OPENCV_FISHEYE"};
  for (size_t i = 0; i < 3; ++i) {
    const std::vector<double>& p = rig.cameras[i].camera.params();
    EXPECT_EQ(cams[i][0], std::to_string(i + 1));
    EXPECT_EQ(cams[i][1], names[i]);
    ASSERT_EQ(cams[i].size(), 4 + p.size());
    EXPECT_EQ(std::stod(cams[i][4]), p[0]);
    EXPECT_EQ(std::stod(cams[i][5]), p[1]);
    EXPECT_EQ(std::stod(cams[i][6]), p[2] + 0.5);  // COLMAP: top-left pixel centre at (0.5, 0.5)
    EXPECT_EQ(std::stod(cams[i][7]), p[3] + 0.5);
    for (size_t k = 4; k < p.size(); ++k) EXPECT_EQ(std::stod(cams[i][4 + k]), p[k]) << "param " << k;  // same order
  }
}

TEST(Colmap, ImagesProjectLikeRigsimShiftedByHalfAPixel) {
  const Rig rig = test::MixedRig();
  const FramesFile frames = test::TwoFrames();
  const ColmapModelText m = ColmapModel(rig, frames);
  const auto images = DataLines(m.images);
  const auto cams = DataLines(m.cameras);
  ASSERT_EQ(images.size(), 6u);  // 2 frames x 3 cameras; the POINTS2D lines are empty
  const Eigen::Vector3d x_world(0.3, -1.2, -2.0);
  for (size_t k = 0; k < images.size(); ++k) {
    const auto& im = images[k];
    const size_t c = k / 2, f = k % 2;  // camera by camera, as COLMAP's feature_extractor numbers them
    EXPECT_EQ(im[0], std::to_string(k + 1));
    EXPECT_EQ(im[8], std::to_string(c + 1));
    EXPECT_EQ(im[9], rig.cameras[c].name + "/" + frames.frames[f].name + ".png");
    const Eigen::Quaterniond q(std::stod(im[1]), std::stod(im[2]), std::stod(im[3]), std::stod(im[4]));
    EXPECT_GE(q.w(), 0.0);
    const Eigen::Vector3d t(std::stod(im[5]), std::stod(im[6]), std::stod(im[7]));
    const Eigen::Vector3d x_cam = q * x_world + t;
    const Rigid3d truth = *rig.cameras[c].cam_from_rig * *frames.frames[f].rig_from_world;
    EXPECT_LT((x_cam - truth * x_world).norm(), 1e-12);
    if (c == 1) {  // the PINHOLE camera: COLMAP's projection fx x/z + cx with the exported cx
      const double fx = std::stod(cams[1][4]), fy = std::stod(cams[1][5]), cx = std::stod(cams[1][6]), cy = std::stod(cams[1][7]);
      const Eigen::Vector2d colmap_px(fx * x_cam.x() / x_cam.z() + cx, fy * x_cam.y() / x_cam.z() + cy);
      const auto ours = rig.cameras[1].camera.ImgFromCam(x_cam);
      ASSERT_TRUE(ours.has_value());
      EXPECT_LT((colmap_px - (*ours + Eigen::Vector2d(0.5, 0.5))).norm(), 1e-9);
    }
  }
  EXPECT_EQ(DataLines(m.points3d).size(), 0u);
}

TEST(Colmap, ImagesAreNamedByTheGivenFunction) {
  ColmapExportOptions o;
  o.image_name = [](const std::string& cam, const std::string& frame) {
    return cam + "/" + frame + (cam == "cam1" ? ".JPG" : ".png");
  };
  const ColmapModelText m = ColmapModel(test::MixedRig(), test::TwoFrames(), o);
  std::vector<std::string> names;
  for (const auto& line : DataLines(m.images)) {
    if (line.size() == 10) names.push_back(line[9]);
  }
  ASSERT_EQ(names.size(), 2 * test::MixedRig().cameras.size());
  EXPECT_EQ(names[2], "cam1/000000.JPG");
  for (const std::string& name : names) {
    EXPECT_EQ(name.substr(name.size() - 4), name.rfind("cam1/", 0) == 0 ? ".JPG" : ".png") << name;
  }
  EXPECT_EQ(DataLines(ColmapModel(test::MixedRig(), test::TwoFrames()).images)[2][9], "cam1/000000.png");  // default
}

// COLMAP numbers images camera by camera, each camera's in the order of their names: frames
// listed out of name order get the ids of their names' order.
TEST(Colmap, ImageIdsFollowCamerasThenNames) {
  FramesFile frames = test::TwoFrames();
  std::swap(frames.frames[0], frames.frames[1]);
  const auto images = DataLines(ColmapModel(test::MixedRig(), frames).images);
  ASSERT_EQ(images.size(), 6u);
  for (size_t k = 0; k < images.size(); ++k) {
    EXPECT_EQ(images[k][0], std::to_string(k + 1));
    EXPECT_EQ(images[k][8], std::to_string(k / 2 + 1));
    EXPECT_EQ(images[k][9], test::MixedRig().cameras[k / 2].name + "/00000" + std::to_string(k % 2) + ".png");
  }
}

// triangulate.sh lists each camera's images in id order, with COLMAP's intrinsics (cx, cy + 0.5).
TEST(Colmap, TriangulateScriptExtractsEachCameraInIdOrder) {
  const Rig rig = test::MixedRig();
  const std::string script = ColmapModel(rig, test::TwoFrames()).triangulate_script;
  // cam1: PINHOLE 600 600 401 298 in rigsim.
  const std::string cam1 = "extract PINHOLE 600,600,401.5,298.5 << 'END_OF_LIST'\ncam1/000000.png\ncam1/000001.png\nEND_OF_LIST\n";
  EXPECT_NE(script.find(cam1), std::string::npos) << script;
  EXPECT_LT(script.find("extract OPENCV "), script.find("extract PINHOLE "));
  EXPECT_LT(script.find("extract PINHOLE "), script.find("extract OPENCV_FISHEYE "));
  EXPECT_NE(script.find("point_triangulator"), std::string::npos);
}

TEST(Colmap, NeedsPoses) {
  Rig rig = test::MixedRig();
  FramesFile frames = test::TwoFrames();
  frames.frames[1].rig_from_world.reset();
  EXPECT_THROW(ColmapModel(rig, frames), std::invalid_argument);
}

}  // namespace
}  // namespace rigsim
