// `rigsim make-rig --placement road` through the built binary: an imported car rig stands in a lane
// of the shipped street, its front and rear cameras looking along the street; a scene without a
// road, or the option without a scene, is refused and nothing is written.

#include <cmath>
#include <filesystem>
#include <string>

#include <Eigen/Geometry>
#include <gtest/gtest.h>

#include "dataset/dataset.h"
#include "geometry/rig.h"
#include "gltf/gltf_loader.h"
#include "rigs/placement.h"
#include "testing/temp_dir.h"
#include "tests/rigsim_cli.h"

#ifndef RIGSIM_SOURCE_DIR
#error "RIGSIM_SOURCE_DIR must name the source tree"
#endif

namespace rigsim {
namespace {
namespace fs = std::filesystem;

const std::string kAssets = std::string(RIGSIM_SOURCE_DIR) + "/assets/scenes/";

// A car's rig as an imported calibration has it: the frame is the front camera's (at the origin),
// two side cameras and a rear camera 1.3 m behind it.
Rig CarRig() {
  Rig rig;
  const Camera cam(CameraModelId::kPinhole, 640, 400, {400, 400, 319.5, 199.5});
  auto add = [&](const char* name, double yaw_deg, const Eigen::Vector3d& centre_in_rig) {
    const Eigen::Matrix3d rig_from_cam = Eigen::AngleAxisd(DegToRad(yaw_deg), Eigen::Vector3d::UnitY()).toRotationMatrix();
    rig.cameras.push_back({name, cam, Rigid3d(rig_from_cam, centre_in_rig).Inverse(), 0.0});
  };
  add("front", 0, {0, 0, 0});
  add("right", 90, {0.7, 0, -0.4});
  add("left", -90, {-0.2, 0, -0.4});
  add("rear", 180, {0.1, 0, -1.3});
  return rig;
}

TEST(RoadPlacementCli, AnImportedCarRigDrivesTheStreetInItsLane) {
  const TempDir dir;
  WriteRig(CarRig(), dir / "car.json");
  const std::string street = kAssets + "street.glb";
  const CliResult r = RunRigsim({"make-rig", "--type", "file", "--rig-file", (dir / "car.json").string(), "--scene", street,
                                 "--placement", "road", "--frames", "3", "--step", "1.5", "--out", (dir / "out").string()},
                                dir / "rigsim");
  ASSERT_EQ(r.code, 0) << r.err;
  EXPECT_NE(r.out.find("placed on the road at"), std::string::npos) << r.out;
  EXPECT_NE(r.out.find("right-hand lane"), std::string::npos) << r.out;
  const Rig rig = ReadRig(dir / "out" / "rig.json");
  const FramesFile frames = ReadFrames(dir / "out" / "frames.json");
  ASSERT_EQ(frames.frames.size(), 3u);
  const Scene scene = LoadGltf(street);
  for (const Frame& f : frames.frames) {
    const Rigid3d world_from_rig = f.rig_from_world->Inverse();
    // The street's road is x in [-5, 5] at y = 0, along z: the rig's origin (its front camera)
    // stands 1.6 m up in a lane, 2.5 m from the centre line.
    EXPECT_NEAR(world_from_rig.translation.y(), 1.6, 1e-6) << f.name;
    EXPECT_NEAR(std::abs(world_from_rig.translation.x()), 2.5, 0.3) << f.name;
    for (const char* name : {"front", "rear"}) {
      const Rigid3d world_from_cam = world_from_rig * rig.cameras[rig.FindCamera(name)].cam_from_rig->Inverse();
      const Eigen::Vector3d axis = world_from_cam.rotation * Eigen::Vector3d::UnitZ();
      EXPECT_LT(std::abs(axis.x()), std::sin(DegToRad(3.0))) << name << " looks along the street (z), frame " << f.name;
      const auto hit = CastRay(scene, world_from_cam.translation, axis);
      EXPECT_TRUE(!hit || *hit > 20.0) << name << ": its central ray meets a surface " << *hit << " m away, frame "
                                        << f.name;
    }
  }
}

TEST(RoadPlacementCli, ASceneWithoutRoadOrNoSceneIsRefusedAndNothingWritten) {
  const TempDir dir;
  const std::string plaza = kAssets + "plaza.glb";
  const CliResult no_road = RunRigsim({"make-rig", "--type", "surround", "--scene", plaza, "--placement", "road", "--out",
                                       (dir / "out").string()},
                                      dir / "rigsim");
  EXPECT_NE(no_road.code, 0);
  EXPECT_NE(no_road.err.find(plaza + ": no surface labelled road"), std::string::npos) << no_road.err;
  EXPECT_NE(no_road.err.find("sidewalk"), std::string::npos) << "the ground's classes are named: " << no_road.err;
  const CliResult no_scene = RunRigsim({"make-rig", "--type", "surround", "--placement", "road", "--out", (dir / "out").string()},
                                       dir / "rigsim");
  EXPECT_NE(no_scene.code, 0);
  EXPECT_NE(no_scene.err.find("give --scene too"), std::string::npos) << no_scene.err;
  // A loop wider than the street's 10 m road fits on no spot of it.
  const CliResult loop = RunRigsim({"make-rig", "--type", "surround", "--scene", kAssets + "street.glb", "--placement", "road",
                                    "--trajectory", "loop", "--circle-radius", "12", "--frames", "8", "--out",
                                    (dir / "out").string()},
                                   dir / "rigsim");
  EXPECT_NE(loop.code, 0);
  EXPECT_NE(loop.err.find("no spot on the road"), std::string::npos) << loop.err;
  EXPECT_NE(loop.err.find("--circle-radius"), std::string::npos) << loop.err;
  EXPECT_FALSE(fs::exists(dir / "out"));
  EXPECT_TRUE(StagingFolders(dir / "out").empty());
}

}  // namespace
}  // namespace rigsim
