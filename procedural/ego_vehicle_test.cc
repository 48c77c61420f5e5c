#include "procedural/ego_vehicle.h"

#include <cmath>
#include <fstream>
#include <stdexcept>
#include <string>
#include <vector>

#include <Eigen/Geometry>
#include <gmock/gmock.h>
#include <gtest/gtest.h>

#include "gltf/gltf_loader.h"
#include "labels/cityscapes.h"
#include "testing/expect_error.h"
#include "testing/temp_dir.h"

namespace rigsim {
namespace {

// A camera at `centre` (rig frame) looking along `forward`, with the rig's y (down) as its down
// where it can.
RigCamera CameraAt(const std::string& name, const Eigen::Vector3d& centre, const Eigen::Vector3d& forward) {
  const Eigen::Vector3d z = forward.normalized();
  Eigen::Vector3d down = Eigen::Vector3d::UnitY() - z * z.y();
  if (down.norm() < 1e-6) down = Eigen::Vector3d::UnitZ();
  const Eigen::Vector3d y = down.normalized(), x = y.cross(z);
  Eigen::Matrix3d rig_from_cam;
  rig_from_cam << x, y, z;
  const Eigen::Quaterniond cam_from_rig(rig_from_cam.transpose());
  RigCamera cam{name, Camera(CameraModelId::kPinhole, 64, 48, {40, 40, 31.5, 23.5}),
                Rigid3d(cam_from_rig, -(cam_from_rig * centre)), 0.0};
  return cam;
}

// A surround-like rig: four cameras 4 m and 1.8 m apart looking out, and a ring's two front cameras.
Rig CarRig() {
  Rig rig;
  rig.cameras = {CameraAt("front", {0, 0, 2}, {0, 0, 1}), CameraAt("right", {0.9, 0.02, 0}, {1, 0, 0}),
                 CameraAt("back", {0, 0, -2}, {0, 0, -1}), CameraAt("left", {-0.9, 0, 0}, {-1, 0.3, 0})};
  return rig;
}

// Bounds of the body's corners, rig frame.
Eigen::AlignedBox3f Bounds(const EgoVehicleMeshes& body) {
  Eigen::AlignedBox3f box;
  for (const MeshData* m : {&body.paint, &body.glass}) {
    for (const Eigen::Vector3f& p : m->positions) box.extend(p);
  }
  return box;
}

TEST(EgoVehicle, BodyLiesUnderTheCamerasAndAroundThem) {
  const Rig rig = CarRig();
  const EgoVehicleMeshes body = EgoVehicleInRig(rig, 1.6);
  ASSERT_FALSE(body.paint.indices.empty());
  ASSERT_FALSE(body.glass.indices.empty());
  const Eigen::AlignedBox3f box = Bounds(body);
  // The roof 5 cm below the lowest camera (y down), the sills 0.2 m above the ground.
  EXPECT_NEAR(box.min().y(), 0.02 + 0.05, 1e-5);
  EXPECT_NEAR(box.max().y(), 1.6 - 0.2, 1e-5);
  // Wider and longer than the cameras' footprint: every camera stands over the body.
  for (const RigCamera& c : rig.cameras) {
    const Eigen::Vector3f centre = c.cam_from_rig->SourceOriginInTarget().cast<float>();
    EXPECT_LT(box.min().x(), centre.x());
    EXPECT_GT(box.max().x(), centre.x());
    EXPECT_LT(box.min().z(), centre.z());
    EXPECT_GT(box.max().z(), centre.z());
    EXPECT_LT(centre.y(), box.min().y()) << c.name << " is above the roof";
  }
  // A bonnet in front of the front camera, a car's length at least.
  EXPECT_GT(box.max().z(), 2.0f + 1.5f);
  EXPECT_GT(box.sizes().z(), 4.5f);
}

TEST(EgoVehicle, ACompactRigGetsACarSizedBody) {
  Rig rig;
  rig.cameras = {CameraAt("a", {-0.06, 0, 0}, {0, 0, 1}), CameraAt("b", {0.06, 0, 0}, {0, 0, 1})};
  const Eigen::AlignedBox3f box = Bounds(EgoVehicleInRig(rig, 1.6));
  EXPECT_GT(box.sizes().x(), 1.5f);
  EXPECT_GT(box.sizes().z(), 3.5f);
}

TEST(EgoVehicle, ACameraLookingIntoTheBodyIsRefused) {
  Rig rig = CarRig();
  rig.cameras.push_back(CameraAt("down", {0.2, 0, 0.5}, {0, 1, 0}));  // straight down at the roof 5 cm below
  EXPECT_THAT([&] { EgoVehicleInRig(rig, 1.6); }, ThrowsWith<std::invalid_argument>("camera 'down' looks into the car body"));
  rig.cameras.back().cam_from_rig.reset();
  EXPECT_THAT([&] { EgoVehicleInRig(rig, 1.6); }, ThrowsWith<std::invalid_argument>("camera 'down' has no cam_from_rig"));
}

TEST(EgoVehicle, GlbLoadsAsAGlossyEgoVehicleAndTurnsBackIntoTheRigFrame) {
  const TempDir dir;
  const Rig rig = CarRig();
  const std::vector<uint8_t> glb = EgoVehicleGlb(rig, 1.6);
  const std::filesystem::path path = dir.path() / kEgoVehicleFile;
  std::ofstream(path, std::ios::binary).write(reinterpret_cast<const char*>(glb.data()), std::streamsize(glb.size()));
  Scene scene = LoadGltf(path);
  ASSERT_EQ(scene.meshes.size(), 2u);  // paint and glass, one node
  for (const SceneMesh& m : scene.meshes) {
    EXPECT_EQ(m.class_id, 1);  // Cityscapes' ego vehicle
    EXPECT_EQ(m.instance_id, scene.meshes[0].instance_id);
    ASSERT_GE(m.material, 0);
    EXPECT_LT(scene.materials[m.material].roughness, 0.3f) << "glossy enough to reflect";
  }
  // In the file the roof is up (+Y): above the sills.
  Eigen::AlignedBox3f in_file;
  for (const SceneMesh& m : scene.meshes) {
    for (const Eigen::Vector3f& p : m.positions) in_file.extend(p);
  }
  EXPECT_NEAR(in_file.max().y(), -(0.02f + 0.05f), 1e-5);
  EgoVehicleToRigFrame(scene);
  Eigen::AlignedBox3f in_rig;
  for (const SceneMesh& m : scene.meshes) {
    for (const Eigen::Vector3f& p : m.positions) in_rig.extend(p);
  }
  const Eigen::AlignedBox3f expected = Bounds(EgoVehicleInRig(rig, 1.6));
  EXPECT_TRUE(in_rig.min().isApprox(expected.min(), 1e-5f));
  EXPECT_TRUE(in_rig.max().isApprox(expected.max(), 1e-5f));
  // The same rig gives the same bytes.
  EXPECT_EQ(EgoVehicleGlb(rig, 1.6), glb);
}

}  // namespace
}  // namespace rigsim
