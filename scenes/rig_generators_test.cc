#include "scenes/rig_generators.h"

#include <gtest/gtest.h>

namespace rigsim {
namespace {

TEST(RingRig, CamerasFaceOutwardsFromLeftToRight) {
  RingRigOptions o;
  o.num_cameras = 4;
  o.yaw_spacing_deg = 60;
  const Rig rig = MakeRingRig(o);
  ASSERT_EQ(rig.cameras.size(), 4u);
  double previous_yaw = -1e9;
  for (const RigCamera& c : rig.cameras) {
    const Rigid3d rig_from_cam = c.cam_from_rig->Inverse();
    const Eigen::Vector3d axis = rig_from_cam.rotation * Eigen::Vector3d::UnitZ();
    const Eigen::Vector3d centre = rig_from_cam.translation;
    EXPECT_NEAR(centre.norm(), o.radius_m, 1e-12);
    EXPECT_NEAR(axis.y(), 0.0, 1e-12);                            // horizontal
    EXPECT_LT((axis - centre.normalized()).norm(), 1e-12);        // facing outwards
    const double yaw = RadToDeg(std::atan2(axis.x(), axis.z()));  // + = right
    EXPECT_GT(yaw, previous_yaw);
    if (previous_yaw > -1e9) {
      EXPECT_NEAR(yaw - previous_yaw, 60.0, 1e-9);
    }
    previous_yaw = yaw;
    // Image y stays down.
    EXPECT_LT((rig_from_cam.rotation * Eigen::Vector3d::UnitY() - Eigen::Vector3d::UnitY()).norm(), 1e-12);
  }
}

TEST(RingRig, DistortedCameraKeepsTheFieldOfView) {
  RingRigOptions o;
  const Rig rig = MakeRingRig(o);
  const Camera& barrel = rig.cameras[o.distorted_camera].camera;
  const Camera& pinhole = rig.cameras[0].camera;
  EXPECT_EQ(barrel.model(), CameraModelId::kOpenCV);
  const double half = DegToRad(o.hfov_deg / 2);
  const Eigen::Vector3d edge_ray(std::sin(half), 0.0, std::cos(half));
  EXPECT_NEAR(barrel.ImgFromCam(edge_ray)->x(), o.width - 0.5, 1e-9);
  EXPECT_NEAR(pinhole.ImgFromCam(edge_ray)->x(), o.width - 0.5, 1e-9);
  // The whole sensor is imaged.
  EXPECT_TRUE(barrel.CamFromImg(Eigen::Vector2d(-0.5, -0.5)).has_value());
}

TEST(RigPlacement, HeadingZeroLooksDownMinusZUpright) {
  const Rigid3d rig_from_world = RigFromWorldAt(Eigen::Vector3d(1, 1.6, 2), 0.0);
  EXPECT_LT((rig_from_world * Eigen::Vector3d(1, 1.6, -3) - Eigen::Vector3d(0, 0, 5)).norm(), 1e-12);
  EXPECT_LT((rig_from_world * Eigen::Vector3d(1, 2.6, 2)).y(), 0.0);  // world up = rig -y
  const Rigid3d right = RigFromWorldAt(Eigen::Vector3d::Zero(), 90.0);
  EXPECT_GT((right * Eigen::Vector3d(5, 0, 0)).z(), 4.99);
}

TEST(Trajectory, MovesForwardByTheStep) {
  const FramesFile f = MakeStraightTrajectory(Eigen::Vector3d(0, 1.6, 0), 0.0, 3, 2.0, 0.5);
  ASSERT_EQ(f.frames.size(), 3u);
  EXPECT_EQ(f.frames[2].name, "000002");
  EXPECT_DOUBLE_EQ(f.frames[2].timestamp_s, 1.0);
  const Eigen::Vector3d c2 = f.frames[2].rig_from_world->SourceOriginInTarget();
  EXPECT_LT((c2 - Eigen::Vector3d(0, 1.6, -4)).norm(), 1e-12);
}

}  // namespace
}  // namespace rigsim
