#include "rigs/rig_spec.h"

#include <cmath>

#include <gmock/gmock.h>
#include <gtest/gtest.h>

#include "testing/expect_error.h"
#include "testing/temp_dir.h"

namespace rigsim {
namespace {

TEST(RigSpec, OverridesReachEveryType) {
  RigSpec s;
  s.width = 320;
  s.height = 200;
  s.hfov_deg = 70.0;
  s.baseline_m = 0.5;
  for (RigType type : kPresetRigTypes) {
    s.type = type;
    const Rig rig = BuildPresetRig(s);
    for (const RigCamera& c : rig.cameras) {
      EXPECT_EQ(c.camera.width(), 320) << RigTypeName(type);
      EXPECT_EQ(c.camera.height(), 200) << RigTypeName(type);
    }
  }
  s.type = RigType::kWideBaseline;
  const Rig wide = BuildPresetRig(s);
  const double baseline = (wide.cameras[0].cam_from_rig->Inverse().translation -
                           wide.cameras[1].cam_from_rig->Inverse().translation).norm();
  EXPECT_NEAR(baseline, 0.5, 1e-12);
}

TEST(RigSpec, RigTypesHaveOneNameEach) {
  for (RigType type : kAllRigTypes) EXPECT_EQ(RigTypeFromName(RigTypeName(type)), type);
  EXPECT_THROW(RigTypeFromName("tri"), std::invalid_argument);
}

TEST(RigSpec, ALensReplacesEveryCamerasOwn) {
  RigSpec s;
  s.width = 640;
  s.height = 360;
  LensOptions fisheye;
  fisheye.kind = LensOptions::Kind::kFisheye;
  fisheye.fisheye_fov_deg = 190.0;
  s.lens = fisheye;
  for (RigType type : kPresetRigTypes) {
    s.type = type;
    for (const RigCamera& c : BuildPresetRig(s).cameras) {
      EXPECT_EQ(c.camera.model(), CameraModelId::kOpenCVFisheye) << RigTypeName(type);
      // The side edges of the image see 95 deg off the axis.
      const auto ray = c.camera.CamFromImg(Eigen::Vector2d(-0.5, 179.5));
      ASSERT_TRUE(ray.has_value());
      EXPECT_NEAR(RadToDeg(std::atan2(std::abs(ray->x()), ray->z())), 95.0, 0.01) << RigTypeName(type);
    }
  }
  LensOptions opencv;
  opencv.kind = LensOptions::Kind::kOpenCV;
  opencv.k1 = -0.3;
  s.lens = opencv;
  s.type = RigType::kRing;
  const Rig ring = BuildPresetRig(s);
  for (const RigCamera& c : ring.cameras) {
    ASSERT_EQ(c.camera.model(), CameraModelId::kOpenCV);
    EXPECT_DOUBLE_EQ(c.camera.params()[4], -0.3);
    EXPECT_DOUBLE_EQ(c.camera.params()[5], 0.072);
  }
  // Without a lens the ring keeps its own: pinhole but one barrel-distorted camera.
  s.lens = LensOptions{};
  const Rig preset = BuildPresetRig(s);
  EXPECT_EQ(preset.cameras[0].camera.model(), CameraModelId::kPinhole);
  EXPECT_EQ(preset.cameras[1].camera.model(), CameraModelId::kOpenCV);
}

TEST(RigSpec, WithoutASceneTheTrajectoryStartsWhereItSays) {
  RigSpec s;
  s.trajectory.num_frames = 3;
  s.trajectory.start_world = Eigen::Vector3d(1, 1.6, 2);
  const std::optional<PlacedRig> placed = MakePlacedRig(s, nullptr);
  ASSERT_TRUE(placed.has_value());
  EXPECT_FALSE(placed->placement.has_value());
  ASSERT_EQ(placed->frames.frames.size(), 3u);
  EXPECT_NEAR((placed->frames.frames[0].rig_from_world->Inverse().translation - Eigen::Vector3d(1, 1.6, 2)).norm(), 0.0,
              1e-12);
}

}  // namespace
}  // namespace rigsim

namespace rigsim {
namespace {

TEST(RigSpec, AFileRigIsTheFilesCamerasAndABadFileIsNamed) {
  const TempDir dir;
  RigSpec preset;
  preset.ring.num_cameras = 3;
  preset.width = 200;
  preset.height = 100;
  const Rig written = BuildPresetRig(preset);
  WriteRig(written, dir / "rig.json");
  RigSpec s;
  s.type = RigType::kFile;
  s.rig_file = (dir / "rig.json").string();
  s.width = 999;  // a file's cameras keep their own size
  const Rig read = BuildPresetRig(s);
  ASSERT_EQ(read.cameras.size(), 3u);
  for (size_t i = 0; i < 3; ++i) {
    EXPECT_EQ(read.cameras[i].camera.width(), 200);
    EXPECT_LT((read.cameras[i].cam_from_rig->translation - written.cameras[i].cam_from_rig->translation).norm(), 1e-12);
  }
  // It drives the paths as any rig does.
  s.trajectory.kind = TrajectoryKind::kHandheld;
  s.trajectory.num_frames = 4;
  ASSERT_TRUE(MakePlacedRig(s, nullptr).has_value());
  // A camera without its place on the rig, a missing file and a file rig without a file are refused.
  WriteFile(dir / "loose.json", R"({"cameras": [{"name": "cam0", "model": "PINHOLE", "width": 64, "height": 48,
    "params": [50, 50, 31.5, 23.5]}]})");
  EXPECT_THAT([&] { ReadRigFile((dir / "loose.json").string()); },
              ThrowsWith<std::runtime_error>((dir / "loose.json").string() + ": camera 'cam0' has no cam_from_rig"));
  EXPECT_THROW(ReadRigFile((dir / "absent.json").string()), std::runtime_error);
  s.rig_file.clear();
  EXPECT_THROW(BuildPresetRig(s), std::invalid_argument);
}

TEST(RigSpec, OverlapZeroPartsNeighboursCompletely) {
  RigSpec s;
  s.ring.num_cameras = 4;
  s.hfov_deg = 85.0;
  s.overlap_percent = 0.0;
  const Rig rig = BuildPresetRig(s);
  for (size_t i = 0; i + 1 < rig.cameras.size(); ++i) {
    const RigCamera& a = rig.cameras[i];
    const RigCamera& b = rig.cameras[i + 1];
    const Eigen::Matrix3d b_from_a = (*b.cam_from_rig * a.cam_from_rig->Inverse()).RotationMatrix();
    EXPECT_EQ(AngularOverlap(a.camera, b.camera, b_from_a), 0.0) << i;
    EXPECT_EQ(AngularOverlap(b.camera, a.camera, b_from_a.transpose()), 0.0) << i;
  }
  // Unset is the spacing, as before.
  s.overlap_percent.reset();
  const Rig spaced = BuildPresetRig(s);
  const double yaw = RadToDeg(Eigen::AngleAxisd((*spaced.cameras[1].cam_from_rig * spaced.cameras[0].cam_from_rig->Inverse()).rotation).angle());
  EXPECT_NEAR(yaw, s.ring.yaw_spacing_deg, 1e-9);
  // Four cameras of 95 deg cannot all part: the last would see into the first.
  s.overlap_percent = 0.0;
  s.hfov_deg = 95.0;
  EXPECT_THROW(BuildPresetRig(s), std::invalid_argument);
}

}  // namespace
}  // namespace rigsim
