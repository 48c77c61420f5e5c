#include "dataset/capture_poses.h"

#include <cmath>
#include <stdexcept>
#include <vector>

#include <Eigen/Geometry>
#include <gtest/gtest.h>

namespace rigsim {
namespace {

// Two frames 0.1 s apart: the rig moves 1 m along world x and turns 10 deg about y.
FramesFile TwoFrames() {
  FramesFile f;
  const Rigid3d second(Eigen::Quaterniond(Eigen::AngleAxisd(10.0 * M_PI / 180, Eigen::Vector3d::UnitY())),
                       Eigen::Vector3d::Zero());
  f.frames.push_back(Frame{"f0", Rigid3d(), 0.0});
  Rigid3d moved = second;
  moved.translation = -(moved.rotation * Eigen::Vector3d(1, 0, 0));  // centre at x = 1
  f.frames.push_back(Frame{"f1", moved, 0.1});
  return f;
}

RigCamera Cam(double offset_s, double readout_s) {
  RigCamera c;
  c.name = "cam";
  c.camera = Camera(CameraModelId::kPinhole, 8, 4, {4, 4, 3.5, 1.5});
  c.cam_from_rig = Rigid3d();
  c.time_offset_s = offset_s;
  c.readout_s = readout_s;
  return c;
}

TEST(CapturePoses, AnUntimedCameraSeesFromItsFrameExactly) {
  const FramesFile frames = TwoFrames();
  const RigCamera cam = Cam(0.0, 0.0);
  const CapturePoses poses({cam}, frames);
  EXPECT_FALSE(poses.timed());
  const ViewPose p = poses.Of(cam, frames.frames[1]);
  ASSERT_EQ(p.cam_from_world_rows.size(), 1u);
  EXPECT_EQ(p.Row(0).translation, frames.frames[1].rig_from_world->translation);
}

TEST(CapturePoses, AnOffsetCameraIsWhereTheRigIsAtItsCaptureTime) {
  const FramesFile frames = TwoFrames();
  const RigCamera cam = Cam(0.025, 0.0);
  const CapturePoses poses({cam}, frames);
  EXPECT_TRUE(poses.timed());
  const Rigid3d at = poses.Of(cam, frames.frames[0]).Row(0);
  EXPECT_NEAR(at.SourceOriginInTarget().x(), 0.25, 1e-12);  // a quarter of the way
  EXPECT_NEAR(Eigen::AngleAxisd(at.rotation).angle() * 180 / M_PI, 2.5, 1e-9);
}

TEST(CapturePoses, ARollingShutterHasOnePosePerRowInReadoutOrder) {
  const FramesFile frames = TwoFrames();
  RigCamera cam = Cam(0.0, 0.04);
  const CapturePoses poses({cam}, frames);
  const ViewPose p = poses.Of(cam, frames.frames[0]);
  ASSERT_EQ(p.cam_from_world_rows.size(), 4u);
  for (int y = 0; y < 4; ++y) EXPECT_NEAR(p.Row(y).SourceOriginInTarget().x(), 10.0 * cam.RowTime(y), 1e-12) << y;
  cam.readout_bottom_to_top = true;
  const ViewPose up = poses.Of(cam, frames.frames[0]);
  EXPECT_NEAR(up.Row(3).SourceOriginInTarget().x(), 0.0, 1e-12);
  EXPECT_GT(up.Row(0).SourceOriginInTarget().x(), 0.0);
}

TEST(CapturePoses, RepeatedTimestampsAreRefusedOnlyWhenACameraIsTimed) {
  FramesFile frames = TwoFrames();
  frames.frames[1].timestamp_s = 0.0;
  EXPECT_NO_THROW(CapturePoses({Cam(0.0, 0.0)}, frames));
  EXPECT_THROW(CapturePoses({Cam(0.01, 0.0)}, frames), std::invalid_argument);
}

}  // namespace
}  // namespace rigsim
