#include "calibrator/model/rig_state.h"

#include <Eigen/Geometry>
#include <gtest/gtest.h>

namespace rigsim {
namespace {

// A view's pose is cam_from_rig after rig_from_world: a world point goes into the rig frame first,
// then into the camera.
TEST(RigPoses, AViewSeesTheWorldThroughTheRigThenTheCamera) {
  const Rigid3d cam_from_rig(Eigen::Quaterniond(Eigen::AngleAxisd(0.5, Eigen::Vector3d::UnitY())), {0.3, 0.0, -0.1});
  const Rigid3d rig_from_world(Eigen::Quaterniond(Eigen::AngleAxisd(-0.8, Eigen::Vector3d::UnitZ())), {2.0, 1.0, 0.5});
  RigPoses poses;
  poses.cam_from_rig = {Rigid3d(), cam_from_rig};
  poses.rig_from_world = {Rigid3d(), rig_from_world};
  const Eigen::Vector3d x(1.0, -2.0, 7.0);
  ASSERT_TRUE(poses.Posed(1, 1));
  const Eigen::Vector3d in_cam = poses.CamFromWorld(1, 1) * x;
  const Eigen::Vector3d expected = cam_from_rig.rotation * (rig_from_world.rotation * x + rig_from_world.translation) +
                                   cam_from_rig.translation;
  EXPECT_LT((in_cam - expected).norm(), 1e-12);
  EXPECT_LT(((poses.CamFromWorld(0, 1) * x) - (rig_from_world * x)).norm(), 1e-12);  // camera 0 is the rig frame
}

TEST(RigPoses, AViewOfACameraOrFrameWithoutAPoseIsNotPosed) {
  RigPoses poses;
  poses.cam_from_rig = {Rigid3d(), std::nullopt};
  poses.rig_from_world = {Rigid3d(), Rigid3d(), std::nullopt};
  EXPECT_TRUE(poses.Posed(0, 1));
  EXPECT_FALSE(poses.Posed(1, 0));   // the camera has no pose
  EXPECT_FALSE(poses.Posed(0, 2));   // the frame has none
  EXPECT_FALSE(poses.Posed(2, 0));   // no such camera
  EXPECT_FALSE(poses.Posed(0, 3));   // no such frame
  EXPECT_FALSE(poses.Posed(-1, 0));
}

}  // namespace
}  // namespace rigsim
