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

TEST(EgoVehicle, BodyLiesUnderTheCamerasAndAroundThem) {
  const Rig rig = CarRig();
  const EgoVehicleMeshes body = EgoVehicleInRig(rig, 1.6);
  ASSERT_FALSE(body.paint.indices.empty());
  ASSERT_FALSE(body.glass.indices.empty());
  const Eigen::AlignedBox3f box = Bounds(body);
  // The roof 5 cm below the lowest camera (y down; the car levelled to the cameras, the right one
  // 2 cm lower, by 0.7 degrees), the sills 0.2 m above the ground.
  double lowest = std::numeric_limits<double>::infinity();
  for (const RigCamera& c : rig.cameras) {
    const double below = Hit(body, c.cam_from_rig->SourceOriginInTarget(), Eigen::Vector3d::UnitY());
    EXPECT_GE(below, kRoofGap - 1e-4) << c.name;
    lowest = std::min(lowest, below);
  }
  EXPECT_NEAR(lowest, kRoofGap, 1e-4);
  EXPECT_NEAR(box.max().y(), 1.6 - 0.2, 0.02);
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


// Cameras at one height grouped closer than a car's roof is long and wide, as on a roof rack: a
// ring of four looking out, and ddad-scene01's arrangement (a front camera, two more 0.15 and 0.7 m
// behind it and beside it, within 3 cm of its height). Each stands at the roof's edge it looks out
// over, so it sees that edge no higher than a camera at the roof's side edge does (kRoofGap down
// over kRoofMargin out), not across a roof that fills the lower half of its view; and the body is
// still under it.
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

// A camera of a rig in its rig frame turned by `yaw_deg` (about the rig's y, positive to the right)
// and pitched down by `pitch_deg`, at `centre`: an 85-degree pinhole (1936 x 1216, f 1058), or a
// 48-degree one (f 2160), as ddad-scene01's cameras.
RigCamera DdadCamera(const std::string& name, const Eigen::Vector3d& centre, double yaw_deg, double pitch_deg, double f) {
  const double yaw = yaw_deg * M_PI / 180, pitch = pitch_deg * M_PI / 180;
  const Eigen::Vector3d forward(std::sin(yaw) * std::cos(pitch), std::sin(pitch), std::cos(yaw) * std::cos(pitch));
  RigCamera cam = CameraAt(name, centre, forward);
  cam.camera = Camera(CameraModelId::kPinhole, 1936, 1216, {f, f, 967.5, 607.5});
  return cam;
}

// ddad-scene01's three cameras (truth_rig.json, rounded): the front camera, 48 degrees wide, and
// the front-left and front-right ones, 85 degrees wide, turned 53 and 52 degrees out, 0.15 m left
// and 0.70 m right of it, within 3 cm of its height, level to a degree.
Rig DdadRig(double side_pitch_deg = 0) {
  Rig rig;
  rig.cameras = {DdadCamera("CAMERA_01", {0, 0, 0}, 0, 0, 2160),
                 DdadCamera("CAMERA_05", {-0.146, -0.007, 0}, -52.8, 0.6 + side_pitch_deg, 1058),
                 DdadCamera("CAMERA_06", {0.702, -0.027, -0.015}, 52.1, -0.9 + side_pitch_deg, 1058)};
  return rig;
}

// The ray through pixel (x, y) of `cam`, in the rig frame, from the camera's centre.
Eigen::Vector3d RayInRig(const RigCamera& cam, double x, double y) {
  return cam.cam_from_rig->rotation.conjugate() * *cam.camera.CamFromImg(Eigen::Vector2d(x, y));
}

// The highest row of column `x` whose ray meets the body (image rows top down), or the image's
// height when none does.
int TopRowOfBody(const EgoVehicleMeshes& body, const RigCamera& cam, double x) {
  const Eigen::Vector3d centre = cam.cam_from_rig->SourceOriginInTarget();
  for (int y = 0; y < cam.camera.height(); ++y) {
    if (std::isfinite(Hit(body, centre, RayInRig(cam, x, y)))) return y;
  }
  return cam.camera.height();
}

// The rule on a real car's rig: ddad-scene01's side cameras see their car as a strip along the
// bottom of their views, the front camera none of it (in its photos: the body's top in the side
// views 22-24 degrees below their axis, rows 1042-1085 of 1216, across the columns towards the
// car's front and the middle; none in CAMERA_01). The side cameras stand at the roof's
// front corners: in the half of their view towards the car's front they see the roof's edge, the
// windshield and the bonnet beyond it, no higher than 19 degrees below their horizon (within the
// lowest 20 % of their rows when level). Pitched 10 degrees down, they see more of it.
TEST(EgoVehicle, DdadSideCamerasSeeTheirCarAlongTheBottomOfTheirViewsAndTheFrontCameraNone) {
  for (const double pitch : {0.0, 10.0}) {
    SCOPED_TRACE("side cameras pitched " + std::to_string(pitch) + " deg down");
    const Rig rig = DdadRig(pitch);
    const EgoVehicleMeshes body = EgoVehicleInRig(rig, 1.55);
    const RigCamera& front = rig.cameras[0];
    for (const double x : {0.0, 967.5, 1935.0}) EXPECT_EQ(TopRowOfBody(body, front, x), 1216) << "CAMERA_01 column " << x;
    for (const RigCamera& side : {rig.cameras[1], rig.cameras[2]}) {
      // Columns towards the car's front: CAMERA_05 (front-left) its right half, CAMERA_06 its left.
      const bool front_on_the_right = side.name == "CAMERA_05";
      for (const double x : {0.0, 480.0, 967.5, 1450.0, 1935.0}) {
        const int top = TopRowOfBody(body, side, x);
        SCOPED_TRACE(side.name + " column " + std::to_string(x) + ": the body from row " + std::to_string(top));
        // No higher than 19 degrees below the horizon (row 972 of 1216 level: the lowest 20 %).
        EXPECT_GT(top, 607.5 + 1058 * std::tan((19 - pitch) * M_PI / 180));
        if (front_on_the_right ? x >= 967.5 : x <= 967.5) {
          EXPECT_LT(top, 1216) << "no body towards the car's front";
        }
      }
    }
  }
}

// A front camera at the roof's front edge looks out over the windshield and the bonnet: it sees the
// body up to the bonnet's front edge, kRoofMargin + 0.8 + 1.1 m ahead of the roof's front and
// kRoofGap + 0.4 + 0.2 m below the lowest camera, no higher: ddad-scene01's front camera (its view
// reaching 15.8 degrees down) none of it, a camera on a long car ahead of the others the same.
TEST(EgoVehicle, AFrontCameraSeesTheBonnetUpToItsFrontEdgeAndNoHigher) {
  const double bonnet_ahead = kRoofMargin + 0.8 + 1.1, bonnet_below = kRoofGap + 0.4 + 0.2;
  const double edge_deg = std::atan2(bonnet_below, bonnet_ahead) * 180 / M_PI;  // 18.0 degrees
  Rig car;  // 4 m long and 1.8 m wide: the front camera 2 m ahead of the side ones
  car.cameras = {CameraAt("front", {0, 0, 2}, {0, 0, 1}), CameraAt("right", {0.9, 0, 0}, {1, 0, 0}),
                 CameraAt("back", {0, 0, -2}, {0, 0, -1}), CameraAt("left", {-0.9, 0, 0}, {-1, 0, 0})};
  for (const Rig& rig : {DdadRig(), car}) {
    const RigCamera& front = rig.cameras[0];
    SCOPED_TRACE(front.name);
    const EgoVehicleMeshes body = EgoVehicleInRig(rig, 1.55);
    const Eigen::Vector3d centre = front.cam_from_rig->SourceOriginInTarget();
    const auto below = [](double deg) {
      return Eigen::Vector3d(0, std::sin(deg * M_PI / 180), std::cos(deg * M_PI / 180));
    };
    EXPECT_FALSE(std::isfinite(Hit(body, centre, below(edge_deg - 0.3)))) << "above the bonnet's front edge";
    const double t = Hit(body, centre, below(edge_deg + 0.3));
    EXPECT_NEAR(t * std::cos((edge_deg + 0.3) * M_PI / 180), bonnet_ahead, 0.1) << "the bonnet's front edge";
    // Straight down: the roof, kRoofGap below.
    EXPECT_NEAR(Hit(body, centre, Eigen::Vector3d::UnitY()), kRoofGap, 0.005);
  }
}

// The car is a car's size below its beltline however small the rig: ddad-scene01's cameras span
// 0.85 m across and 1.5 cm along; the body is kMinBodyWidth wide and kMinBodyLength long, its extra
// length in the boot (no camera looks out over the rear), so the bonnet ahead of the cameras is as
// on a longer rig.
TEST(EgoVehicle, ASmallRigGetsACarSizedBodyGrownWhereNoCameraLooks) {
  const Rig rig = DdadRig();
  const Eigen::AlignedBox3f box = Bounds(EgoVehicleInRig(rig, 1.55));
  // (The car levelled to the cameras, 1.5 degrees rolled to the rig frame.)
  EXPECT_NEAR(box.sizes().x(), kMinBodyWidth, 0.03);
  EXPECT_NEAR(box.sizes().z(), kMinBodyLength, 0.01);
  EXPECT_NEAR(box.max().z(), kRoofMargin + 0.8 + 1.1, 0.02);
  // The roof is the cameras' footprint and its margins, not a car's roof: kRoofGap under the front
  // camera up to kRoofMargin ahead of it, the windshield further down beyond.
  const EgoVehicleMeshes body = EgoVehicleInRig(rig, 1.55);
  const Eigen::Vector3d down = Eigen::Vector3d::UnitY();
  EXPECT_NEAR(Hit(body, {0, 0, kRoofMargin - 0.01}, down), kRoofGap, 0.005);
  EXPECT_GT(Hit(body, {0, 0, kRoofMargin + 0.05}, down), kRoofGap + 0.02);
  EXPECT_GT(Hit(body, {-0.146 - kRoofMargin - 0.05, 0, 0}, down), kRoofGap + 0.3) << "left of CAMERA_05: the beltline";
}

// Centres of a car rig's cameras on a level roof (the car's frame: x right, y down, z forward), 4 m
// and 1.8 m apart, seen in a rig frame turned from the car's by `rig_from_car` and moved by `offset`.
std::vector<Eigen::Vector3d> RoofCentresInRig(const Eigen::Matrix3d& rig_from_car, const Eigen::Vector3d& offset) {
  std::vector<Eigen::Vector3d> centres;
  for (const Eigen::Vector3d& c : {Eigen::Vector3d(0, 0, 2), Eigen::Vector3d(0.9, 0, 0), Eigen::Vector3d(0, 0, -2),
                                   Eigen::Vector3d(-0.9, 0, 0), Eigen::Vector3d(0.4, 0, 1.2)}) {
    centres.push_back(rig_from_car * c + offset);
  }
  return centres;
}

double DegreesBetween(const Eigen::Vector3d& a, const Eigen::Vector3d& b) {
  return std::atan2(a.cross(b).norm(), a.dot(b)) * 180 / M_PI;
}

// A rig frame pitched (and rolled) a few degrees off its car: the car's frame found from the
// cameras is level, its down the rig's gravity, and a rotation.
TEST(EgoVehicle, TheCarFrameOfATiltedRigIsLevelWithGravityDown) {
  const Eigen::Vector3d offset(0.3, -1.2, 0.5);
  const Eigen::Matrix3d pitched = Eigen::AngleAxisd(3 * M_PI / 180, Eigen::Vector3d::UnitX()).toRotationMatrix();
  const Eigen::Matrix3d rig_from_car = RigFromCar(RoofCentresInRig(pitched, offset));
  EXPECT_NEAR(rig_from_car.determinant(), 1.0, 1e-12);
  EXPECT_LT((rig_from_car.transpose() * rig_from_car - Eigen::Matrix3d::Identity()).cwiseAbs().maxCoeff(), 1e-12);
  // Down is the rig's gravity; a pure pitch leaves right the rig's x, so the whole frame is the
  // pitch. The plane's slope is ridge-regularised (0.1 m per camera against 4 m of spread), which
  // leaves a 3 degree tilt 0.02 degrees short at most.
  EXPECT_LT(DegreesBetween(rig_from_car.col(1), pitched * Eigen::Vector3d::UnitY()), 0.02);
  EXPECT_GT(DegreesBetween(rig_from_car.col(1), Eigen::Vector3d::UnitY()), 2.98);  // not the rig's own y
  EXPECT_LT((rig_from_car - pitched).cwiseAbs().maxCoeff(), 4e-4) << rig_from_car;
  // Pitched and rolled: down is still gravity (the ridge on the roof's 1.8 m width leaves the 2 degree
  // roll 0.06 degrees short); forward is the rig's z levelled, right completes it.
  const Eigen::Matrix3d tilted = (Eigen::AngleAxisd(3 * M_PI / 180, Eigen::Vector3d::UnitX()) *
                                  Eigen::AngleAxisd(-2 * M_PI / 180, Eigen::Vector3d::UnitZ())).toRotationMatrix();
  const Eigen::Matrix3d levelled = RigFromCar(RoofCentresInRig(tilted, offset));
  EXPECT_NEAR(levelled.determinant(), 1.0, 1e-12);
  EXPECT_LT(DegreesBetween(levelled.col(1), tilted * Eigen::Vector3d::UnitY()), 0.07);
  EXPECT_NEAR(levelled.col(1).dot(levelled.col(2)), 0.0, 1e-12);
  // forward: the rig's z with its part along down taken out, so in the plane of the two
  EXPECT_NEAR(levelled.col(2).dot(Eigen::Vector3d::UnitZ().cross(levelled.col(1))), 0.0, 1e-12);
  EXPECT_GT(levelled.col(2).z(), 0.99);
  EXPECT_LT((levelled.col(0) - levelled.col(1).cross(levelled.col(2))).norm(), 1e-12);
}

// The car is levelled only when the cameras lie on one plane, tilted 5 degrees at most: else the
// rig frame is the car's. Cameras in a line across the car give no pitch.
TEST(EgoVehicle, TheCarFrameIsTheRigFrameBeyondFiveDegreesOrOffThePlane) {
  const Eigen::Vector3d offset(0, -1.5, 0);
  const auto pitch = [](double deg) { return Eigen::AngleAxisd(deg * M_PI / 180, Eigen::Vector3d::UnitX()).toRotationMatrix(); };
  EXPECT_EQ(RigFromCar(RoofCentresInRig(pitch(6), offset)), Eigen::Matrix3d::Identity());
  EXPECT_NE(RigFromCar(RoofCentresInRig(pitch(4.5), offset)), Eigen::Matrix3d::Identity());
  std::vector<Eigen::Vector3d> off_plane = RoofCentresInRig(pitch(2), offset);
  EXPECT_NE(RigFromCar(off_plane), Eigen::Matrix3d::Identity());
  off_plane.push_back(pitch(2) * Eigen::Vector3d(0.1, -0.08, 0.3) + offset);  // mid-roof, 8 cm above the others'
  EXPECT_EQ(RigFromCar(off_plane), Eigen::Matrix3d::Identity());
  const Eigen::Matrix3d rolled = Eigen::AngleAxisd(2 * M_PI / 180, Eigen::Vector3d::UnitZ()).toRotationMatrix();
  std::vector<Eigen::Vector3d> line;
  for (double x : {-0.6, 0.0, 0.6}) line.push_back(rolled * Eigen::Vector3d(x, 0, 1.5) + offset);
  const Eigen::Matrix3d across = RigFromCar(line);
  EXPECT_NEAR(across.col(1).z(), 0.0, 1e-12);  // no pitch from cameras all at one z
  // The roll is found, to the ridge's 4 % on a line 1.2 m long.
  EXPECT_LT(DegreesBetween(across.col(1), rolled * Eigen::Vector3d::UnitY()), 0.1);
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
  EgoVehicleToRigFrame(scene);
  Eigen::AlignedBox3f in_rig;
  for (const SceneMesh& m : scene.meshes) {
    for (const Eigen::Vector3f& p : m.positions) in_rig.extend(p);
  }
  const Eigen::AlignedBox3f expected = Bounds(EgoVehicleInRig(rig, 1.6));
  EXPECT_NEAR(in_file.max().y(), -expected.min().y(), 1e-5);
  EXPECT_TRUE(in_rig.min().isApprox(expected.min(), 1e-5f));
  EXPECT_TRUE(in_rig.max().isApprox(expected.max(), 1e-5f));
  // The same rig gives the same bytes.
  EXPECT_EQ(EgoVehicleGlb(rig, 1.6), glb);
}

}  // namespace
}  // namespace rigsim
