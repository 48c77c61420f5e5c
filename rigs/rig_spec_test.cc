#include "rigs/rig_spec.h"

#include <cmath>

#include <gtest/gtest.h>

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
