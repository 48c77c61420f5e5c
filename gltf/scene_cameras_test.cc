#include "gltf/scene_cameras.h"

#include <algorithm>
#include <cmath>
#include <filesystem>
#include <numbers>
#include <stdexcept>
#include <string>
#include <vector>

#include <Eigen/Geometry>
#include <gmock/gmock.h>
#include <gtest/gtest.h>
#include <nlohmann/json.hpp>

#include "gltf/gltf_loader.h"
#include "testing/expect_error.h"
#include "testing/gltf_builder.h"
#include "testing/temp_dir.h"

namespace rigsim {
namespace {

using nlohmann::json;
namespace fs = std::filesystem;

fs::path WriteGltf(const fs::path& dir, const std::string& name, const json& doc) {
  const fs::path path = dir / (name + ".gltf");
  WriteFile(path, doc.dump(1));
  return path;
}

json Perspective(double yfov, double aspect = 0.0) {
  json p = {{"yfov", yfov}, {"znear", 0.1}};
  if (aspect > 0) p["aspectRatio"] = aspect;
  return {{"type", "perspective"}, {"perspective", p}};
}

// cam_from_world of a camera at `centre` whose OpenCV axes (right, down, forward) are the given
// world directions: the analytic answer the loader's conversion must reproduce.
Rigid3d CamFromWorld(const Eigen::Vector3d& right, const Eigen::Vector3d& down, const Eigen::Vector3d& forward,
                     const Eigen::Vector3d& centre) {
  Eigen::Matrix3d world_from_cam;
  world_from_cam << right, down, forward;
  return Rigid3d(world_from_cam, centre).Inverse();
}

void ExpectPoseNear(const Rigid3d& actual, const Rigid3d& expected, const std::string& what) {
  EXPECT_LT(RotationDifferenceDeg(actual.rotation, expected.rotation), 1e-9) << what;
  EXPECT_LT((actual.translation - expected.translation).norm(), 1e-9)
      << what << ": " << actual.translation.transpose() << " expected " << expected.translation.transpose();
}

// GltfCamerasDocument (testing/gltf_builder.h), whose cameras the loader must place so:
//  - node 0 "front": glTF's -Z view axis points along world -X: OpenCV forward = -X, down = -Y,
//    right = -Z.
//  - node 2 "back": centre (-4, 0, -10), looking along +Z: forward = +Z, down = -Y, right = -X.
//  - node 3: orthographic.
// Traversal meets "back" first; file order still makes "front" the reference.
const Rigid3d kFrontFromWorld = CamFromWorld({0, 0, -1}, {0, -1, 0}, {-1, 0, 0}, {1, 2, 3});
const Rigid3d kBackFromWorld = CamFromWorld({-1, 0, 0}, {0, -1, 0}, {0, 0, 1}, {-4, 0, -10});

TEST(SceneCameras, LoaderReadsCamerasWithParentTransformsInFileOrder) {
  const Scene scene = LoadGltf(WriteGltf(TempDir(), "two", GltfCamerasDocument()));
  ASSERT_EQ(scene.cameras.size(), 3u);
  EXPECT_EQ(scene.cameras[0].name, "front");
  EXPECT_EQ(scene.cameras[0].node, 0);
  EXPECT_EQ(scene.cameras[1].name, "back");
  EXPECT_EQ(scene.cameras[2].name, "top");
  EXPECT_TRUE(scene.cameras[2].orthographic);
  EXPECT_NEAR(scene.cameras[0].yfov_rad, std::numbers::pi / 3, 1e-12);
  EXPECT_EQ(scene.cameras[0].aspect_ratio, 0.0);
  EXPECT_EQ(scene.cameras[1].aspect_ratio, 2.0);
  EXPECT_NEAR(scene.cameras[0].znear_m, 0.1, 1e-12);
  ExpectPoseNear(scene.cameras[0].cam_from_world, kFrontFromWorld, "front");
  ExpectPoseNear(scene.cameras[1].cam_from_world, kBackFromWorld, "back (parented, scaled parent)");
}

TEST(SceneCameras, RigIsRelativeToTheFirstCameraAndReproducesTheWorldPoses) {
  const Scene scene = LoadGltf(WriteGltf(TempDir(), "two", GltfCamerasDocument()));
  const SceneCameraRig r = RigFromSceneCameras(scene, 640, 480);
  ASSERT_EQ(r.rig.cameras.size(), 2u);
  EXPECT_EQ(r.rig.cameras[0].name, "front");
  EXPECT_EQ(r.rig.cameras[1].name, "back");
  ASSERT_EQ(r.frames.frames.size(), 1u);
  EXPECT_EQ(r.frames.frames[0].name, "000000");
  EXPECT_EQ(r.frames.frames[0].timestamp_s, 0.0);
  EXPECT_EQ(r.frames.scene, "two.gltf");
  const Rigid3d rig_from_world = *r.frames.frames[0].rig_from_world;
  ExpectPoseNear(rig_from_world, kFrontFromWorld, "rig_from_world = the first camera's pose");
  ExpectPoseNear(*r.rig.cameras[0].cam_from_rig, Rigid3d(), "reference camera");
  ExpectPoseNear(*r.rig.cameras[1].cam_from_rig, kBackFromWorld * kFrontFromWorld.Inverse(), "back from front");
  // Rendering uses cam_from_rig * rig_from_world: both cameras' world poses come back.
  ExpectPoseNear(*r.rig.cameras[1].cam_from_rig * rig_from_world, kBackFromWorld, "back in the world");
  // Front looks along world -X, which is back's right (+x): back's right turned towards front's view.
  EXPECT_TRUE((r.rig.cameras[1].cam_from_rig->RotationMatrix() * Eigen::Vector3d::UnitZ()).isApprox(Eigen::Vector3d::UnitX(), 1e-12));
  // Intrinsics: yfov 60 deg over 480 rows; front has no aspectRatio (square pixels), back's 2.0
  // stretches 640 columns over a horizontal field twice the vertical one's tangent.
  const double fy = 240.0 / std::tan(std::numbers::pi / 6);
  const Camera& front = r.rig.cameras[0].camera;
  const Camera& back = r.rig.cameras[1].camera;
  EXPECT_EQ(front.model(), CameraModelId::kPinhole);
  EXPECT_EQ(front.width(), 640);
  EXPECT_EQ(front.height(), 480);
  EXPECT_NEAR(front.fy(), fy, 1e-9);
  EXPECT_NEAR(front.fx(), fy, 1e-9);
  EXPECT_NEAR(front.cx(), 319.5, 1e-12);
  EXPECT_NEAR(front.cy(), 239.5, 1e-12);
  EXPECT_NEAR(back.fy(), fy, 1e-9);
  EXPECT_NEAR(back.fx(), 320.0 / (2.0 * std::tan(std::numbers::pi / 6)), 1e-9);
  // Warnings: the orthographic camera by name, back's non-square pixels.
  ASSERT_EQ(r.warnings.size(), 2u);
  EXPECT_NE(r.warnings[0].find("'top'"), std::string::npos) << r.warnings[0];
  EXPECT_NE(r.warnings[0].find("orthographic"), std::string::npos) << r.warnings[0];
  EXPECT_NE(r.warnings[1].find("'back'"), std::string::npos) << r.warnings[1];
  EXPECT_NE(r.warnings[1].find("not square"), std::string::npos) << r.warnings[1];
}

TEST(SceneCameras, ViewCentreLandsAtThePrincipalPointAndGltfUpIsImageUp) {
  const Scene scene = LoadGltf(WriteGltf(TempDir(), "two", GltfCamerasDocument()));
  const SceneCameraRig r = RigFromSceneCameras(scene, 640, 480);
  const Rigid3d rig_from_world = *r.frames.frames[0].rig_from_world;
  // Back's glTF camera frame: centre (-4, 0, -10), glTF x (right) = world -X, glTF y (up) = world +Y,
  // view along glTF -Z = world +Z.
  const Eigen::Vector3d centre(-4, 0, -10), gl_right(-1, 0, 0), gl_up(0, 1, 0), gl_back(0, 0, -1);
  const RigCamera& back = r.rig.cameras[1];
  const Rigid3d cam_from_world = *back.cam_from_rig * rig_from_world;
  const auto on_axis = back.camera.ImgFromCam(cam_from_world * (centre - 7.0 * gl_back));
  ASSERT_TRUE(on_axis);
  EXPECT_LT((*on_axis - Eigen::Vector2d(back.camera.cx(), back.camera.cy())).norm(), 1e-9);
  // A point up and to the right in the glTF camera's view is up (smaller y) and right in the image.
  const auto up_right = back.camera.ImgFromCam(cam_from_world * (centre + 1.0 * gl_right + 1.0 * gl_up - 5.0 * gl_back));
  ASSERT_TRUE(up_right);
  EXPECT_NEAR(up_right->x(), back.camera.cx() + back.camera.fx() / 5.0, 1e-9);
  EXPECT_NEAR(up_right->y(), back.camera.cy() - back.camera.fy() / 5.0, 1e-9);
  // The glTF view volume's top edge (yfov/2 above the axis) is the image's top edge, y = -0.5.
  const double t = std::tan(std::numbers::pi / 6);
  const auto top = back.camera.ImgFromCam(cam_from_world * (centre + t * gl_up - gl_back));
  ASSERT_TRUE(top);
  EXPECT_NEAR(top->y(), -0.5, 1e-9);
}

TEST(SceneCameras, NoPerspectiveCameraIsAnErrorNamingTheFile) {
  const TempDir dir;
  json doc = GltfCamerasDocument();
  doc.erase("cameras");
  for (json& n : doc["nodes"]) n.erase("camera");
  const fs::path none = WriteGltf(dir, "no_cameras", doc);
  EXPECT_THAT([&] { RigFromSceneCameras(LoadGltf(none), 640, 480); },
              ThrowsNaming<std::runtime_error>(none, "no perspective camera"));
  // Only an orthographic camera: the message names it.
  doc = GltfCamerasDocument();
  doc["nodes"][0].erase("camera");
  doc["nodes"][2].erase("camera");
  const fs::path ortho = WriteGltf(dir, "ortho", doc);
  EXPECT_THAT([&] { RigFromSceneCameras(LoadGltf(ortho), 640, 480); },
              ThrowsNaming<std::runtime_error>(ortho, "orthographic cameras cannot be rig cameras: 'top'"));
  EXPECT_THROW(RigFromSceneCameras(LoadGltf(WriteGltf(dir, "two", GltfCamerasDocument())), 8, 480), std::invalid_argument);
}

TEST(SceneCameras, BadCamerasAreSkippedWithWarningsAndNamesAreMadeUsable) {
  const TempDir dir;
  json doc = GltfCamerasDocument();
  doc["cameras"][1]["perspective"]["yfov"] = 4.0;  // > pi
  doc["nodes"][0]["name"] = "a/b";
  doc["nodes"].push_back({{"name", "a/b"}, {"camera", 0}, {"scale", {1, -1, 1}}});  // mirrored
  doc["nodes"].push_back({{"name", "a_b"}, {"camera", 0}});
  doc["scenes"][0]["nodes"] = {0, 1, 3, 4, 5};
  const Scene scene = LoadGltf(WriteGltf(dir, "bad", doc));
  bool yfov_warned = false, mirror_warned = false;
  for (const std::string& w : scene.warnings) {
    yfov_warned |= w.find("node 2 'back' (camera 1): yfov") != std::string::npos;
    mirror_warned |= w.find("node 4 'a/b' (camera 0): the node's transform mirrors") != std::string::npos;
  }
  EXPECT_TRUE(yfov_warned);
  EXPECT_TRUE(mirror_warned);
  const SceneCameraRig r = RigFromSceneCameras(scene, 64, 48);
  ASSERT_EQ(r.rig.cameras.size(), 2u);
  EXPECT_EQ(r.rig.cameras[0].name, "a_b");    // separators replaced
  EXPECT_EQ(r.rig.cameras[1].name, "a_b_5");  // repeated name made unique
}

// Names become folder names: a blank one is replaced like an empty one, and names that differ only
// in letter case (one folder on macOS and Windows) are made unique like repeated ones.
TEST(SceneCameras, BlankNamesAndNamesDifferingInCaseAreMadeUsable) {
  const TempDir dir;
  json doc = {{"asset", {{"version", "2.0"}}}, {"cameras", {Perspective(1.0)}}, {"nodes", json::array()}};
  for (const char* name : {" \t", "Cam", "cam", "", "CAMERA0"}) {
    doc["nodes"].push_back({{"name", name}, {"camera", 0}, {"translation", {double(doc["nodes"].size()), 0, 0}}});
  }
  const SceneCameraRig r = RigFromSceneCameras(LoadGltf(WriteGltf(dir, "names", doc)), 64, 48);
  std::vector<std::string> names;
  for (const RigCamera& c : r.rig.cameras) names.push_back(c.name);
  EXPECT_EQ(names, (std::vector<std::string>{"camera0", "Cam", "cam_2", "camera3", "CAMERA0_4"}));
  EXPECT_EQ(std::count_if(r.warnings.begin(), r.warnings.end(), [](const std::string& w) { return w.find("repeats") != std::string::npos; }), 2);
  // The made-up name may be taken already ("CAM_2" by "Cam_2", letter case aside): the suffix repeats.
  doc["nodes"] = {{{"name", "Cam_2"}, {"camera", 0}}, {{"name", "cam"}, {"camera", 0}}, {{"name", "CAM"}, {"camera", 0}}};
  names.clear();
  for (const RigCamera& c : RigFromSceneCameras(LoadGltf(WriteGltf(dir, "taken", doc)), 64, 48).rig.cameras) names.push_back(c.name);
  EXPECT_EQ(names, (std::vector<std::string>{"Cam_2", "cam", "CAM_2_2"}));
}

}  // namespace
}  // namespace rigsim
