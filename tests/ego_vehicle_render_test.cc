// The rig's own vehicle end to end: make-rig's body file (procedural/ego_vehicle.h) loaded, turned
// into the rig frame and attached to the renderer: it shows in the lower part of cameras that look
// out past the roof and in none that looks up, on the same pixels whatever the rig's pose and
// motion (rolling shutter included), and a render without it keeps its bytes.
#include <cmath>
#include <cstdint>
#include <fstream>
#include <string>
#include <vector>

#include <Eigen/Geometry>
#include <gtest/gtest.h>

#include "gltf/gltf_loader.h"
#include "procedural/ego_vehicle.h"
#include "renderer/renderer.h"
#include "rigs/trajectories.h"
#include "testing/temp_dir.h"

namespace rigsim {
namespace {

constexpr uint8_t kEgo = 1, kRoad = 7;

RigCamera CameraAt(const std::string& name, const Eigen::Vector3d& centre, const Eigen::Vector3d& forward) {
  const Eigen::Vector3d z = forward.normalized();
  Eigen::Vector3d down = Eigen::Vector3d::UnitY() - z * z.y();
  if (down.norm() < 1e-6) down = Eigen::Vector3d::UnitZ();
  const Eigen::Vector3d y = down.normalized(), x = y.cross(z);
  Eigen::Matrix3d rig_from_cam;
  rig_from_cam << x, y, z;
  const Eigen::Quaterniond cam_from_rig(rig_from_cam.transpose());
  return {name, Camera(CameraModelId::kPinhole, 64, 48, {40, 40, 31.5, 23.5}), Rigid3d(cam_from_rig, -(cam_from_rig * centre)), 0.0};
}

// A car rig: a front camera, a side camera, and one looking straight up.
Rig CarRig() {
  Rig rig;
  rig.cameras = {CameraAt("front", {0, 0, 2}, {0, 0, 1}), CameraAt("right", {0.9, 0, 0}, {1, 0, 0}),
                 CameraAt("up", {0, 0, 0}, {0, -1, 0.001})};
  return rig;
}

// A road (the plane y = 0, glTF world) for the body to stand on, walled in 30 m around the origin
// (so that the world looks different from where the rig drives).
Scene Road() {
  Scene scene;
  auto add = [&](const char* name, uint8_t class_id, std::vector<Eigen::Vector3f> corners) {
    SceneMesh mesh;
    mesh.name = name;
    mesh.class_id = class_id;
    mesh.instance_id = uint16_t(scene.meshes.size() + 1);
    mesh.positions = std::move(corners);
    mesh.indices = {0, 1, 2, 0, 2, 3};
    scene.meshes.push_back(mesh);
  };
  add("road", kRoad, {{-200, 0, -200}, {200, 0, -200}, {200, 0, 200}, {-200, 0, 200}});
  for (const float s : {-30.0f, 30.0f}) {
    add("wall x", 11, {{s, 0, -30}, {s, 0, 30}, {s, 20, 30}, {s, 20, -30}});
    add("wall z", 11, {{-30, 0, s}, {30, 0, s}, {30, 20, s}, {-30, 20, s}});
  }
  return scene;
}

// The body make-rig writes for `rig`, loaded as render loads it.
Scene EgoVehicle(const Rig& rig, const TempDir& dir) {
  const std::vector<uint8_t> glb = EgoVehicleGlb(rig, 1.6);
  const std::filesystem::path path = dir.path() / kEgoVehicleFile;
  std::ofstream(path, std::ios::binary).write(reinterpret_cast<const char*>(glb.data()), std::streamsize(glb.size()));
  Scene scene = LoadGltf(path);
  EgoVehicleToRigFrame(scene);
  return scene;
}

// The rig driving and turning: 1.6 m above the road, at 10 m/s, turning 20 deg/s.
Rigid3d RigFromWorld(double t) { return RigFromWorldAt(Eigen::Vector3d(10 * t, 1.6, -3 * t), 20 * t); }

std::vector<bool> EgoMask(const RenderedView& view) {
  std::vector<bool> mask;
  for (int y = 0; y < view.label.height; ++y) {
    for (int x = 0; x < view.label.width; ++x) mask.push_back(view.label.at(x, y) == kEgo);
  }
  return mask;
}

int CountEgo(const RenderedView& view, int y_begin, int y_end) {
  int n = 0;
  for (int y = y_begin; y < y_end; ++y) {
    for (int x = 0; x < view.label.width; ++x) n += view.label.at(x, y) == kEgo;
  }
  return n;
}

RenderOptions Options() {
  RenderOptions options;
  options.samples_per_pixel = 4;
  return options;
}

TEST(EgoVehicleRender, ShowsInTheLowerPartOfCamerasLookingOutAndNotInOneLookingUp) {
  const TempDir dir;
  const Rig rig = CarRig();
  const Scene road = Road();
  const Scene body = EgoVehicle(rig, dir);
  Renderer renderer(road);
  renderer.SetAttached(body);
  for (const RigCamera& cam : rig.cameras) {
    const Rigid3d cam_from_world = *cam.cam_from_rig * RigFromWorld(0);
    const RenderedView view = renderer.Render(cam.camera, cam_from_world, Options(), *cam.cam_from_rig);
    const int h = cam.camera.height();
    if (cam.name == "up") {
      EXPECT_EQ(CountEgo(view, 0, h), 0);
      continue;
    }
    EXPECT_EQ(CountEgo(view, 0, h / 2), 0) << cam.name << ": the body is below the horizon";
    EXPECT_GT(CountEgo(view, h / 2, h), 64) << cam.name << ": at least a row of its lower half shows the body";
    // Ground truth of body pixels is the body's: near, with the road behind it hidden (straight
    // down ahead: the bottom row's middle third; its corners may see the road beside the car).
    for (int x = cam.camera.width() / 3; x < 2 * cam.camera.width() / 3; ++x) {
      EXPECT_EQ(view.label.at(x, h - 1), kEgo) << cam.name << " bottom row, column " << x;
      EXPECT_GT(view.range.at(x, h - 1), 0.0f);
      EXPECT_LT(view.range.at(x, h - 1), 2.0f);  // the road is 3 m away there
    }
  }
}

TEST(EgoVehicleRender, MovesWithTheRigWhateverItsPoseAndMotion) {
  const TempDir dir;
  Rig rig = CarRig();
  const Scene road = Road();
  const Scene body = EgoVehicle(rig, dir);
  Renderer renderer(road);
  renderer.SetAttached(body);
  for (RigCamera& cam : rig.cameras) {
    if (cam.name == "up") continue;
    const RenderedView still = renderer.Render(cam.camera, *cam.cam_from_rig * RigFromWorld(0), Options(), *cam.cam_from_rig);
    const RenderedView later = renderer.Render(cam.camera, *cam.cam_from_rig * RigFromWorld(1.5), Options(), *cam.cam_from_rig);
    EXPECT_EQ(EgoMask(still), EgoMask(later)) << cam.name;
    // A rolling shutter and an exposure on the turning, driving rig: the body does not shear or blur.
    cam.readout_s = 0.03;
    cam.exposure_s = 0.01;
    const Rigid3d cam_from_rig = *cam.cam_from_rig;
    MovingCameraView moving{&cam, 0.7, [&](double t) { return cam_from_rig * RigFromWorld(t); }};
    const RenderedView rolling = renderer.Render(moving, Options());
    EXPECT_EQ(EgoMask(still), EgoMask(rolling)) << cam.name;
    // The road beyond the body does move: the views differ elsewhere.
    EXPECT_NE(still.range.data, rolling.range.data);
  }
}

TEST(EgoVehicleRender, GlossyPaintReflectsTheWorld) {
  const TempDir dir;
  const Rig rig = CarRig();
  const Scene road = Road();
  Scene body = EgoVehicle(rig, dir);
  Renderer renderer(road);
  renderer.SetAttached(body);
  const RigCamera& cam = rig.cameras[1];
  const Rigid3d cam_from_world = *cam.cam_from_rig * RigFromWorld(0);
  const RenderedView glossy = renderer.Render(cam.camera, cam_from_world, Options(), *cam.cam_from_rig);
  Scene matte = body;
  for (Material& m : matte.materials) m.roughness = 1.0f;
  Renderer matte_renderer(road);
  matte_renderer.SetAttached(matte);
  const RenderedView plain = matte_renderer.Render(cam.camera, cam_from_world, Options(), *cam.cam_from_rig);
  EXPECT_EQ(glossy.label.data, plain.label.data);
  EXPECT_NE(glossy.rgb.data, plain.rgb.data) << "the paint's reflection changes its colour";
}

TEST(EgoVehicleRender, WithoutItTheBytesAreUnchanged) {
  const TempDir dir;
  const Rig rig = CarRig();
  const Scene road = Road();
  const Scene body = EgoVehicle(rig, dir);
  Renderer plain(road);
  Renderer with_body(road);
  with_body.SetAttached(body);
  for (const RigCamera& cam : rig.cameras) {
    const Rigid3d cam_from_world = *cam.cam_from_rig * RigFromWorld(0);
    const RenderedView before = plain.Render(cam.camera, cam_from_world, Options());
    // No body attached: a camera's place on the rig changes nothing.
    const RenderedView placed = plain.Render(cam.camera, cam_from_world, Options(), *cam.cam_from_rig);
    // A body attached, but a view without a place on the rig does not show it.
    const RenderedView unplaced = with_body.Render(cam.camera, cam_from_world, Options());
    for (const RenderedView* v : {&placed, &unplaced}) {
      EXPECT_EQ(v->rgb.data, before.rgb.data) << cam.name;
      EXPECT_EQ(v->label.data, before.label.data) << cam.name;
      EXPECT_EQ(v->range.data, before.range.data) << cam.name;
    }
  }
}

}  // namespace
}  // namespace rigsim
