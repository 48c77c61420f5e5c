#include "procedural/ego_vehicle.h"

#include <cmath>
#include <fstream>
#include <limits>
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

// Distance along the ray (origin, unit dir) to the nearest triangle of the body (Moller-Trumbore),
// infinity when it meets none.
double Hit(const EgoVehicleMeshes& body, const Eigen::Vector3d& origin, const Eigen::Vector3d& dir) {
  double nearest = std::numeric_limits<double>::infinity();
  for (const MeshData* m : {&body.paint, &body.glass}) {
    for (size_t i = 0; i + 2 < m->indices.size(); i += 3) {
      const Eigen::Vector3d a = m->positions[m->indices[i]].cast<double>();
      const Eigen::Vector3d e1 = m->positions[m->indices[i + 1]].cast<double>() - a;
      const Eigen::Vector3d e2 = m->positions[m->indices[i + 2]].cast<double>() - a;
      const Eigen::Vector3d p = dir.cross(e2), s = origin - a, q = s.cross(e1);
      const double det = e1.dot(p);
      if (std::abs(det) < 1e-12) continue;
      const double u = s.dot(p) / det, v = dir.dot(q) / det, t = e2.dot(q) / det;
      if (u >= 0 && v >= 0 && u + v <= 1 && t >= 0) nearest = std::min(nearest, t);
    }
  }
  return nearest;
}

// Cameras at one height grouped closer than a car's roof is long and wide, as on a roof rack: a
// ring of four looking out, and ddad-scene01's arrangement (a front camera, two more 0.15 and 0.7 m
// behind it and beside it, within 3 cm of its height). Each sees the roof's edge, in the direction
// it looks, no higher than a camera at the roof's side edge does (kRoofGap down over kRoofMargin
// out), not across a roof that fills the lower half of its view; and the body is still under it.
TEST(EgoVehicle, CamerasAtOneHeightSeeTheRoofOnlyLowInTheirViews) {
  Rig ring, rack;
  ring.cameras = {CameraAt("front", {0, 0, 0.5}, {0, 0, 1}), CameraAt("right", {0.5, 0, 0}, {1, 0, 0}),
                  CameraAt("back", {0, 0, -0.5}, {0, 0, -1}), CameraAt("left", {-0.5, 0, 0}, {-1, 0, 0})};
  rack.cameras = {CameraAt("front", {0, 0, 0}, {0, 0, 1}), CameraAt("left", {-0.15, 0.01, -0.15}, {-1, 0, 0.3}),
                  CameraAt("right", {0.15, -0.02, -0.7}, {1, 0, -0.4})};
  const double edge_slope = kRoofGap / kRoofMargin;
  for (const Rig* rig : {&ring, &rack}) {
    const EgoVehicleMeshes body = EgoVehicleInRig(*rig, 1.6);
    const float roof = Bounds(body).min().y();  // y down: the body's top
    for (const RigCamera& c : rig->cameras) {
      SCOPED_TRACE(std::string(rig == &ring ? "ring " : "rack ") + c.name);
      const Eigen::Vector3d centre = c.cam_from_rig->SourceOriginInTarget();
      Eigen::Vector3d level = c.cam_from_rig->rotation.conjugate() * Eigen::Vector3d::UnitZ();
      level.y() = 0;
      level.normalize();
      // A little above the edge's depression the camera sees past the roof (the bonnet or boot far
      // beyond it may still show); a ray straight down meets the roof within half a metre.
      const Eigen::Vector3d above_edge = (level + 0.9 * edge_slope * Eigen::Vector3d::UnitY()).normalized();
      const double t = Hit(body, centre, above_edge);
      if (std::isfinite(t)) EXPECT_GT((centre + t * above_edge).y(), roof + 0.01) << "meets the roof " << t << " m out";
      EXPECT_LT(Hit(body, centre, Eigen::Vector3d::UnitY()), 0.5);
    }
  }
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
